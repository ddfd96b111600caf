"""A deterministic 4-connected grid whose cells carry propositions: the base of the office and
craft worlds used for learning task specifications.

The environment itself pays no reward: what the agent should achieve is a task specification
(an LTLf formula over the cell propositions), turned into rewards by a reward machine. States are
cell ids ``y * width + x``; actions are ``up right down left`` (``up`` increases ``y``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.errors import ModelError
from symlearn.grounding.labeling import Labeling
from symlearn.mdp import TabularMDP

ACTIONS = ("up", "right", "down", "left")
_MOVES = {0: (0, 1), 1: (1, 0), 2: (0, -1), 3: (-1, 0)}

Cell = tuple[int, int]


class LabelledGridEnv(gym.Env):
    """Grid with walls between neighbouring cells and propositions on cells.

    ``walls`` holds blocked moves as ``(cell, action)``; a blocked move leaves the agent in place,
    as does a move off the grid. ``info["labels"]`` of reset and step lists the propositions true
    in the new cell.
    """

    metadata = {"render_modes": ["ansi"]}

    def __init__(self, width: int, height: int, objects: Mapping[Cell, Iterable[str]], start: Cell,
                 walls: Iterable[tuple[Cell, int]] = (), *, max_steps: int = 200,
                 meanings: Mapping[str, str] | None = None, render_mode: str | None = None) -> None:
        if width < 1 or height < 1:
            raise ModelError(f"grid must be at least 1x1, got {width}x{height}")
        self.width, self.height = width, height
        self.start = tuple(start)
        for cell in [self.start, *objects]:
            if not self._inside(cell):
                raise ModelError(f"cell {cell} lies outside the {width}x{height} grid")
        self.objects = {tuple(c): frozenset(p) for c, p in objects.items()}
        self.walls = frozenset((tuple(c), int(a)) for c, a in walls)
        self.max_steps = max_steps
        self.render_mode = render_mode
        self.observation_space = spaces.Discrete(width * height)
        self.action_space = spaces.Discrete(len(ACTIONS))
        self._labeling = Labeling({self.state_of(c): p for c, p in self.objects.items()}, meanings=meanings)
        self._state = self.state_of(self.start)
        self._steps = 0

    # --- coordinates --------------------------------------------------------------------------
    def _inside(self, cell: Cell) -> bool:
        return 0 <= cell[0] < self.width and 0 <= cell[1] < self.height

    def state_of(self, cell: Cell) -> int:
        return int(cell[1]) * self.width + int(cell[0])

    def cell_of(self, state: int) -> Cell:
        return int(state) % self.width, int(state) // self.width

    def next_state(self, state: int, action: int) -> int:
        cell = self.cell_of(state)
        if (cell, int(action)) in self.walls:
            return int(state)
        dx, dy = _MOVES[int(action)]
        target = (cell[0] + dx, cell[1] + dy)
        return self.state_of(target) if self._inside(target) else int(state)

    @property
    def labeling(self) -> Labeling:
        """Ground-truth labeling of cells by propositions."""
        return self._labeling

    # --- gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._state = self.state_of(self.start)
        self._steps = 0
        return self._state, {"labels": sorted(self._labeling.label(self._state))}

    def step(self, action):
        if not self.action_space.contains(action):
            raise ModelError(f"action {action!r} is not one of 0..3 ({', '.join(ACTIONS)})")
        self._state = self.next_state(self._state, action)
        self._steps += 1
        truncated = self._steps >= self.max_steps
        return self._state, 0.0, False, truncated, {"labels": sorted(self._labeling.label(self._state))}

    def render(self) -> str:
        rows = []
        for y in reversed(range(self.height)):
            row = []
            for x in range(self.width):
                if self.state_of((x, y)) == self._state:
                    row.append("A")
                else:
                    props = self.objects.get((x, y))
                    row.append("".join(sorted(props))[:1] if props else ".")
            rows.append(" ".join(row))
        return "\n".join(rows)

    # --- exact model --------------------------------------------------------------------------
    def to_tabular(self) -> TabularMDP:
        """The deterministic dynamics as a :class:`TabularMDP` (no reward, no terminal states)."""
        n = self.width * self.height
        transitions = np.zeros((n, len(ACTIONS), n))
        for s in range(n):
            for a in range(len(ACTIONS)):
                transitions[s, a, self.next_state(s, a)] = 1.0
        initial = np.zeros(n)
        initial[self.state_of(self.start)] = 1.0
        names = [f"x{x}y{y}" for y in range(self.height) for x in range(self.width)]
        return TabularMDP(transitions, np.zeros((n, len(ACTIONS))), initial, np.zeros(n, dtype=bool),
                          state_names=names, action_names=ACTIONS)
