"""Users' environments with the less common gymnasium spaces, as module sources a test drops into
a folder of its own (reached as ``module:EnvId``, as a researcher's file would be)."""

from __future__ import annotations

#: Discrete observations numbered from 2 and Discrete actions from -1 (``start != 0`` on both):
#: a walk on 2..9 whose ``info["cost"]`` is 1 on cell 5
OFFSET_WALK = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class OffsetWalk(gym.Env):
    def __init__(self, horizon=20):
        self.horizon = horizon
        self.observation_space = spaces.Discrete(8, start=2)
        self.action_space = spaces.Discrete(3, start=-1)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.cell, self.t = 2, 0
        return self.cell, {}

    def step(self, action):
        if not self.action_space.contains(action):
            raise ValueError(f"action {action!r} outside {self.action_space}")
        self.cell = int(np.clip(self.cell + int(action), 2, 9))
        self.t += 1
        return self.cell, float(self.cell == 9), self.cell == 9, self.t >= self.horizon, {"cost": float(self.cell == 5)}


gym.register("OffsetWalk-v0", entry_point=OffsetWalk)
'''

#: a point steered by a few choices at once: ``MultiDiscrete([3, 3])`` (``SwitchBoard-v0``) or
#: ``MultiBinary(2)`` (``kind="binary"``); right of ``x = 0.5`` is forbidden (``info["cost"]``)
SWITCH_BOARD = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class SwitchBoard(gym.Env):
    feature_names = ("x", "y")

    def __init__(self, kind="multi", horizon=20):
        self.kind, self.horizon = kind, horizon
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = spaces.MultiDiscrete([3, 3]) if kind == "multi" else spaces.MultiBinary(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.t = self.np_random.uniform(-0.5, 0.0, 2), 0
        return self.p.astype(np.float32), {}

    def step(self, action):
        action = np.asarray(action)
        if not self.action_space.contains(action.astype(self.action_space.dtype)) or action.shape != (2,):
            raise ValueError(f"action {action!r} outside {self.action_space}")
        move = action - 1 if self.kind == "multi" else 2 * action - 1
        before = self.p[0]
        self.p = np.clip(self.p + 0.1 * move, -1.0, 1.0)
        self.t += 1
        return (self.p.astype(np.float32), float(self.p[0] - before), False, self.t >= self.horizon,
                {"cost": float(self.p[0] > 0.5)})


gym.register("SwitchBoard-v0", entry_point=SwitchBoard)
'''

#: a scalar observation (``Box`` of shape ``()``, reset returning a numpy scalar), one step per
#: episode: guess the hidden number; a guess above 0.8 costs 1
ONE_GUESS = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class OneGuess(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(-1.0, 1.0, (), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x = np.float32(self.np_random.uniform(-1, 1))
        return self.x, {}

    def step(self, action):
        guess = float(np.asarray(action).reshape(-1)[0])
        return np.float32(0.0), -abs(self.x - guess), True, False, {"cost": float(guess > 0.8)}


gym.register("OneGuess-v0", entry_point=OneGuess)
'''

#: a Dict observation with a Discrete part beside a vector (``record()`` stores the part as one
#: integer column, the policy's numeric view one-hot): a point with a gear; right of 0.5 costs 1
GEARED_POINT = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class GearedPoint(gym.Env):
    def __init__(self, horizon=15):
        self.horizon = horizon
        self.observation_space = spaces.Dict({"pos": spaces.Box(-1.0, 1.0, (2,), np.float32),
                                              "gear": spaces.Discrete(3)})
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)

    def _observation(self):
        return {"pos": self.p.astype(np.float32), "gear": self.gear}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.gear, self.t = self.np_random.uniform(-0.9, -0.5, 2), 0, 0
        return self._observation(), {}

    def step(self, action):
        action = np.clip(np.asarray(action, float), -1, 1)
        self.gear = int(min(2, abs(action[0]) * 3))
        before = self.p[0]
        self.p = np.clip(self.p + 0.1 * action, -1.0, 1.0)
        self.t += 1
        return (self._observation(), float(self.p[0] - before), False, self.t >= self.horizon,
                {"cost": float(self.p[0] > 0.5)})


gym.register("GearedPoint-v0", entry_point=GearedPoint)
'''

#: no time limit and never done: a point on a line, paid for going right; right of 0.5 costs 1
ENDLESS_LINE = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class EndlessLine(gym.Env):
    feature_names = ("x",)

    def __init__(self, horizon=None):   # horizon: a time limit of its own, none registered
        self.horizon = horizon
        self.observation_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.0, 0
        return np.array([self.x], np.float32), {}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.05 if action else -0.05), -1.0, 1.0))
        self.t += 1
        cut = self.horizon is not None and self.t >= self.horizon
        return np.array([self.x], np.float32), self.x, False, cut, {"cost": float(self.x > 0.5)}


gym.register("EndlessLine-v0", entry_point=EndlessLine)
'''

#: environments that misbehave on their 5th step: ``FaultyMotor-v0`` raises, ``BlindSensor-v0``
#: observes NaN
FAULTY = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class FaultyMotor(gym.Env):
    observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
    action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return np.zeros(2, np.float32), {}

    def step(self, action):
        self.t += 1
        if self.t == 5:
            raise RuntimeError("motor fault")
        return np.zeros(2, np.float32), 0.0, False, self.t >= 10, {}


class BlindSensor(FaultyMotor):
    def step(self, action):
        self.t += 1
        seen = np.full(2, np.nan if self.t == 5 else 0.0, np.float32)
        return seen, 0.0, False, self.t >= 10, {}


gym.register("FaultyMotor-v0", entry_point=FaultyMotor, disable_env_checker=True)
gym.register("BlindSensor-v0", entry_point=BlindSensor, disable_env_checker=True)
'''

#: a point observed as a ``(2, 3)`` Box (a matrix, not a picture): row 0 holds ``(x, y, 0)``, row 1
#: ``(-x, -y, 0)``; right of ``x = 0.5`` is forbidden (``info["cost"]``)
MATRIX_POINT = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class MatrixPoint(gym.Env):
    observation_space = spaces.Box(-1.0, 1.0, (2, 3), np.float32)
    action_space = spaces.Box(-0.1, 0.1, (2,), np.float32)

    def _seen(self):
        return np.array([[self.p[0], self.p[1], 0.0], [-self.p[0], -self.p[1], 0.0]], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.t = self.np_random.uniform(-0.9, -0.5, 2), 0
        return self._seen(), {}

    def step(self, action):
        self.p = np.clip(self.p + np.clip(action, -0.1, 0.1), -1.0, 1.0)
        self.t += 1
        return self._seen(), float(action[0]), False, self.t >= 20, {"cost": float(self.p[0] > 0.5)}


gym.register("MatrixPoint-v0", entry_point=MatrixPoint)
'''

#: lamps switched by ``MultiBinary(3)`` actions, counted in an integer ``Box`` observation; the
#: environment refuses an action that is not of integers (stable-baselines3 samples floats)
LAMP_COUNTER = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class LampCounter(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(0, 100, shape=(3,), dtype=np.int64)
        self.action_space = spaces.MultiBinary(3)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.count, self.t = np.zeros(3, dtype=np.int64), 0
        return self.count.copy(), {}

    def step(self, action):
        if np.asarray(action).dtype.kind not in "biu":
            raise TypeError(f"action {action!r} is not of integers")
        self.count = np.minimum(self.count + action, 100)
        self.t += 1
        return self.count.copy(), float(np.sum(action)), False, self.t >= 10, {"cost": float(action[0])}


gym.register("LampCounter-v0", entry_point=LampCounter)
'''
