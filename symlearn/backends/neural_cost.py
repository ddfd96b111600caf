"""A learned neural cost as an agent uses it: per PPO rollout, or per step for stable-baselines3.

The cost itself -- ``C(s, a) = lambda . phi(s, a)``, its network and its files -- is the neural
ICRL learners' artefact, :class:`symlearn.learners.neural.NeuralCost`. Backends never import
learners, so these adapters take any object that evaluates a batch the way it does:

* ``cost(obs, actions)`` -> ``(B,)``, one call for the whole batch (``actions`` None when the
  cost reads states only);
* ``cost.uses_actions``: whether it reads actions;
* ``cost.action_spec``: the :mod:`symlearn.rl.spaces` description of the action space it was
  learned for; a Box's ``low``/``high`` bound the actions it is shown;
* ``cost.observation_spec`` (optional): the observation space's; a rollout's Discrete
  observations (one-hot rows) and actions (indices) reach the cost as the space's ids.

:class:`NeuralRolloutCost` is ``train_ppo(cost_fn=...)`` (a learned cost under PPO-Lagrangian),
:class:`NeuralRolloutReward` ``train_ppo(reward_fn=...)`` (``r - C``, what the ICRL learners'
policies learn from), and :class:`NeuralStepCost` the per-step form of
:class:`~symlearn.backends.lagrangian.StepCostWrapper` (SB3 learners), as
:mod:`symlearn.backends.dnf_cost` gives the same two forms of a DNF.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.rl.spaces import rollout_values

BOX = {"kind": "box"}  # a cost that names no observation space reads the rows as they are


class NeuralRolloutCost:
    """``rollout -> [T, N]`` costs of a :class:`~symlearn.rl.ppo.Rollout` (its ``obs`` and
    ``actions``), one evaluation of all ``T x N`` steps."""

    info_keys: tuple[str, ...] = ()  # nothing from the steps' info: the cost reads states (and actions)

    def __init__(self, cost: Any) -> None:
        self.cost = cost

    def __call__(self, rollout: Any) -> np.ndarray:
        cost = self.cost
        T, N = rollout.rewards.shape
        # the rollout holds the agent's encoding: a Discrete observation one-hot, a Discrete
        # action as its index 0..n-1; the cost reads the environment's values (ids from `start`)
        obs = rollout_values(rollout.obs.reshape(T * N, -1), getattr(cost, "observation_spec", BOX))
        actions = None if not cost.uses_actions else rollout_values(
            rollout.actions.reshape(T * N, *rollout.actions.shape[2:]), cost.action_spec)
        if actions is not None and "low" in cost.action_spec:  # PPO's are unclipped; the env saw them clipped
            low = [-np.inf if x is None else x for x in cost.action_spec["low"]]
            high = [np.inf if x is None else x for x in cost.action_spec["high"]]
            actions = np.clip(actions.reshape(T * N, -1), low, high)
        return cost(obs, actions).reshape(T, N)


class NeuralRolloutReward:
    """``rollout -> rewards - cost`` ``[T, N]``: the environment's reward minus the learned cost."""

    info_keys: tuple[str, ...] = ()

    def __init__(self, cost: Any) -> None:
        self.rollout_cost = NeuralRolloutCost(cost)

    def __call__(self, rollout: Any) -> np.ndarray:
        return rollout.rewards - self.rollout_cost(rollout)


class NeuralStepCost:
    """``(observation, action, next_observation, info) -> (1,)``: the cost of one step, for
    :class:`~symlearn.backends.lagrangian.StepCostWrapper`. The action is taken as given: SB3
    hands the environment actions already inside the space (unlike PPO's rollouts)."""

    def __init__(self, cost: Any) -> None:
        self.cost = cost

    def __call__(self, observation: Any, action: Any, next_observation: Any, info: dict[str, Any]) -> np.ndarray:
        actions = None if not self.cost.uses_actions else np.asarray(action)[None]
        return np.asarray(self.cost(np.asarray(observation)[None], actions), dtype=np.float64).reshape(1)


__all__ = ["NeuralRolloutCost", "NeuralRolloutReward", "NeuralStepCost"]
