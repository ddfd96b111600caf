"""Three environments written as a user would, for ``benchmarks/plain_ppo_defaults.py`` and
``benchmarks/dnf_depth_cost.py`` (nobody tuned symlearn on them): a 1-D lander with discrete thrust, a Dict-observation robot that must go round a
forbidden disk, and a 3-D point with velocities whose speed limit is a violation. Each reports
``info["cost"]``; none names its features. ``lander_expert``, ``sorter_expert`` and ``arm_expert`` are
scripted demonstrators of the kind a user has: controllers with 5 % random thrusts or a little
noise, not perfect (a few landings are hard)."""
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Lander(gym.Env):
    """1-D lander: obs [height, velocity], Discrete(3) thrust. Fast near the ground is a violation."""

    def __init__(self, horizon=200):
        self.horizon = horizon
        self.observation_space = spaces.Box(np.array([0.0, -10.0], np.float32), np.array([12.0, 10.0], np.float32))
        self.action_space = spaces.Discrete(3)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.h = self.np_random.uniform(6.0, 10.0)
        self.v = self.np_random.uniform(-1.0, 0.0)
        self.t = 0
        return np.array([self.h, self.v], np.float32), {}

    def step(self, a):
        thrust = (0.0, 0.15, 0.3)[int(a)]
        self.v += -0.2 + thrust
        self.h = max(0.0, self.h + 0.1 * self.v * 5)
        self.t += 1
        cost = float(self.h < 2.0 and abs(self.v) > 1.5)
        reward = -0.01 * int(a)
        terminated = self.h <= 0.0
        if terminated:
            reward += 10.0 if abs(self.v) < 1.0 else -5.0
        return np.array([self.h, self.v], np.float32), reward, terminated, self.t >= self.horizon, {"cost": cost}


class Sorter(gym.Env):
    """Dict observation: {'pos': Box(2), 'carry': Discrete(2)}; a disk in the middle is forbidden."""

    def __init__(self, horizon=60):
        self.horizon = horizon
        self.observation_space = spaces.Dict({"pos": spaces.Box(-1, 1, (2,), np.float32), "carry": spaces.Discrete(2)})
        self.action_space = spaces.Box(-0.1, 0.1, (2,), np.float32)

    def _obs(self):
        return {"pos": self.p.astype(np.float32), "carry": int(self.carry)}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p = np.array([self.np_random.uniform(-0.9, -0.7), self.np_random.uniform(-0.9, -0.7)])
        self.carry = 0
        self.t = 0
        return self._obs(), {}

    def step(self, a):
        before = np.linalg.norm(self.p - (0.8, 0.8))
        self.p = np.clip(self.p + np.clip(a, -0.1, 0.1), -1, 1)
        self.t += 1
        after = np.linalg.norm(self.p - (0.8, 0.8))
        if after < 0.15:
            self.carry = 1
        cost = float(np.linalg.norm(self.p) < 0.35)
        return self._obs(), float(before - after), bool(after < 0.1), self.t >= self.horizon, {"cost": cost}


class Arm3(gym.Env):
    """3-D point with velocity: obs (6,) position+velocity, Box(3) accelerations; speed > 0.5 is a violation."""

    def __init__(self, horizon=80):
        self.horizon = horizon
        self.observation_space = spaces.Box(-np.inf, np.inf, (6,), np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (3,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x = self.np_random.uniform(-1, 1, 3)
        self.v = np.zeros(3)
        self.t = 0
        return np.concatenate([self.x, self.v]), {}

    def step(self, a):
        a = np.clip(a, -1, 1)
        self.v = 0.9 * self.v + 0.1 * a
        self.x = self.x + 0.1 * self.v
        self.t += 1
        dist = np.linalg.norm(self.x)
        cost = float(np.linalg.norm(self.v) > 0.5)
        return np.concatenate([self.x, self.v]), -dist, False, self.t >= self.horizon, {"cost": cost}


# scripted demonstrators (benchmarks/dnf_depth_cost.py records their demonstrations)
def lander_expert(seed=0):
    rng = np.random.default_rng(seed)
    def act(obs):
        h, v = float(obs[0]), float(obs[1])
        target = -max(0.4, 0.35 * h)
        a = 2 if v < target - 0.1 else (1 if v < target + 0.1 else 0)
        return int(a) if rng.random() > 0.05 else int(rng.integers(3))
    return act


def sorter_expert(seed=0):
    rng = np.random.default_rng(seed)
    def act(obs):
        p = np.asarray(obs["pos"], float)
        goal = np.array([0.8, 0.8])
        # go around the disk: first right along the bottom, then up
        way = np.array([0.8, -0.8]) if p[0] < 0.6 and p[1] < 0.0 else goal
        d = way - p
        step = np.clip(d, -0.1, 0.1) + rng.normal(0, 0.01, 2)
        return step.astype(np.float32)
    return act


def arm_expert(seed=0):
    rng = np.random.default_rng(seed)
    def act(obs):
        x, v = obs[:3], obs[3:]
        a = -2.0 * x - 3.0 * v
        return np.clip(a + rng.normal(0, 0.1, 3), -1, 1).astype(np.float32)
    return act


gym.register("Lander-v0", entry_point=Lander)
gym.register("Sorter-v0", entry_point=Sorter)
gym.register("Arm3-v0", entry_point=Arm3)
