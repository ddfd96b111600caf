"""The guide's own environments (docs/GUIDE.md): a point robot on the plane, written as a user would.

``GuideRobot-v0``: the robot starts on the left of the square [-1, 1]^2 and is paid for every bit
of progress to the right, but the floor beyond ``x > wall`` is off limits: entering it is a
violation, reported as ``info["cost"] = 1.0`` (the safety-gymnasium convention). Observation and
``info["features"]`` are the position; ``feature_names`` names the two columns.

``GuideTour-v0``: the same robot has two stations to visit, the charger (top left) and the dock
(top right), in any order; the reward is 1 on each first arrival. ``camera=True`` turns the
observation into a 24 x 24 grayscale picture of the floor (for reward machines from video). It
reports no ground-truth cost, so ``info`` has no ``"cost"`` key (n/a, not 0).

``careful_expert`` and ``tour_expert`` are scripted demonstrators; importing the module registers
both ids with gymnasium, which is what ``--env guide_robot:GuideRobot-v0`` relies on.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

STEP = 0.1  # largest move per axis and step
CHARGER = np.array([-0.5, 0.3])
DOCK = np.array([0.5, 0.3])
STATION_RADIUS = 0.1
PIXELS = 24


class GuideRobot(gym.Env):
    """A point robot paid for moving right; the region x > wall is forbidden."""

    feature_names = ("x", "y")  # the columns of info["features"] (DNF rules read these)
    observation_names = ("x", "y")  # the observation's entries (`--cost-inputs x,y` reads these)

    def __init__(self, wall: float = 0.5, horizon: int = 40):
        self.wall, self.horizon = float(wall), int(horizon)
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Box(-STEP, STEP, (2,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.position = np.array([self.np_random.uniform(-0.9, -0.6), self.np_random.uniform(-0.9, 0.9)])
        self.t = 0
        return self.position.astype(np.float32), {"features": self.position.copy()}

    def step(self, action):
        before = self.position[0]
        self.position = np.clip(self.position + np.clip(action, -STEP, STEP), -1.0, 1.0)
        self.t += 1
        info = {"cost": float(self.position[0] > self.wall), "features": self.position.copy()}
        reward = float(self.position[0] - before)
        return self.position.astype(np.float32), reward, False, self.t >= self.horizon, info


def careful_expert(wall: float = 0.5, seed: int = 0):
    """Heads right, stops short of the wall and drifts up and down there: safe, not timid."""
    rng = np.random.default_rng(seed)
    stop = wall - 0.1  # where it halts: a margin of one step before the wall

    def act(observation):
        x = float(observation[0])
        dx = np.clip(stop - x, -STEP, STEP) + rng.uniform(-0.01, 0.01)
        return np.array([dx, rng.uniform(-STEP, STEP)], dtype=np.float32)

    return act


class GuideTour(gym.Env):
    """Visit the charger and the dock (either order); ``camera=True``: observations are pictures."""

    feature_names = ("x", "y")

    def __init__(self, horizon: int = 60, camera: bool = False):
        self.horizon, self.camera = int(horizon), bool(camera)
        self.observation_space = (spaces.Box(0, 255, (PIXELS, PIXELS), np.uint8) if self.camera
                                  else spaces.Box(-1.0, 1.0, (2,), np.float32))
        self.action_space = spaces.Box(-STEP, STEP, (2,), np.float32)

    def _observe(self):
        return render(self.position) if self.camera else self.position.astype(np.float32)

    def _info(self):
        return {"features": self.position.copy(), "visited": sorted(self.visited)}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.position = np.array([0.0, -0.3]) + self.np_random.uniform(-0.05, 0.05, 2)
        self.t, self.visited = 0, set()
        return self._observe(), self._info()

    def step(self, action):
        self.position = np.clip(self.position + np.clip(action, -STEP, STEP), -1.0, 1.0)
        self.t += 1
        reward = 0.0
        for name, where in (("charger", CHARGER), ("dock", DOCK)):
            if name not in self.visited and np.linalg.norm(self.position - where) < STATION_RADIUS:
                self.visited.add(name)
                reward += 1.0
        return self._observe(), reward, False, self.t >= self.horizon, self._info()


def render(position) -> np.ndarray:
    """A 24 x 24 top view: the two stations as faint squares, the robot as a bright blob."""
    axis = (np.arange(PIXELS) + 0.5) / PIXELS * 2 - 1
    xx, yy = np.meshgrid(axis, -axis)
    image = np.zeros((PIXELS, PIXELS))
    for where in (CHARGER, DOCK):
        image[(abs(xx - where[0]) < 0.1) & (abs(yy - where[1]) < 0.1)] = 60.0
    image += 195.0 * np.exp(-((xx - position[0]) ** 2 + (yy - position[1]) ** 2) / (2 * 0.2 ** 2))
    return np.clip(image, 0, 255).astype(np.uint8)


def tour_expert(env, prefer_charger: float = 0.8, seed: int = 0, pause: int = 8):
    """Waits at the start, visits both stations (charger first with probability ``prefer_charger``),
    pausing at each, then parks at the last. Reads the robot's position from ``env``, so it works
    with ``camera=True`` too."""
    rng = np.random.default_rng(seed)
    plan: list = []

    def act(_observation):
        robot = env.unwrapped
        if robot.t == 0:  # a new episode: choose this episode's order
            stations = [CHARGER, DOCK] if rng.random() < prefer_charger else [DOCK, CHARGER]
            plan[:] = [("wait", None, 5)] + [item for s in stations for item in (("go", s, 0), ("wait", None, pause))]
        jitter = rng.uniform(-0.004, 0.004, 2)
        while plan:
            kind, target, left = plan[0]
            if kind == "go":
                delta = target - robot.position
                if np.linalg.norm(delta) < 0.02:
                    plan.pop(0)
                    continue
                return np.clip(delta, -STEP, STEP).astype(np.float32)
            if left > 0:
                plan[0] = (kind, target, left - 1)
                return jitter.astype(np.float32)
            plan.pop(0)
        return jitter.astype(np.float32)  # parked at the last station

    return act


gym.register("GuideRobot-v0", entry_point=GuideRobot)
gym.register("GuideTour-v0", entry_point=GuideTour)
