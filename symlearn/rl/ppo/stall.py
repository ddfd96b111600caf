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
estimate stayed above its limit, the window's second half removed less than :attr:`PROGRESS` of
the first half's mean excess, and the multiplier, already at :attr:`HEAVY` or more when the window began
(the constraint weighing at least as much as the reward: before, an exploring agent is still
learning what the cost is), grew by at least :attr:`RISE` (a multiplier that does not grow means
the limit is being met on average), and the second half's mean is still at least :attr:`NEAR_PEAK` of
the largest the run has seen (a policy that has cut its cost from its worst to a floor it cannot
go below -- a learned cost that charges every state a little, with a limit of 0 -- has learned what
a fresh actor would; BlockedPoint's safe agents pay such a floor of 14 per episode, a fiftieth of
their peak). It fires at most :attr:`MAX_RESETS` times, never
in the last :attr:`LATE` of the run (a fresh actor needs time to learn), and the window starts
again after a reset.

Off by default (``reset_actor="never"``): measured on seven tasks x 4 seeds and BlockedPoint with a
learned wall (docs/BENCHMARKS.md, "A fresh actor for a policy stuck over its limit"), it saves
BlockedPoint's seed 2 and lowers SafeNav CarGoal's true cost at a higher return, but on learned
formulas whose limit no policy meets (the rover's, SafeNav PointGoal's) it fires in nearly every
run, and even where the old actor is put back the lost trial changes the outcome (the rover's
return 4.06 -> -0.58 at the same cost).

A reset is a trial: the old actor's weights are kept, and one window later the fresh actor is set
against them by the objective the policy climbs at the multipliers of that moment (the mean return
over its scale minus each cost estimate over its scale times its multiplier, each actor over its
own window). Where the fresh actor scores lower the old one is put back and no further trial is
made: where every long episode pays -- a learned formula charging a balancing CartPole -- a fresh
actor finds the cheap way out, ending its episodes at once, and would keep it (measured: 9 steps
instead of 500 on every seed, docs/BENCHMARKS.md).
"""

from __future__ import annotations

from collections import deque

import numpy as np

__all__ = ["LagrangianStall"]


class LagrangianStall:
    """``LagrangianConfig(reset_actor="auto")``'s rule (module doc). ``update`` once per iteration
    with the cost estimate the multipliers were updated from (None when they were not), the
    multipliers after the update, the mean return of the episodes that ended (NaN: none did) and
    the scales the advantages are divided by (reward first, then each cost; ones for raw
    advantages). It answers ``"reset"`` (give the actor fresh weights now, keeping the old ones),
    ``"restore"`` (the trial lost: put the old actor back) or None."""

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
        # per update: (estimate, multipliers, mean return)
        self.window: deque[tuple[np.ndarray, np.ndarray, float]] = deque(maxlen=self.size)
        self.resets: list[int] = []
        self.restored: list[int] = []
        self.peak = np.zeros_like(self.limits)
        self.given_up = False
        self._before: list[tuple[np.ndarray, np.ndarray, float]] | None = None   # the old actor's window

    def update(self, iteration: int, estimate: np.ndarray | None, multipliers: np.ndarray,
               mean_return: float = float("nan"), scales: np.ndarray | None = None) -> str | None:
        if estimate is None:
            return None
        self.window.append((np.asarray(estimate, dtype=np.float64).copy(),
                            np.asarray(multipliers, dtype=np.float64).copy(), float(mean_return)))
        self.peak = np.maximum(self.peak, self.window[-1][0])
        if len(self.window) < self.size:
            return None
        if self._before is not None:
            return self._judge(iteration, multipliers, scales)
        if (self.given_up or len(self.resets) >= self.MAX_RESETS
                or iteration > (1 - self.LATE) * self.n_iterations):
            return None
        estimates = np.array([w[0] for w in self.window])
        first, last = self.window[0], self.window[-1]
        above = np.all(estimates > self.limits, axis=0)
        # halves, not end points: one rollout's estimate is noisy (the toy's 78-145 per episode
        # while its policy was learning the safe route)
        half = len(estimates) // 2
        excess_early = estimates[:half].mean(axis=0) - self.limits
        excess_late = estimates[half:].mean(axis=0) - self.limits
        stuck = (above & (excess_late > (1 - self.PROGRESS) * excess_early) & (first[1] >= self.HEAVY)
                 & (last[1] - first[1] >= self.RISE) & (estimates[half:].mean(axis=0) >= self.NEAR_PEAK * self.peak))
        if not stuck.any():
            return None
        self.resets.append(int(iteration))
        self._before = list(self.window)
        self.window.clear()
        return "reset"

    def _judge(self, iteration: int, multipliers: np.ndarray, scales: np.ndarray | None) -> str | None:
        """A window after a reset: the fresh actor against the old one, both by the objective the
        policy climbs at today's multipliers -- return over its scale minus each cost over its
        scale times its multiplier. A fresh actor can lose: where every long episode pays (a
        learned formula charging a balancing CartPole), starting over finds the cheap way out,
        ending episodes early, before it finds the reward again."""
        fresh, old = list(self.window), self._before
        self._before = None
        if self._score(fresh, multipliers, scales) >= self._score(old, multipliers, scales):
            return None
        self.restored.append(int(iteration))
        self.given_up = True   # a fresh actor lost once here: no more trials
        self.window.clear()
        return "restore"

    @staticmethod
    def _score(window: list[tuple[np.ndarray, np.ndarray, float]], multipliers: np.ndarray,
               scales: np.ndarray | None) -> float:
        returns = [r for _, _, r in window if np.isfinite(r)]
        reward = float(np.mean(returns)) if returns else 0.0
        costs = np.mean([e for e, _, _ in window], axis=0)
        scale = np.ones(1 + len(costs)) if scales is None or len(scales) != 1 + len(costs) else np.asarray(scales)
        return reward / scale[0] - float(np.asarray(multipliers) @ (costs / scale[1:]))
