"""Blocked MuJoCo: gymnasium's v5 robots behind a wall, the thesis' blocked robot tasks.

After Malik et al. (2021) and Liu et al. (2023), as the thesis uses them (section 2.5.2): each
robot is paid for moving (in either direction) and a wall at ``x = wall`` forbids the side its
easier gait would take; :mod:`~symlearn.envs.blocked_mujoco_tasks` has the table (robots, walls,
rewards, episode lengths). The broken ant of the transfer experiment (section 2.5.4, Fig 2.4) is
the blocked ant with two legs' actuators disabled.

* **Observation**: the v5 robot's, with the root's position kept, so it starts with ``x``
  (``observation_names``; derived from the model's joints: ``x``, the other position
  coordinates, then ``v_<joint>`` velocities). The ant leaves out v5's 78 contact forces by
  default (``contact_forces=False``): they are zero on most steps, do not bear on the wall, and
  differ between the ant and the broken ant, whose cost should transfer; ``contact_forces=True``
  appends them (``cfrc_<body>_<component>``), as the benchmark's ant had them.
* **Cost** ``info["cost"]`` = 1.0 when the ``x`` reached lies beyond the wall, ``info["violation"]``
  the same as a bool, ``info["features"]`` = ``[x]`` (``feature_names``); :meth:`BlockedMujoco.is_unsafe`
  is the same test on observations, vectorised. A violation does not end the episode (the
  violation rate per step is the measure); v5's own termination (a fallen walker or pendulum)
  is kept; episodes are truncated after ``max_episode_steps``.
* The robot is the bare v5 environment (``robot``); :class:`BlockedMujoco` is itself the
  unwrapped environment, so ``env.unwrapped`` has ``observation_names`` and ``is_unsafe``, and
  :meth:`BlockedMujoco.set_state` places the robot (tests, figures).

Needs the ``mujoco`` extra; the ``make_*`` functions raise
:class:`~symlearn.errors.MissingDependencyError` naming it when the wheel is absent (this module
imports without it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from contextlib import contextmanager
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.envs.blocked_mujoco_tasks import BROKEN_ANT_ACTUATORS, TASKS, BlockedTask
from symlearn.errors import DataError

FEATURE_NAMES = ("x",)


class BlockedMujoco(gym.Env):
    """A v5 MuJoCo ``robot`` behind a wall at ``x = wall`` (see the module docstring).

    ``disabled_actuators``: action entries forced to 0 before the robot sees them (the broken ant).
    """

    def __init__(self, robot: gym.Env, task: BlockedTask, wall: float, max_episode_steps: int,
                 disabled_actuators: Sequence[int] = ()) -> None:
        self.robot, self.task = robot, task
        self.wall, self.max_episode_steps = float(wall), int(max_episode_steps)
        self.disabled_actuators = tuple(int(i) for i in disabled_actuators)
        self.observation_space, self.action_space = robot.observation_space, robot.action_space
        # Only the mode the robot was built with: gymnasium's env checker renders every declared
        # mode, and MuJoCo rendering needs an OpenGL context that headless machines lack.
        self.render_mode = robot.render_mode
        self.metadata = {"render_modes": [] if robot.render_mode is None else [robot.render_mode],
                         "render_fps": robot.metadata["render_fps"]}
        self.observation_names = observation_names(robot)
        self.feature_names = FEATURE_NAMES
        if len(self.observation_names) != robot.observation_space.shape[0]:
            raise ValueError(f"{task.gym_id}: {len(self.observation_names)} observation names for "
                             f"{robot.observation_space.shape[0]} entries")  # a v5 layout we do not know
        self.steps = 0

    def is_unsafe(self, observations: Any) -> np.ndarray | bool:
        """Whether observations (``(..., >=1)``, ``x`` first) lie beyond the wall; vectorised."""
        x = np.asarray(observations, dtype=np.float64)[..., 0]
        unsafe = x < self.wall if self.task.side == "below" else x > self.wall
        return bool(unsafe) if np.ndim(unsafe) == 0 else unsafe

    def set_state(self, qpos: Any, qvel: Any) -> np.ndarray:
        """Place the robot (MuJoCo's ``qpos``, ``qvel``); returns the observation there."""
        self.robot.set_state(np.asarray(qpos, dtype=np.float64), np.asarray(qvel, dtype=np.float64))
        return self.robot._get_obs()

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        obs, info = self.robot.reset(seed=seed, options=options)
        self.steps = 0
        return obs, {**info, **self._ground_truth(obs)}

    def step(self, action: Any):
        if self.disabled_actuators:
            action = np.array(action, dtype=np.float32)  # a copy: the caller's action stays as given
            action[list(self.disabled_actuators)] = 0.0
        obs, reward, terminated, _, info = self.robot.step(action)
        self.steps += 1
        reward = self.task.reward(reward, info, obs)
        return obs, reward, terminated, self.steps >= self.max_episode_steps, {**info, **self._ground_truth(obs)}

    def _ground_truth(self, obs: np.ndarray) -> dict[str, Any]:
        x = float(obs[0])  # is_unsafe on one observation, without its array round trip (every step)
        violation = x < self.wall if self.task.side == "below" else x > self.wall
        return {"cost": float(violation), "violation": violation, "features": np.array([x])}

    def render(self):
        return self.robot.render()

    def close(self) -> None:
        self.robot.close()


def observation_names(robot: gym.Env) -> tuple[str, ...]:
    """Names of a v5 robot's observation with positions kept: ``x`` first, then the model's
    other position coordinates, ``v_`` velocities and (the ant's, if kept) contact forces."""
    import mujoco

    model = robot.unwrapped.model
    positions, velocities = [], []
    for j in range(model.njnt):
        name = model.joint(j).name
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:  # a floating base: 3-D position, quaternion
            positions += ["x", "y", "z", "qw", "qx", "qy", "qz"]
            velocities += ["vx", "vy", "vz", "wx", "wy", "wz"]
        else:  # slide and hinge joints: one coordinate each
            positions.append(name)
            velocities.append(f"v_{name}")
    positions[0] = "x"  # the root's slide along x (its own name, e.g. rootx, says no more than x)
    names = positions + velocities
    extra = robot.observation_space.shape[0] - len(names)
    if extra == 6 * (model.nbody - 1):  # v5's contact forces of every body but the world
        bodies = [model.body(b).name or f"body{b}" for b in range(1, model.nbody)]
        names += [f"cfrc_{body}_{c}" for body in bodies for c in ("rx", "ry", "rz", "fx", "fy", "fz")]
    return tuple(names)


# --- factories (the registry's entries; keyword arguments are what --env-kwargs may set) ---------

def make_blocked_half_cheetah(wall: float = -3.0, max_episode_steps: int = 1000, **kwargs: Any) -> BlockedMujoco:
    """HalfCheetah-v5 behind a wall (``x < wall`` forbidden); ``kwargs`` go to the robot."""
    return make_blocked("half-cheetah", wall, max_episode_steps, **kwargs)


def make_blocked_ant(wall: float = -3.0, max_episode_steps: int = 500, contact_forces: bool = False,
                     **kwargs: Any) -> BlockedMujoco:
    """Ant-v5 behind a wall (``x < wall`` forbidden), paid for its distance from the origin."""
    return make_blocked("ant", wall, max_episode_steps, include_cfrc_ext_in_observation=_flag(contact_forces),
                        **kwargs)


def make_broken_ant(wall: float = -3.0, max_episode_steps: int = 500, contact_forces: bool = False,
                    disabled_actuators: Sequence[int] = BROKEN_ANT_ACTUATORS, **kwargs: Any) -> BlockedMujoco:
    """The blocked ant with ``disabled_actuators`` (default: two legs, Malik et al.'s) forced to 0;
    same observation and action spaces as :func:`make_blocked_ant`, so its costs load here."""
    return make_blocked("ant", wall, max_episode_steps, disabled_actuators,
                        include_cfrc_ext_in_observation=_flag(contact_forces), **kwargs)


def make_blocked_walker2d(wall: float = -3.0, max_episode_steps: int = 500, **kwargs: Any) -> BlockedMujoco:
    """Walker2d-v5 behind a wall (``x < wall`` forbidden); v5's fall ends the episode."""
    return make_blocked("walker2d", wall, max_episode_steps, **kwargs)


def make_blocked_swimmer(wall: float = 0.5, max_episode_steps: int = 500, **kwargs: Any) -> BlockedMujoco:
    """Swimmer-v5 before a wall (``x > wall`` forbidden)."""
    return make_blocked("swimmer", wall, max_episode_steps, **kwargs)


def make_biased_inverted_pendulum(wall: float = -0.015, max_episode_steps: int = 100,
                                  **kwargs: Any) -> BlockedMujoco:
    """InvertedPendulum-v5 paid more left of its start, where ``x < wall`` is forbidden (``wall``
    moves the constraint only: the reward's ramp stays between ``x = -0.01`` and 0)."""
    return make_blocked("inverted-pendulum", wall, max_episode_steps, **kwargs)


def make_blocked(task: str, wall: float | None = None, max_episode_steps: int | None = None,
                 disabled_actuators: Sequence[int] = (), **kwargs: Any) -> BlockedMujoco:
    """The blocked ``task`` of :data:`~symlearn.envs.blocked_mujoco_tasks.TASKS` (its own wall
    and episode length unless given); ``kwargs`` go to the v5 robot."""
    from symlearn.optional import require

    if task not in TASKS:
        raise DataError(f"unknown blocked MuJoCo task {task!r}", hint="known: " + ", ".join(TASKS))
    spec = TASKS[task]
    wall = spec.wall if wall is None else _number("wall", wall)
    if not math.isfinite(wall):
        raise DataError(f"wall must be finite, got {wall!r}")
    steps = spec.max_episode_steps if max_episode_steps is None else max_episode_steps
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise DataError(f"max_episode_steps must be an integer of at least 1, got {steps!r}")
    if kwargs.get("exclude_current_positions_from_observation"):
        raise DataError("a blocked task keeps the root's position in the observation: its wall is about x",
                        hint="leave exclude_current_positions_from_observation out")
    require("mujoco", "blocked MuJoCo environments")
    route_mujoco_warnings()
    with _quiet_model_notices():
        robot = gym.make(spec.gym_id, **{**spec.robot_kwargs, **kwargs}).unwrapped
    n_actions = robot.action_space.shape[0]
    disabled = list(disabled_actuators)
    if any(isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < n_actions for i in disabled):
        robot.close()
        raise DataError(f"disabled_actuators must be action indices in 0..{n_actions - 1}, got {disabled!r}")
    return BlockedMujoco(robot, spec, wall, int(steps), disabled)


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        raise DataError(f"{name} must be a number, got {value!r}")
    return float(value)


def _flag(value: Any) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise DataError(f"contact_forces must be true or false, got {value!r}")
    return bool(value)


def route_mujoco_warnings() -> None:
    """MuJoCo writes its warnings to ``MUJOCO_LOG.TXT`` in the working directory unless a handler
    is installed; send them to Python's :mod:`warnings` instead (once per process, only when no
    handler is set)."""
    import warnings

    import mujoco

    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(lambda text: warnings.warn(f"MuJoCo: {text}", RuntimeWarning, stacklevel=2))


@contextmanager
def _quiet_model_notices():
    """Gymnasium's HalfCheetah model uses a compiler attribute MuJoCo 3 deprecates, and MuJoCo says
    so on every load: a notice about gymnasium's file that no user of ours can act on (and that
    fails code run with warnings as errors). Other MuJoCo warnings pass."""
    import warnings

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="MuJoCo: compiler attribute .* is deprecated",
                                category=RuntimeWarning)
        yield


__all__ = ["FEATURE_NAMES", "BlockedMujoco", "make_biased_inverted_pendulum", "make_blocked", "make_blocked_ant",
           "make_blocked_half_cheetah", "make_blocked_swimmer", "make_blocked_walker2d", "make_broken_ant",
           "observation_names", "route_mujoco_warnings"]
