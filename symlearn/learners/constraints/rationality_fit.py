"""The MaxEnt model's inverse temperature, fitted to the demonstrations by maximum likelihood.

Maximum-likelihood constraint inference plans with a nominal MaxEnt policy whose actions are
weighted by ``exp(rationality x reward)``. How sharply that policy prefers short, rewarding paths
decides which undemonstrated pairs it visits, and so which constraints are inferred first: too
random (a small rationality against a small step cost) and the first iterations go to pairs of
long wandering paths the expert never needed; too sharp and the nominal policy stays on one
path, so constraints off it are never inferred. No single number suits every reward scale.

The temperature is a parameter of the same likelihood the constraints are chosen by, so it is
fitted the same way: before the loop, the rationality that maximises the mean log-probability
of the demonstrated actions under the goal-conditioned nominal policies of the *unconstrained*
model (only the moves that do not exist, and ``known`` constraints, removed). One bounded scalar
search over ``log rationality`` in [``LOW``, ``HIGH``]; each evaluation is one backward pass per
goal. Fitted without the constraints it is biased low (the expert's detours around forbidden
pairs look like randomness), which errs on the side that still infers constraints.

Where the reward is ``"sparse"`` (1 for entering the goal) every goal-reaching trajectory earns
the same ``exp(rationality)`` and the temperature cancels from the policy: nothing to fit, 1 is
used. The same holds for any reward that makes the likelihood flat (checked, not assumed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.mdp import TabularMDP

#: the search interval of the fitted rationality
LOW, HIGH = 0.05, 100.0


@dataclass(frozen=True)
class RationalityFit:
    """What the fit found: the value used, where it came from, and the likelihood at it."""

    value: float
    source: str  # "fitted", "given", or "flat" (the reward leaves the likelihood flat: 1 is used)
    mean_log_likelihood: float | None = None  # per demonstrated step, at ``value``
    at_one: float | None = None  # the same at rationality 1, for comparison
    evaluations: int = 0

    def as_dict(self) -> dict[str, Any]:
        return {"value": self.value, "source": self.source, "mean_log_likelihood": self.mean_log_likelihood,
                "at_one": self.at_one, "evaluations": self.evaluations}


def check_rationality(value: float, name: str = "rationality") -> float:
    """``value`` as a float, refused unless it is positive and finite (``name`` in the message: the
    API's keyword or the CLI's flag)."""
    from symlearn.errors import SymlearnError

    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise SymlearnError(f"{name} must be a positive number or 'auto', got {value:g}")
    return value


def demonstration_log_likelihood(mdp: TabularMDP, episodes, reward_of, rationality: float, horizon: int,
                                 allowed: np.ndarray | None) -> float:
    """Mean log-probability per demonstrated step of the demonstrated actions under the
    goal-conditioned MaxEnt policies (each demonstration scored by the policy towards the state
    it ended in; ``reward_of(goal)`` gives the unscaled reward array)."""
    from symlearn.mdp.episodes import final_states
    from symlearn.rl.maxent import maxent_backward_pass

    ends = final_states(episodes)
    total, steps = 0.0, 0
    for goal in sorted(set(ends.tolist())):
        policy = maxent_backward_pass(mdp, [goal], horizon, reward=rationality * reward_of(goal),
                                      allowed=allowed).policy
        for episode, end in zip(episodes, ends):
            if end != goal:
                continue
            n = len(episode.actions)
            p = policy[episode.states[:n], episode.actions]
            total += float(np.log(np.maximum(p, 1e-300)).sum())
            steps += n
    return total / max(steps, 1)


def fit_rationality(mdp: TabularMDP, episodes, reward_of, horizon: int, allowed: np.ndarray | None, *,
                    sparse: bool = False) -> RationalityFit:
    """The maximum-likelihood rationality (see the module docstring)."""
    if sparse or not any(len(e.actions) for e in episodes):
        return RationalityFit(1.0, "flat")
    from scipy.optimize import minimize_scalar

    cache: dict[float, float] = {}

    def negative(log_beta: float) -> float:
        if log_beta not in cache:
            cache[log_beta] = -demonstration_log_likelihood(mdp, episodes, reward_of, math.exp(log_beta), horizon,
                                                            allowed)
        return cache[log_beta]

    at_one = -negative(0.0)
    ends = (-negative(math.log(LOW)), -negative(math.log(HIGH)))
    if max(abs(at_one - ends[0]), abs(at_one - ends[1])) < 1e-9:
        return RationalityFit(1.0, "flat", at_one, at_one, len(cache))
    found = minimize_scalar(negative, bounds=(math.log(LOW), math.log(HIGH)), method="bounded",
                            options={"xatol": 0.02})
    # the bounded search may stop inside when the optimum is an end of the interval: keep the best seen
    best = min(cache, key=cache.get)
    value = round(math.exp(best if cache[best] < found.fun else float(found.x)), 4)  # 4 digits: it is printed
    return RationalityFit(value, "fitted", -negative(math.log(value)), at_one, len(cache))


__all__ = ["HIGH", "LOW", "RationalityFit", "check_rationality", "demonstration_log_likelihood", "fit_rationality"]
