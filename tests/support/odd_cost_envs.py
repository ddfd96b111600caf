"""A user's environment whose ``info["cost"]`` comes in the shapes people write (a vector of
constraints, a list, ``None`` where nothing is paid, a complex number by mistake), as a module
source a test drops into a folder of its own (reached as ``module:EnvId``)."""

from __future__ import annotations

#: ``OddCost-v0``: a line walk from 0, paid for stepping right; ``info["cost"]`` on every step is
#: ``{"vector": [x > 0.25, 0], "list": [x > 0.25], "none": None, "complex": 0j, "text": "0"}[kind]``
ODD_COST = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class OddCost(gym.Env):
    feature_names = ("x",)

    def __init__(self, kind="vector", horizon=10):
        self.kind, self.horizon = kind, horizon
        self.observation_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.0, 0
        return np.array([self.x], np.float32), {}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.1 if action else -0.1), -1.0, 1.0))
        self.t += 1
        paid = float(self.x > 0.25)
        cost = {"vector": np.array([paid, 0.0]), "list": [paid], "none": None, "complex": 0j,
                "text": "1" if paid else "0"}[self.kind]
        return np.array([self.x], np.float32), float(action), False, self.t >= self.horizon, {"cost": cost}


gym.register("OddCost-v0", entry_point=OddCost)
'''

#: ``MatrixAction-v0``: acts in a ``Box(-1, 1, (2, 2))`` (``MultiDiscrete([[2, 3], [2, 2]])`` with
#: ``kind="multi"``): stable-baselines3's PPO trains in it, a demonstration cannot store it
MATRIX_ACTION = """
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class MatrixAction(gym.Env):
    observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)

    def __init__(self, kind="box"):
        self.action_space = (spaces.Box(-1.0, 1.0, (2, 2), np.float32) if kind == "box"
                             else spaces.MultiDiscrete([[2, 3], [2, 2]]))

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return np.zeros(2, np.float32), {}

    def step(self, action):
        self.t += 1
        return np.zeros(2, np.float32), float(np.sum(action)), False, self.t >= 5, {}


gym.register("MatrixAction-v0", entry_point=MatrixAction)
"""
