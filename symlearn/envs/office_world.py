"""The office world: a 12x9 grid of nine 3x3 rooms joined by doors (Toro Icarte et al., 2018).

Propositions: ``a b c d`` four offices, ``e`` mail, ``f`` coffee (two machines), ``g`` the
delivery office, ``n`` decorations the agent must not step on. The agent starts at (2, 1).
The task specifications are those of the thesis, Table 5.1 (``T`` is "then": ``F(x & X F y)``).
"""

from __future__ import annotations

from symlearn.envs.labelled_grid import LabelledGridEnv
from symlearn.envs.registry import formulas

WIDTH, HEIGHT, ROOM = 12, 9, 3
START = (2, 1)
OBJECTS = {
    (1, 1): {"a"}, (10, 1): {"b"}, (10, 7): {"c"}, (1, 7): {"d"},
    (7, 4): {"e"}, (8, 2): {"f"}, (3, 6): {"f"}, (4, 4): {"g"},
    (4, 1): {"n"}, (7, 1): {"n"}, (4, 7): {"n"}, (7, 7): {"n"}, (1, 4): {"n"}, (10, 4): {"n"},
}
MEANINGS = {"a": "office A", "b": "office B", "c": "office C", "d": "office D", "e": "mail room",
            "f": "coffee machine", "g": "delivery office", "n": "decoration (must not be touched)"}
# Doors between horizontally adjacent rooms: the cell pair (x, y) <-> (x + 1, y).
HORIZONTAL_DOORS = [(x, y) for y in (1, 7) for x in (2, 5, 8)]
# Doors between vertically adjacent rooms: the cell pair (x, y) <-> (x, y + 1).
VERTICAL_DOORS = [(x, 5) for x in (1, 4, 7, 10)] + [(x, 2) for x in (1, 10)]

# Task name -> ground-truth LTLf formula; the table of every bundled task is the registry.
TASKS = formulas("office")


def _walls():
    up, right, down, left = range(4)
    walls = set()
    # Every room border blocks movement, ...
    for x in range(WIDTH):
        for y0 in range(0, HEIGHT, ROOM):
            walls.add(((x, y0), down))
            walls.add(((x, y0 + ROOM - 1), up))
    for y in range(HEIGHT):
        for x0 in range(0, WIDTH, ROOM):
            walls.add(((x0, y), left))
            walls.add(((x0 + ROOM - 1, y), right))
    # ... except where a door joins two rooms.
    for x, y in HORIZONTAL_DOORS:
        walls.discard(((x, y), right))
        walls.discard(((x + 1, y), left))
    for x, y in VERTICAL_DOORS:
        walls.discard(((x, y), up))
        walls.discard(((x, y + 1), down))
    return walls


def make_office_world(max_steps: int = 200, render_mode: str | None = None) -> LabelledGridEnv:
    return LabelledGridEnv(WIDTH, HEIGHT, OBJECTS, START, _walls(), max_steps=max_steps,
                           meanings=MEANINGS, render_mode=render_mode)
