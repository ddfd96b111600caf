"""The thesis' toy navigation task (section 4.3.1, Figure 4.1): a point in the unit square.

The agent starts at ``(0.1, 0.1)`` and must reach ``(0.9, 0.9)``. The safe set is the
L-shaped union of two closed rectangles,

    ``[0.1, 0.7] x [0.1, 0.3]  U  [0.7, 0.9] x [0.1, 0.9]``

(along the bottom, then up the right-hand side); everything else, in particular the direct
diagonal, is unsafe. The features are the position itself (``x``, ``y``: the thesis'
``phi^0``, ``phi^1``), so the DNF the thesis extracts from its expert tree is a formula over
``x`` and ``y``.

* **Action**: a velocity ``(dx, dy)`` in ``Box(-1, 1, (2,))``, clipped per entry and scaled by
  ``speed`` (0.05 per step); the position is clipped to the unit square.
* **Observation**: the position, ``float32``; ``info["features"]`` the same as ``float64``.
* **Reward**: progress to the goal (decrease of the distance to ``(0.9, 0.9)``), plus
  ``goal_reward`` (1.0, as Safety-Gym's goal bonus) on the step that reaches it. Progress alone
  pays almost nothing for *finishing*: an agent hovering just outside the goal circle earns all
  but the last few hundredths, so under a cost (which the last steps near the learned border
  may risk) hovering was as good as arriving. ``goal_reward=0`` gives the progress-only reward.
* **Cost**: ``info["cost"]`` = 1.0 when the new position lies outside the safe set.
* **Termination** within ``goal_radius`` (0.05) of the goal; truncation after ``max_steps``.

:func:`expert_demonstrations` follows the safe L-shaped route with a little noise and never
leaves the safe set.

>>> env = ToyNavigationEnv()
>>> observation, info = env.reset(seed=0)
>>> observation.tolist(), info["cost"]
([0.10000000149011612, 0.10000000149011612], 0.0)
>>> is_safe(0.5, 0.5), is_safe(0.8, 0.5), is_safe(0.4, 0.2)
(False, True, True)
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError

START = (0.1, 0.1)
GOAL = (0.9, 0.9)
#: The safe set: a union of closed rectangles ``(x_low, x_high, y_low, y_high)``.
SAFE_RECTANGLES: tuple[tuple[float, float, float, float], ...] = ((0.1, 0.7, 0.1, 0.3), (0.7, 0.9, 0.1, 0.9))
FEATURE_NAMES = ("x", "y")
#: The unsafe set as the DNF text of :mod:`symlearn.logic.dnf` (outside both rectangles).
UNSAFE_DNF = "\n".join(["x < 0.1", "x > 0.9", "y < 0.1", "y > 0.9", "x < 0.7 & y > 0.3"])


def is_safe(x: float, y: float) -> bool:
    """Whether ``(x, y)`` lies in the safe set (boundaries included)."""
    return any(x0 <= x <= x1 and y0 <= y <= y1 for x0, x1, y0, y1 in SAFE_RECTANGLES)


class ToyNavigationEnv(gym.Env):
    """``ToyNavigationEnv(speed=0.05, goal_radius=0.05, max_steps=200, goal_reward=1.0, render_mode=None)``."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, speed: float = 0.05, goal_radius: float = 0.05, max_steps: int = 200,
                 render_mode: str | None = None, goal_reward: float = 1.0) -> None:
        if not 0 < speed <= 1 or goal_radius <= 0 or max_steps < 1:
            raise DataError(f"need 0 < speed <= 1, goal_radius > 0, max_steps >= 1; got {speed}, {goal_radius}, "
                            f"{max_steps}")
        if not math.isfinite(goal_reward):
            raise DataError(f"goal_reward must be finite, got {goal_reward}")
        self.goal_reward = float(goal_reward)
        if render_mode not in (None, "rgb_array"):
            raise DataError(f"unknown render mode {render_mode!r}", hint="use 'rgb_array' or None")
        self.speed, self.goal_radius, self.max_steps = float(speed), float(goal_radius), int(max_steps)
        self.render_mode = render_mode
        self.observation_space = spaces.Box(0.0, 1.0, shape=(2,), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.feature_names = FEATURE_NAMES
        self.position = np.array(START, dtype=np.float64)
        self.steps = 0

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self.position = np.array(START, dtype=np.float64)
        self.steps = 0
        return self._observation(), self._info()

    def next_position(self, action: Any) -> np.ndarray:
        """Where ``action`` takes the agent from its current position (no side effect)."""
        move = np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1.0, 1.0) * self.speed
        return np.clip(self.position + move, 0.0, 1.0)

    def step(self, action):
        before = self.distance()
        self.position = self.next_position(action)
        self.steps += 1
        after = self.distance()
        terminated = after <= self.goal_radius
        reward = before - after + (self.goal_reward if terminated else 0.0)
        return self._observation(), reward, terminated, self.steps >= self.max_steps, self._info()

    def distance(self) -> float:
        return math.hypot(self.position[0] - GOAL[0], self.position[1] - GOAL[1])

    def _observation(self) -> np.ndarray:
        return self.position.astype(np.float32)

    def _info(self) -> dict[str, Any]:
        return {"cost": 0.0 if is_safe(*self.position) else 1.0, "features": self.position.copy()}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        size = 128
        centres = (np.arange(size) + 0.5) / size
        x, y = centres[None, :], centres[::-1, None]
        image = np.empty((size, size, 3), dtype=np.uint8)
        image[:] = (230, 120, 120)  # unsafe
        for x0, x1, y0, y1 in SAFE_RECTANGLES:
            image[(x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)] = (235, 235, 235)
        image[(x - GOAL[0]) ** 2 + (y - GOAL[1]) ** 2 <= self.goal_radius ** 2] = (60, 190, 90)
        image[(x - self.position[0]) ** 2 + (y - self.position[1]) ** 2 <= 0.02 ** 2] = (40, 40, 40)
        return image


# --- the expert -------------------------------------------------------------------------------

def _inside(point: np.ndarray, rectangle: tuple[float, float, float, float]) -> bool:
    x0, x1, y0, y1 = rectangle
    return x0 <= point[0] <= x1 and y0 <= point[1] <= y1


def expert_demonstrations(n: int = 10, seed: int | None = 0, noise: float = 0.1, *,
                          env: ToyNavigationEnv | None = None) -> Demonstrations:
    """``n`` expert episodes along the safe L-shaped route, as vector-state demonstrations.

    The expert drives to a corner waypoint near ``(0.8, 0.2)`` (jittered per episode by about
    ``noise / 2``, kept inside ``[0.72, 0.88] x [0.12, 0.28]``), then up to ``(0.88, 0.88)``
    (just inside the goal circle). Each leg stays inside one convex rectangle of the safe set:
    ``[0.1, 0.9] x [0.1, 0.3]`` for the first, ``[0.7, 0.9] x [0.1, 0.9]`` for the second.
    Every action gets Gaussian noise of standard deviation ``noise``; a noisy action whose step
    would leave the current rectangle is replaced by the clean one, which moves straight toward
    the waypoint (so, by convexity, stays inside). Hence no state is ever unsafe.

    States are the positions (``(T, 2)`` floats), actions the 2-D velocities, rewards the
    environment's; ``info`` holds the episode seed and whether it reached the goal.
    """
    if n < 1:
        raise DataError(f"n must be at least 1, got {n}")
    if noise < 0:
        raise DataError(f"noise must be >= 0, got {noise}")
    env = env or ToyNavigationEnv()
    rng = np.random.default_rng(seed)
    legs = ((0.1, 0.9, 0.1, 0.3), SAFE_RECTANGLES[1])
    trajectories = []
    for episode in range(n):
        episode_seed = int(rng.integers(2**31))
        corner = np.clip(np.array([0.8, 0.2]) + rng.normal(0.0, noise / 2, size=2), [0.72, 0.12], [0.88, 0.28])
        waypoints = (corner, np.array([0.88, 0.88]))
        observation, info = env.reset(seed=episode_seed)
        states, actions, rewards = [info["features"]], [], []
        leg, done, terminated = 0, False, False
        while not done:
            position = env.position
            if leg == 0 and _inside(position, legs[1]) and np.hypot(*(corner - position)) < 0.02:
                leg = 1
            heading = waypoints[leg] - position
            length = float(np.hypot(*heading))
            clean = heading / env.speed if length <= env.speed else heading / length
            action = clean + rng.normal(0.0, noise, size=2) if noise > 0 else clean
            if not _inside(env.next_position(action), legs[leg]):
                action = clean
            action = np.clip(action, -1.0, 1.0)
            observation, reward, terminated, truncated, info = env.step(action)
            states.append(info["features"])
            actions.append(action)
            rewards.append(reward)
            done = terminated or truncated
        trajectories.append(Trajectory(np.array(states), np.array(actions), rewards,
                                       info={"seed": episode_seed, "reached_goal": bool(terminated)}))
    metadata = {"env": "symlearn/toy-navigation-v0", "expert": "scripted L-route", "seed": seed, "n_episodes": n,
                "noise": noise, "features": list(FEATURE_NAMES)}
    return Demonstrations(trajectories, metadata=metadata)


def make_toy_navigation(**kwargs: Any) -> ToyNavigationEnv:
    """The registry's factory."""
    return ToyNavigationEnv(**kwargs)


__all__ = ["FEATURE_NAMES", "GOAL", "SAFE_RECTANGLES", "START", "UNSAFE_DNF", "ToyNavigationEnv",
           "expert_demonstrations", "is_safe", "make_toy_navigation"]
