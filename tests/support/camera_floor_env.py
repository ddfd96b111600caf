"""A user's camera environment, as a module source a test drops into a folder of its own: a
``(16, 16, 3)`` uint8 picture of a white square on a blue floor, moved by ``Discrete(5)``
actions (stay, right, down, left, up); reaching the bottom-right corner ends the episode. Its
768 pixels are more candidate inputs than a neural cost's input selection can eliminate one at a
time. ``waiting_expert()`` waits 5 steps, drives right along the top, waits 6 steps in the top
right corner, then drives down."""

from __future__ import annotations

CAMERA_FLOOR = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class CameraFloor(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(0, 255, (16, 16, 3), np.uint8)
        self.action_space = spaces.Discrete(5)

    def _picture(self):
        picture = np.zeros((16, 16, 3), np.uint8)
        picture[..., 2] = 40
        row, column = self.position
        picture[row:row + 2, column:column + 2] = 255
        return picture

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.position = [0, 0]
        return self._picture(), {}

    def step(self, action):
        dr, dc = [(0, 0), (0, 1), (1, 0), (0, -1), (-1, 0)][int(action)]
        self.position = [min(max(self.position[0] + dr, 0), 14), min(max(self.position[1] + dc, 0), 14)]
        done = self.position == [14, 14]
        return self._picture(), float(done), done, False, {}


gym.register("CameraFloor-v0", entry_point=CameraFloor, max_episode_steps=60)
'''


def waiting_expert():
    """A fresh policy (picture -> action) for one episode; see the module doc."""
    import numpy as np

    state = {"t": 0, "waited": 0}

    def act(picture):
        state["t"] += 1
        if state["t"] <= 5:
            return 0
        rows, columns = np.nonzero(picture[..., 0] == 255)
        row, column = rows.min(), columns.min()
        if (row, column) == (0, 14) and state["waited"] < 6:
            state["waited"] += 1
            return 0
        return 1 if column < 14 else 2 if row < 14 else 0

    return act
