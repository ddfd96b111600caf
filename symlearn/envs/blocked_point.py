"""BlockedPoint: a point mass paid for moving along x, blocked behind a wall at ``x = wall``.

The numpy, CPU-sized stand-in for the thesis' blocked MuJoCo tasks (section 2.5.2, after Malik
et al. 2021 and Liu et al. 2023): the agent is paid for distance travelled along ``x`` in either
direction, moving *toward* the wall is easier (as the "easy" direction of the blocked robots),
and the ground-truth constraint forbids the side of the wall away from the start. An agent that
ignores the constraint runs into the forbidden region within a few dozen steps; the constrained
optimum runs the other way at the slower speed.

The thesis gives no numbers for such an environment; ours are:

* **State** ``(x, y, vx, vy)``; the observation is the state as ``float32`` (so it includes the
  ``x`` position the constraint is about); ``info["features"]`` is the position ``(x, y)``.
* **Start**: ``x`` uniform between ``wall + 0.5`` and ``wall + 3.5`` (on the start side, i.e.
  ``wall - 3.5 .. wall - 0.5`` when the wall lies at positive ``x``), ``y`` uniform in
  ``[-0.5, 0.5]``, at rest. Starts that spread up to the wall let demonstrations show how close
  to it an expert may go: with a single start far from the wall, every state between the start
  and the wall would look as unvisited (hence as forbidden) to a constraint learner as the
  forbidden side itself.
* **Action** ``(ax, ay)`` in ``Box(-1, 1, (2,))`` (clipped). Velocity is damped toward the
  commanded one: ``v <- damping * v + (1 - damping) * max_speed * gain * a`` with ``gain`` 1
  toward the wall and ``away_gain`` (0.6) away from it along ``x`` (1 along ``y``); then
  ``p <- p + v``, positions clipped to ``+-arena``.
* **Reward** ``|x' - x| / max_speed`` per step (at most 1 toward the wall, ``away_gain`` away
  from it).
* **Cost** ``info["cost"]`` = 1.0 when the reached position is beyond the wall (``x < wall``
  for a wall left of the start, ``x > wall`` for one to its right), else 0.0; ``info["violation"]``
  the same as a bool.
* No termination (a violation does not end the episode: the violation rate per step is the
  measure); truncation after ``max_steps`` (100).

:func:`expert_demonstrations` is the constrained optimum, scripted: full speed away from the
wall with a little Gaussian noise; it never crosses the wall (it never moves toward it).

>>> env = BlockedPoint(wall=-3.0)
>>> obs, info = env.reset(seed=0)
>>> bool(-2.5 <= obs[0] <= 0.5), info["cost"]
(True, 0.0)
>>> env.is_unsafe(np.array([-3.5, 0.0])), env.is_unsafe(np.array([-2.5, 0.0]))
(True, False)
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError

FEATURE_NAMES = ("x", "y")
OBSERVATION_NAMES = ("x", "y", "vx", "vy")


#: the largest arena half-width of the point environments: observations are float32, which holds
#: positions this large to ~0.06 (an arena of 1e308 overflowed the observation space's bounds)
MAX_ARENA = 1e6
#: the longest episode the bundled environments accept (max_steps): 9e18 was accepted, and an
#: episode that never ends ran a recording to its own step cap, 33 s, instead of a refusal
MAX_EPISODE_STEPS = 1_000_000
#: what an episode length must be, as the environments' refusals say it
EPISODE_STEPS_RULE = f"a whole number in [1, {MAX_EPISODE_STEPS:,}]"


def episode_steps_ok(value: object) -> bool:
    """Whether ``value`` is a ``max_steps`` the bundled environments accept: a whole number in
    ``[1, MAX_EPISODE_STEPS]`` (an int, a float such as ``1e3`` from JSON, or a numpy number)."""
    return isinstance(value, numbers.Real) and 1 <= value <= MAX_EPISODE_STEPS and value == int(value)


def point_spaces(arena: float, max_speed: float) -> tuple[spaces.Box, spaces.Box]:
    """The observation ``(x, y, vx, vy)`` and action spaces of the point environments (BlockedPoint
    and PointCircle share them, so a cost learned in one loads in the other)."""
    high = np.array([arena, arena, max_speed, max_speed], dtype=np.float32)
    return spaces.Box(-high, high, dtype=np.float32), spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)


def beyond_wall(positions: np.ndarray, wall: float) -> np.ndarray | bool:
    """Whether positions (``(..., >=1)``, ``x`` first) lie beyond the wall at ``x = wall`` (the
    forbidden side is ``x < wall`` for ``wall <= 0``, else ``x > wall``); vectorised."""
    x = np.asarray(positions, dtype=np.float64)[..., 0]
    unsafe = x < wall if wall <= 0 else x > wall
    return bool(unsafe) if np.ndim(unsafe) == 0 else unsafe
START_OFFSETS = (0.5, 3.5)  # the start's distance from the wall: uniform in this range
START_Y = 0.5  # |y| at the start at most this


class BlockedPoint(gym.Env):
    """``BlockedPoint(wall=-3.0, max_speed=0.15, away_gain=0.6, damping=0.5, max_steps=100, arena=30.0)``."""

    metadata = {"render_modes": []}

    def __init__(self, wall: float = -3.0, max_speed: float = 0.15, away_gain: float = 0.6, damping: float = 0.5,
                 max_steps: int = 100, arena: float = 30.0) -> None:
        checks = [("wall", math.isfinite(wall) and abs(wall) < arena - START_OFFSETS[1], f"finite, |wall| < "
                   f"arena - {START_OFFSETS[1]}"),
                  ("max_speed", 0 < max_speed <= 1, "in (0, 1]"), ("away_gain", 0 < away_gain <= 1, "in (0, 1]"),
                  ("damping", 0 <= damping < 1, "in [0, 1)"),
                  ("max_steps", episode_steps_ok(max_steps), EPISODE_STEPS_RULE),
                  ("arena", math.isfinite(arena) and START_OFFSETS[1] < arena <= MAX_ARENA,
                   f"in ({START_OFFSETS[1]}, {MAX_ARENA:g}]")]
        for name, ok, need in checks:
            if not ok:
                raise DataError(f"BlockedPoint: {name} must be {need}, got {locals()[name]!r}")
        self.wall, self.max_speed, self.away_gain = float(wall), float(max_speed), float(away_gain)
        self.damping, self.max_steps, self.arena = float(damping), int(max_steps), float(arena)
        # the forbidden side: -1 when the wall is left of the start region (x < wall forbidden)
        self.side = -1.0 if self.wall <= 0 else 1.0
        self.observation_space, self.action_space = point_spaces(arena, max_speed)
        self.feature_names = FEATURE_NAMES
        self.observation_names = OBSERVATION_NAMES
        self.state = np.zeros(4)
        self.steps = 0

    # --- ground truth --------------------------------------------------------------------------

    def is_unsafe(self, positions: np.ndarray) -> np.ndarray | bool:
        """Whether positions (``(..., >=1)``, ``x`` first) lie beyond the wall; vectorised."""
        return beyond_wall(positions, self.wall)

    def start_box(self) -> tuple[np.ndarray, np.ndarray]:
        """The box ``(low, high)`` of start observations."""
        near, far = START_OFFSETS
        x_low, x_high = sorted((self.wall - self.side * near, self.wall - self.side * far))
        return np.array([x_low, -START_Y, 0.0, 0.0]), np.array([x_high, START_Y, 0.0, 0.0])

    # --- gymnasium -----------------------------------------------------------------------------

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        low, high = self.start_box()
        self.state = self.np_random.uniform(low, high)
        self.steps = 0
        return self.state.astype(np.float32), self._info()

    def step(self, action):
        a = np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1.0, 1.0)
        x_before = self.state[0]
        gain_x = 1.0 if a[0] * self.side > 0 else self.away_gain
        command = self.max_speed * np.array([gain_x * a[0], a[1]])
        velocity = self.damping * self.state[2:] + (1.0 - self.damping) * command
        position = np.clip(self.state[:2] + velocity, -self.arena, self.arena)
        self.state = np.concatenate([position, velocity])
        self.steps += 1
        reward = abs(position[0] - x_before) / self.max_speed
        return self.state.astype(np.float32), float(reward), False, self.steps >= self.max_steps, self._info()

    def _info(self) -> dict[str, Any]:
        unsafe = self.is_unsafe(self.state[:2])
        return {"cost": 1.0 if unsafe else 0.0, "violation": unsafe, "features": self.state[:2].copy()}


# --- the expert -------------------------------------------------------------------------------

def expert_demonstrations(n: int = 10, seed: int | None = 0, noise: float = 0.1, *,
                          env: BlockedPoint | None = None) -> Demonstrations:
    """``n`` episodes of the scripted constrained optimum: full speed away from the wall, with
    Gaussian action noise of standard deviation ``noise`` (clipped to the action box).

    States are the observations ``(T + 1, 4)`` (the reset one, then every state reached),
    actions ``(T, 2)``, rewards the environment's; ``info`` holds the episode seed and the
    number of violations (always 0: the expert never moves toward the wall).
    """
    if n < 1:
        raise DataError(f"n must be at least 1, got {n}")
    if not noise >= 0:
        raise DataError(f"noise must be >= 0, got {noise}")
    env = env or BlockedPoint()
    rng = np.random.default_rng(seed)
    away = np.array([-env.side, 0.0])
    trajectories = []
    for _ in range(n):
        episode_seed = int(rng.integers(2**31))
        obs, _ = env.reset(seed=episode_seed)
        states, actions, rewards, violations = [obs], [], [], 0
        done = False
        while not done:
            action = np.clip(away + rng.normal(0.0, noise, size=2), -1.0, 1.0)
            action[0] = away[0] * max(abs(action[0]), 0.0)  # noise never turns it toward the wall
            obs, reward, terminated, truncated, info = env.step(action)
            states.append(obs)
            actions.append(action)
            rewards.append(reward)
            violations += int(info["violation"])
            done = terminated or truncated
        trajectories.append(Trajectory(np.array(states), np.array(actions), rewards,
                                       info={"seed": episode_seed, "violations": violations}))
    metadata = {"env": "symlearn/blocked-point-v0", "expert": "scripted: full speed away from the wall",
                "seed": seed, "n_episodes": n, "noise": noise, "wall": env.wall,
                "observation_names": list(OBSERVATION_NAMES)}
    return Demonstrations(trajectories, metadata=metadata)


__all__ = ["FEATURE_NAMES", "OBSERVATION_NAMES", "BlockedPoint", "expert_demonstrations"]
