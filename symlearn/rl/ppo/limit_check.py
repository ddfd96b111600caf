"""Whether a PPO-Lagrangian run ended with its cost limit out of reach (a one-line warning).

When no policy the agent finds meets the limit -- a learned formula that also flags the expert's
own states, a limit of 0 on a cost every route pays -- the multiplier keeps rising and, with
return-unit advantages, the reward's weight ``1 / (1 + lambda)`` falls towards 0: the agent ends
safe-looking but useless, and nothing else in the result says why (the SafeNav runs on learned
formulas in docs/BENCHMARKS.md: the multiplier at 11-17 after 100k steps, the return near 0).
:func:`limit_warnings` reads that off the history: over the last third of the iterations (at least
:data:`MIN_WINDOW`), every multiplier update saw the cost above the limit, the multiplier rose,
and it ended at :data:`HEAVY_MULTIPLIER` or more -- with return-unit advantages the multiplier has
no units, and 9 leaves the reward a tenth of the policy's objective. A run that merely pays a
little cost in its stochastic rollouts while its greedy policy is safe (the README's toy recipe:
the multiplier creeps from 3.5 to 3.7 over the last 32 iterations at about 2 cost steps an
episode) is not warned about. Raw advantages give the multiplier the units of reward over cost,
so no threshold is meaningful there and nothing is said.
"""

from __future__ import annotations

from collections.abc import Sequence

from symlearn.rl.ppo.records import PPOIteration

__all__ = ["limit_warnings", "MIN_WINDOW", "HEAVY_MULTIPLIER"]

#: iterations with a multiplier update needed in the window before anything is said
MIN_WINDOW = 3
#: a multiplier at least this large leaves the reward at most 1 / (1 + 9) of the objective
HEAVY_MULTIPLIER = 9.0


def limit_warnings(history: Sequence[PPOIteration], cost_limits: Sequence[float], *,
                   advantage_scale: str = "returns") -> list[str]:
    """One warning per constraint whose cost stayed above its limit while its multiplier rose to
    :data:`HEAVY_MULTIPLIER` or more over the last third of the run; ``[]`` for a run without a
    Lagrangian, one that met its limits, or one with raw advantages."""
    if advantage_scale != "returns":
        return []
    updated = [h for h in history if h.cost_estimate]
    window = updated[-max(MIN_WINDOW, len(updated) // 3):]
    if len(window) < MIN_WINDOW:
        return []
    warnings = []
    reward_weight = 1 / (1 + sum(window[-1].multipliers))  # of the advantage A = (A_r - sum l_i A_ci) / (1 + sum l_i)
    for i, limit in enumerate(cost_limits):
        estimates = [h.cost_estimate[i] for h in window]
        first, last = window[0].multipliers[i], window[-1].multipliers[i]
        if min(estimates) > limit and last > first and last >= HEAVY_MULTIPLIER:
            name = "the cost" if len(cost_limits) == 1 else f"cost {i}"
            warnings.append(
                f"{name} stayed above --cost-limit {limit:g} for the last {len(window)} iterations "
                f"(last estimate {estimates[-1]:.3g} per episode) while the multiplier rose from {first:.3g} "
                f"to {last:.3g} (the reward {reward_weight:.0%} of the objective): the limit may be out of reach "
                "for this cost, and the agent trades its reward away for it; a learned formula that also flags the expert (see `learn dnf --validation`) "
                "needs a limit of at least what the expert pays, else raise --steps")
    return warnings
