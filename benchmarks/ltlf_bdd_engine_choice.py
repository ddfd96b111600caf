"""Which BDD engine for the LTLf -> DFA translation: ours (symlearn/logic/bdd.py), dd's pure-Python
``autoref`` or dd's CUDD bindings (``dd.cudd``), on the translation's own workload.

The translation of ``F p1 & ... & F pn`` does two things per state S (a set of pending ``F``
obligations, 2^n states):

* **compose**: its transition function ``T_S = AND_{i in S} (p_i | f_i)`` with the letter's
  propositions ``p_*`` above the obligations ``f_*`` (built as ``(p_i | f_i) & T_{S - {i}}`` for
  the smallest ``i``, each ``T`` once, as the translation's memo does);
* **walk**: the proposition layer of ``T_S``, each node once overall, collecting the successor
  obligations (the first nodes below the layer) — what becomes the transition diagram.

Every engine does exactly this work, in one process, engines interleaved per repetition (best
of ``--repeat``). dd is optional: ``pip install dd==0.6.0`` (its wheel includes CUDD).

    nice -n 10 .venv/bin/python benchmarks/ltlf_bdd_engine_choice.py --n 10,12,14 \\
        --json benchmarks/results/ltlf_bdd_engine_choice.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))


def subsets_by_size(n: int) -> list[tuple[int, ...]]:
    import itertools

    return [s for k in range(n + 1) for s in itertools.combinations(range(n), k)]


def run_ours(n: int) -> dict:
    from symlearn.logic.bdd import BDD, TRUE

    bdd = BDD()
    p = [bdd.var(i) for i in range(n)]
    f = [bdd.var(n + i) for i in range(n)]
    start = time.perf_counter()
    memo = {(): TRUE}
    for s in subsets_by_size(n):
        if s:
            memo[s] = bdd.apply_and(bdd.apply_or(p[s[0]], f[s[0]]), memo[s[1:]])
    composed = time.perf_counter()
    level, low, high = bdd.level, bdd.low, bdd.high
    seen, leaves = set(), set()
    for s in memo:
        stack = [memo[s]]
        while stack:
            u = stack.pop()
            if u <= TRUE or level[u] >= n:
                leaves.add(u)
            elif u not in seen:
                seen.add(u)
                stack.append(low[u])
                stack.append(high[u])
    walked = time.perf_counter()
    return {"compose_s": composed - start, "walk_s": walked - composed, "layer_nodes": len(seen),
            "successors": len(leaves)}


def run_dd(n: int, module) -> dict:
    bdd = module.BDD()
    names = [f"p{i}" for i in range(n)] + [f"f{i}" for i in range(n)]
    bdd.declare(*names)
    bdd.reorder({name: i for i, name in enumerate(names)})  # the translation's order, kept fixed
    if hasattr(bdd, "configure"):
        try:
            bdd.configure(reordering=False)
        except Exception:  # pragma: no cover - engines without the option
            pass
    p = [bdd.var(f"p{i}") for i in range(n)]
    f = [bdd.var(f"f{i}") for i in range(n)]
    start = time.perf_counter()
    memo = {(): bdd.true}
    for s in subsets_by_size(n):
        if s:
            memo[s] = (p[s[0]] | f[s[0]]) & memo[s[1:]]
    composed = time.perf_counter()
    seen, leaves = set(), set()
    for s in memo:
        stack = [memo[s]]
        while stack:
            u = stack.pop()
            if u.var is None or u.level >= n:  # a constant, or the first obligation node
                leaves.add(u)
            elif u not in seen:
                seen.add(u)
                # dd's low/high of a complemented edge are the complemented children (CUDD)
                stack.append(u.low)
                stack.append(u.high)
    walked = time.perf_counter()
    return {"compose_s": composed - start, "walk_s": walked - composed, "layer_nodes": len(seen),
            "successors": len(leaves)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", default="10,12,14")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    engines = {"ours": run_ours}
    try:
        import dd.autoref

        engines["dd.autoref (pure Python)"] = lambda n: run_dd(n, dd.autoref)
    except ImportError:
        print("dd not installed: pip install dd==0.6.0", file=sys.stderr)
    try:
        import dd.cudd

        engines["dd.cudd (CUDD)"] = lambda n: run_dd(n, dd.cudd)
    except ImportError:
        pass
    rows = []
    print(f"# {' '.join(sys.argv)}  (load average {os.getloadavg()})")
    print("| n | engine | compose s | walk s | total s | layer nodes | successors |")
    print("|---|---|---|---|---|---|---|")
    for n in map(int, args.n.split(",")):
        best: dict[str, dict] = {}
        for _ in range(args.repeat):
            for name, run in engines.items():
                got = run(n)
                got["total_s"] = got["compose_s"] + got["walk_s"]
                if name not in best or got["total_s"] < best[name]["total_s"]:
                    best[name] = got
        for name, got in best.items():
            rows.append({"n": n, "engine": name, **got})
            print(f"| {n} | {name} | {got['compose_s']:.3f} | {got['walk_s']:.3f} | {got['total_s']:.3f} | "
                  f"{got['layer_nodes']} | {got['successors']} |", flush=True)
    if args.json:
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "machine": platform.machine(),
                                         "python": platform.python_version(), "load_average": os.getloadavg(),
                                         "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
