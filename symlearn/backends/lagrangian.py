"""A Lagrangian reward for learners that know no cost: ``r - lambda . c`` through gymnasium wrappers.

Any reward-maximising learner (stable-baselines3's PPO, SAC, DQN ...) becomes a Lagrangian one
with three pieces:

* :class:`StepCostWrapper` adds a learned cost ``c(s, a, s')`` to every step as
  ``info["learned_cost"]`` (a DNF through its feature names, a neural cost ...), leaving the
  environment's own ``info["cost"]`` -- the ground truth -- where it was;
* :class:`LagrangianReward` gives the learner ``r - lambda . c``, ``c`` read from ``info[cost_key]``
  (``"cost"``: the environment's; ``"learned_cost"``: the wrapper's), ``lambda`` from a
  :class:`SharedMultipliers` that every copy of a vectorised environment holds; the
  environment's reward stays readable as ``info["env_reward"]``;
* something updates the multipliers from the costs the agent incurs: for stable-baselines3,
  :func:`symlearn.backends.sb3.lagrangian_callback`.

:class:`FeatureVectorWrapper` turns a dict ``info["features"]`` (named features) into the vector a
formula's evaluator reads, in a fixed name order.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.errors import DataError, SymlearnError
from symlearn.rl.ppo import LagrangianConfig, Multipliers

StepCost = Callable[[Any, Any, Any, dict], Any]


class FeatureVectorWrapper(gym.Wrapper):
    """``info["features"]`` as a float64 vector in ``names`` order (from a dict of named values)."""

    def __init__(self, env: gym.Env, names: Sequence[str]) -> None:
        super().__init__(env)
        self.names = tuple(names)

    def _vector(self, info: dict[str, Any]) -> dict[str, Any]:
        raw = info.get("features")
        if isinstance(raw, dict):
            missing = [n for n in self.names if n not in raw]
            if missing:
                raise DataError(f"info['features'] has no {missing[0]!r}", hint="features: " + ", ".join(raw))
            info = dict(info)
            info["features"] = np.array([float(raw[n]) for n in self.names], dtype=np.float64)
        return info

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        return observation, self._vector(info)

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        return observation, reward, terminated, truncated, self._vector(info)


class StepCostWrapper(gym.Wrapper):
    """``info[key] = cost(observation, action, next_observation, info)`` on every step (a vector)."""

    def __init__(self, env: gym.Env, cost: StepCost, *, key: str = "learned_cost") -> None:
        super().__init__(env)
        if not callable(cost):
            raise SymlearnError(f"the step cost must be callable, got {cost!r}")
        self.cost, self.key = cost, key
        self._observation: Any = None

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        self._observation = observation
        return observation, info

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        info = dict(info)
        cost = np.asarray(self.cost(self._observation, action, observation, info), dtype=np.float64).reshape(-1)
        if not np.isfinite(cost).all():
            raise DataError(f"the learned cost is not finite: {cost.tolist()}")
        info[self.key] = cost
        self._observation = observation
        return observation, reward, terminated, truncated, info


class SharedMultipliers:
    """The multipliers of one Lagrangian run, shared by every environment copy and the updater.

    ``config`` gives the limit(s) and the update rule of :class:`~symlearn.rl.ppo.Multipliers`;
    ``fixed`` pins them instead (``fixed=[1.0]``: the cost is simply subtracted)."""

    def __init__(self, config: LagrangianConfig | None = None, n_costs: int = 1, *,
                 fixed: Sequence[float] | None = None) -> None:
        if (config is None) == (fixed is None):
            raise SymlearnError("give a LagrangianConfig or fixed multipliers")
        self.config = config
        self.rule = None if config is None else Multipliers(config, n_costs)
        self.values = np.asarray(fixed, dtype=np.float64).reshape(-1) if fixed is not None else self.rule.values.copy()
        if len(self.values) != n_costs:
            raise SymlearnError(f"{len(self.values)} multiplier(s) for {n_costs} cost(s)")
        self.history: list[dict[str, Any]] = []

    def update(self, mean_costs: np.ndarray, step: int) -> np.ndarray:
        """One step of the update rule from the estimated cost per episode (no-op when fixed)."""
        if self.rule is not None:
            self.values = self.rule.update(mean_costs).copy()
        self.history.append({"step": int(step), "cost": [float(c) for c in np.reshape(mean_costs, -1)],
                             "multipliers": [float(m) for m in self.values]})
        return self.values


class LagrangianReward(gym.Wrapper):
    """The learner's reward is ``r - lambda . info[cost_key]``; ``info["env_reward"]`` keeps ``r``.

    A step without ``info[cost_key]`` costs 0: an environment may report its cost only on the
    steps that pay it. Whether any step reports one is for the multiplier's updater to check
    (:func:`symlearn.backends.sb3.lagrangian_callback` refuses a first rollout without any)."""

    def __init__(self, env: gym.Env, multipliers: SharedMultipliers, *, cost_key: str = "cost") -> None:
        super().__init__(env)
        self.multipliers, self.cost_key = multipliers, cost_key

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        lambdas = self.multipliers.values
        raw = info.get(self.cost_key)
        if raw is None:  # not paid on this step: no penalty
            info = dict(info)
            info["env_reward"] = float(reward)
            return observation, float(reward), terminated, truncated, info
        cost = np.asarray(raw, dtype=np.float64).reshape(-1)
        if cost.size != lambdas.size:
            raise DataError(f"info[{self.cost_key!r}] has {cost.size} entries for {lambdas.size} multiplier(s)",
                            hint="a cost keeps its length on every step (one entry per constraint, one multiplier "
                                 "each)")
        info = dict(info)
        info["env_reward"] = float(reward)
        return observation, float(reward) - float(lambdas @ cost), terminated, truncated, info


__all__ = ["FeatureVectorWrapper", "LagrangianReward", "SharedMultipliers", "StepCost", "StepCostWrapper"]
