"""Environments a user might write, as module sources a test drops into a folder of its own.

They live outside the package on purpose: the resolver must reach them as ``module:EnvId``
through an import from the current directory, as it would a researcher's file.
"""

from __future__ import annotations

from pathlib import Path

POINT_ROBOT = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class PointRobot(gym.Env):
    """A point in [-1, 1]^2 paid for moving right; x > wall is forbidden (info["cost"])."""

    feature_names = ("px", "py")

    def __init__(self, wall=0.5, horizon=40):
        self.wall, self.horizon = wall, horizon
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Box(-0.1, 0.1, (2,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.position = self.np_random.uniform(-0.9, -0.5, size=2)
        self.t = 0
        return self.position.astype(np.float32), {"features": self.position.copy()}

    def step(self, action):
        before = self.position[0]
        self.position = np.clip(self.position + np.clip(action, -0.1, 0.1), -1.0, 1.0)
        self.t += 1
        info = {"cost": float(self.position[0] > self.wall), "features": self.position.copy()}
        return (self.position.astype(np.float32), float(self.position[0] - before), False,
                self.t >= self.horizon, info)


gym.register("PointRobot-v0", entry_point=PointRobot)
'''

#: the same robot without ground truth and without names: what many users have
PLAIN_ROBOT = POINT_ROBOT.replace('    feature_names = ("px", "py")\n', "").replace(
    'info = {"cost": float(self.position[0] > self.wall), "features": self.position.copy()}', "info = {}").replace(
    '{"features": self.position.copy()}', "{}").replace("PointRobot-v0", "PlainRobot-v0")

#: a cost reported only on the steps that pay it: ``info["cost"] = 1.0`` on a step whose action
#: differs from the one before (a gear change), no ``"cost"`` key on the other steps. The first step
#: of an episode never has one, and a greedy policy (one action for the one observation) never
#: changes gear, while a sampling one does: its training steps report costs, its evaluation none.
GEAR_SWITCH = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class GearSwitch(gym.Env):
    feature_names = ("x", "y")

    def __init__(self, horizon=16):
        self.horizon = horizon
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.t, self.previous = 0, None
        return np.zeros(2, dtype=np.float32), {}

    def step(self, action):
        action = int(action)
        info = {"cost": 1.0} if self.previous is not None and action != self.previous else {}
        self.previous = action
        self.t += 1
        return np.zeros(2, dtype=np.float32), float(action), False, self.t >= self.horizon, info


gym.register("GearSwitch-v0", entry_point=GearSwitch)
'''


#: a cart that observes (vel, pos) and reports info["features"] as a dict {"pos": ..., "vel": ...}:
#: the features' names are not the observation's
SWAPPED_CART = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class SwappedCart(gym.Env):
    """Observes (vel, pos); reports info["features"] as a dict {"pos": ..., "vel": ...}."""

    def __init__(self):
        self.observation_space = spaces.Box(-2.0, 2.0, (2,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)

    def _out(self):
        return np.array([self.vel, self.pos], np.float32), {"features": {"pos": self.pos, "vel": self.vel}}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos, self.vel, self.t = float(self.np_random.uniform(-1.0, -0.5)), 0.0, 0
        return self._out()

    def step(self, action):
        self.vel = float(np.clip(0.8 * self.vel + 0.05 * float(np.asarray(action).reshape(-1)[0]), -0.2, 0.2))
        self.pos, self.t = float(np.clip(self.pos + self.vel, -1.5, 1.5)), self.t + 1
        observation, info = self._out()
        return observation, -abs(self.pos - 1.0), False, self.t >= 30, {**info, "cost": float(self.pos > 0.6)}


gym.register("SwappedCart-v0", entry_point=SwappedCart)
'''


def write_module(folder: Path, name: str, source: str) -> Path:
    path = Path(folder) / f"{name}.py"
    path.write_text(source)
    return path


def careful_expert(wall: float = 0.5):
    """Moves right but stops short of the wall (the behaviour the constraint explains)."""
    import numpy as np

    def act(observation):
        x = float(observation[0])
        return np.array([0.1 if x < wall - 0.12 else 0.0, 0.05], dtype=np.float32)

    return act
