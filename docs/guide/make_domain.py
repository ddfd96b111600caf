"""Write the guide's domain folder and demonstrations: python make_domain.py [--episodes N]

floor_domain/   the point robot's floor as a 4 x 3 grid (domain.toml, floor.lp, bias.las,
                model.npz, states.jsonl, actions.jsonl): a rug covers (1,0) and (1,1); the
                robot drives from (0,0) to the goal (3,0)
floor_demos.jsonl   routes of a careful driver who goes round the rug through (1,2)

The nominal model lets the robot drive over the rug; only the demonstrations show that
it must not (the rule `symlearn learn constraints` should find).
"""

import argparse
import json
from pathlib import Path

import numpy as np

from symlearn.data import Demonstrations, Trajectory

WIDTH, HEIGHT, GOAL = 4, 3, (3, 0)
RUG = {(1, 0), (1, 1)}
MOVES = {"north": (0, 1), "south": (0, -1), "east": (1, 0), "west": (-1, 0)}
ACTIONS = [f"move({d})" for d in MOVES] + ["wait"]
CELLS = [(x, y) for y in range(HEIGHT) for x in range(WIDTH)]

BACKGROUND = """\
% the floor: one state's at/2 fact and one action atom give one answer set
dir(north; south; east; west).
delta(north, 0, 1). delta(south, 0, -1). delta(east, 1, 0). delta(west, -1, 0).
rug(1, 0). rug(1, 1).
rug_ahead(D) :- at(X, Y), delta(D, DX, DY), rug(X + DX, Y + DY).
"""
BIAS = """\
#modeb(1, move(var(dir)), (positive)).
#modeb(1, rug_ahead(var(dir)), (positive)).
#modeb(1, wait, (positive)).
#maxv(1).
"""


def model():
    n_s, n_a = len(CELLS), len(ACTIONS)
    P, R = np.zeros((n_s, n_a, n_s)), np.full((n_s, n_a), -1.0)
    available = np.ones((n_s, n_a), dtype=bool)
    for i, (x, y) in enumerate(CELLS):
        for a, name in enumerate(ACTIONS):
            target = (x, y)
            if name != "wait":
                dx, dy = MOVES[name[5:-1]]
                target = (x + dx, y + dy)
                if target not in CELLS:
                    available[i, a], target = False, (x, y)  # no move off the floor
            P[i, a, CELLS.index(target)] = 1.0
    terminal = np.array([c == GOAL for c in CELLS])
    P[terminal], R[terminal] = 0.0, 0.0
    P[terminal, :, CELLS.index(GOAL)] = 1.0
    initial = np.array([c == (0, 0) for c in CELLS], dtype=float)
    return {"transitions": P, "initial": initial, "terminal": terminal, "available": available, "rewards": R}


def careful_routes(arrays, n, seed):
    """Shortest routes that never cross the rug (its tassels catch the wheels), ties broken at random."""
    P, R, ok = arrays["transitions"], arrays["rewards"], arrays["available"].copy()
    for i, (x, y) in enumerate(CELLS):
        for a, name in enumerate(ACTIONS[:4]):
            dx, dy = MOVES[name[5:-1]]
            ok[i, a] &= (x + dx, y + dy) not in RUG
    V = np.zeros(len(CELLS))
    for _ in range(100):
        Q = np.where(ok, R + P @ V, -np.inf)
        Q[arrays["terminal"]] = 0.0
        V = Q.max(axis=1)
    rng, routes = np.random.default_rng(seed), []
    for _ in range(n):
        s, states, actions = 0, [0], []
        while not arrays["terminal"][s]:
            a = int(rng.choice(np.flatnonzero(Q[s] >= Q[s].max() - 1e-9)))
            s = int(np.argmax(P[s, a]))
            states.append(s)
            actions.append(ACTIONS[a])
        routes.append(Trajectory(states=states, actions=actions))
    return Demonstrations(routes)


parser = argparse.ArgumentParser()
parser.add_argument("--episodes", type=int, default=20)
n = parser.parse_args().episodes
folder = Path("floor_domain")
folder.mkdir(exist_ok=True)
(folder / "floor.lp").write_text(BACKGROUND)
(folder / "bias.las").write_text(BIAS)
arrays = model()
np.savez(folder / "model.npz", **arrays)
(folder / "states.jsonl").write_text("".join(
    json.dumps({"id": i, "facts": f"at({x},{y}).", "name": f"({x},{y})"}) + "\n" for i, (x, y) in enumerate(CELLS)))
(folder / "actions.jsonl").write_text("".join(json.dumps({"id": i, "atom": a}) + "\n" for i, a in enumerate(ACTIONS)))
(folder / "domain.toml").write_text('name = "floor"\ndescription = "the guide robot\'s floor with a rug"\n'
                                    'background = "floor.lp"\nbias = "bias.las"\nmodel = "model.npz"\n'
                                    'states = "states.jsonl"\nactions = "actions.jsonl"\n')
careful_routes(arrays, n, seed=0).save("floor_demos.jsonl")
print(f"wrote {folder}/ and floor_demos.jsonl ({n} routes)")
