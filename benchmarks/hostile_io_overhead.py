"""What the hostile-input checks cost on valid input: readers and guard printing in two trees.

Each workload runs in a child process per source tree, alternating trees ``--rounds`` times (so
machine load hits both alike); the best time per workload and tree is kept:

* ``jsonl``: read 2000 demonstrations (50 steps, discrete states, symbol actions, labels, info)
  written as JSONL (size cap, UTF-8 check, duplicate-key hook, dtype and depth checks);
* ``npz``: the same as NPZ (member headers read and row counts checked before decompressing);
* ``automaton``: load the JSON of the 256-state DFA of ``F p0 & ... & F p7`` (guards parsed);
* ``guards``: print every guard of the DFAs of 12 Dwyer-style formulas and of ``F p0 & ... & F p7``
  from a fresh process (sum-of-products printing, cube fast path, factored fallback).

Make the "before" tree without touching the working copy::

    mkdir -p /tmp/before && git archive HEAD symlearn grammars | tar -x -C /tmp/before
    .venv/bin/python benchmarks/hostile_io_overhead.py /tmp/before . --rounds 5

writes ``benchmarks/results/hostile_io_overhead.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve()

FORMULAS = ["G(p -> F q)", "F p & G !q", "G(p -> X q)", "p U q", "(p U q) & G(r -> F s)", "F(p & X F q)",
            "G(p -> (q U r))", "!(F p) | F(p & F q)", "G F p & G F q", "(a T b) & G !c", "F(a & X(b U c))",
            "G(a -> X X b)"]

CHILD = r"""
import json, sys, time
from pathlib import Path
work = Path(sys.argv[1]); which = sys.argv[2]

def best(fn, repeat=3):
    result = float("inf")
    for _ in range(repeat):
        start = time.perf_counter(); fn(); result = min(result, time.perf_counter() - start)
    return result

if which in ("jsonl", "npz"):
    from symlearn.data import load
    print(json.dumps(best(lambda: load(work / f"demos.{which}"))))
elif which == "automaton":
    from symlearn.logic.automata import load_automaton
    from symlearn.logic import guards
    def run():
        guards._parse_cached.cache_clear()
        load_automaton(work / "dfa.json")
    print(json.dumps(best(run)))
else:
    from symlearn.logic.ltlf import parse, to_dfa
    dfas = [to_dfa(parse(f)) for f in json.loads(sys.argv[3])]
    start = time.perf_counter()
    n = sum(len(str(g)) for d in dfas for q in d.states for g, _ in d.successors(q))
    print(json.dumps(time.perf_counter() - start))
"""


def prepare(work: Path) -> None:
    import random

    from symlearn.data import Demonstrations, Trajectory
    from symlearn.logic.ltlf import parse, to_dfa

    rng = random.Random(0)
    trajectories = []
    for i in range(2000):
        states = [rng.randrange(64) for _ in range(50)]
        trajectories.append(Trajectory(states=states, actions=[f"go({rng.choice('nesw')})" for _ in range(49)],
                                       labels=[["hole"] if s % 7 == 0 else [] for s in states], info={"seed": i}))
    demos = Demonstrations(trajectories)
    demos.save(work / "demos.jsonl")
    demos.save(work / "demos.npz")
    (work / "dfa.json").write_text(to_dfa(parse(" & ".join(f"F p{i}" for i in range(8)))).to_json())


def run(tree: Path, work: Path, which: str) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree.resolve()), SYMLEARN_QUIET="1")
    formulas = FORMULAS + [" & ".join(f"F p{i}" for i in range(8))]
    out = subprocess.run([sys.executable, "-c", CHILD, str(work), which, json.dumps(formulas)], env=env,
                         capture_output=True, text=True, check=True, cwd=work)
    return float(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--out", type=Path, default=HERE.parent / "results" / "hostile_io_overhead.json")
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="symlearn-overhead-"))
    prepare(work)
    times: dict[str, dict[str, float]] = {}
    for _ in range(args.rounds):
        for which in ("jsonl", "npz", "automaton", "guards"):
            for label, tree in (("before", args.before), ("after", args.after)):
                value = run(tree, work, which)
                slot = times.setdefault(which, {})
                slot[label] = min(slot.get(label, float("inf")), value)
    rows = {k: {**v, "ratio_after_before": round(v["after"] / v["before"], 3)} for k, v in times.items()}
    report = {"command": "python benchmarks/hostile_io_overhead.py " + " ".join(sys.argv[1:] if argv is None else argv),
              "machine": platform.platform(), "python": platform.python_version(), "cpus": os.cpu_count(),
              "rounds": args.rounds, "seconds": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1) + "\n")
    for which, row in rows.items():
        print(f"{which:10s} before {row['before'] * 1000:9.1f} ms  after {row['after'] * 1000:9.1f} ms  "
              f"ratio {row['ratio_after_before']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
