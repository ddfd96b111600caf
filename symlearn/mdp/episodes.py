"""Demonstrations read against a :class:`~symlearn.mdp.TabularMDP`: checked, then counted.

Shared by the tabular constraint learners. Clear mistakes (a state or action id the model does
not have, a non-integer state) raise :class:`~symlearn.errors.DataError` naming the
demonstration and step; what looks like noise in recorded data (a step the model gives
probability zero, a demonstrated pair that breaks a given constraint set when the caller
allows it) is counted and reported in one warning.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from symlearn.errors import DataError, DemonstrationError, ModelError
from symlearn.mdp import TabularMDP


def as_tabular(model: Any) -> TabularMDP:
    """``model`` itself, or the exact model of an environment that offers ``to_tabular()``."""
    mdp = model if isinstance(model, TabularMDP) else getattr(getattr(model, "unwrapped", model), "to_tabular", lambda: model)()
    if not isinstance(mdp, TabularMDP):
        raise ModelError(f"{type(model).__name__} is not a TabularMDP and has no to_tabular()")
    return mdp


@dataclass(frozen=True)
class TabularEpisode:
    states: np.ndarray  # (T,) int
    actions: np.ndarray  # (T,) or (T - 1,) int


def tabular_episodes(demos: Iterable[Any], mdp: TabularMDP) -> list[TabularEpisode]:
    """Integer state and action arrays of each demonstration, validated against ``mdp``.

    Accepts :class:`~symlearn.data.Demonstrations`, or any iterable of trajectories or of
    ``(states, actions)`` pairs. Episodes this function already returned for the same model
    are handed back as they are (a learner that wraps another checks the data once, and its
    noise warning is not repeated).
    """
    items = list(demos)
    if items and all(isinstance(item, TabularEpisode) for item in items):
        return items
    episodes = []
    for i, item in enumerate(items):
        states, actions = (item.states, item.actions) if hasattr(item, "states") else item
        if actions is None:
            raise DemonstrationError(f"demonstration {i} has no actions", demonstration=i,
                                     hint="constraint inference needs state-action pairs")
        s = _ids(states, f"demonstration {i}: states", mdp.n_states, "state", mdp.state_names, (i, "states"))
        a = _ids(actions, f"demonstration {i}: actions", mdp.n_actions, "action", mdp.action_names, (i, "actions"))
        if len(a) not in (len(s), len(s) - 1):
            raise DemonstrationError(f"demonstration {i}: {len(a)} actions for {len(s)} states", demonstration=i,
                                     key="actions")
        _check_goal_label(i, getattr(item, "info", None), s, mdp)
        episodes.append(TabularEpisode(s, a))
    if not episodes:
        raise DataError("no demonstrations were given")
    impossible = sum(int(np.sum(mdp.transitions[e.states[:-1], e.actions[: len(e.states) - 1], e.states[1:]] == 0))
                     for e in episodes if len(e.states) > 1)
    if impossible:
        warnings.warn(f"{impossible} demonstrated step(s) have probability zero under the model "
                      "(treated as noise and kept)", stacklevel=3)
    return episodes


def state_sequences(demos: Iterable[Any], n_states: int, names: Sequence[str] = ()) -> list[np.ndarray]:
    """The integer state ids of each demonstration (actions, when present, are not read).

    The states-only reading of :func:`tabular_episodes`, with the same checks and messages, for
    learners that look at visited states only (specification learning). Accepts
    :class:`~symlearn.data.Demonstrations`, trajectories or plain state sequences.
    """
    if isinstance(demos, (str, bytes)) or not isinstance(demos, Iterable):
        raise DataError(f"demonstrations must be Demonstrations or a list of trajectories, not {type(demos).__name__}")
    sequences = []
    for i, item in enumerate(demos):
        states = item.states if hasattr(item, "states") else item
        try:
            array = np.asarray(states)
        except (TypeError, ValueError):
            raise DemonstrationError(f"demonstration {i}: states must be state ids", demonstration=i,
                                     key="states") from None
        if array.size == 0:
            raise DemonstrationError(f"demonstration {i} is empty", demonstration=i, key="states")
        sequences.append(_ids(array, f"demonstration {i}: states", n_states, "state", names, (i, "states")))
    if not sequences:
        raise DataError("no demonstrations were given")
    return sequences


def _check_goal_label(i: int, info: Any, states: np.ndarray, mdp: TabularMDP) -> None:
    """A demonstration may say which goal it pursued (``info["goal"]``, a state id or name).

    The learners take the state where a demonstration ends as its goal, so a label that
    names another state means the file and the learners disagree about the task: say so.
    """
    if not isinstance(info, dict) or "goal" not in info:
        return
    label = info["goal"]
    goal = _ids([label], f"demonstration {i}: goal label", mdp.n_states, "state", mdp.state_names)[0]
    if int(goal) != int(states[-1]):
        end = mdp.state_names[int(states[-1])] if mdp.state_names else int(states[-1])
        raise DataError(f"demonstration {i} is labelled with goal {label!r} but ends in state {end!r}",
                        hint="a demonstration must end where its goal is; fix the label or cut the trajectory")


def _ids(values: Any, where: str, size: int, what: str, names: Sequence[str],
         origin: tuple[int, str] | None = None) -> np.ndarray:
    """``values`` as checked integer ids; ``origin`` (demonstration index, key) makes the errors
    :class:`DemonstrationError` s that a command can locate in the file."""

    def error(message: str, step: int | None = None, hint: str | None = None) -> DataError:
        if origin is None:
            return DataError(message, hint=hint)
        return DemonstrationError(message, demonstration=origin[0], key=origin[1], step=step, hint=hint)

    array = np.asarray(values)
    if array.dtype.kind == "b" or array.dtype.kind == "O":
        raise error(f"{where} must be integer {what} ids, got {array.dtype}")
    if array.ndim != 1:
        raise error(f"{where} must be one {what} id per step, got shape {array.shape}")
    if array.dtype.kind in "US":  # names: map through the model's names
        lookup = {n: k for k, n in enumerate(names)}
        unknown = [t for t, v in enumerate(array.tolist()) if v not in lookup]
        if unknown:
            hint = (f"the model's {what}s are {', '.join(names[:8])}{'...' if len(names) > 8 else ''}" if names
                    else f"the model's {what}s have no names: give ids 0..{size - 1}")
            raise error(f"{where}: unknown {what} {array.tolist()[unknown[0]]!r} (step {unknown[0]})", unknown[0], hint)
        return np.array([lookup[v] for v in array.tolist()], dtype=np.int64)
    if array.size and (array.dtype.kind not in "iu"):
        if array.dtype.kind == "f" and np.all(np.equal(np.mod(array, 1), 0)):
            array = array.astype(np.int64)
        else:
            raise error(f"{where} must be integer {what} ids, got {array.dtype}")
    array = array.astype(np.int64)
    bad = np.flatnonzero((array < 0) | (array >= size))
    if bad.size:
        step = int(bad[0])
        raise error(f"{where}: step {step}: {what} {int(array[step])} is outside the environment (0..{size - 1})",
                    step, hint=f"{bad.size} step(s) out of range; were the demonstrations recorded in another "
                               "environment?")
    return array


def demonstrated_pairs(episodes: Sequence[TabularEpisode], mdp: TabularMDP) -> np.ndarray:
    """Boolean (S, A): the pairs that occur in some demonstration."""
    seen = np.zeros((mdp.n_states, mdp.n_actions), dtype=bool)
    for e in episodes:
        seen[e.states[: len(e.actions)], e.actions] = True
    return seen


def require_steps(episodes: Sequence[TabularEpisode]) -> None:
    """Refuse demonstrations that take no action at all (one-state episodes): with no demonstrated
    pair every pair looks avoided, and a constraint learner forbade every pair of the domain."""
    if not any(len(e.actions) for e in episodes):
        raise DataError(f"the demonstrations take no action ({len(episodes)} episode(s), 0 steps): "
                        "there is no choice to learn constraints from",
                        hint="give each demonstration its 'actions' (one per state, or one fewer) "
                             "and at least one step")


def check_constraints(
    episodes: Sequence[TabularEpisode],
    forbidden: np.ndarray,
    on_violation: Literal["error", "warn"] = "error",
) -> int:
    """Count demonstrated steps that break the constraint set ``forbidden``; raise on any
    (``"error"``) or warn with the count (``"warn"``, for noisy data). Returns the count."""
    count, first = 0, None
    for i, e in enumerate(episodes):
        hits = np.flatnonzero(forbidden[e.states[: len(e.actions)], e.actions])
        if hits.size and first is None:
            first = (i, int(hits[0]), int(e.states[hits[0]]), int(e.actions[hits[0]]))
        count += int(hits.size)
    if count and on_violation == "error":
        i, t, s, a = first
        raise DemonstrationError(f"demonstration {i}, step {t}: state {s}, action {a} breaks the given constraints "
                                 f"({count} violating step(s) in all)", demonstration=i, key="actions", step=t,
                                 hint="fix the demonstrations or the constraint set; on_violation='warn' treats "
                                      "them as noise")
    if count:
        warnings.warn(f"{count} demonstrated step(s) break the given constraints (treated as noise)", stacklevel=3)
    return count


def discounted_counts(
    episodes: Sequence[TabularEpisode], mdp: TabularMDP, discount: float, horizon: int | None = None
) -> np.ndarray:
    """Mean over demonstrations of ``sum_t discount**t [s_t = s, a_t = a]``, shape (S, A)."""
    counts = np.zeros((mdp.n_states, mdp.n_actions))
    for e in episodes:
        n = len(e.actions) if horizon is None else min(len(e.actions), horizon)
        np.add.at(counts, (e.states[:n], e.actions[:n]), discount ** np.arange(n))
    return counts / len(episodes)


def final_states(episodes: Sequence[TabularEpisode]) -> np.ndarray:
    return np.array([int(e.states[-1]) for e in episodes], dtype=np.int64)
