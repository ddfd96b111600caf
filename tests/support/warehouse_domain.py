"""A user's domain written from scratch: a warehouse robot (not one of the bundled domains).

A 4 x 3 floor with two shelves in the middle, a pick station at (0, 0) and a drop station at
(3, 2). The robot moves, waits, picks a parcel at the pick station and drops it at the drop
station, which ends the episode. An alarm goes off at random (``alarm_prob`` per step); while it
rings the robot must not move. Driving into a shelf is forbidden too (the robot bumps and stays).
Moves off the floor do not exist (the ``available`` array says so).

``write_warehouse(folder)`` writes the domain folder (``domain.toml``, ``bk.lp``, ``bias.las``,
``model.npz``, ``states.jsonl``, ``actions.jsonl``, ``truth.lp``, ``labeling.json``);
``expert_demonstrations(folder_or_arrays, n, seed)`` records a rule-abiding expert.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

WIDTH, HEIGHT = 4, 3
SHELVES = {(1, 1), (2, 1)}
PICK, DROP = (0, 0), (3, 2)
MOVES = {"north": (0, 1), "south": (0, -1), "east": (1, 0), "west": (-1, 0)}
ACTIONS = [f"move({d})" for d in MOVES] + ["wait", "pick", "drop"]

BACKGROUND = """\
% warehouse background: with one state's facts and one action atom, one answer set
dir(north; south; east; west).
delta(north, 0, 1). delta(south, 0, -1). delta(east, 1, 0). delta(west, -1, 0).
shelf(1, 1). shelf(2, 1).
station(pick, 0, 0). station(drop, 3, 2).
blocked(D) :- at(X, Y), delta(D, DX, DY), shelf(X + DX, Y + DY).
atStation(S) :- at(X, Y), station(S, X, Y).
"""

BIAS = """\
#modeb(1, alarm, (positive)).
#modeb(1, loaded, (positive)).
#modeb(1, move(var(dir)), (positive)).
#modeb(1, blocked(var(dir)), (positive)).
#modeb(1, wait, (positive)).
#modeb(1, pick, (positive)).
#maxv(1).
"""

TRUTH = """\
% the warehouse's real rules
:- alarm, move(D).
:- move(D), blocked(D).
"""


def states() -> list[tuple]:
    cells = [(x, y) for y in range(HEIGHT) for x in range(WIDTH) if (x, y) not in SHELVES]
    return [(c, alarm, loaded) for c in cells for alarm in (0, 1) for loaded in (0, 1)] + ["done"]


def build_arrays(alarm_prob: float = 0.2) -> dict[str, np.ndarray]:
    """transitions, initial, terminal, available, rewards of the nominal model."""
    all_states = states()
    ids = {s: i for i, s in enumerate(all_states)}
    n_s, n_a = len(all_states), len(ACTIONS)
    P = np.zeros((n_s, n_a, n_s))
    R = np.full((n_s, n_a), -1.0)
    available = np.ones((n_s, n_a), dtype=bool)
    done = ids["done"]
    P[done, :, done] = 1.0
    R[done] = 0.0
    alarm_next = [(0, 1.0 - alarm_prob), (1, alarm_prob)]
    for s in all_states[:-1]:
        (x, y), alarm, loaded = s
        i = ids[s]
        for a, name in enumerate(ACTIONS):
            cell, load, finished = (x, y), loaded, False
            if name.startswith("move("):
                dx, dy = MOVES[name[5:-1]]
                target = (x + dx, y + dy)
                if not (0 <= target[0] < WIDTH and 0 <= target[1] < HEIGHT):
                    available[i, a] = False  # no such move: leave the floor
                elif target not in SHELVES:
                    cell = target  # into a shelf: bump and stay
            elif name == "pick" and (x, y) == PICK:
                load = 1
            elif name == "drop" and loaded:
                finished = (x, y) == DROP
                load = 0
            if finished:
                P[i, a, done] = 1.0
                R[i, a] = 10.0
                continue
            for next_alarm, p in alarm_next:
                if p > 0:
                    P[i, a, ids[(cell, next_alarm, load)]] += p
    initial = np.zeros(n_s)
    initial[ids[(PICK, 0, 0)]] = 1.0
    terminal = np.zeros(n_s, dtype=bool)
    terminal[done] = True
    return {"transitions": P, "initial": initial, "terminal": terminal, "available": available, "rewards": R}


def state_name(state) -> str:
    if state == "done":
        return "done"
    (x, y), alarm, loaded = state
    return f"({x},{y})" + (" alarm" if alarm else "") + (" loaded" if loaded else "")


def state_facts(state) -> str:
    if state == "done":
        return "finished."
    (x, y), alarm, loaded = state
    return " ".join([f"at({x},{y})."] + (["alarm."] if alarm else []) + (["loaded."] if loaded else []))


def labeling_document() -> dict:
    table = []
    for i, s in enumerate(states()):
        if s == "done":
            table.append([i, ["delivered"]])
            continue
        props = [name for name, cell in (("at_pick", PICK), ("at_drop", DROP)) if s[0] == cell]
        if s[2]:
            props.append("loaded")
        if props:
            table.append([i, props])
    return {"symlearn": "labeling", "format_version": 1, "kind": "table",
            "propositions": [{"name": "at_pick", "meaning": "robot at the pick station"},
                             {"name": "at_drop", "meaning": "robot at the drop station"},
                             {"name": "loaded", "meaning": "robot carries a parcel"},
                             {"name": "delivered", "meaning": "the parcel was dropped at the station"}],
            "table": table}


def write_warehouse(folder: str | Path, *, alarm_prob: float = 0.2, truth: bool = True,
                    labeling: bool = True) -> Path:
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "bk.lp").write_text(BACKGROUND)
    (folder / "bias.las").write_text(BIAS)
    np.savez(folder / "model.npz", **build_arrays(alarm_prob))
    (folder / "states.jsonl").write_text("".join(json.dumps({"id": i, "facts": state_facts(s), "name": state_name(s)})
                                                 + "\n" for i, s in enumerate(states())))
    (folder / "actions.jsonl").write_text("".join(json.dumps({"id": i, "atom": a}) + "\n"
                                                  for i, a in enumerate(ACTIONS)))
    toml = ['name = "warehouse"', 'description = "warehouse robot: shelves, stations, alarm"',
            'background = "bk.lp"', 'bias = "bias.las"', 'model = "model.npz"', 'states = "states.jsonl"',
            'actions = "actions.jsonl"']
    if truth:
        (folder / "truth.lp").write_text(TRUTH)
        toml.append('truth = "truth.lp"')
    if labeling:
        (folder / "labeling.json").write_text(json.dumps(labeling_document(), indent=1))
        toml.append('labeling = "labeling.json"')
    (folder / "domain.toml").write_text("\n".join(toml) + "\n")
    return folder


def truth_mask(arrays: dict[str, np.ndarray] | None = None) -> np.ndarray:
    """The forbidden pairs by the rules, computed here in Python (independently of clingo)."""
    all_states = states()
    arrays = arrays or build_arrays()
    mask = np.zeros((len(all_states), len(ACTIONS)), dtype=bool)
    for i, s in enumerate(all_states[:-1]):
        (x, y), alarm, _ = s
        for a, name in enumerate(ACTIONS):
            if not arrays["available"][i, a] or not name.startswith("move("):
                continue
            dx, dy = MOVES[name[5:-1]]
            mask[i, a] = bool(alarm) or (x + dx, y + dy) in SHELVES
    return mask


def expert_demonstrations(n: int, seed: int = 0, *, alarm_prob: float = 0.2, atoms: bool = False):
    """``n`` deliveries by an expert that obeys the rules (shortest route, waits out alarms).

    Actions are ids, or ASP atoms with ``atoms=True`` (both are valid demonstration files)."""
    from symlearn.data import Demonstrations, Trajectory

    arrays = build_arrays(alarm_prob)
    P, R = arrays["transitions"], arrays["rewards"]
    forbidden = truth_mask(arrays) | ~arrays["available"]
    # value iteration on the allowed pairs; ties broken at random among optimal actions
    V = np.zeros(P.shape[0])
    for _ in range(500):
        Q = np.where(forbidden, -np.inf, R + 0.95 * P @ V)
        Q[arrays["terminal"]] = 0.0
        V = Q.max(axis=1)
    rng = np.random.default_rng(seed)
    start = int(np.argmax(arrays["initial"]))
    trajectories = []
    for _ in range(n):
        s, visited, actions = start, [start], []
        for _ in range(100):
            q = Q[s]
            a = int(rng.choice(np.flatnonzero(q >= q.max() - 1e-9)))
            s = int(rng.choice(P.shape[0], p=P[s, a]))
            actions.append(ACTIONS[a] if atoms else a)
            visited.append(s)
            if arrays["terminal"][s]:
                break
        trajectories.append(Trajectory(states=visited, actions=actions))
    return Demonstrations(trajectories)
