"""MiniGrid worlds for the specification-learning tests: a scripted breadth-first demonstrator,
DoorKey's labeling, and a room with two tiles that can be visited in either order.

Importing this module registers ``TwoTileRoom-v0`` (reached from the CLI as
``--env tests.support.minigrid_tasks:TwoTileRoom-v0``): a 7x7 MiniGrid room, fully observed
(the observation is the grid's encoding, a ``(7, 7, 3)`` uint8 array), whose agent starts in the
middle; a red tile ``a`` and a blue tile ``b`` lie in opposite corners, four moves away each.
A visited tile turns grey, and the episode ends (reward 1) once both were visited. ``info["tile"]``
names the tile the agent stands on. The demonstrator always visits ``a`` first.
"""

from __future__ import annotations

import copy
from collections import deque
from collections.abc import Callable, Sequence

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from minigrid.core.grid import Grid
from minigrid.core.mission import MissionSpace
from minigrid.core.world_object import Floor
from minigrid.minigrid_env import MiniGridEnv
from minigrid.wrappers import FullyObsWrapper, ImgObsWrapper

DOORKEY_ACTIONS = (0, 1, 2, 3, 5)  # left, right, forward, pickup, toggle


def bfs_plan(env: MiniGridEnv, reached: Callable[[MiniGridEnv, bool], bool], actions: Sequence[int],
             limit: int = 5000) -> list[int]:
    """The shortest action sequence from ``env``'s current state (simulated on copies) after
    which ``reached(copy, terminated)`` holds; ties go to the earlier action in ``actions``."""
    start = copy.deepcopy(env)
    frontier = deque([(start, [])])
    seen = {start.hash()}
    while frontier and len(seen) < limit:
        state, plan = frontier.popleft()
        for a in actions:
            nxt = copy.deepcopy(state)
            _, _, terminated, truncated, _ = nxt.step(a)
            if reached(nxt, terminated):
                return [*plan, a]
            if terminated or truncated:
                continue
            key = nxt.hash()
            if key not in seen:
                seen.add(key)
                frontier.append((nxt, [*plan, a]))
    raise RuntimeError("no plan found")


class PlannedPolicy:
    """``policy(observation)`` for ``symlearn.data.record``: plans at the first step of every
    episode (``step_count == 0``) through ``sub_goals`` in order, then replays the plan."""

    def __init__(self, env, sub_goals: Sequence[Callable[[MiniGridEnv, bool], bool]], actions: Sequence[int]):
        self.env, self.sub_goals, self.actions = env, list(sub_goals), list(actions)
        self.plan: list[int] = []

    def __call__(self, _observation):
        base = self.env.unwrapped
        if base.step_count == 0:
            self.plan, state = [], copy.deepcopy(base)
            for goal in self.sub_goals:
                part = bfs_plan(state, goal, self.actions)
                for a in part:
                    state.step(a)
                self.plan += part
        return self.plan.pop(0)


def doorkey_solved(_env: MiniGridEnv, terminated: bool) -> bool:
    return terminated


# --- the two-tile room -------------------------------------------------------------------------------

TILES = {"a": ((1, 1), "red"), "b": ((5, 5), "blue")}


class TwoTileRoom(MiniGridEnv):
    def __init__(self, max_steps: int = 60, **kwargs):
        super().__init__(mission_space=MissionSpace(mission_func=lambda: "visit both tiles"), grid_size=7,
                         max_steps=max_steps, see_through_walls=True, **kwargs)
        self.action_space = spaces.Discrete(3)  # left, right, forward: nothing else does anything here
        self.visited: set[str] = set()

    def _gen_grid(self, width, height):
        self.grid = Grid(width, height)
        self.grid.wall_rect(0, 0, width, height)
        for (x, y), color in TILES.values():
            self.grid.set(x, y, Floor(color))
        self.agent_pos, self.agent_dir = np.array((3, 3)), 3
        self.visited = set()
        self.mission = "visit both tiles"

    def step(self, action):
        obs, _, terminated, truncated, info = super().step(action)
        tile = next((name for name, (pos, _) in TILES.items() if tuple(self.agent_pos) == pos), None)
        reward = 0.0
        if tile is not None and tile not in self.visited:
            self.visited.add(tile)
            self.grid.set(*TILES[tile][0], Floor("grey"))
            obs = self.gen_obs()
            if len(self.visited) == len(TILES):
                terminated, reward = True, 1.0
        info = {**info, "tile": tile}
        return obs, reward, terminated, truncated, info


def make_room(**kwargs):
    return ImgObsWrapper(FullyObsWrapper(TwoTileRoom(**kwargs)))


def on_tile(name: str) -> Callable[[MiniGridEnv, bool], bool]:
    return lambda env, _terminated: tuple(env.agent_pos) == TILES[name][0]


def room_demonstrator(env) -> PlannedPolicy:
    """Visits ``a``, then ``b`` (the order it prefers; the room allows both)."""
    return PlannedPolicy(env, [on_tile("a"), on_tile("b")], (0, 1, 2))


if "TwoTileRoom-v0" not in gym.registry:
    gym.register(id="TwoTileRoom-v0", entry_point=make_room)
