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

import math
from collections.abc import Sequence

from symlearn.rl.ppo.records import PPOIteration

__all__ = ["limit_warnings", "MIN_WINDOW", "HEAVY_MULTIPLIER", "SATURATED_SHARE", "GAVE_UP"]

#: iterations with a multiplier update needed in the window before anything is said
MIN_WINDOW = 3
#: a multiplier at least this large leaves the reward at most 1 / (1 + 9) of the objective
HEAVY_MULTIPLIER = 9.0
#: the reward's return scale at most this share of its largest: every episode earns about the same
SATURATED_SHARE = 0.05


#: what each kind of cost adds to the warning: a learned cost that also charges the expert's own
#: states needs a limit of at least what the expert pays; the environment's own cost (``None``) has
#: no expert to point at, and a run on it was told about formulas it never had (issue 24)
_COST_HINTS = {
    "dnf": "a learned formula that also flags the expert (see `learn dnf --validation`) needs a limit of at least "
           "what the expert pays, else raise --steps",
    "neural": "a learned cost needs a limit of at least what it charges the expert (the default without "
              "--cost-limit), else raise --steps",
    None: "raise --steps, or check that some policy of the environment keeps the limit",
}


def limit_warnings(history: Sequence[PPOIteration], cost_limits: Sequence[float], *,
                   advantage_scale: str = "returns", reward_floor: float = 0.01,
                   cost_kind: str | None = "dnf", cost_floor: float = 0.01,
                   zero_slack: float = 0.0) -> list[str]:
    """One warning per constraint whose cost stayed above its limit while its multiplier rose to
    :data:`HEAVY_MULTIPLIER` or more over the last third of the run; ``[]`` for a run without a
    Lagrangian, one that met its limits, or one with raw advantages. A run whose limit was broken
    throughout the window while the reward's returns stopped varying gets :func:`_saturated`'s
    warning as well. ``cost_kind`` is what the Lagrangian constrained -- ``"dnf"`` (a learned
    formula), ``"neural"`` (a learned network) or ``None`` (the environment's ``info["cost"]``) --
    and picks the advice that ends the warning. A run that kept its limits but ended earning much
    less than it had earned within them gets :func:`_gave_up_reward`'s warning (``cost_floor``:
    ``LagrangianConfig.cost_scale_floor``, ``zero_slack``: ``LagrangianConfig.zero_limit_slack``,
    the settings it names)."""
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
                f"for this cost, and the agent trades its reward away for it; {_COST_HINTS.get(cost_kind, _COST_HINTS[None])}")
    return (warnings + _saturated(history, window, cost_limits, reward_floor) + _ending_early(history, window)
            + _gave_up_reward(updated, window, cost_limits, cost_floor, zero_slack))


#: iterations in the moving mean of returns and cost estimates that :func:`_gave_up_reward` compares
SMOOTH = 5
#: the run's end kept less than this share of the best gain over its start made within the limits
GAVE_UP = 0.5
#: a gain counts only when it is at least this share of the spread of the run's (smoothed) returns
NOTABLE = 0.25
#: "nothing found": the end lies within this share of the spread of the run's returns from their lowest
NOTHING = 0.1
#: a smoothed cost estimate within ``limit + LIMIT_SLACK x`` its largest counts as within the limit
LIMIT_SLACK = 0.05


def _gave_up_reward(updated: Sequence[PPOIteration], window: Sequence[PPOIteration], cost_limits: Sequence[float],
                    cost_floor: float, zero_slack: float = 0.0) -> list[str]:
    """Safe but not useful, read off the run: over the last third (``window``) every cost estimate
    stayed within its limit on average (up to :data:`LIMIT_SLACK` of its largest), the Lagrangian
    on, and the mean return (moving means over :data:`SMOOTH` updates; gains count from
    :data:`NOTABLE` of the spread of the run's returns) either

    * kept less than :data:`GAVE_UP` of what the run had gained over its first iterations at its
      best stretch *within the limits*: a policy the run had already found earned more without
      breaking anything, and the one it ends with keeps further from what the cost forbids than the
      limit asks. With return-unit advantages the cause measured (docs/BENCHMARKS.md, issue 24's
      second pass: the no-fly drone, 10.9 within the limit at iterations 28-32, 2.9 at the end) is
      the cost's own scale: as the agent stops paying, the spread of the cost's returns shrinks to
      a hundredth of its widest and every remaining violation weighs up to 100x more; holding it at
      its widest (``cost_scale_floor=1``, named unless already set) took that drone to its goal at
      cost 0. At limits of 0 the multiplier itself never comes down either; ``zero_limit_slack``
      (``zero_slack``, named unless already set) lets it, and took the drone to its goal on 2 of 3
      seeds where the floor's 1 also let a lava grid's agent back onto its lava step
      (docs/BENCHMARKS.md, "Over-cautious agents at limit 0"); or
    * ended at the bottom of the run's returns (within :data:`NOTHING` of their spread) while
      only stretches that paid the cost earned notably more: no safe way to the reward was found
      (the speed cart's seeds 1 and 2, which docked while exploring at a cost and never after).
      Said so, since the limit was kept and no other warning would speak.

    A task whose safe policies all earn about what the first iterations earned, or a run that
    ended over its limit (the other warnings' case), gets nothing from here."""
    if len(window) < MIN_WINDOW or not any(sum(h.multipliers) > 0 for h in window):
        return []
    points = [h for h in updated if math.isfinite(h.mean_return)]
    if len(points) < SMOOTH + len(window) // 2:
        return []

    def moving(values: Sequence[float]) -> list[float]:
        return [sum(values[i - SMOOTH + 1:i + 1]) / SMOOTH for i in range(SMOOTH - 1, len(values))]

    returns = moving([h.mean_return for h in points])
    estimates = [moving([h.cost_estimate[i] for h in points]) for i in range(len(cost_limits))]
    tolerance = [limit + LIMIT_SLACK * max(max(e), 0.0) for limit, e in zip(cost_limits, estimates)]
    within = [all(e[j] <= t for e, t in zip(estimates, tolerance)) for j in range(len(returns))]
    ending = [h for h in window if math.isfinite(h.mean_return)]
    if not ending or not all(sum(h.cost_estimate[i] for h in window) / len(window) <= t
                             for i, t in enumerate(tolerance)):
        return []   # the limit was not kept at the end: limit_warnings' own case
    start, end = returns[0], sum(h.mean_return for h in ending) / len(ending)
    spread = max(returns) - min(returns)
    if spread <= 0:
        return []
    safe = [(r, j) for j, (r, ok) in enumerate(zip(returns, within)) if ok]
    best, at = max(safe) if safe else (-math.inf, 0)
    if best - start >= NOTABLE * spread:
        if end - start >= GAVE_UP * (best - start):
            return []
        first, last = points[at].iteration, points[at + SMOOTH - 1].iteration
        remedy = ("--cost-scale-floor 1 (LagrangianConfig.cost_scale_floor) holds the cost's scale at its widest"
                  if cost_floor < 1.0 else "more --steps, or a --cost-limit above 0 to give it room")
        if not zero_slack and all(limit == 0 for limit in cost_limits):   # the multiplier can only rise at 0
            remedy += ("; or --zero-limit-slack 0.25 (LagrangianConfig.zero_limit_slack), which lets the multiplier "
                       "come down once the agent stops paying")
        return [f"the return fell from {best:.3g} (iterations {first}-{last}, within the cost limit) to {end:.3g} "
                f"over the last {len(window)} iterations while the cost stayed within the limit: the agent keeps the "
                "limit but gave up reward it had earned within it, keeping further from what the cost forbids than "
                "it must (as it stops paying, the cost's spread shrinks and each remaining violation weighs more); "
                + remedy]
    top, bottom = max(returns), min(returns)
    if end - bottom > NOTHING * spread or best - end >= NOTABLE * spread:
        return []
    return [f"the return ended at the lowest the run saw ({end:.3g}; at most {top:.3g}, only while the cost was "
            "paid) while the cost stayed within the limit: the agent found no safe way to the reward in these "
            "steps. If one exists, more --steps may find it; if every way pays, the limit costs all of the reward "
            "(a --cost-limit above 0 allows some)"]


#: episodes this many times shorter than at their longest, and returns this share of their best
SHORTER, POORER = 4.0, 0.5


def _ending_early(history: Sequence[PPOIteration], window: Sequence[PPOIteration]) -> list[str]:
    """Episodes that grew much shorter while the return fell and the multiplier was on: with a cost
    no policy can avoid (paid at the start, before any action can help), ending the episode early --
    a crash, a fall -- is the cheapest policy, and PPO-Lagrangian finds it (docs/BENCHMARKS.md,
    realistic traffic: a speed cap below the start speed, episodes of three steps at the end). A
    task whose episodes shorten because the goal is reached sooner earns more, not less: no warning."""
    def finished(records: Sequence[PPOIteration]) -> list[PPOIteration]:   # iterations in which episodes ended
        return [h for h in records if h.episodes and math.isfinite(h.mean_length) and math.isfinite(h.mean_return)]

    ended, recent = finished(history), finished(window)
    if not ended or not recent or not any(sum(h.multipliers) > 0 for h in recent):
        return []
    longest, best = max(h.mean_length for h in ended), max(h.mean_return for h in ended)
    length = sum(h.mean_length for h in recent) / len(recent)
    earned = sum(h.mean_return for h in recent) / len(recent)
    if best <= 0 or length * SHORTER > longest or earned > POORER * best:
        return []
    return [f"the episodes grew {longest / max(length, 1e-9):.0f}x shorter (mean length {longest:.0f} -> {length:.0f} "
            f"steps) while the return fell ({best:.3g} -> {earned:.3g}): the agent may be ending its episodes "
            "early (a crash, a fall) to stop paying the cost; if part of the cost cannot be avoided (paid at the "
            "start, whatever the agent does), give --cost-limit at least that much"]


def _saturated(history: Sequence[PPOIteration], window: Sequence[PPOIteration], cost_limits: Sequence[float],
               reward_floor: float) -> list[str]:
    """A constraint broken on every update of the window while its multiplier rose, and the
    reward's return scale ended at most :data:`SATURATED_SHARE` of the largest it had: every
    episode earns about the same (a pole balanced to the time limit), and in units of that spread
    the small reward differences left outweigh the cost at any multiplier the run reaches
    (docs/BENCHMARKS.md: CartPole with a line the cart must keep left of, 3 of 5 seeds safe at the
    defaults, 5 of 5 with ``reward_scale_floor=1``). Nothing when the floor is already raised."""
    scales = [h.return_scales[0] for h in history if h.return_scales]
    if not scales or reward_floor >= SATURATED_SHARE or max(scales) <= 0:
        return []
    share = scales[-1] / max(scales)
    broken = any(min(h.cost_estimate[i] for h in window) > limit
                 and window[-1].multipliers[i] > window[0].multipliers[i] for i, limit in enumerate(cost_limits))
    if share > SATURATED_SHARE or not broken:
        return []
    return [f"the reward's returns vary {1 / share:.0f}x less than at their widest (every episode earns about the "
            "same), and in units of that spread the reward's small differences outweigh the cost: hold the "
            "reward's scale at its widest with --reward-scale-floor 1 (LagrangianConfig.reward_scale_floor)"]
