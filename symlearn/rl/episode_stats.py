"""Finished episodes and the costs they report, as training and evaluation account for them.

:class:`CostReader` reads a step's ``info["cost"]`` (a number or a vector whose length, once
seen, stays fixed; NaN/inf refused), :class:`FinishedEpisode` is one episode's sums,
:class:`EpisodeStats` many as arrays (:func:`episode_stats`). PPO's rollouts
(:mod:`symlearn.rl.ppo.rollouts`) and the one evaluation loop (:mod:`symlearn.rl.evaluation`)
both count through them, so a cost means the same in training and in evaluation. Numpy only:
evaluating a stable-baselines3 or tabular policy loads nothing of our PPO.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from symlearn.errors import DataError


def plain(value: Any) -> Any:
    """JSON-able: tuples -> lists, NaN -> None, numpy scalars -> Python."""
    if isinstance(value, dict):
        return {key: plain(v) for key, v in value.items()}
    if isinstance(value, (tuple, list, np.ndarray)):
        return [plain(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return None if not math.isfinite(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


class NoCostReported(DataError):
    """A Lagrangian constrains ``info["cost"]``, and none of the ``steps`` of its first rollout
    reported one (a step without it costs 0 once another has reported one)."""

    def __init__(self, message: str, *, steps: int, hint: str | None = None) -> None:
        super().__init__(message, hint=hint)
        self.steps = steps


class BadCostReport(DataError):
    """The environment's ``info["cost"]`` is no number, not finite, or changes its length: an
    error in the environment, which a command must not blame on the demonstrations file it was
    reading when the environment stepped (:func:`symlearn.cli.output.blame_file`)."""

    about_the_environment = True


def _where(where: str | Callable[[], str] | None, env_index: int | None, step: int | None) -> str:
    if callable(where):   # formatted only for an error: the samplers read a cost on every step
        where = where()
    if where:
        return where
    if env_index is not None:
        return f"training step {step}, environment copy {env_index}"
    return "a step" if step is None else f"step {step}"


class CostReader:
    """Reads ``info["cost"]``: a number or a vector whose length, once seen, stays fixed."""

    def __init__(self, n: int | None) -> None:
        self.n = n  # None until the first cost arrives (or the Lagrangian limits fix it)
        self.seen = False

    def read(self, info: dict[str, Any], env_index: int | None = None, step: int | None = None, *,
             where: str | Callable[[], str] | None = None) -> np.ndarray | None:
        """The step's cost vector, or None where it reports none. An error says where the step
        was: ``where`` as given (``"evaluation episode 2, step 7"``, or a function returning it,
        called only for the error), else, for the copies PPO's training steps side by side,
        ``training step 1234, environment copy 0`` (``step`` counts the steps of all copies)."""
        raw = info.get("cost")
        if raw is None:
            return None
        try:
            # numbers and booleans only: text ("1") converted silently and np.sum of it failed
            # inside stable-baselines3's loop; complex numbers lose their imaginary part
            array = np.asarray(raw)
            if array.dtype.kind not in "biuf":
                raise TypeError
            cost = array.astype(np.float64, copy=False).reshape(-1)
        except (TypeError, ValueError):
            raise BadCostReport(f"info['cost'] must be a number or a vector of numbers, got {raw!r} "
                            f"({_where(where, env_index, step)})") from None
        if cost.size == 0:
            raise BadCostReport(f"info['cost'] is empty ({_where(where, env_index, step)})")
        if not np.all(np.isfinite(cost)):
            raise BadCostReport(f"info['cost'] is not finite: {cost.tolist()} ({_where(where, env_index, step)})",
                            hint="an environment must report a finite cost on every step")
        if self.n is None:
            self.n = cost.size
        elif cost.size != self.n:
            before = "the cost limits name" if not self.seen else "earlier steps reported"
            raise BadCostReport(f"info['cost'] has {cost.size} entries, {before} {self.n} "
                            f"({_where(where, env_index, step)})",
                            hint="report one cost per constraint on every step, always in the same order")
        self.seen = True
        return cost

    def accept(self, k: int) -> None:
        """A whole rollout's costs arrived at once (``cost_fn``): ``k`` per step, fixed once seen."""
        if self.n is None:
            self.n = k
        elif k != self.n:
            before = "the cost limits name" if not self.seen else "earlier rollouts had"
            raise DataError(f"cost_fn returned {k} cost(s) per step, {before} {self.n}",
                            hint="return one cost per constraint, always in the same order")
        self.seen = True


def summed_cost(info: dict[str, Any], *, where: str | Callable[[], str]) -> float | None:
    """One step's ``info["cost"]`` summed over its constraints, read and checked as
    :class:`CostReader` reads it (None where the step reports none, ``None`` included): the
    samplers that only need the total (neural ICRL's episodes, stable-baselines3's monitor,
    tabular Q-learning) so refuse what training refuses in one line, instead of failing on
    ``float(None)`` or summing text. ``where`` names the step in an error (``episode 3, step 7``;
    a function is called only then)."""
    raw = info.get("cost")
    # the usual report, a finite Python number, without the arrays (tabular Q-learning reads one
    # per step: 6.5 us through the reader against 0.06 us for float() before the checks)
    if (type(raw) is float and math.isfinite(raw)) or type(raw) is bool \
            or (type(raw) is int and -2**63 <= raw < 2**63):   # beyond int64 numpy refuses it: the reader's error
        return float(raw)
    cost = CostReader(None).read(info, where=where)
    return None if cost is None else float(cost.sum())


class FinishedEpisode(NamedTuple):
    """One episode that ended: its return, length, cost sum per constraint (empty before the first
    cost arrived) and the environment step count (over all copies) at the end of the round of
    steps in which it ended."""

    episode_return: float
    length: int
    costs: np.ndarray
    end_step: int


@dataclass(frozen=True)
class EpisodeStats:
    """Finished episodes: return, length, cost sum per constraint ``(E, k)``, and the environment
    step count (over all copies, at the end of the round of steps in which it ended) of its end."""

    returns: np.ndarray
    lengths: np.ndarray
    costs: np.ndarray
    end_steps: np.ndarray

    def __len__(self) -> int:
        return len(self.returns)

    def as_dict(self) -> dict[str, Any]:
        return {"returns": plain(self.returns), "lengths": plain(self.lengths), "costs": plain(self.costs),
                "end_steps": plain(self.end_steps)}


def episode_costs(episodes: Sequence[FinishedEpisode], n_costs: int) -> np.ndarray:
    """The episodes' cost sums as ``(E, n_costs)``: an episode that ended before the first cost
    arrived cost 0."""
    costs = np.zeros((len(episodes), n_costs))
    for j, episode in enumerate(episodes):
        costs[j, : episode.costs.size] = episode.costs
    return costs


def episode_stats(episodes: Sequence[FinishedEpisode], n_costs: int) -> EpisodeStats:
    """Finished episodes as the arrays of :class:`EpisodeStats`."""
    return EpisodeStats(np.array([e.episode_return for e in episodes]),
                        np.array([e.length for e in episodes], dtype=np.int64), episode_costs(episodes, n_costs),
                        np.array([e.end_step for e in episodes], dtype=np.int64))


__all__ = ["BadCostReport", "CostReader", "summed_cost", "NoCostReported", "EpisodeStats", "FinishedEpisode", "episode_costs", "episode_stats", "plain"]
