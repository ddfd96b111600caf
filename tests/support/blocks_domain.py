"""Two more users' domain folders, written from scratch (neither bundled nor the warehouse).

``write_blocks(folder)``: three blocks ``a`` (3 kg), ``b`` (2 kg), ``c`` (1 kg); ``stack(X,Y)`` puts
clear ``X`` on clear ``Y``, ``unstack(X)`` puts ``X`` on the table; a three-block tower ends the
episode. Arity-2 predicates and action atoms with two arguments, states named with unicode
(``a▸b · c``: ``b`` on ``a``, ``c`` alone), a comment and a non-ASCII description in
``domain.toml``, a feature map. True rule: never put a heavier block on a lighter one,
``:- stack(X, Y), heavier(X, Y).``

``write_elevator(folder)``: floors 0..3, door open or closed, a call on one floor; ``up``,
``down``, ``open``, ``close``, ``wait``; opening the door on the called floor serves the call.
Every file with CRLF line endings, ``%`` comments and non-ASCII text; states without names.
True rules: ``:- door_open, up.`` and ``:- door_open, down.``

``expert_demonstrations(spec, arrays, n, seed, by_name=)``: a rule-abiding expert (value
iteration on the pairs the true rules allow, ties broken at random), starting anywhere.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np

# --- blocks ---------------------------------------------------------------------------------
WEIGHT = {"a": 3, "b": 2, "c": 1}


def _block_configurations() -> list[frozenset]:
    """Every arrangement of a, b, c as a set of stacks (tuples bottom to top)."""
    out = set()
    for order in itertools.permutations("abc"):
        for cuts in itertools.product((0, 1), repeat=2):  # cut after position 1 and/or 2
            stacks, current = [], [order[0]]
            for block, cut in zip(order[1:], cuts):
                if cut:
                    stacks.append(tuple(current))
                    current = []
                current.append(block)
            stacks.append(tuple(current))
            out.add(frozenset(stacks))
    return sorted(out, key=sorted)


def _block_step(state, action):
    tops = {stack[-1]: stack for stack in state}
    stacks = set(state)
    if action.startswith("stack("):
        x, y = action[6], action[8]
        if x not in tops or y not in tops:
            return None
        stacks -= {tops[x], tops[y]}
        if len(tops[x]) > 1:
            stacks.add(tops[x][:-1])
        stacks.add(tops[y] + (x,))
        target = frozenset(stacks)
        return target, (10.0 if any(len(s) == 3 for s in target) else -1.0)
    x = action[8]
    if x not in tops or len(tops[x]) == 1:
        return None
    stacks -= {tops[x]}
    stacks |= {tops[x][:-1], (x,)}
    return frozenset(stacks), -1.0


BLOCKS = SimpleNamespace(
    states=_block_configurations(),
    actions=[f"stack({x},{y})" for x in "abc" for y in "abc" if x != y] + [f"unstack({x})" for x in "abc"],
    terminal=lambda s: any(len(stack) == 3 for stack in s),
    step=_block_step,
    forbidden=lambda s, a: a.startswith("stack(") and WEIGHT[a[6]] > WEIGHT[a[8]],
    facts=lambda s: " ".join(f"on_table({t[0]})." + "".join(f" on({hi},{lo})." for lo, hi in zip(t, t[1:]))
                             for t in sorted(s)),
    name=lambda s: " · ".join("▸".join(t) for t in sorted(s)),
    background="% blocks world: three blocks, weights in kg\n"
               "block(a; b; c).\nweight(a, 3). weight(b, 2). weight(c, 1).\n"
               "heavier(X, Y) :- weight(X, WX), weight(Y, WY), WX > WY.\n",
    bias="% which rules may be learned\n"
         "#modeb(1, stack(var(block), var(block)), (positive)).\n"
         "#modeb(1, unstack(var(block)), (positive)).\n"
         "#modeb(1, heavier(var(block), var(block)), (positive)).\n"
         "#modeb(1, on(var(block), var(block)), (positive)).\n"
         "#maxv(2).\n",
    truth=":- stack(X, Y), heavier(X, Y).\n",
    toml='# blocks: a user\'s domain\nname = "blocks"\ndescription = "Klötze: schwer auf leicht ist verboten"\n'
         'background = "bk.lp"\nbias = "bias.las"\nmodel = "model.npz"\nstates = "states.jsonl"\n'
         'actions = "actions.jsonl"\ntruth = "truth.lp"\nfeatures = "features.json"\n',
    crlf=False, named=True)

# --- elevator -------------------------------------------------------------------------------
FLOORS = 4


def _elevator_step(state, action):
    floor, door, call = state
    if action == "up":
        return None if floor == FLOORS - 1 else ((floor + 1, door, call), -1.0)
    if action == "down":
        return None if floor == 0 else ((floor - 1, door, call), -1.0)
    if action == "open":
        return ("served", 10.0) if floor == call else ((floor, 1, call), -1.0)
    if action == "close":
        return (floor, 0, call), -1.0
    return state, -1.0


ELEVATOR = SimpleNamespace(
    states=[(f, d, c) for f in range(FLOORS) for d in (0, 1) for c in range(FLOORS)] + ["served"],
    actions=["up", "down", "open", "close", "wait"],
    terminal=lambda s: s == "served",
    step=_elevator_step,
    forbidden=lambda s, a: s[1] == 1 and a in ("up", "down"),
    facts=lambda s: "" if s == "served" else f"floor({s[0]}). call({s[2]})." + (" door_open." if s[1] else ""),
    name=None,
    background="% Aufzug: elevator background (é, ü, →)\n"
               "here :- call(C), floor(C).   % at the called floor\n",
    bias="% bias: élévateur\n#modeb(1, door_open, (positive)).\n#modeb(1, up, (positive)).\n"
         "#modeb(1, down, (positive)).\n#modeb(1, here, (positive)).\n#modeb(1, close, (positive)).\n#maxv(1).\n",
    truth="% the real rules\n:- door_open, up.\n:- door_open, down.\n",
    toml='# elevator: CRLF line endings\nname = "elevator"\ndescription = "Aufzug: Türen offen → nicht fahren"\n'
         'background = "bk.lp"   # program\nbias = "bias.las"\nmodel = "model.npz"\nstates = "states.jsonl"\n'
         'actions = "actions.jsonl"\ntruth = "truth.lp"\n',
    crlf=True, named=False)


# --- writing --------------------------------------------------------------------------------
def build_arrays(spec) -> dict[str, np.ndarray]:
    """transitions, initial (every non-terminal state alike), terminal, available, rewards."""
    ids = {s: i for i, s in enumerate(spec.states)}
    n_s, n_a = len(spec.states), len(spec.actions)
    P, R = np.zeros((n_s, n_a, n_s)), np.full((n_s, n_a), -1.0)
    available = np.ones((n_s, n_a), dtype=bool)
    terminal = np.array([spec.terminal(s) for s in spec.states])
    for i, s in enumerate(spec.states):
        for a, action in enumerate(spec.actions):
            out = None if terminal[i] else spec.step(s, action)
            if out is None:
                P[i, a, i], R[i, a] = 1.0, 0.0
                available[i, a] = bool(terminal[i])
                continue
            P[i, a, ids[out[0]]], R[i, a] = 1.0, out[1]
    initial = (~terminal).astype(float) / (~terminal).sum()
    return {"transitions": P, "initial": initial, "terminal": terminal, "available": available, "rewards": R}


def truth_mask(spec, arrays) -> np.ndarray:
    return np.array([[bool(arrays["available"][i, a]) and not arrays["terminal"][i] and spec.forbidden(s, action)
                      for a, action in enumerate(spec.actions)] for i, s in enumerate(spec.states)])


def write_domain(spec, folder: str | Path) -> Path:
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    newline = "\r\n" if spec.crlf else "\n"

    def text(name: str, content: str) -> None:
        (folder / name).write_bytes(content.replace("\n", newline).encode("utf-8"))

    text("bk.lp", spec.background)
    text("bias.las", spec.bias)
    text("truth.lp", spec.truth)
    text("domain.toml", spec.toml)
    arrays = build_arrays(spec)
    np.savez(folder / "model.npz", **arrays)
    rows = [{"id": i, "facts": spec.facts(s), **({"name": spec.name(s)} if spec.named else {})}
            for i, s in enumerate(spec.states)]
    text("states.jsonl", "".join(json.dumps(r, ensure_ascii=False) + "\n" for r in rows))
    text("actions.jsonl", "".join(json.dumps({"id": i, "atom": a}) + "\n" for i, a in enumerate(spec.actions)))
    if "features.json" in spec.toml:
        table = [[float(max(len(t) for t in s)), float(len(s))] for s in spec.states]
        text("features.json", json.dumps({"symlearn": "feature-map", "format_version": 1,
                                          "names": ["height", "stacks"], "table": table}))
    return folder


def expert_demonstrations(spec, n: int, seed: int = 0, *, by_name: bool = False, path: str | Path | None = None):
    """``n`` episodes of the rule-abiding expert, states as ids or (``by_name``) names, actions as
    atoms; saved to ``path`` (JSONL) when given."""
    from symlearn.data import Demonstrations, Trajectory

    arrays = build_arrays(spec)
    P, R = arrays["transitions"], arrays["rewards"]
    blocked = truth_mask(spec, arrays) | ~arrays["available"]
    V = np.zeros(len(spec.states))
    for _ in range(200):
        Q = np.where(blocked, -np.inf, R + 0.95 * P @ V)
        Q[arrays["terminal"]] = 0.0
        V = Q.max(axis=1)
    rng = np.random.default_rng(seed)
    trajectories = []
    for _ in range(n):
        s = int(rng.choice(len(V), p=arrays["initial"]))
        states, actions = [s], []
        while not arrays["terminal"][s] and len(actions) < 30:
            a = int(rng.choice(np.flatnonzero(Q[s] >= Q[s].max() - 1e-9)))
            s = int(np.argmax(P[s, a]))
            states.append(s)
            actions.append(spec.actions[a])
        shown = [spec.name(spec.states[x]) for x in states] if by_name else states
        trajectories.append(Trajectory(states=shown, actions=actions))
    demos = Demonstrations(trajectories)
    if path is not None:
        demos.save(path)
    return demos
