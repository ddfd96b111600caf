"""Blocked MuJoCo: gymnasium v5 HalfCheetah behind a wall, the thesis' blocked robot task.

After Malik et al. (2021) and Liu et al. (2023), as the thesis uses it (section 2.5.2): the
cheetah is paid for speed in *either* direction, and the constraint forbids the region
``x < wall`` (``wall = -3``) behind its start. Running backward is the easier gait for the
half-cheetah early in training, so an agent that ignores the constraint crosses the wall;
the constrained optimum runs forward.

* **Observation**: HalfCheetah-v5's with the root's x position kept
  (``exclude_current_positions_from_observation=False``): 18 entries, ``x`` first
  (``observation_names``), so a learned cost can read the position the constraint is about.
* **Reward**: ``|x velocity| * forward_reward_weight - ctrl_cost`` (v5's forward reward made
  direction-free; its control cost unchanged).
* **Cost** ``info["cost"]`` = 1.0 when the x position after the step is beyond the wall;
  ``info["violation"]`` the same as a bool. No termination on a violation (the violation rate per
  step is the measure); episodes truncated after ``max_episode_steps`` (1000, as v5).

Needs the ``mujoco`` extra (the ``mujoco`` wheel); :func:`make_blocked_half_cheetah` raises
:class:`~symlearn.errors.SymlearnError` naming it when absent.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.errors import DataError, SymlearnError

_JOINTS = ("rootx", "rootz", "rooty", "bthigh", "bshin", "bfoot", "fthigh", "fshin", "ffoot")
#: HalfCheetah-v5's observation with positions kept: joint positions, then velocities
OBSERVATION_NAMES = ("x", *_JOINTS[1:], *(f"v_{name}" for name in _JOINTS))


class BlockedHalfCheetah(gym.Wrapper):
    """A HalfCheetah-v5 environment (with x in the observation) behind a wall at ``x = wall``."""

    observation_names = OBSERVATION_NAMES

    def __init__(self, env: gym.Env, wall: float = -3.0) -> None:
        super().__init__(env)
        if not np.isfinite(wall):
            raise DataError(f"wall must be finite, got {wall!r}")
        if env.observation_space.shape != (len(OBSERVATION_NAMES),):
            raise DataError(f"BlockedHalfCheetah needs HalfCheetah-v5 with x in the observation "
                            f"(shape ({len(OBSERVATION_NAMES)},)), got {env.observation_space.shape}")
        self.wall = float(wall)

    def is_unsafe(self, observations: Any) -> np.ndarray | bool:
        """Whether observations (``(..., >=1)``, x first) lie behind the wall; vectorised."""
        unsafe = np.asarray(observations, dtype=np.float64)[..., 0] < self.wall
        return bool(unsafe) if np.ndim(unsafe) == 0 else unsafe

    def reset(self, **kwargs: Any):
        obs, info = self.env.reset(**kwargs)
        return obs, {**info, "cost": 0.0, "violation": False}

    def step(self, action: Any):
        obs, _, terminated, truncated, info = self.env.step(action)
        unwrapped = self.env.unwrapped
        # v5: reward = forward_reward_weight * x_velocity - ctrl_cost; paid for speed either way
        reward = unwrapped._forward_reward_weight * abs(float(info["x_velocity"])) + float(info["reward_ctrl"])
        violation = bool(float(info["x_position"]) < self.wall)
        return obs, reward, terminated, truncated, {**info, "cost": float(violation), "violation": violation}


def make_blocked_half_cheetah(wall: float = -3.0, max_episode_steps: int = 1000, **kwargs: Any) -> BlockedHalfCheetah:
    """``HalfCheetah-v5`` (positions kept in the observation, ``kwargs`` passed on) behind the wall."""
    import importlib.util

    if importlib.util.find_spec("mujoco") is None:
        raise SymlearnError("blocked MuJoCo environments need the mujoco wheel",
                            hint="pip install 'symlearn[mujoco]'")
    _route_mujoco_warnings()
    if int(max_episode_steps) < 1:
        raise DataError(f"max_episode_steps must be at least 1, got {max_episode_steps}")
    env = gym.make("HalfCheetah-v5", exclude_current_positions_from_observation=False,
                   max_episode_steps=int(max_episode_steps), **kwargs)
    return BlockedHalfCheetah(env, wall)


def _route_mujoco_warnings() -> None:
    """MuJoCo writes its warnings (HalfCheetah-v5's model triggers a deprecation warning on
    every load) to ``MUJOCO_LOG.TXT`` in the working directory unless a handler is installed; send
    them to Python's :mod:`warnings` instead (once per process, only when no handler is set)."""
    import warnings

    import mujoco

    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(lambda text: warnings.warn(f"MuJoCo: {text}", RuntimeWarning, stacklevel=2))


__all__ = ["OBSERVATION_NAMES", "BlockedHalfCheetah", "make_blocked_half_cheetah"]
