"""The kitchen domain folder of the fifth sweep of users' files (issue 25): a robot carries an
egg, a pan or a glass between fridge, counter, stove and sink; two of its three truth rules join
an object and a place through two variables, so they have 5 body literals, beyond the ILP's default
of 3 (``learn constraints --max-body``):

    :- put, at(P), hot(P), holding(O), fragile(O).     % nothing fragile on the stove
    :- take(O), busy.                                  % one thing at a time
    :- put, at(P), wet(P), holding(O), metal(O).       % no pan into the sink

Experts (value iteration on the allowed pairs, as ``benchmarks/hidden_domains.py``): ``optimal``
(random ties), ``b2`` (Boltzmann 2), ``few`` (3 Boltzmann-2 episodes), ``noisy`` (Boltzmann 2, but
3 % of the steps a random available move: a few break the rules). The script checks that
``truth.lp`` forbids exactly what the Python rules do.

    python benchmarks/sweep5_kitchen.py OUT
    symlearn learn constraints --domain OUT/kitchen --demos OUT/kitchen_b2.jsonl --max-body 5 --json

Results in docs/BENCHMARKS.md ("Fifth sweep of users' files").
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.hidden_domains import build_arrays, demonstrations, python_truth, q_values  # noqa: E402

PLACES = {0: "fridge", 1: "counter", 2: "stove", 3: "sink"}
OBJECTS = ["egg", "pan", "glass"]


def states():
    return [(p, h, d) for p in range(4) for h in ["none"] + OBJECTS for d in (0, 1)] + ["end"]


def step(s, a):
    p, h, d = s
    if a.startswith("move("):
        t = p + int(a[5:-1])
        return None if not 0 <= t <= 3 else [(1.0, (t, h, d), -1.0)]
    if a.startswith("take("):
        return [(1.0, s if p != 0 else (p, a[5:-1], d), -1.0)]
    if a == "put":
        if h == "none":
            return [(1.0, s, -1.0)]
        if p == 2 and h in ("pan", "egg"):
            return [(1.0, "end", 10.0 if h == "pan" else 12.0)]
        return [(1.0, (p, "none", d), -0.5)]
    return [(1.0, s, -1.0)]


def forbidden(s, a):
    p, h, _ = s
    return ((a == "put" and h in ("egg", "glass") and PLACES[p] == "stove") or (a.startswith("take(") and h != "none")
            or (a == "put" and h == "pan" and PLACES[p] == "sink"))


def facts(s):
    if s == "end":
        return "served."
    p, h, d = s
    return " ".join([f"at({PLACES[p]})."] + ([f"holding({h})."] if h != "none" else []) + (["dirty."] if d else []))


SPEC = SimpleNamespace(
    name="kitchen", states=states(), actions=["move(-1)", "move(1)", "take(egg)", "take(pan)", "take(glass)", "put", "wait"],
    step=step, terminal=lambda s: s == "end", initial=lambda s: s != "end" and s[1] == "none", facts=facts,
    forbidden=forbidden, sname=lambda s: "end" if s == "end" else f"{PLACES[s[0]]}/{s[1]}/{'dirty' if s[2] else 'clean'}")
BK = ("place(fridge; counter; stove; sink).\nhot(stove). wet(sink).\nfragile(egg). fragile(glass). metal(pan).\n"
      "busy :- holding(_).\n")
BIAS = "".join(f"#modeb(1, {m}, (positive)).\n" for m in [
    "put", "take(var(obj))", "at(var(place))", "holding(var(obj))", "fragile(var(obj))", "metal(var(obj))",
    "hot(var(place))", "wet(var(place))", "busy", "dirty"]) + "#maxv(2).\n"
TRUTH = (":- put, at(P), hot(P), holding(O), fragile(O).\n:- take(O), busy.\n"
         ":- put, at(P), wet(P), holding(O), metal(O).\n")


def noisy(arrays, forbid, n, seed, slip=0.03, beta=2.0):
    """Boltzmann-``beta`` episodes where each step is, with probability ``slip``, a random available move."""
    from symlearn.data import Demonstrations, Trajectory

    rng = np.random.default_rng(seed)
    Q = q_values(arrays, forbid, beta)
    P, out, broken = arrays["transitions"], [], 0
    for _ in range(n):
        s = int(rng.choice(len(arrays["initial"]), p=arrays["initial"]))
        states_, actions = [s], []
        while not arrays["terminal"][s] and len(actions) < 100:
            if rng.random() < slip:
                a = int(rng.choice(np.flatnonzero(arrays["available"][s])))
                broken += bool(forbid[s, a])
            else:
                w = np.exp(beta * (Q[s] - Q[s].max()))
                a = int(rng.choice(len(w), p=w / w.sum()))
            s = int(rng.choice(P.shape[0], p=P[s, a]))
            states_.append(s)
            actions.append(SPEC.actions[a])
        out.append(Trajectory(states=states_, actions=actions))
    return Demonstrations(out), broken


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    args = ap.parse_args()
    from symlearn.grounding import Domain

    out = Path(args.out)
    folder = out / "kitchen"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "bk.lp").write_text(BK)
    (folder / "bias.las").write_text(BIAS)
    (folder / "truth.lp").write_text(TRUTH)
    arrays = build_arrays(SPEC)
    np.savez(folder / "model.npz", **arrays)
    (folder / "states.jsonl").write_text("".join(json.dumps({"id": i, "facts": facts(s), "name": SPEC.sname(s)}) + "\n"
                                                 for i, s in enumerate(SPEC.states)))
    (folder / "actions.jsonl").write_text("".join(json.dumps({"id": i, "atom": a}) + "\n"
                                                  for i, a in enumerate(SPEC.actions)))
    (folder / "domain.toml").write_text('name = "kitchen"\nbackground = "bk.lp"\nbias = "bias.las"\nmodel = "model.npz"\n'
                                        'states = "states.jsonl"\nactions = "actions.jsonl"\ntruth = "truth.lp"\n')
    d = Domain.from_folder(folder)
    py = python_truth(SPEC, arrays)
    assert np.array_equal(py, d.truth_forbidden & ~d.unavailable)
    forbid = d.truth_forbidden | d.unavailable
    print(f"kitchen: {d.n_states} states x {d.n_actions} actions, {int(py.sum())} pairs forbidden by the truth")
    for label, beta, n in [("optimal", None, 100), ("b2", 2.0, 100), ("few", 2.0, 3)]:
        demos, _ = demonstrations(SPEC, arrays, forbid, n, 0, beta)
        demos.save(out / f"kitchen_{label}.jsonl")
        print(f"  {label}: {len(demos)} episodes, {sum(len(t.actions) for t in demos)} steps")
    demos, broken = noisy(arrays, forbid, 100, 1)
    demos.save(out / "kitchen_noisy.jsonl")
    print(f"  noisy: {len(demos)} episodes, {sum(len(t.actions) for t in demos)} steps, {broken} break a truth rule")


if __name__ == "__main__":
    main()
