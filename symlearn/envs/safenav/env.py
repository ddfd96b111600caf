"""SafeNav: Safety-Gym's Point/Car x Goal1/Push1 re-created in numpy (thesis section 4.4.1).

Safety-Gymnasium and OmniSafe need MuJoCo and do not install here, so this is a small planar
re-creation with the parts the thesis' constraint learning uses: a robot
(:mod:`~symlearn.envs.safenav.agents`), a task (:mod:`~symlearn.envs.safenav.tasks`), a random
layout of 8 hazards (:mod:`~symlearn.envs.safenav.layout`), lidars
(:mod:`~symlearn.envs.safenav.lidar`) and the observation
(:mod:`~symlearn.envs.safenav.observation`).

* **Actions**: ``Box(-1, 1, (2,))`` -- Point: (forward force, rotation); Car: (left wheel,
  right wheel).
* **Observation**: a flat ``float32`` Box (40 values for Goal, 59 for Push); its first 20 are
  the features below.
* **Reward**: progress to the goal (Push: box progress to the goal + robot progress to the
  box), +1 on reaching the goal, after which a new goal appears.
* **Cost**: ``info["cost"]`` is 1.0 when the robot's centre is inside a hazard disc (radius
  0.2), else 0.0 -- the ground truth the constraint learners try to recover.
* **Features**: ``info["features"]`` is the thesis' 20-vector ``[a_x, a_y, v_x, v_y, d_0 ..
  d_15]`` (``float64``; names in :data:`FEATURE_NAMES`), the input of the DNF learner.
* **Episodes** end by truncation after ``max_steps`` (1000, as Safety-Gym); no termination.
* The arena: objects are placed in ``[-1.5, 1.5]^2`` (Safety-Gym level 1), and walls at ``+-2``
  keep robot and box nearby (level 1 has no walls; ``wall=None`` removes them).

Every reset draws a new layout from the seeded generator, so ``reset(seed=s)`` replays exactly.
:meth:`SafeNavEnv.place` puts robot, box, goal or hazards where a test or a figure needs them.

>>> env = SafeNavEnv("car", "push")
>>> observation, info = env.reset(seed=0)
>>> observation.shape, info["features"].shape, env.action_space.shape
((59,), (20,), (2,))
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.envs.safenav.agents import DT, RADIUS, AgentState, make_agent
from symlearn.envs.safenav.layout import sample_layout
from symlearn.envs.safenav.lidar import MAX_DIST, N_BINS, pseudo_lidar
from symlearn.envs.safenav.observation import (
    FEATURE_NAMES, N_FEATURES, SENSOR_LIMITS, clip, compass, observation_bounds, observation_names,
)

_A, _V, _W = SENSOR_LIMITS["a_x"], SENSOR_LIMITS["v_x"], SENSOR_LIMITS["gyro"]
from symlearn.envs.safenav.tasks import PushTask, make_task
from symlearn.errors import DataError

DEFAULT_MAX_STEPS = 1000


class SafeNavEnv(gym.Env):
    """``SafeNavEnv(agent="point"|"car", task="goal"|"push", max_steps=1000, n_hazards=8,
    hazard_radius=0.2, extent=1.5, wall=2.0, lidar_max_dist=3.0, render_mode=None)``
    (see the module docstring)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": int(round(1 / DT))}

    def __init__(self, agent: str = "point", task: str = "goal", *, max_steps: int = DEFAULT_MAX_STEPS,
                 n_hazards: int = 8, hazard_radius: float = 0.2, extent: float = 1.5, wall: float | None = 2.0,
                 lidar_max_dist: float = MAX_DIST, render_mode: str | None = None) -> None:
        if max_steps < 1:
            raise DataError(f"max_steps must be at least 1, got {max_steps}")
        if n_hazards < 0 or hazard_radius <= 0:
            raise DataError(f"need n_hazards >= 0 and hazard_radius > 0, got {n_hazards} and {hazard_radius}")
        if wall is not None and wall < extent + RADIUS:
            raise DataError(f"the walls (+-{wall}) must enclose the placement area (+-{extent})")
        if render_mode not in (None, "rgb_array"):
            raise DataError(f"unknown render mode {render_mode!r}", hint="use 'rgb_array' or None")
        self.robot = make_agent(agent)
        self.task = make_task(task)
        self.agent_name, self.task_name = agent, task
        self.max_steps = int(max_steps)
        self.n_hazards, self.hazard_radius = int(n_hazards), float(hazard_radius)
        self.extent, self.wall, self.lidar_max_dist = float(extent), wall, float(lidar_max_dist)
        self.render_mode = render_mode
        self.push = isinstance(self.task, PushTask)
        self.observation_names = observation_names(self.push)
        low, high = observation_bounds(self.push)
        self.observation_space = spaces.Box(low, high, dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.feature_names = FEATURE_NAMES
        self.state = AgentState()
        self.hazards = np.zeros((0, 2))
        self.steps = 0
        self.goals_reached = 0
        self._accel = (0.0, 0.0)
        self._hazard_lidar = np.zeros(N_BINS)
        self._raster = None

    # --- gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        layout = sample_layout(self.np_random, n_hazards=self.n_hazards, hazard_radius=self.hazard_radius,
                               goal_radius=self.task.goal_radius, box_radius=self.task.box_radius,
                               extent=self.extent)
        heading = float(self.np_random.uniform(0.0, 2 * math.pi))
        self.state = AgentState(float(layout.agent[0]), float(layout.agent[1]), heading)
        self.hazards = layout.hazards
        self.task.reset(layout.goal, layout.box, self.state)
        self.steps = 0
        self.goals_reached = 0
        self._accel = (0.0, 0.0)
        observation, features = self._observe()
        return observation, {"cost": self._cost(), "features": features, "goal_met": False, "goals_reached": 0}

    def step(self, action):
        state = self.state
        vx, vy = state.vx, state.vy
        self.robot.step(state, action)
        self.task.physics(state, self.wall)
        if self.wall is not None:
            limit = self.wall - RADIUS
            if not -limit <= state.x <= limit:
                state.x, state.vx = max(-limit, min(limit, state.x)), 0.0
            if not -limit <= state.y <= limit:
                state.y, state.vy = max(-limit, min(limit, state.y)), 0.0
        c, s = math.cos(state.heading), math.sin(state.heading)
        ax, ay = (state.vx - vx) / DT, (state.vy - vy) / DT
        self._accel = (c * ax + s * ay, -s * ax + c * ay)
        self.steps += 1
        reward, met = self.task.reward(state)
        if met:
            self.goals_reached += 1
            self.task.new_goal(self.np_random, state, self.hazards, self.hazard_radius, self.extent)
        observation, features = self._observe()
        info = {"cost": self._cost(), "features": features, "goal_met": met, "goals_reached": self.goals_reached}
        return observation, float(reward), False, self.steps >= self.max_steps, info

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        from symlearn.envs.safenav.render import Raster, draw

        if self._raster is None:
            self._raster = Raster(256, (self.wall or self.extent + 0.5) + 0.1)
        return draw(self._raster, wall=self.wall, hazards=self.hazards, hazard_radius=self.hazard_radius,
                    goal=self.task.goal, goal_radius=self.task.goal_radius,
                    box=self.task.box if self.push else None, box_radius=self.task.box_radius,
                    agent_xy=(self.state.x, self.state.y), heading=self.state.heading, agent_radius=RADIUS)

    # --- ground truth and features ------------------------------------------------------------
    def in_hazard(self, x: float, y: float) -> bool:
        """Whether the point ``(x, y)`` lies inside (or on the edge of) a hazard disc."""
        if not len(self.hazards):
            return False
        d2 = (self.hazards[:, 0] - x) ** 2 + (self.hazards[:, 1] - y) ** 2
        return bool(d2.min() <= self.hazard_radius ** 2)

    def _cost(self) -> float:
        return 1.0 if self.in_hazard(self.state.x, self.state.y) else 0.0

    def features(self) -> np.ndarray:
        """The thesis' 20 features of the current state (a copy)."""
        return self._observe()[1]

    def _observe(self) -> tuple[np.ndarray, np.ndarray]:
        state = self.state
        x, y, heading = state.x, state.y, state.heading
        obs = np.empty(self.observation_space.shape[0], dtype=np.float64)
        obs[0], obs[1] = clip(self._accel[0], _A), clip(self._accel[1], _A)
        u, w = state.body_velocity()
        obs[2], obs[3] = clip(u, _V), clip(w, _V)
        if len(self.hazards):
            pseudo_lidar(x, y, heading, self.hazards, self.hazard_radius, max_dist=self.lidar_max_dist,
                         out=obs[4:4 + N_BINS])
        else:
            obs[4:4 + N_BINS] = 0.0
        obs[N_FEATURES] = clip(state.yaw_rate, _W)
        start = N_FEATURES + 1
        self._target(obs, start, x, y, heading, self.task.goal)
        if self.push:
            self._target(obs, start + N_BINS + 3, x, y, heading, self.task.box)
        return obs.astype(np.float32), obs[:N_FEATURES].copy()

    def _target(self, obs: np.ndarray, start: int, x: float, y: float, heading: float, where: np.ndarray) -> None:
        pseudo_lidar(x, y, heading, where[None, :], 0.0, max_dist=self.lidar_max_dist,
                     out=obs[start:start + N_BINS])
        obs[start + N_BINS:start + N_BINS + 3] = compass(x, y, heading, where)

    # --- scenes for tests and figures ---------------------------------------------------------
    def place(self, *, agent: tuple[float, float] | None = None, heading: float | None = None,
              velocity: tuple[float, float] | None = None, goal: tuple[float, float] | None = None,
              box: tuple[float, float] | None = None, hazards: Any | None = None):
        """Move robot, goal, box or hazards (after a reset); returns ``(observation, info)`` there.

        The robot stops (zero velocity and yaw rate, unless ``velocity`` is given in the world
        frame) and the reward's progress distances restart from the new positions.
        """
        state = self.state
        if agent is not None:
            state.x, state.y = float(agent[0]), float(agent[1])
        if heading is not None:
            state.heading = float(heading) % (2 * math.pi)
        state.vx, state.vy = (0.0, 0.0) if velocity is None else (float(velocity[0]), float(velocity[1]))
        state.yaw_rate = 0.0
        self._accel = (0.0, 0.0)
        if hazards is not None:
            self.hazards = np.asarray(hazards, dtype=np.float64).reshape(-1, 2)
        if box is not None and not self.push:
            raise DataError("only Push tasks have a box")
        self.task.reset(self.task.goal if goal is None else np.asarray(goal, dtype=np.float64),
                        (self.task.box if box is None else np.asarray(box, dtype=np.float64)) if self.push else None,
                        state)
        observation, features = self._observe()
        return observation, {"cost": self._cost(), "features": features, "goal_met": False,
                             "goals_reached": self.goals_reached}


def make_safenav(agent: str = "point", task: str = "goal", **kwargs: Any) -> SafeNavEnv:
    """The registry's factory: ``make_safenav("car", "push", max_steps=500)``."""
    return SafeNavEnv(agent, task, **kwargs)


__all__ = ["DEFAULT_MAX_STEPS", "FEATURE_NAMES", "SafeNavEnv", "make_safenav"]
