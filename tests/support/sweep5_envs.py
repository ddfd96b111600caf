"""Users' environments of the fifth sweep (docs/BENCHMARKS.md, "Fifth sweep of users'
environments"): kinds no earlier sweep wrote, used by ``tests/cli/test_user_env_sweep_round5.py``
as ``sweep5_envs:...`` (this folder is on ``sys.path`` in the tests).

Each is a point on the square ``[-1, 1]^2`` moved by its action; ``info["cost"]`` is 1 above
``y = 0.5``. The classes differ only in what the sweep found mishandled: the shape of the action,
how the columns are named, and how the module offers them (``Walker`` is registered nowhere:
``--env sweep5_envs:Walker`` names the class itself)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

_MOVES = np.array([[1, 0], [-1, 0], [0, 1], [0, -1]], dtype=np.float32)


class Walker(gym.Env):
    """Four moves of 0.2; reward the x coordinate; ends at the right edge or after 30 steps."""

    observation_space = spaces.Box(-1, 1, (2,), np.float32)
    action_space = spaces.Discrete(4)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.p = np.zeros(2, np.float32)
        self.t = 0
        return self.p.copy(), {}

    def _moved(self, delta):
        self.t += 1
        self.p = np.clip(self.p + delta, -1, 1).astype(np.float32)
        return (self.p.copy(), float(self.p[0]), bool(self.p[0] >= 1), self.t >= 30,
                {"cost": float(self.p[1] > 0.5)})

    def step(self, action):
        return self._moved(0.2 * _MOVES[int(action)])


class MatrixPush(Walker):
    """Acts in a ``(1, 2)`` ``Box``: the push as a row vector; refuses any other shape."""

    action_space = spaces.Box(-1, 1, (1, 2), np.float32)

    def step(self, action):
        action = np.asarray(action)
        if action.shape != (1, 2):
            raise ValueError(f"MatrixPush acts in (1, 2) arrays, got shape {action.shape}")
        return self._moved(0.2 * np.clip(action[0], -1, 1))


class ScalarPush(Walker):
    """Acts in a scalar ``Box(())``: a push along x."""

    action_space = spaces.Box(-1, 1, (), np.float32)

    def step(self, action):
        if np.shape(action) != ():
            raise ValueError(f"ScalarPush acts in scalars, got shape {np.shape(action)}")
        return self._moved(np.array([0.2 * float(np.clip(action, -1, 1)), 0.0], np.float32))


class TwinNames(Walker):
    """Names both columns ``x``."""

    feature_names = ("x", "x")


class ThreeNames(Walker):
    """Names three columns of a two-column observation."""

    feature_names = ("x", "y", "z")


class ForgetsReward(Walker):
    """A branch of ``step`` forgets its reward (``None``) on the third step."""

    def step(self, action):
        observation, reward, terminated, truncated, info = super().step(action)
        return observation, (None if self.t == 3 else reward), terminated, truncated, info


class ThreeNumbers(Walker):
    """Declares a ``(2,)`` observation and returns three numbers."""

    def reset(self, *, seed=None, options=None):
        observation, info = super().reset(seed=seed, options=options)
        return np.append(observation, 0.0).astype(np.float32), info

    def step(self, action):
        observation, *rest = super().step(action)
        return (np.append(observation, 0.0).astype(np.float32), *rest)


class LateNames(Walker):
    """``feature_names`` a property that raises (names built only after something the user forgot)."""

    @property
    def feature_names(self):
        raise RuntimeError("names not ready")


class Blinded(Walker):
    """Observes NaN for x on its fourth step."""

    def step(self, action):
        observation, *rest = super().step(action)
        if self.t == 4:
            observation[0] = np.nan
        return (observation, *rest)


def not_an_env():
    """A function, not an environment class: ``--env sweep5_envs:not_an_env`` is refused."""
    return None


gym.register("sweep5/MatrixPush-v0", entry_point=MatrixPush, max_episode_steps=20)
gym.register("sweep5/ScalarPush-v0", entry_point=ScalarPush, max_episode_steps=20)
gym.register("sweep5/TwinNames-v0", entry_point=TwinNames, max_episode_steps=20)
gym.register("sweep5/ThreeNames-v0", entry_point=ThreeNames, max_episode_steps=20)
gym.register("sweep5/ForgetsReward-v0", entry_point=ForgetsReward, max_episode_steps=20)
gym.register("sweep5/ThreeNumbers-v0", entry_point=ThreeNumbers, max_episode_steps=20)
gym.register("sweep5/LateNames-v0", entry_point=LateNames, max_episode_steps=20)
gym.register("sweep5/Blinded-v0", entry_point=Blinded, max_episode_steps=20)
