"""Three more domain folders nobody tuned the learner on (issue 25, second sweep): an elevator
(2 truth rules), a warehouse with doors along a corridor (3), a recycling sorter with gloves and
typed bins (3; constants in the bias), with demonstrations by experts that obey ``truth.lp``
(the experts, the folder writer and the check that ``truth.lp`` means what the Python rules
mean are those of ``benchmarks/hidden_domains.py``):

    python benchmarks/fresh_domains.py OUTDIR [--n 100] [--seed 0] [--betas 2]
    symlearn domain check OUTDIR/elevator --demos OUTDIR/elevator_boltzmann2.jsonl
    symlearn learn constraints --domain OUTDIR/elevator --demos OUTDIR/elevator_boltzmann2.jsonl -o rules.lp
    symlearn ilp check rules.lp

Results in docs/BENCHMARKS.md (issue 25, "Fresh domains, second sweep").
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from hidden_domains import write_demonstration_sets, write_domain  # noqa: E402

# --------------------------------------------------------------------------------------- elevator
# Floors 0..3; a passenger calls from floor 1, 2 or 3 (random at the start) and wants the ground
# floor. The nominal cabin moves with its doors open, and letting the passenger out anywhere ends
# the ride with the same +10 (the user's reward does not know where).


def e_states():
    return [(f, d, r, c) for f in range(4) for d in (0, 1) for r in (0, 1) for c in (1, 2, 3)] + ["done"]


def e_step(s, a):
    f, d, r, c = s
    n = [f, d, r, c]
    if a.startswith("go("):
        t = f + (1 if a == "go(up)" else -1)
        if not 0 <= t <= 3:
            return None
        n[0] = t
    elif a == "open":
        n[1] = 1
    elif a == "close":
        n[1] = 0
    elif a == "board":
        if d and f == c and not r:
            n[2] = 1
    elif a == "alight":
        if r and d:
            return [(1.0, "done", 10.0)]
    return [(1.0, tuple(n), -1.0)]


def e_forbidden(s, a):
    f, d, r, c = s
    return (a.startswith("go(") and d) or (a == "alight" and f != 0)


def e_facts(s):
    if s == "done":
        return "finished."
    f, d, r, c = s
    return " ".join([f"floor({f}).", f"call({c})."] + (["doors_open."] if d else []) + (["riding."] if r else []))


ELEVATOR = SimpleNamespace(
    name="elevator",
    description="elevator: fetch a passenger from the floor that called and bring them to the ground floor",
    states=e_states(),
    actions=["go(up)", "go(down)", "open", "close", "board", "alight", "wait"],
    step=e_step,
    terminal=lambda s: s == "done",
    initial=lambda s: s != "done" and s[:3] == (0, 0, 0),
    facts=e_facts,
    sname=lambda s: "done" if s == "done" else e_facts(s).replace(".", "").replace(" ", ","),
    forbidden=e_forbidden,
    # for `learn spec --domain`: the folder's labeling.json (a table of state ids)
    labels={"doors": "the doors are open", "riding": "the passenger is in the cabin",
            "at_call": "the cabin is at the floor that called", "ground": "the cabin is at the ground floor",
            "delivered": "the passenger got out"},
    label=lambda s: ["delivered"] if s == "done" else (["doors"] if s[1] else []) + (["riding"] if s[2] else [])
    + (["at_call"] if s[0] == s[3] else []) + (["ground"] if s[0] == 0 else []),
    background="""\
% elevator: floors 0..3, doors, a passenger called from call(C)
way(up; down).
upper :- floor(F), F > 0.
ground :- floor(0).
at_call :- floor(F), call(F).
doors_closed :- floor(_), not doors_open.
""",
    bias="""\
#modeb(1, go(var(way)), (positive)).
#modeb(1, doors_open, (positive)).
#modeb(1, doors_closed, (positive)).
#modeb(1, riding, (positive)).
#modeb(1, upper, (positive)).
#modeb(1, ground, (positive)).
#modeb(1, at_call, (positive)).
#modeb(1, open, (positive)).
#modeb(1, close, (positive)).
#modeb(1, board, (positive)).
#modeb(1, alight, (positive)).
#modeb(1, wait, (positive)).
#maxv(1).
""",
    truth="""\
:- go(D), doors_open.    % never move with the doors open
:- alight, upper.        % the passenger gets out at the ground floor only
""",
)

# -------------------------------------------------------------------------------------- warehouse
# Rooms 0..3 along a corridor, a door between each neighbouring pair (open or shut, random at the
# start). A crate waits in room 0; the dock is room 3. The nominal robot drives through shut doors
# (it breaks them), opens and shuts doors with the crate in its arms, and may drop the crate
# anywhere for the same +10.


def w_states():
    return [(r, doors, h) for r in range(4) for doors in range(8) for h in (0, 1)] + ["done"]


def w_door(r, t):
    return min(r, t)  # door i is between rooms i and i+1


def w_step(s, a):
    r, doors, h = s
    side = {"left": -1, "right": 1}
    if a.startswith("move("):
        t = r + side[a[5:-1]]
        if not 0 <= t <= 3:
            return None
        return [(1.0, (t, doors, h), -1.0)]
    if a.startswith("open(") or a.startswith("shut("):
        t = r + side[a[5:-1]]
        if not 0 <= t <= 3:
            return None
        bit = 1 << w_door(r, t)
        return [(1.0, (r, doors | bit if a.startswith("open") else doors & ~bit, h), -1.0)]
    if a == "pick":
        return [(1.0, (r, doors, 1 if r == 0 else h), -1.0)]
    if a == "drop":
        if h:
            return [(1.0, "done", 10.0)]
    return [(1.0, s, -1.0)]


def w_forbidden(s, a):
    r, doors, h = s
    side = {"left": -1, "right": 1}
    if a.startswith("move("):
        t = r + side[a[5:-1]]
        return not doors >> w_door(r, t) & 1
    if a.startswith("open(") or a.startswith("shut("):
        return bool(h)
    return a == "drop" and r != 3


def w_facts(s):
    if s == "done":
        return "finished."
    r, doors, h = s
    return " ".join([f"in({r})."] + [f"open_door({i})." for i in range(3) if doors >> i & 1]
                    + (["carrying."] if h else []))


WAREHOUSE = SimpleNamespace(
    name="warehouse",
    description="warehouse robot: carry the crate from room 0 to the dock in room 3 through doors",
    states=w_states(),
    actions=["move(left)", "move(right)", "open(left)", "open(right)", "shut(left)", "shut(right)", "pick", "drop",
             "wait"],
    step=w_step,
    terminal=lambda s: s == "done",
    initial=lambda s: s != "done" and s[0] == 0 and s[2] == 0,
    facts=w_facts,
    sname=lambda s: "done" if s == "done" else w_facts(s).replace(".", "").replace(" ", ","),
    forbidden=w_forbidden,
    labels={"carrying": "the robot holds the crate", "dock": "the robot is in room 3",
            "delivered": "the crate is on the dock"},
    label=lambda s: ["delivered"] if s == "done" else (["carrying"] if s[2] else []) + (["dock"] if s[0] == 3 else []),
    background="""\
% warehouse: rooms 0..3, door I between rooms I and I+1, dock in room 3
side(left; right).
room(0..3).
door_of(left, R - 1) :- in(R), R > 0.
door_of(right, R) :- in(R), R < 3.
shut_ahead(S) :- door_of(S, I), not open_door(I).
at_dock :- in(3).
off_dock :- in(R), R != 3.
empty_handed :- in(_), not carrying.
""",
    bias="""\
#modeb(1, move(var(side)), (positive)).
#modeb(1, open(var(side)), (positive)).
#modeb(1, shut(var(side)), (positive)).
#modeb(1, shut_ahead(var(side)), (positive)).
#modeb(1, carrying, (positive)).
#modeb(1, empty_handed, (positive)).
#modeb(1, at_dock, (positive)).
#modeb(1, off_dock, (positive)).
#modeb(1, pick, (positive)).
#modeb(1, drop, (positive)).
#modeb(1, wait, (positive)).
#maxv(1).
""",
    truth="""\
:- move(S), shut_ahead(S).   % doors are opened, not driven through
:- open(S), carrying.        % both hands on the crate
:- shut(S), carrying.
:- drop, off_dock.           % the crate goes to the dock
""",
)

# ----------------------------------------------------------------------------------------- sorter
# One item on the belt, glass, paper or plastic (random); the robot may wear gloves, picks the
# item and puts it in one of three bins. Any bin ends the episode with the same +10. Glass needs
# gloves, gloves stay on while holding, the bin must accept the kind.
KINDS = ("glass", "paper", "plastic")


def s_states():
    return [(k, h, g) for k in KINDS for h in (0, 1) for g in (0, 1)] + ["done"]


def s_step(s, a):
    k, h, g = s
    if a == "pick":
        return [(1.0, (k, 1, g), -1.0)]
    if a == "gloves_on":
        return [(1.0, (k, h, 1), -1.0)]
    if a == "gloves_off":
        return [(1.0, (k, h, 0), -1.0)]
    if a.startswith("put("):
        if h:
            return [(1.0, "done", 10.0)]
    return [(1.0, s, -1.0)]


def s_forbidden(s, a):
    k, h, g = s
    if a.startswith("put("):
        return a[4:-1] != k
    return (a == "pick" and k == "glass" and not g) or (a == "gloves_off" and h)


def s_facts(s):
    if s == "done":
        return "finished."
    k, h, g = s
    return " ".join([f"item({k})."] + (["holding."] if h else []) + (["gloved."] if g else []))


SORTER = SimpleNamespace(
    name="sorter",
    description="recycling sorter: an item of one of three kinds, gloves, three bins",
    states=s_states(),
    actions=["pick", "gloves_on", "gloves_off", "put(glass)", "put(paper)", "put(plastic)", "wait"],
    step=s_step,
    terminal=lambda s: s == "done",
    initial=lambda s: s != "done" and s[1:] == (0, 0),
    facts=s_facts,
    sname=lambda s: "done" if s == "done" else s_facts(s).replace(".", "").replace(" ", ","),
    forbidden=s_forbidden,
    background="""\
% sorter: bin(B) accepts kind B
bin(glass; paper; plastic).
wrong_bin(B) :- bin(B), item(K), B != K.
bare_hands :- item(_), not gloved.
""",
    bias="""\
#modeb(1, put(var(bin)), (positive)).
#modeb(1, wrong_bin(var(bin)), (positive)).
#modeb(1, item(const(kind)), (positive)).
#constant(kind, glass).
#constant(kind, paper).
#constant(kind, plastic).
#modeb(1, holding, (positive)).
#modeb(1, gloved, (positive)).
#modeb(1, bare_hands, (positive)).
#modeb(1, pick, (positive)).
#modeb(1, gloves_on, (positive)).
#modeb(1, gloves_off, (positive)).
#modeb(1, wait, (positive)).
#maxv(1).
""",
    truth="""\
:- put(B), wrong_bin(B).            % the bin of the item's kind
:- pick, item(glass), bare_hands.   % glass with gloves only
:- gloves_off, holding.
""",
)

def write_labeling(spec, folder: Path) -> None:
    """The folder's ``labeling.json`` (a table labeling, docs/FORMATS.md) and its key in domain.toml."""
    table = [[i, spec.label(s)] for i, s in enumerate(spec.states) if spec.label(s)]
    (folder / "labeling.json").write_text(json.dumps(
        {"symlearn": "labeling", "format_version": 1, "kind": "table",
         "propositions": [{"name": k, "meaning": v} for k, v in spec.labels.items()], "table": table}))
    with open(folder / "domain.toml", "a") as f:
        f.write('labeling = "labeling.json"\n')


SPECS = {"elevator": ELEVATOR, "warehouse": WAREHOUSE, "sorter": SORTER}


# ------------------------------------------------------------------- sub-goal tours (learn pdfa)
# A cook in a 2-D kitchen visits the fridge (0, 0), the stove (5, 0) and the table (2.5, 4), in
# one of three orders (60 / 30 / 10 %), lingering 6-10 steps at each, walking ~0.3 per step with
# noise; the state is (x, y, hand) with hand 1 while holding something (after the fridge).
STATIONS = {"fridge": (0.0, 0.0), "stove": (5.0, 0.0), "table": (2.5, 4.0)}
ORDERS = [(("fridge", "stove", "table"), 0.6), (("stove", "fridge", "table"), 0.3), (("fridge", "table", "stove"), 0.1)]


def tours(n, seed):
    from symlearn.data import Demonstrations, Trajectory
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        order = ORDERS[rng.choice(len(ORDERS), p=[p for _, p in ORDERS])][0]
        pos, hand, states = np.array([2.5, -2.0]) + rng.normal(0, 0.2, 2), 0.0, []
        for station in order:
            goal = np.array(STATIONS[station])
            while np.linalg.norm(goal - pos) > 0.3:
                pos = pos + 0.3 * (goal - pos) / np.linalg.norm(goal - pos) + rng.normal(0, 0.05, 2)
                states.append([*pos, hand])
            hand = 1.0 if station == "fridge" else hand
            for _ in range(int(rng.integers(6, 11))):
                states.append([*(goal + rng.normal(0, 0.05, 2)), hand])
        out.append(Trajectory(states=np.array(states)))
    return Demonstrations(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--betas", default="2")
    ap.add_argument("--domains", default=",".join(SPECS))
    args = ap.parse_args()
    from symlearn.grounding import Domain
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tours(args.n, args.seed).save(out / "cook_tours.jsonl")
    print(f"cook_tours.jsonl: {args.n} tours (x, y, hand)", flush=True)
    for name in args.domains.split(","):
        spec = SPECS[name]
        folder = write_domain(spec, out / name)
        if hasattr(spec, "label"):
            write_labeling(spec, folder)
        write_demonstration_sets(name, spec, Domain.from_folder(folder), out, args.n, args.seed, args.betas)


if __name__ == "__main__":
    main()
