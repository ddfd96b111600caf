"""When PPO-Lagrangian's policy is stuck on the wrong side of its constraint: a fresh actor.

A policy that found a rewarding behaviour the constraint forbids before the multiplier priced it
(BlockedPoint's agent running backward through the wall in its first 10k steps) may never leave
it: when the way out takes many consecutive deviations, every single one scores worse, the
policy's entropy only falls, and the cost advantage of any one action is near zero because every
action of the behaviour pays alike. The multiplier then rises without end and nothing changes
(docs/BENCHMARKS.md: a learned wall on BlockedPoint, seed 2 ran through it at multiplier 10 while
seeds 0 and 1 turned at 3). A fresh actor -- the critics, the observation statistics and the
multipliers kept -- learns from scratch under the price the multiplier has reached, as neural
ICRL's ``reset_actor="auto"`` does between its policy phases
(:class:`symlearn.learners.neural.alternation.Stall`).

:class:`LagrangianStall` watches the multiplier updates. Over the last :attr:`WINDOW` of the run's
iterations (at least :attr:`MIN_WINDOW` updates) it fires when, for some constraint, every
estimate stayed above its limit, the last estimate removed less than :attr:`PROGRESS` of the
first one's excess, and the multiplier, already at :attr:`HEAVY` or more when the window began
(the constraint weighing at least as much as the reward: before, an exploring agent is still
learning what the cost is), grew by at least :attr:`RISE` (a multiplier that does not grow means
the limit is being met on average), and the last estimate is still at least :attr:`NEAR_PEAK` of
the largest the run has seen (a policy that has cut its cost from its worst to a floor it cannot
go below -- a learned cost that charges every state a little, with a limit of 0 -- has learned what
a fresh actor would; BlockedPoint's safe agents pay such a floor of 14 per episode, a fiftieth of
their peak). It fires at most :attr:`MAX_RESETS` times, never
in the last :attr:`LATE` of the run (a fresh actor needs time to learn), and the window starts
again after a reset.
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["LagrangianStall", "RESET_ACTOR_RULES"]

RESET_ACTOR_RULES = ("auto", "never")


class LagrangianStall:
    """``LagrangianConfig(reset_actor="auto")``'s rule (module doc); ``update`` once per
    iteration with the cost estimate the multipliers were updated from (or None when they were
    not) and the multipliers after the update; True: reset the actor now."""

    WINDOW = 0.1       # of the run's iterations
    MIN_WINDOW = 8     # multiplier updates
    PROGRESS = 0.1     # of the excess over the limit
    RISE = 0.5         # multiplier units (with return-scaled advantages: half the reward's weight)
    HEAVY = 1.0        # the multiplier at the window's start (return-scaled: the cost weighs as the reward)
    NEAR_PEAK = 0.5    # of the largest estimate of the run
    MAX_RESETS = 2
    LATE = 1 / 3       # of the run

    def __init__(self, n_iterations: int, limits: np.ndarray) -> None:
        self.n_iterations = int(n_iterations)
        self.limits = np.asarray(limits, dtype=np.float64)
        self.size = max(self.MIN_WINDOW, int(round(self.WINDOW * self.n_iterations)))
        self.window: deque[tuple[np.ndarray, np.ndarray]] = deque(maxlen=self.size)
        self.resets: list[int] = []
        self.peak = np.zeros_like(self.limits)

    def update(self, iteration: int, estimate: np.ndarray | None, multipliers: np.ndarray) -> bool:
        if estimate is None:
            return False
        self.window.append((np.asarray(estimate, dtype=np.float64).copy(),
                            np.asarray(multipliers, dtype=np.float64).copy()))
        self.peak = np.maximum(self.peak, self.window[-1][0])
        if (len(self.window) < self.size or len(self.resets) >= self.MAX_RESETS
                or iteration > (1 - self.LATE) * self.n_iterations):
            return False
        estimates = np.array([e for e, _ in self.window])
        first, last = self.window[0], self.window[-1]
        above = np.all(estimates > self.limits, axis=0)
        excess_first, excess_last = first[0] - self.limits, last[0] - self.limits
        stuck = (above & (excess_last > (1 - self.PROGRESS) * excess_first) & (first[1] >= self.HEAVY)
                 & (last[1] - first[1] >= self.RISE) & (last[0] >= self.NEAR_PEAK * self.peak))
        if not stuck.any():
            return False
        self.resets.append(int(iteration))
        self.window.clear()
        return True
