"""A user's own environment, as someone outside symlearn would write it: importing this module
registers ``HazardRobot-v0`` with gymnasium (``--env point_robot_env:HazardRobot-v0``).

A point in the unit square moves by its (clipped) action towards a goal at the top right; a
hazard strip ``hazard_low < x < hazard_high`` below ``y < 0.6`` costs 1 per step inside it
(``info["cost"]``, the safety-gymnasium convention). The observation is ``(x, y)``; the names
are the ``feature_names`` attribute, or -- with ``named_features=True`` -- only the keys of a dict
``info["features"]``.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np


class PointRobot(gym.Env):
    def __init__(self, hazard_low: float = 0.4, hazard_high: float = 0.6, max_steps: int = 50,
                 named_features: bool = False, discrete: bool = False) -> None:
        self.hazard = (float(hazard_low), float(hazard_high))
        self.max_steps = int(max_steps)
        self.named = bool(named_features)
        if not self.named:
            self.feature_names = ("x", "y")
        self.observation_space = gym.spaces.Box(0.0, 1.0, shape=(2,), dtype=np.float32)
        self.action_space = gym.spaces.Discrete(4) if discrete else \
            gym.spaces.Box(-0.1, 0.1, shape=(2,), dtype=np.float32)
        self.position = np.zeros(2)
        self.t = 0

    def _info(self) -> dict:
        x, y = self.position
        unsafe = self.hazard[0] < x < self.hazard[1] and y < 0.6
        features = {"x": float(x), "y": float(y)} if self.named else self.position.copy()
        return {"cost": 1.0 if unsafe else 0.0, "features": features}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.position = np.array([0.1, 0.1]) + self.np_random.uniform(0.0, 0.05, size=2)
        self.t = 0
        return self.position.astype(np.float32), self._info()

    def step(self, action):
        if isinstance(self.action_space, gym.spaces.Discrete):
            move = np.array([(0.1, 0.0), (-0.1, 0.0), (0.0, 0.1), (0.0, -0.1)][int(action)])
        else:
            move = np.clip(np.asarray(action, dtype=np.float64), -0.1, 0.1)
        before = np.linalg.norm(self.position - 1.0)
        self.position = np.clip(self.position + move, 0.0, 1.0)
        self.t += 1
        after = np.linalg.norm(self.position - 1.0)
        reached = after < 0.15
        reward = float(before - after) + (1.0 if reached else 0.0)
        return self.position.astype(np.float32), reward, bool(reached), self.t >= self.max_steps, self._info()


if "HazardRobot-v0" not in gym.registry:
    gym.register("HazardRobot-v0", entry_point=PointRobot)
