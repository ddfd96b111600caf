"""The five block tasks of the thesis' Table 7.1 and their ground truth.

A task is blocks with start places, *placements* (block -> goal ``x, y, level``) and precedences
(a block goes on another only after that one is in place). A *configuration* is the set of
placements done so far; every set closed under the precedences can be reached. The ground truth
the thesis compares against has one proposition per configuration, true when every block is within
:data:`TOLERANCE` of where that configuration puts it (its goal if placed, its start otherwise);
the ground-truth machine moves from configuration ``S`` to ``S + {b}`` on the proposition of the
larger one and pays 1 on reaching the full configuration (:meth:`BlockTask.truth_structure`).

==========  ===========================================  ==========  ==============
task        goal                                          orderings   Table 7.1 demos
==========  ===========================================  ==========  ==============
stack-2     red on green                                  1           1
place-2     red and blue to their places (any order)      2           2
pyramid-3   red and green side by side, blue on both      2           2
stack-3     red on green, then blue on red                1           1
place-3     red, green and blue to their places           6           6
==========  ===========================================  ==========  ==============

>>> task = TASKS["pyramid-3"]
>>> [o for o in task.orderings()]
[(0, 1, 2), (1, 0, 2)]
>>> task.truth_structure()["propositions"]
('at_start', 'at_red', 'at_green', 'at_red_green', 'at_red_green_blue')
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.envs.rendered_blocks.world import BLOCK, BlockWorld

TOLERANCE = 0.4 * BLOCK  # a block this close (table units, same level) to its place is there


@dataclass(frozen=True)
class Placement:
    block: int
    goal: tuple[float, float, int]  # x, y, level
    after: tuple[int, ...] = ()  # placements (by index) that must be done first


@dataclass(frozen=True)
class BlockTask:
    name: str
    blocks: tuple[tuple[str, float, float], ...]  # name, start x, start y
    placements: tuple[Placement, ...]
    description: str = ""

    # -- configurations ---------------------------------------------------------------------------
    def orderings(self) -> list[tuple[int, ...]]:
        """Every order of the placements the precedences allow (one demonstration each)."""
        return [order for order in itertools.permutations(range(len(self.placements)))
                if all(set(self.placements[p].after) <= set(order[:k]) for k, p in enumerate(order))]

    def configurations(self) -> list[frozenset[int]]:
        """Reachable sets of done placements, in order of size then of first appearance in an ordering."""
        seen: list[frozenset[int]] = []
        for size in range(len(self.placements) + 1):
            for order in self.orderings():
                config = frozenset(order[:size])
                if config not in seen:
                    seen.append(config)
        return seen

    def proposition(self, config: frozenset[int]) -> str:
        if not config:
            return "at_start"
        return "at_" + "_".join(self.blocks[self.placements[p].block][0] for p in sorted(config))

    def layout(self, config: frozenset[int]) -> np.ndarray:
        """``(n, 3)`` positions (x, y, level) of every block in a configuration."""
        positions = np.array([[x, y, 0.0] for _, x, y in self.blocks])
        for p in config:
            positions[self.placements[p].block] = self.placements[p].goal
        return positions

    def world(self) -> BlockWorld:
        return BlockWorld(self.blocks)

    def configuration_of(self, positions: np.ndarray) -> int | None:
        """Index (in :meth:`configurations`) of the configuration the positions show, or None."""
        for k, config in enumerate(self.configurations()):
            layout = self.layout(config)
            planar = np.linalg.norm(positions[:, :2] - layout[:, :2], axis=1)
            if np.all(planar < TOLERANCE) and np.all(np.abs(positions[:, 2] - layout[:, 2]) < 0.25):
                return k
        return None

    def truth_label(self, positions: np.ndarray) -> frozenset[str]:
        """The ground-truth propositions holding at ``positions`` (at most one)."""
        k = self.configuration_of(positions)
        return frozenset() if k is None else frozenset({self.proposition(self.configurations()[k])})

    def placement_error(self, positions: np.ndarray) -> float:
        """Mean distance (x, y and height, table units) of every block to its final place."""
        final = self.layout(frozenset(range(len(self.placements))))
        offset = positions - final
        offset[:, 2] *= BLOCK
        return float(np.mean(np.linalg.norm(offset, axis=1)))

    def truth_structure(self) -> dict[str, Any]:
        """The ground-truth machine as plain data: ``propositions`` (one per configuration, state
        ``k`` = configuration ``k``), ``initial`` 0, ``edges`` ``{(u, proposition): v}``,
        ``accepting`` (the full configuration)."""
        configs = self.configurations()
        props = tuple(self.proposition(c) for c in configs)
        edges = {}
        for u, config in enumerate(configs):
            for v, other in enumerate(configs):
                if config < other and len(other - config) == 1:
                    edges[(u, props[v])] = v
        return {"propositions": props, "initial": 0, "edges": edges,
                "accepting": (configs.index(frozenset(range(len(self.placements)))),)}


_R, _G, _B = 0, 1, 2
TASKS: dict[str, BlockTask] = {
    "stack-2": BlockTask("stack-2", (("red", 0.25, 0.35), ("green", 0.65, 0.55)),
                         (Placement(_R, (0.65, 0.55, 1)),), "stack red on green"),
    "place-2": BlockTask("place-2", (("red", 0.2, 0.3), ("blue", 0.25, 0.7)),
                         (Placement(0, (0.72, 0.35, 0)), Placement(1, (0.78, 0.72, 0))),
                         "put red and blue on their places, in any order"),
    "pyramid-3": BlockTask("pyramid-3", (("red", 0.2, 0.25), ("green", 0.2, 0.75), ("blue", 0.45, 0.2)),
                           (Placement(_R, (0.6, 0.6, 0)), Placement(_G, (0.72, 0.6, 0)),
                            Placement(_B, (0.66, 0.6, 1), after=(0, 1))),
                           "red and green side by side (any order), then blue on both"),
    "stack-3": BlockTask("stack-3", (("red", 0.2, 0.3), ("green", 0.5, 0.7), ("blue", 0.8, 0.3)),
                         (Placement(_R, (0.5, 0.7, 1)), Placement(_B, (0.5, 0.7, 2), after=(0,))),
                         "red on green, then blue on red"),
    "place-3": BlockTask("place-3", (("red", 0.18, 0.22), ("green", 0.2, 0.5), ("blue", 0.22, 0.8)),
                         (Placement(_R, (0.62, 0.3, 0)), Placement(_G, (0.8, 0.52, 0)), Placement(_B, (0.6, 0.78, 0))),
                         "put red, green and blue on their places, in any order"),
}

__all__ = ["BlockTask", "Placement", "TASKS", "TOLERANCE"]
