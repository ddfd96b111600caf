"""PointCircle: the kinematic point of the thesis' transfer experiment (section 2.5.4, Fig. 2.4).

The thesis (after Malik et al. 2021, who took the task from Achiam et al.'s CPO) transfers a
cost learned for one agent to "the point agent, whose reward encourages it to move
counterclockwise in a circle at a distance of 10 units from its initial location". The thesis
gives no more; ours is the CPO reward on a kinematic point, with the constraint of the source
task (a wall at ``x = wall``, -3 by default as in the blocked robots), so that a cost learned on
:class:`~symlearn.envs.blocked_point.BlockedPoint` (whose observation has the same layout) can
train an agent here unchanged:

* **State/observation** ``(x, y, vx, vy)`` as ``float32``, the same names and order as
  BlockedPoint's; ``(vx, vy)`` is the last step's displacement. ``info["features"]`` = ``(x, y)``.
* **Start** at the origin (``+-0.1`` uniform jitter), at rest.
* **Action** a velocity ``(ax, ay)`` in ``Box(-1, 1, (2,))`` (clipped), times ``max_speed``
  (0.5): kinematic, no inertia.
* **Reward** ``(-y * vx + x * vy) / (1 + | |p| - radius |) / radius``: CPO's circle reward (the
  angular momentum of the step, damped off the circle), divided by ``radius`` so that running
  the circle at full speed earns about ``max_speed`` per step.
* **Cost** ``info["cost"]`` = 1.0 when the reached position is beyond the wall (``x < wall``
  for ``wall <= 0``, else ``x > wall``); ``info["violation"]`` the same as a bool. The circle
  of radius 10 crosses ``x = -3``, so the unconstrained optimum violates on about 40 % of its
  steps once it runs the circle.
* No termination; truncation after ``max_steps`` (200).

>>> env = PointCircle()
>>> obs, info = env.reset(seed=0)
>>> obs.shape, info["cost"]
((4,), 0.0)
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

# BlockedPoint's observation layout, names and wall test: a cost learned there reads the same here
from symlearn.envs.blocked_point import (EPISODE_STEPS_RULE, FEATURE_NAMES, MAX_ARENA, OBSERVATION_NAMES, beyond_wall,
                                         episode_steps_ok, point_spaces)
from symlearn.errors import DataError

START_JITTER = 0.1


class PointCircle(gym.Env):
    """``PointCircle(radius=10.0, wall=-3.0, max_speed=0.5, max_steps=200, arena=30.0)``."""

    metadata = {"render_modes": []}

    def __init__(self, radius: float = 10.0, wall: float = -3.0, max_speed: float = 0.5, max_steps: int = 200,
                 arena: float = 30.0) -> None:
        checks = [("radius", math.isfinite(radius) and 0 < radius < arena, "in (0, arena)"),
                  ("wall", math.isfinite(wall) and START_JITTER < abs(wall) < arena, f"finite, {START_JITTER} < "
                   "|wall| < arena"),
                  ("max_speed", math.isfinite(max_speed) and max_speed > 0, "> 0"),
                  ("max_steps", episode_steps_ok(max_steps), EPISODE_STEPS_RULE),
                  ("arena", math.isfinite(arena) and 1 < arena <= MAX_ARENA, f"in (1, {MAX_ARENA:g}]")]
        for name, ok, need in checks:
            if not ok:
                raise DataError(f"PointCircle: {name} must be {need}, got {locals()[name]!r}")
        self.radius, self.wall, self.max_speed = float(radius), float(wall), float(max_speed)
        self.max_steps, self.arena = int(max_steps), float(arena)
        self.observation_space, self.action_space = point_spaces(arena, max_speed)
        self.feature_names = FEATURE_NAMES
        self.observation_names = OBSERVATION_NAMES
        self.state = np.zeros(4)
        self.steps = 0

    def is_unsafe(self, positions: np.ndarray) -> np.ndarray | bool:
        """Whether positions (``(..., >=1)``, ``x`` first) lie beyond the wall; vectorised."""
        return beyond_wall(positions, self.wall)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self.state = np.concatenate([self.np_random.uniform(-START_JITTER, START_JITTER, 2), np.zeros(2)])
        self.steps = 0
        return self.state.astype(np.float32), self._info()

    def step(self, action):
        a = np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1.0, 1.0)
        x, y = self.state[:2]
        new = np.clip(self.state[:2] + self.max_speed * a, -self.arena, self.arena)
        vx, vy = new - self.state[:2]
        self.state = np.array([new[0], new[1], vx, vy])
        self.steps += 1
        reward = (-y * vx + x * vy) / (1.0 + abs(math.hypot(*new) - self.radius)) / self.radius
        return self.state.astype(np.float32), float(reward), False, self.steps >= self.max_steps, self._info()

    def _info(self) -> dict[str, Any]:
        unsafe = self.is_unsafe(self.state[:2])
        return {"cost": 1.0 if unsafe else 0.0, "violation": unsafe, "features": self.state[:2].copy()}


__all__ = ["FEATURE_NAMES", "OBSERVATION_NAMES", "PointCircle"]
