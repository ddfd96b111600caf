"""A user's sparse-reward grid (a benchmark task of benchmarks/multiplier_start.py): reward 1 only at the
goal, a wall of hazard cells (info["cost"] 1) across the shortest route with one gap at the top row, so
the safe route is a detour; 5 x 9 cells, 80 steps."""
import gymnasium as gym
import numpy as np


class GapGrid(gym.Env):
    def __init__(self, rows=5, cols=9, horizon=80):
        self.rows, self.cols, self.horizon = rows, cols, horizon
        self.observation_space = gym.spaces.Box(0.0, 1.0, (2,), np.float32)
        self.action_space = gym.spaces.Discrete(4)
        self.hazards = {(r, 4) for r in range(rows) if r != 0}   # the gap at the top row

    def _obs(self):
        return np.array([self.pos[0] / (self.rows - 1), self.pos[1] / (self.cols - 1)], dtype=np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos, self.t = (self.rows - 1, 0), 0
        return self._obs(), {}

    def step(self, action):
        dr, dc = [(1, 0), (-1, 0), (0, 1), (0, -1)][int(action)]
        self.pos = (min(max(self.pos[0] + dr, 0), self.rows - 1), min(max(self.pos[1] + dc, 0), self.cols - 1))
        self.t += 1
        goal = self.pos == (self.rows - 1, self.cols - 1)
        return self._obs(), float(goal), goal, self.t >= self.horizon, {"cost": float(self.pos in self.hazards)}


gym.register("GapGrid-v0", entry_point=GapGrid)  # as a user module registers its id
