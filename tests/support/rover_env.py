"""A user's rover, written for benchmarks/lagrangian_multiplier_grid.py after the defaults were chosen
(nobody tuned on it): position and velocity in 2-D (damped, accelerated by the action), a pond of
radius 0.45 at the origin to avoid (``info["cost"]`` 1 inside it), a target at (0.8, 0.8) reached
from (-0.8, -0.8) (+5, the episode ends), -0.01 x the distance per step, 150 steps at most.
``expert`` goes around the pond by the bottom-right corner (return about 4.5, 41 steps, no cost).
Registers ``Rover-v0`` on import."""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

POND = np.array([0.0, 0.0]); POND_R = 0.45
TARGET = np.array([0.8, 0.8])

class Rover(gym.Env):
    def __init__(self, max_steps=150):
        self.observation_space = spaces.Box(-2, 2, (4,), np.float32)
        self.action_space = spaces.Box(-1, 1, (2,), np.float32)
        self.max_steps = max_steps
    def _obs(self):
        return np.concatenate([self.p, self.v]).astype(np.float32)
    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.p = np.array([-0.8, -0.8]) + self.np_random.uniform(-0.1, 0.1, 2)
        self.v = np.zeros(2); self.t = 0
        return self._obs(), {"cost": 0.0}
    def step(self, a):
        a = np.clip(np.asarray(a, float), -1, 1)
        self.v = 0.8 * self.v + 0.02 * a
        self.p = np.clip(self.p + self.v, -1.5, 1.5)
        self.t += 1
        d = np.linalg.norm(self.p - TARGET)
        reached = d < 0.1
        reward = -0.01 * d + (5.0 if reached else 0.0)
        cost = float(np.linalg.norm(self.p - POND) < POND_R)
        return self._obs(), reward, bool(reached), self.t >= self.max_steps, {"cost": cost}

def expert(obs):
    p, v = obs[:2], obs[2:]
    # waypoint: go via the bottom-right corner around the pond
    wp = np.array([0.8, -0.8]) if p[0] < 0.6 else TARGET
    return np.clip(3.0 * (wp - p) - 6.0 * v, -1, 1)

gym.register("Rover-v0", entry_point=Rover)
