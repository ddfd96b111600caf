"""Validation on held-out demonstrations: what a user can check without ground truth (issue #25).

A learned constraint should not forbid what the expert does. Holding out a share of the
demonstrations before learning and counting the held-out expert steps the learned constraint
forbids measures exactly that, on data the learner never saw: 0 is what a correct constraint
gives (the expert obeys the true one); a positive share means the constraint is too strict
somewhere the expert goes (too few demonstrations there, or a rule that over-generalises).

>>> from symlearn.data import Demonstrations, Trajectory
>>> demos = Demonstrations([Trajectory(states=[0, 1, 2], actions=[0, 1]) for _ in range(10)])
>>> train, held = holdout(demos, 0.2, seed=0)
>>> len(train), len(held)
(8, 2)
>>> import numpy as np
>>> forbidden = np.zeros((3, 2), dtype=bool); forbidden[1, 1] = True
>>> report = forbidden_pairs_report(forbidden, [(np.array(t.states), np.array(t.actions)) for t in held], 0.2,
...                                 len(train))
>>> report.forbidden, report.steps, report.share
(2, 4, 0.5)
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError, SymlearnError


@dataclass(frozen=True)
class Validation:
    """Held-out expert steps (or states) a learned constraint forbids."""

    fraction: float
    n_train: int  # demonstrations learned from
    n_held_out: int  # demonstrations held out
    steps: int  # held-out steps (state-action pairs) or states checked
    forbidden: int  # of those, how many the learned constraint forbids
    first: str | None = None  # "demonstration I, step T: what" of the first forbidden one
    unit: str = "steps"

    @property
    def share(self) -> float:
        return self.forbidden / self.steps if self.steps else 0.0

    @property
    def per_demonstration(self) -> float:
        """The held-out demonstrations' mean count of forbidden steps (states) each: what the
        learned constraint, as a cost of 1 per step, charges an unseen expert episode -- its
        false-alarm floor, the least a cost limit on it can ask of a policy that behaves like the
        expert (``share`` x the mean held-out episode length)."""
        return self.forbidden / self.n_held_out if self.n_held_out else 0.0

    def warning(self) -> str | None:
        """One line when the learned constraint forbids held-out expert behaviour, else None."""
        if not self.forbidden:
            return None
        return (f"the learned constraint forbids {self.forbidden} of {self.steps} held-out expert {self.unit} "
                f"({self.share:.1%}; first: {self.first}): it is stricter than the expert somewhere; give more "
                "demonstrations there or check the rule")

    def as_dict(self) -> dict[str, Any]:
        return {**asdict(self), "share": self.share, "per_demonstration": self.per_demonstration}


def holdout(demonstrations: Any, fraction: float, *, seed: int = 0):
    """``(train, held_out)``: whole demonstrations, ``fraction`` of them (at least one each side)
    drawn at random with ``seed`` and held out."""
    from symlearn.data import Demonstrations

    if isinstance(fraction, bool) or not isinstance(fraction, (int, float)) or not 0.0 < float(fraction) < 1.0:
        raise SymlearnError(f"the validation fraction must lie strictly between 0 and 1, got {fraction!r}",
                            hint="e.g. --validation 0.2 holds out a fifth of the demonstrations")
    from symlearn.mdp.episodes import TabularEpisode

    items = demonstrations if isinstance(demonstrations, Demonstrations) else list(demonstrations)
    if isinstance(items, list) and not (items and all(isinstance(e, TabularEpisode) for e in items)):
        items = Demonstrations(items)  # checked episodes stay a list (their split keeps them checked)
    demos = items
    n = len(demos)
    if n < 2:
        raise DataError(f"validation needs at least 2 demonstrations to hold some out, got {n}")
    train, held = holdout_indices(n, fraction, seed=seed)
    if isinstance(demos, list):
        return [demos[i] for i in train], [demos[i] for i in held]
    return demos[train], demos[held]


def holdout_indices(n: int, fraction: float, *, seed: int = 0) -> tuple[list[int], list[int]]:
    """``(train, held_out)``: the sorted indices of :func:`holdout`'s split of ``n`` demonstrations."""
    n_held = min(n - 1, max(1, int(round(fraction * n))))
    order = np.random.default_rng(seed).permutation(n)
    return sorted(order[n_held:].tolist()), sorted(order[:n_held].tolist())


def forbidden_pairs_report(forbidden: np.ndarray, episodes: Sequence[tuple[np.ndarray, np.ndarray]],
                           fraction: float, n_train: int,
                           describe: Callable[[int, int], str] | None = None,
                           numbers: Sequence[int] | None = None) -> Validation:
    """The held-out steps ``(s_t, a_t)`` of ``episodes`` (``(states, actions)`` id arrays) that the
    ``(S, A)`` mask ``forbidden`` forbids. ``numbers``: each episode's index among all the
    demonstrations (as in their file), so the first forbidden step is named where it is."""
    steps = hits = 0
    first = None
    for i, (states, actions) in enumerate(episodes):
        states, actions = np.asarray(states)[: len(actions)], np.asarray(actions)
        bad = np.flatnonzero(forbidden[states, actions])
        steps += len(actions)
        hits += len(bad)
        if len(bad) and first is None:
            t = int(bad[0])
            what = describe(int(states[t]), int(actions[t])) if describe else f"state {states[t]}, action {actions[t]}"
            first = (f"held-out demonstration {i}, step {t}: {what}" if numbers is None else
                     f"demonstration {numbers[i]} (held out), step {t}: {what}")
    return Validation(float(fraction), n_train, len(episodes), steps, hits, first)


def unsafe_states_report(predict: Callable[[np.ndarray], np.ndarray], held_states: Sequence[np.ndarray],
                         names: Sequence[str], fraction: float, n_train: int) -> Validation:
    """The held-out states (``[T, k]`` feature rows per demonstration) that ``predict`` calls unsafe."""
    steps = hits = 0
    first = None
    for i, X in enumerate(held_states):
        unsafe = np.asarray(predict(X), dtype=bool)
        steps += len(unsafe)
        hits += int(unsafe.sum())
        if unsafe.any() and first is None:
            t = int(np.flatnonzero(unsafe)[0])
            point = ", ".join(f"{n}={v:.4g}" for n, v in zip(names, X[t]))
            first = f"held-out demonstration {i}, state {t}: {point}"
    return Validation(float(fraction), n_train, len(held_states), steps, hits, first, unit="states")


#: the rule-file line ``learn dnf --validation`` writes (cli.output.validation_line after a ``# ``):
#: its three whole numbers are what ``train --cost`` reads back -- the held-out count, the states
#: checked and the demonstrations held out -- so nothing rounded is read
_RULE_FILE_LINE = re.compile(r"^#\s*validation: (\d+) of (\d+) held-out expert states unsafe \([^;]*; "
                             r"(\d+) demonstrations? held out, (\d+) learned from\)\s*$")


def rule_file_validation(text: str) -> Validation | None:
    """The held-out check a rule file records in its ``#`` header (``learn dnf --validation``),
    or None where it records none. Only the header is read (the ``#`` lines before the first
    rule): a line written lower down is a user's comment, not the learner's record."""
    for line in text.splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            break
        match = _RULE_FILE_LINE.match(line.strip())
        if match:
            forbidden, steps, held, train = (int(g) for g in match.groups())
            if held == 0 or forbidden > steps:
                raise DataError(f"the rule file's validation line is inconsistent ({forbidden} of {steps} states, "
                                f"{held} demonstrations held out)",
                                hint="delete the line, or learn the file again with learn dnf --validation")
            return Validation(held / (held + train), train, held, steps, forbidden, unit="states")
    return None


__all__ = ["Validation", "forbidden_pairs_report", "holdout", "holdout_indices", "rule_file_validation",
           "unsafe_states_report"]
