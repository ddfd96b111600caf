"""A cost signal for safe RL: a gymnasium wrapper adding ``info["cost"]`` to every step.

The cost of a step is a function of the state the action was taken in and the action:

* a forbidden ``(S, A)`` mask or an ``allowed(state, action)`` rule set: ``violation_cost``
  for a forbidden pair, 0 otherwise;
* ``CostWrapper.from_multipliers(env, lam, phi)``: ``lambda . phi(s, a)`` as learned by
  MCE-ICRL (or any ``(S, A)`` cost array via ``CostWrapper.from_array``).

``info["cost"]`` is the safe-RL convention (Safety-Gymnasium, OmniSafe); with ``penalty`` the
cost times it is also subtracted from the reward, for learners that know no cost.

>>> from symlearn.envs.gridworld import make_gridworld, StochasticGridworld
>>> env = CostWrapper(make_gridworld(0.0), StochasticGridworld(0.0).constraint_mask(), violation_cost=10)
>>> _ = env.reset(seed=0)
>>> [env.step(1)[4]["cost"] for _ in range(2)]   # right, then right into the block
[0.0, 10.0]
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.backends.rules import allowed_function
from symlearn.errors import ModelError, SymlearnError


class CostWrapper(gym.Wrapper):
    """``CostWrapper(env, constraints, violation_cost=1.0, penalty=0.0, state_of=None)``."""

    def __init__(
        self,
        env: gym.Env,
        constraints: Any = None,
        *,
        violation_cost: float = 1.0,
        penalty: float = 0.0,
        state_of: Callable[[Any], Any] | None = None,
        cost_fn: Callable[[Any, int], float] | None = None,
    ) -> None:
        super().__init__(env)
        if (constraints is None) == (cost_fn is None):
            raise SymlearnError("give either constraints (a mask or rule set) or a cost function")
        if not isinstance(env.action_space, gym.spaces.Discrete):
            raise SymlearnError("the cost wrapper needs a Discrete action space")
        if cost_fn is None:
            n_states = int(env.observation_space.n) if isinstance(env.observation_space, gym.spaces.Discrete) else None
            allowed = allowed_function(constraints, int(env.action_space.n), n_states if state_of is None else None)
            cost_fn = lambda s, a: 0.0 if allowed(s, a) else float(violation_cost)  # noqa: E731
        self.cost_fn = cost_fn
        self.penalty = float(penalty)
        self.state_of = state_of or (lambda observation: observation)
        self._observation: Any = None

    @classmethod
    def from_array(cls, env: gym.Env, cost: np.ndarray, **kwargs: Any) -> CostWrapper:
        """Cost from an ``(S, A)`` array (e.g. ``MCEICRL.cost_``)."""
        table = np.asarray(cost, dtype=np.float64)
        n_states, n_actions = int(env.observation_space.n), int(env.action_space.n)
        if table.shape != (n_states, n_actions):
            raise ModelError(f"cost must have shape {(n_states, n_actions)}, got {table.shape}")
        return cls(env, cost_fn=lambda s, a: float(table[int(s), int(a)]), **kwargs)

    @classmethod
    def from_multipliers(cls, env: gym.Env, lam: np.ndarray, phi: np.ndarray, **kwargs: Any) -> CostWrapper:
        """Cost ``C(s, a) = lambda . phi(s, a)`` with ``phi`` of shape (S, A, k)."""
        lam = np.asarray(lam, dtype=np.float64)
        phi = np.asarray(phi, dtype=np.float64)
        if phi.ndim != 3 or phi.shape[2] != lam.shape[0]:
            raise ModelError(f"phi must have shape (S, A, {lam.shape[0]}), got {phi.shape}")
        return cls.from_array(env, phi @ lam, **kwargs)

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        self._observation = observation
        return observation, info

    def step(self, action: Any):
        cost = float(self.cost_fn(self.state_of(self._observation), int(action)))
        observation, reward, terminated, truncated, info = self.env.step(action)
        self._observation = observation
        info = dict(info)
        info["cost"] = cost
        return observation, reward - self.penalty * cost, terminated, truncated, info
