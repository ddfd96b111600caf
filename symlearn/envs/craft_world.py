"""The craft world: a 40x40 open grid with resources ``a`` to ``g`` scattered by a seed
(after Andreas et al. and Toro Icarte et al.; the thesis, Section 5.5, uses 40x40).

Each resource occupies ``per_resource`` distinct cells drawn with ``numpy.random.default_rng(seed)``
(never the start cell); the agent starts in the middle. Task specifications follow the thesis,
Table 5.1.
"""

from __future__ import annotations

import numpy as np

from symlearn.envs.labelled_grid import LabelledGridEnv
from symlearn.envs.registry import formulas
from symlearn.errors import ModelError

SIZE = 40
RESOURCES = ("a", "b", "c", "d", "e", "f", "g")

# Task name -> ground-truth LTLf formula; the table of every bundled task is the registry.
TASKS = formulas("craft")


def make_craft_world(seed: int = 0, size: int = SIZE, per_resource: int = 5, max_steps: int = 400,
                     render_mode: str | None = None) -> LabelledGridEnv:
    start = (size // 2, size // 2)
    free = [(x, y) for y in range(size) for x in range(size) if (x, y) != start]
    needed = per_resource * len(RESOURCES)
    if needed > len(free):
        raise ModelError(f"{needed} resource cells do not fit on a {size}x{size} grid")
    rng = np.random.default_rng(seed)
    picks = rng.choice(len(free), size=needed, replace=False)
    objects = {free[int(i)]: {RESOURCES[k // per_resource]} for k, i in enumerate(picks)}
    meanings = {r: f"resource {r}" for r in RESOURCES}
    return LabelledGridEnv(size, size, objects, start, (), max_steps=max_steps, meanings=meanings,
                           render_mode=render_mode)
