"""Domain folders of the fourth sweep of users' files (issue 25): written as a user might write
them (CRLF, trailing blanks, comments in odd places, non-ASCII names and descriptions, negative
integers in facts and action atoms, string constants that look like variables, a 3-ary predicate
with constants in the bias), each with known truth rules, and demonstrations of experts that obey
them (value iteration on the allowed pairs: ``optimal`` with random ties, ``boltzmannB`` soft):

* ``freezer`` (41 x 7): a corridor -2..2 with a freezer behind a door; ``move(-1)``/``move(1)``;
  4 truth rules (``:- move(D), door_ahead(D), closed.``, ``:- open, alarm.``, ``:- drop, outside.``,
  ``:- pick, alarm.``); files with CRLF line endings;
* ``cards`` (17 x 5): a dealer robot, players ``"Alice"``/``"Bob"``, ``deal("Alice")``; 4 truth rules;
* ``warehouse3`` (65 x 5): shelves with ``slot(Shelf, Kind, Qty)`` facts; 3 truth rules, the
  empty-shelf and glass rules over the 3-ary predicate.

    python benchmarks/sweep4_domains.py OUT [--n 100] [--seed 0]
    symlearn learn constraints --domain OUT/freezer --demos OUT/freezer_boltzmann2.jsonl -o rules.lp

Results in docs/BENCHMARKS.md (issue 25, "Fourth sweep of users' files").
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.hidden_domains import build_arrays, demonstrations, python_truth  # noqa: E402


# ---- freezer: a 1-D corridor -2..2, freezer room at -2 behind a door between -2 and -1
def f_states():
    return [(x, h, d, al) for x in range(-2, 3) for h in (0, 1) for d in (0, 1) for al in (0, 1)] + ["done"]


def f_step(s, a):
    x, h, d, al = s
    alarm = [(0.8, al), (0.2, 1 - al)]
    x2, h2, d2 = x, h, d
    if a.startswith("move("):
        t = x + int(a[5:-1])
        if not -2 <= t <= 2:
            return None
        x2 = t
    elif a == "pick":
        if x == 2 and not h:
            h2 = 1
    elif a == "drop":
        if h:
            return [(1.0, "done", 10.0)]
    elif a == "open":
        if x in (-2, -1):
            d2 = 1
    elif a == "close":
        if x in (-2, -1):
            d2 = 0
    return [(p, (x2, h2, d2, na), -1.0) for p, na in alarm]


def f_forbidden(s, a):
    x, h, d, al = s
    if a.startswith("move(") and ((x == -1 and a == "move(-1)") or (x == -2 and a == "move(1)")) and not d:
        return True
    if a == "open" and al:
        return True
    if a == "drop" and x > -2:
        return True
    if a == "pick" and al:
        return True
    return False


def f_facts(s):
    if s == "done":
        return "finished."
    x, h, d, al = s
    return " ".join([f"at({x})."] + (["holding."] if h else []) + [f"door({'open' if d else 'shut'})."] + (["alarm."] if al else []))


FREEZER = SimpleNamespace(
    name="freezer", states=f_states(), actions=["move(-1)", "move(1)", "pick", "drop", "open", "close", "wait"],
    step=f_step, terminal=lambda s: s == "done",
    initial=lambda s: s != "done" and s[1] == 0 and s[3] == 0 and s[0] >= 0,
    facts=f_facts, forbidden=f_forbidden,
    sname=lambda s: "fertig ✓" if s == "done" else f"x={s[0]}{' 📦' if s[1] else ''}{' door' if s[2] else ''}{' ⚠' if s[3] else ''}",
)
BK_F = """% freezer corridor: cells -2..2   \r
% cell(X, Kind, Temperature): a 3-ary fact per cell, temperatures below zero\r
cell(-2, freezer, -18). cell(-1, hall, 4). cell(0, hall, 20).   % trailing comment\r
cell(1, hall, 20). cell(2, dock, 15).\r
dir(-1; 1).\r
door_ahead(D) :- at(X), dir(D), cell(X, K1, _), cell(X + D, K2, _), K1 != K2, freezer = (K1; K2).\r
closed :- door(shut).\r
outside :- at(X), cell(X, K, _), K != freezer.   \r
calm :- at(_), not alarm.\r
cold(T) :- at(X), cell(X, _, T), T < 0.\r
"""
BIAS_F = """% bias — ünïcode in a comment\r
#modeb(1, move(var(dir)), (positive)).   \r
#modeb(1, door_ahead(var(dir)), (positive)).\r
#modeb(1, closed, (positive)).\r
#modeb(1, outside, (positive)).\r
#modeb(1, alarm, (positive)).\r
#modeb(1, calm, (positive)).\r
#modeb(1, holding, (positive)).\r
#modeb(1, pick, (positive)).\r
#modeb(1, drop, (positive)).\r
#modeb(1, open, (positive)).\r
#modeb(1, close, (positive)).\r
#modeb(1, wait, (positive)).\r
#maxv(1).\r
"""
TRUTH_F = """:- move(D), door_ahead(D), closed.   % never walk into the shut door\r
:- open, alarm.                       % doors stay shut during an alarm\r
:- drop, outside.                     % the box goes into the freezer only\r
:- pick, alarm.\r
"""

# ---- card table: a dealer robot, players named by strings that look like variables
def c_states():
    return [(t, k, sh) for t in ("Alice", "Bob") for k in range(4) for sh in (0, 1)] + ["done"]


def c_step(s, a):
    t, k, sh = s
    other = "Bob" if t == "Alice" else "Alice"
    if a.startswith("deal("):
        if k == 0:
            return [(1.0, s, -1.0)]
        return [(1.0, (other, k - 1, sh), -1.0)]
    if a == "shuffle":
        return [(1.0, (t, k, 1), -1.0)]
    if a == "finish":
        return [(1.0, "done", 10.0)]
    return [(0.5, (t, k, sh), -1.0), (0.5, (other, k, sh), -1.0)]


def c_forbidden(s, a):
    t, k, sh = s
    if a.startswith("deal("):
        p = a[6:-2]
        return p != t or k == 0 or not sh
    if a == "finish":
        return k > 0
    return False


def c_facts(s):
    if s == "done":
        return "over."
    t, k, sh = s
    return f'turn("{t}"). deck({k}).' + (" shuffled." if sh else "")


CARDS = SimpleNamespace(
    name="cards", states=c_states(), actions=['deal("Alice")', 'deal("Bob")', "shuffle", "finish", "wait"],
    step=c_step, terminal=lambda s: s == "done", initial=lambda s: s != "done" and s[1] == 3 and s[2] == 0,
    facts=c_facts, forbidden=c_forbidden,
    sname=lambda s: "over" if s == "done" else f"{s[0]}’s turn, {s[1]} cards{', shuffled' if s[2] else ''}",
)
BK_C = """player("Alice"). player("Bob").
waiting(P) :- player(P), turn(Q), P != Q.
empty_deck :- deck(0).
cards_left :- deck(N), N > 0.
unshuffled :- deck(_), not shuffled.
"""
BIAS_C = """#modeb(1, deal(var(player)), (positive)).
#modeb(1, waiting(var(player)), (positive)).
#modeb(1, turn(var(player)), (positive)).
#modeb(1, empty_deck, (positive)).
#modeb(1, cards_left, (positive)).
#modeb(1, unshuffled, (positive)).
#modeb(1, shuffled, (positive)).
#modeb(1, shuffle, (positive)).
#modeb(1, finish, (positive)).
#modeb(1, wait, (positive)).
#maxv(1).
"""
TRUTH_C = """:- deal(P), waiting(P).
:- deal(P), empty_deck.
:- deal(P), unshuffled.
:- finish, cards_left.
"""

def write(spec, bk, bias, truth, folder, crlf):
    """The folder as a user might write it: CRLF where ``crlf``, names and descriptions not ASCII."""
    folder.mkdir(parents=True, exist_ok=True)
    nl = "\r\n" if crlf else "\n"
    (folder / "bk.lp").write_bytes(bk.encode())
    (folder / "bias.las").write_bytes(bias.encode())
    (folder / "truth.lp").write_bytes(truth.encode())
    arrays = build_arrays(spec)
    np.savez(folder / "model.npz", **arrays)
    (folder / "states.jsonl").write_bytes("".join(json.dumps({"id": i, "facts": spec.facts(s), "name": spec.sname(s)}, ensure_ascii=False) + nl for i, s in enumerate(spec.states)).encode())
    (folder / "actions.jsonl").write_bytes("".join(json.dumps({"id": i, "atom": a}) + nl for i, a in enumerate(spec.actions)).encode())
    (folder / "domain.toml").write_bytes((f'# my {spec.name} domain  {nl}name = "{spec.name} — ünïcode"   # a comment{nl}background = "bk.lp"{nl}bias = "bias.las"{nl}'
        f'model = "model.npz"{nl}states = "states.jsonl"{nl}actions = "actions.jsonl"{nl}truth = "truth.lp"{nl}').encode())
    return arrays


# ---- warehouse3: shelves 1..3 (bolt, glass, nut) with stock 0/1 each, dock at 0; slot(Shelf, Kind, Qty)
KIND = {1: "bolt", 2: "glass", 3: "nut"}


def w_states():
    return [(p, h, q) for p in range(4) for h in (0, 1) for q in itertools.product((0, 1), repeat=3)] + ["done"]


def w_step(s, a):
    p, h, q = s
    if a.startswith("move("):
        t = p + int(a[5:-1])
        if not 0 <= t <= 3:
            return None
        return [(1.0, (t, h, q), -1.0)]
    if a == "pick":
        if p >= 1 and q[p - 1] and not h:
            q2 = list(q); q2[p - 1] = 0
            return [(1.0, (p, 1, tuple(q2)), -1.0)]
        return [(1.0, s, -1.0)]
    if a == "drop":
        if h:
            return [(1.0, "done", 10.0)]
        return [(1.0, s, -1.0)]
    return [(1.0, s, -1.0)]


def w_forbidden(s, a):
    p, h, q = s
    if a == "pick" and p >= 1 and (q[p - 1] == 0 or KIND[p] == "glass"):
        return True
    if a == "drop" and p != 0:
        return True
    return False


def w_facts(s):
    if s == "done":
        return "delivered."
    p, h, q = s
    return " ".join([f"at({p})."] + (["holding."] if h else []) + [f"slot({i}, {KIND[i]}, {q[i - 1]})." for i in (1, 2, 3)])


WH = SimpleNamespace(name="warehouse3", states=w_states(), actions=["move(-1)", "move(1)", "pick", "drop", "wait"],
    step=w_step, terminal=lambda s: s == "done", initial=lambda s: s != "done" and s[0] == 0 and s[1] == 0 and (s[2][0] or s[2][2]),
    facts=w_facts, forbidden=w_forbidden, sname=lambda s: "done" if s == "done" else f"at {s[0]}{' carrying' if s[1] else ''} stock {''.join(map(str, s[2]))}")


BK_W = "dock(0).\noff_dock :- at(P), not dock(P).\non_dock :- at(P), dock(P).\n"
BIAS_W = """#modeb(1, pick, (positive)).
#modeb(1, drop, (positive)).
#modeb(1, move(var(d)), (positive)).
#modeb(1, at(var(pos)), (positive)).
#modeb(1, slot(var(pos), const(kind), const(qty)), (positive)).
#modeb(1, off_dock, (positive)).
#modeb(1, holding, (positive)).
#constant(kind, bolt). #constant(kind, glass). #constant(kind, nut).
#constant(qty, 0). #constant(qty, 1).
#maxv(1).
"""
TRUTH_W = ":- pick, at(P), slot(P, K, 0).\n:- pick, at(P), slot(P, glass, Q).\n:- drop, off_dock.\n"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    from symlearn.grounding import Domain

    out = Path(args.out)
    for spec, bk, bias, truth, crlf in [(FREEZER, BK_F, BIAS_F, TRUTH_F, True), (CARDS, BK_C, BIAS_C, TRUTH_C, False),
                                        (WH, BK_W, BIAS_W, TRUTH_W, False)]:
        arrays = write(spec, bk, bias, truth, out / spec.name, crlf)
        d = Domain.from_folder(out / spec.name)
        py = python_truth(spec, arrays)
        assert np.array_equal(py, d.truth_forbidden & ~d.unavailable), spec.name
        forbidden = d.truth_forbidden | d.unavailable
        print(f"{spec.name}: {d.n_states} states x {d.n_actions} actions, {int(py.sum())} pairs forbidden by the truth")
        for label, beta in [("optimal", None), ("boltzmann2", 2.0), ("boltzmann5", 5.0)]:
            demos, cut = demonstrations(spec, arrays, forbidden, args.n, args.seed, beta)
            demos.save(out / f"{spec.name}_{label}.jsonl")
            print(f"  {label}: {sum(len(t.actions) for t in demos)} steps, {cut} cut at 100 steps")


if __name__ == "__main__":
    main()
