"""The block tasks as a gymnasium environment for a pick-and-place policy on the top-down image.

Observation: the top-down image ``(size, size, 3)`` uint8 (default 48 px) with lighting jitter
and noise. Action: ``MultiDiscrete([size, size, size, size])`` = pick pixel ``(row, col)`` then
place pixel ``(row, col)`` on that image (:func:`~.render.pixel_to_table`); a pick where no free
block is, or a place off the table, leaves the scene as it was. Reward: 1 when every block is at
its goal (the task's full configuration; the episode terminates), else 0, i.e. the sparse
reward; a reward machine supplies the dense one. Episodes are truncated after ``max_moves``
(default: three per placement).

``info``: ``front`` (the front camera's frame of the new scene, what an inferred labeling reads),
``truth`` (the ground-truth proposition set), ``placement_error`` (mean distance of every block to
its final place, table units), ``moved`` (whether the action moved a block), ``positions``.
:meth:`RenderedBlocksEnv.expert_action` gives the scripted demonstrator's next action for an
ordering, to fill replay buffers with demonstrations.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from symlearn.envs.rendered_blocks.render import Lighting, front_view, pixel_to_table, table_to_pixel, top_down_view
from symlearn.envs.rendered_blocks.tasks import TASKS, TOLERANCE, BlockTask
from symlearn.errors import DataError


class RenderedBlocksEnv(gym.Env):
    metadata = {"render_modes": ["rgb_array"]}

    def __init__(self, task: str | BlockTask = "stack-2", size: int = 48, front_size: int = 64,
                 max_moves: int | None = None, lighting: Lighting = Lighting(), render_mode: str | None = None):
        if isinstance(task, str):
            if task not in TASKS:
                raise DataError(f"unknown block task {task!r}", hint="tasks: " + ", ".join(TASKS))
            task = TASKS[task]
        self.task = task
        self.size, self.front_size = int(size), int(front_size)
        self.max_moves = max_moves or 3 * len(task.placements)
        self.lighting = lighting
        self.render_mode = render_mode
        self.names = [name for name, _, _ in task.blocks]
        self.observation_space = gym.spaces.Box(0, 255, (self.size, self.size, 3), np.uint8)
        self.action_space = gym.spaces.MultiDiscrete([self.size] * 4)
        self._goal = len(task.configurations()) - 1

    def _observe(self):
        positions = self.world.positions()
        top = top_down_view(self.names, positions, size=self.size, lighting=self.lighting, rng=self.np_random)
        front = front_view(self.names, positions, size=self.front_size, lighting=self.lighting, rng=self.np_random)
        return top, {"front": front, "truth": self.task.truth_label(positions), "positions": positions,
                     "placement_error": self.task.placement_error(positions)}

    def reset(self, *, seed: int | None = None, options=None):
        super().reset(seed=seed)
        self.world = self.task.world()
        self.moves = 0
        top, info = self._observe()
        info["moved"] = False
        return top, info

    def step(self, action):
        action = np.asarray(action, dtype=int).reshape(4)
        if np.any(action < 0) or np.any(action >= self.size):
            raise DataError(f"action {action.tolist()} is outside the {self.size} x {self.size} image")
        pick = pixel_to_table(int(action[0]), int(action[1]), self.size)
        place = pixel_to_table(int(action[2]), int(action[3]), self.size)
        moved = self.world.pick_place(pick, place)
        self.moves += 1
        top, info = self._observe()
        info["moved"] = moved
        done = self.task.configuration_of(info["positions"]) == self._goal
        return top, float(done), bool(done), bool(self.moves >= self.max_moves and not done), info

    def render(self):
        return front_view(self.names, self.world.positions(), size=self.front_size)

    def expert_action(self, ordering) -> np.ndarray | None:
        """The scripted demonstrator's next action for ``ordering`` (None when all is done)."""
        for p in ordering:
            placement = self.task.placements[p]
            block = self.world.state[placement.block]
            goal = np.asarray(placement.goal, dtype=float)
            if np.linalg.norm(block[:2] - goal[:2]) < TOLERANCE / 2 and abs(block[2] - goal[2]) < 0.5:
                continue
            return np.array([*table_to_pixel(block[0], block[1], self.size),
                             *table_to_pixel(goal[0], goal[1], self.size)])
        return None


__all__ = ["RenderedBlocksEnv"]
