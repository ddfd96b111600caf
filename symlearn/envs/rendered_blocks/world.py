"""Kinematic block-world state: coloured cubes on a square table, moved by pick-and-place.

Coordinates are table units: ``x`` left to right and ``y`` near (front camera side) to far, both
in ``[0, 1]``; a block is a cube of edge :data:`BLOCK` whose position is its footprint centre and
its ``level`` (0 on the table, 1 on one block, ...). There is no physics: a pick takes the highest
block under the point if nothing rests on it; a place puts the held block on the table or on top of
what lies under its footprint. Placing on a single block snaps onto it (a robot's gripper centres
a cube it lowers onto another; without it a pixel-level policy could hardly stack), placing over
two blocks rests on both (a pyramid's top).

>>> world = BlockWorld((("red", 0.2, 0.3), ("green", 0.6, 0.5)))
>>> world.pick_place((0.21, 0.31), (0.63, 0.52))
True
>>> world.positions()[0].round(2).tolist()   # snapped onto green, one level up
[0.6, 0.5, 1.0]
>>> world.pick_place((0.6, 0.5), (0.3, 0.8)), world.positions()[0].tolist()   # the top block goes
(True, [0.3, 0.8, 0.0])
>>> world.pick_place((0.9, 0.9), (0.3, 0.3))   # nothing there to pick
False
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

BLOCK = 0.12  # edge of a block, table units
MARGIN = BLOCK / 2  # a footprint centre stays this far inside the table edges


class BlockWorld:
    """Blocks ``(name, x, y)`` on the table; positions ``(n, 3)`` = ``x, y, level``."""

    def __init__(self, blocks: Sequence[tuple[str, float, float]]) -> None:
        self.names = tuple(name for name, _, _ in blocks)
        self.state = np.array([[x, y, 0.0] for _, x, y in blocks], dtype=np.float64)

    def copy(self) -> BlockWorld:
        other = BlockWorld(())
        other.names, other.state = self.names, self.state.copy()
        return other

    def positions(self) -> np.ndarray:
        return self.state.copy()

    def set_positions(self, positions: np.ndarray) -> None:
        self.state = np.array(positions, dtype=np.float64).reshape(len(self.names), 3)

    # -- geometry ---------------------------------------------------------------------------------
    def _under(self, x: float, y: float, exclude: int | None = None) -> np.ndarray:
        """Indices of blocks whose footprint contains the point."""
        inside = (np.abs(self.state[:, 0] - x) < BLOCK / 2) & (np.abs(self.state[:, 1] - y) < BLOCK / 2)
        if exclude is not None:
            inside[exclude] = False
        return np.flatnonzero(inside)

    def _overlapping(self, x: float, y: float, exclude: int | None = None) -> np.ndarray:
        """Indices of blocks whose footprint overlaps a footprint centred at the point."""
        touch = (np.abs(self.state[:, 0] - x) < BLOCK * 0.999) & (np.abs(self.state[:, 1] - y) < BLOCK * 0.999)
        if exclude is not None:
            touch[exclude] = False
        return np.flatnonzero(touch)

    def free(self, i: int) -> bool:
        """Whether nothing rests on block ``i``."""
        x, y, level = self.state[i]
        above = self._overlapping(x, y, exclude=i)
        return not np.any(self.state[above, 2] > level + 0.5)

    def block_at(self, x: float, y: float) -> int | None:
        """The block a pick at the point would take (the highest one there, if it is free)."""
        under = self._under(x, y)
        if len(under) == 0:
            return None
        top = int(under[np.argmax(self.state[under, 2])])
        return top if self.free(top) else None

    def resting_place(self, i: int, x: float, y: float) -> tuple[float, float, float] | None:
        """Where block ``i`` lands when lowered at the point (None: off the table)."""
        if not (MARGIN <= x <= 1 - MARGIN and MARGIN <= y <= 1 - MARGIN):
            return None
        under = self._under(x, y, exclude=i)
        if len(under):
            top = int(under[np.argmax(self.state[under, 2])])
            touching = self._overlapping(x, y, exclude=i)
            if np.all(self.state[touching, 2] <= self.state[top, 2]) and np.sum(
                    self.state[touching, 2] == self.state[top, 2]) == 1:
                x, y = self.state[top, :2]  # lowered onto one block: the gripper centres it
        touching = self._overlapping(x, y, exclude=i)
        level = (np.max(self.state[touching, 2]) + 1) if len(touching) else 0.0
        return float(x), float(y), float(level)

    def pick_place(self, pick: tuple[float, float], place: tuple[float, float]) -> bool:
        """Move the block at ``pick`` to ``place``; False (nothing moves) when either fails."""
        i = self.block_at(*pick)
        if i is None:
            return False
        target = self.resting_place(i, *place)
        if target is None:
            return False
        self.state[i] = target
        return True


__all__ = ["BLOCK", "BlockWorld", "MARGIN"]
