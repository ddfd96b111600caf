"""Which shallower one-class tree forbids less of the held-out expert behaviour (issue #25).

A one-class tree over many features (a 6-D position-and-velocity state, say) covers the
demonstrated states with boxes that are tight in every direction at once: the formula then calls
most of the held-out expert states unsafe, although nothing is wrong with them, because the
expert never passed through exactly that product of intervals. ``--validation`` measures this;
what the user wants next is what to change. Refitting on the same training demonstrations at
every shallower ``max_depth`` and checking the same held-out states answers it with data, not a
rule of thumb: where the current tree calls more than :data:`ACCEPTABLE_SHARE` of them unsafe,
the advice names the deepest tree whose held-out share is at most
:data:`ACCEPTABLE_SHARE` (the tightest formula that still generalises), or, where none is, the
lowest share if it is at most half of the current one. Each refit costs one tree fit (a tenth
of a second on thousands of points), so the advice is computed only where it can be given.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

ACCEPTABLE_SHARE = 0.05  # held-out expert states a formula may call unsafe and still be advised


@dataclass(frozen=True)
class DepthOption:
    """One refit: its depth, the held-out expert states it calls unsafe, its share of the box."""

    max_depth: int
    held_out_share: float
    unsafe_share: float
    rules: int

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def shallower_options(make_learner: Callable[[int], Any], train: Any, features: Any,
                      held_states: Sequence[np.ndarray], depth: int) -> list[DepthOption]:
    """Fit ``make_learner(d)`` on ``train`` for every ``d`` from ``depth - 1`` down to 1 and score
    each on ``held_states`` (feature rows per held-out demonstration)."""
    steps = sum(len(X) for X in held_states)
    options = []
    for d in range(int(depth) - 1, 0, -1):
        learner = make_learner(d)
        with warnings.catch_warnings():   # the refits' own warnings are not the user's run
            warnings.simplefilter("ignore", UserWarning)
            learner.fit(train, features)
        hits = sum(int(np.asarray(learner.predict(X), dtype=bool).sum()) for X in held_states)
        options.append(DepthOption(d, hits / steps if steps else 0.0, float(learner.unsafe_share_),
                                   len(learner.dnf_.conjunctions)))
    return options


def advised(options: Sequence[DepthOption], current_share: float) -> DepthOption | None:
    """None where ``current_share`` is already within :data:`ACCEPTABLE_SHARE`; else the deepest
    option within it, else the lowest-share one if it at least halves ``current_share``."""
    if current_share <= ACCEPTABLE_SHARE:
        return None
    good = [o for o in options if o.held_out_share <= ACCEPTABLE_SHARE]
    if good:
        return max(good, key=lambda o: o.max_depth)
    if not options:
        return None
    best = min(options, key=lambda o: (o.held_out_share, -o.max_depth))
    return best if best.held_out_share <= current_share / 2 else None


def advice_text(option: DepthOption) -> str:
    return (f"a shallower tree generalises better: --max-depth {option.max_depth} calls "
            f"{option.held_out_share:.1%} of the same held-out states unsafe ({option.rules} rules, "
            f"{option.unsafe_share:.0%} of the box unsafe)")


__all__ = ["ACCEPTABLE_SHARE", "DepthOption", "advice_text", "advised", "shallower_options"]
