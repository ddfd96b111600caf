"""A user's sparse-reward grid (a benchmark task of benchmarks/multiplier_start.py): reward 1 only at the
goal, a wall of hazard cells (info["cost"] 1) across the shortest route with one gap at the top row, so
the safe route is a detour; 5 x 9 cells, 80 steps. ``wall_rows`` moves the wall's cells (rows of the
middle column; a shorter wall leaves a wider gap), ``step_reward`` charges every step that does not
reach the goal (the more usual design)."""
import gymnasium as gym
import numpy as np


class GapGrid(gym.Env):
    def __init__(self, rows=5, cols=9, horizon=80, wall_rows=None, step_reward=0.0):
        self.rows, self.cols, self.horizon, self.step_reward = rows, cols, horizon, float(step_reward)
        self.observation_space = gym.spaces.Box(0.0, 1.0, (2,), np.float32)
        self.action_space = gym.spaces.Discrete(4)
        wall = range(1, rows) if wall_rows is None else wall_rows   # the gap at the top row
        self.hazards = {(int(r), cols // 2) for r in wall}

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
        reward = 1.0 if goal else self.step_reward
        return self._obs(), reward, goal, self.t >= self.horizon, {"cost": float(self.pos in self.hazards)}


gym.register("GapGrid-v0", entry_point=GapGrid)  # as a user module registers its id
