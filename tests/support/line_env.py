"""A one-dimensional world with float observations, for the PPO route of ``learn spec``.

Importing it registers ``Line-v0`` (``--env line_env:Line-v0``): a point on [0, 1] starting at
0.5 steps 0.1 left or right; reaching either end ends the episode; 30 steps at most. Its one
feature is named ``x`` (the ``feature_names`` attribute).
"""

import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Line(gym.Env):
    feature_names = ("x",)

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.5, 0
        return np.array([self.x], np.float32), {}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.1 if action == 1 else -0.1), 0.0, 1.0))
        self.t += 1
        end = self.x < 0.05 or self.x > 0.95
        return np.array([self.x], np.float32), 0.0, end, self.t >= 30, {}


if "Line-v0" not in gym.registry:
    gym.register("Line-v0", entry_point=Line)
