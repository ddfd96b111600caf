"""The stochastic gridworld seen through coordinates: the adapter for PPO with neural costs.

:class:`~symlearn.envs.gridworld.StochasticGridworld` (thesis Fig. 2.1) is already a gymnasium
environment, but its observations are cell ids (``Discrete(49)``): a neural cost over one-hot
ids is a table in disguise and cannot say "the block" any more briefly than by listing its
cells. The thesis ran its gridworld with PPO and neural costs (section 2.5.3); this adapter gives
the learners what a continuous task would -- the position ``(row, col)`` as a ``Box`` -- and the
ground truth the neural ICRL metrics read:

* observation ``float32 (row, col)`` (``observation_names``), the action unchanged
  (``Discrete(4)``: up, right, down, left), the dynamics, reward and stochasticity the wrapped
  environment's;
* ``info["cost"]`` = 1.0 when the step ended in a forbidden cell (the wrapped ``violation``);
* :meth:`is_unsafe` of coordinates, vectorised (a point counts in the cell it rounds to);
* :func:`expert_demonstrations`: episodes of the wrapped environment's expert (optimal under the
  true constraints, :meth:`StochasticGridworld.expert_policy`) recorded as coordinates.

>>> env = CoordinateGridworld(stochasticity=0.0)
>>> obs, info = env.reset(seed=0)
>>> obs.tolist(), info["cost"]
([6.0, 0.0], 0.0)
>>> env.is_unsafe(np.array([[3.0, 2.0], [2.0, 2.0]])).tolist()
[True, False]
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.envs.gridworld import StochasticGridworld

OBSERVATION_NAMES = ("row", "col")


class CoordinateGridworld(gym.Env):
    """:class:`StochasticGridworld` (same arguments) observed as ``(row, col)``."""

    metadata = {"render_modes": ["ansi"]}
    observation_names = OBSERVATION_NAMES

    def __init__(self, stochasticity: float = 0.0, **kwargs: Any) -> None:
        self.grid = StochasticGridworld(stochasticity, **kwargs)
        height, width = self.grid.shape
        self.observation_space = spaces.Box(np.zeros(2, np.float32), np.array([height - 1, width - 1], np.float32),
                                            dtype=np.float32)
        self.action_space = self.grid.action_space
        self.max_steps = self.grid.max_steps

    @property
    def stochasticity(self) -> float:
        return self.grid.stochasticity

    def coordinates(self, state: int) -> np.ndarray:
        return np.asarray(self.grid.state_cell(int(state)), dtype=np.float32)

    def state_of(self, coordinates: Any) -> np.ndarray:
        """Cell ids of coordinates ``(..., 2)`` (rounded and clipped to the grid)."""
        rc = np.rint(np.asarray(coordinates, dtype=np.float64)).astype(np.int64)
        height, width = self.grid.shape
        return np.clip(rc[..., 0], 0, height - 1) * width + np.clip(rc[..., 1], 0, width - 1)

    def is_unsafe(self, coordinates: Any) -> np.ndarray:
        """Whether each point ``(..., 2)`` lies in a forbidden cell."""
        return self.grid.forbidden_states[self.state_of(coordinates)]

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        state, info = self.grid.reset(seed=seed, options=options)
        return self.coordinates(state), {**info, "cost": 0.0}

    def step(self, action: Any):
        state, reward, terminated, truncated, info = self.grid.step(int(np.asarray(action).reshape(())))
        return self.coordinates(state), reward, terminated, truncated, {**info, "cost": float(info["violation"])}

    def render(self) -> str | None:
        return self.grid.render()


def expert_demonstrations(env: CoordinateGridworld, n: int, seed: int | None = 0) -> Any:
    """``n`` episodes of the gridworld's constrained expert, states as coordinates."""
    from symlearn.data import record

    expert = env.grid.expert_policy()
    return record(env, lambda obs: int(expert[int(env.state_of(obs))]), n, seed=seed, max_steps=env.max_steps,
                  metadata={"env": "gridworld (coordinates)", "stochasticity": env.stochasticity,
                            "observation_names": list(OBSERVATION_NAMES)},
                  desc=f"gridworld expert p={env.stochasticity:g}")


__all__ = ["OBSERVATION_NAMES", "CoordinateGridworld", "expert_demonstrations"]
