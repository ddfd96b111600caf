"""Why the one BDD engine runs as two kinds of manager, and what collecting the guard table costs.

symlearn has one ROBDD engine (:mod:`symlearn.logic.bdd`). Guards share one manager for the
whole process; the LTLf -> DFA translation uses a fresh manager per formula. This script
measures, in one run:

1. **Translation manager versus guard table.** For every formula of the LTLf -> DFA benchmark
   families (benchmarks/ltlf_to_dfa.py, including the 201 formulas of the public LTLf learning
   benchmark): the nodes the translation's own manager holds when it is done, and the nodes of
   the edge guards it hands to the shared table. Translating inside the shared table would add
   the first number to it on every call.
2. **A long run.** A stream of random formulas over a pool of propositions is translated and
   each DFA dropped, once with the guard table's collection on (the default) and once with it
   off, each in a fresh process: table size and memory at the end (the table's own structures,
   by ``sys.getsizeof``), peak memory of the process (RSS) and total time.

    .venv/bin/python benchmarks/bdd_engines.py            # about a minute
    .venv/bin/python benchmarks/bdd_engines.py --quick    # collection threshold lowered to 2^14
"""

from __future__ import annotations

import argparse
import json
import platform
import random
import resource
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))


def families(quick: bool) -> dict[str, list]:
    import ltlf_to_dfa as bench

    from symlearn.logic.ltlf import parse

    texts = {
        "conjunctions of n F": bench.conjunctions_of_f(5 if quick else 8),
        "chains of n T": bench.chains_of_t(6 if quick else 10),
        "task templates": bench.task_templates(3 if quick else 6),
        "Dwyer patterns": bench.DWYER,
        "random, k <= 30 operators": bench.random_family([5, 10, 15, 20, 25, 30], 3 if quick else 8, seed=2026),
    }
    out = {name: [parse(t) for t in ts] for name, ts in texts.items()}
    if bench.FORMULAS_TXT.is_file():
        lines = [line.strip() for line in bench.FORMULAS_TXT.read_text().splitlines() if line.strip()]
        out["LTLf learning benchmark (spot)"] = [parse(t, "spot") for t in (lines[::10] if quick else lines)]
    return out


def guard_nodes(dfa) -> int:
    """Distinct nodes of the shared table reachable from the DFA's edge guards."""
    from symlearn.logic import guards

    seen, stack = set(), [g._node for _, g, _ in dfa.edges()]
    while stack:
        u = stack.pop()
        if u > 1 and u not in seen:
            seen.add(u)
            stack += [guards._low[u], guards._high[u]]
    return len(seen)


def translation_versus_guards(quick: bool) -> list[dict]:
    from symlearn.logic.ltlf.to_dfa import DEFAULT_MAX_STATES, _Translation

    rows = []
    for name, formulas in families(quick).items():
        translation_nodes = produced = 0
        for f in formulas:
            translation = _Translation(f)
            dfa = translation.build(DEFAULT_MAX_STATES)
            translation_nodes += len(translation.bdd) - 2
            produced += guard_nodes(dfa)
        rows.append({"family": name, "formulas": len(formulas), "translation_nodes": translation_nodes,
                     "guard_nodes": produced, "ratio": translation_nodes / max(1, produced)})
    return rows


def table_bytes() -> int:
    """Bytes held by the shared guard table: node lists, unique table, caches, guard registry."""
    from symlearn.logic import guards

    m = guards._MANAGER
    total = sum(sys.getsizeof(x) for x in (m.level, m.low, m.high))
    for table in (m._unique, m._and, m._or, m._not, m._support, guards._guards, guards._text_cache,
                  guards._label_cache, guards._key_cache):
        total += sys.getsizeof(table)
        for key, value in table.items():
            total += sys.getsizeof(key) if isinstance(key, tuple) else 0
            total += sys.getsizeof(value) if not isinstance(value, int) else 0
    return total


def stream(n_formulas: int, collect: bool, collect_from: int) -> dict:
    """Translate random formulas, dropping each DFA; report the guard table and the peak memory."""
    import ltlf_to_dfa as bench

    from symlearn.errors import LimitExceededError
    from symlearn.logic import guards
    from symlearn.logic.ltlf import translate

    guards._COLLECT_FROM = guards._collect_at = collect_from if collect else float("inf")
    rng = random.Random(7)
    pool = [f"q{i}" for i in range(40)]
    largest = too_large = 0
    start = time.perf_counter()
    for _ in range(n_formulas):
        f = bench.random_formula(rng, 12, tuple(rng.sample(pool, 10)))
        try:
            translate(f, max_states=2000)
        except LimitExceededError:
            too_large += 1
        largest = max(largest, guards.node_count())
    seconds = time.perf_counter() - start
    return {"collect": collect, "formulas": n_formulas, "over_2000_states": too_large, "seconds": seconds,
            "final_nodes": guards.node_count(), "largest_nodes": largest, "table_mb": table_bytes() / 2 ** 20,
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="fewer formulas")
    parser.add_argument("--json", type=Path, help="also write the results to this JSON file")
    parser.add_argument("--stream", choices=["on", "off"], help=argparse.SUPPRESS)  # one child process
    parser.add_argument("--formulas", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--collect-from", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.stream:
        print(json.dumps(stream(args.formulas, args.stream == "on", args.collect_from)))
        return

    print(f"# {' '.join(sys.argv)}")
    print(f"# machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}")
    rows = translation_versus_guards(args.quick)
    print("\n## nodes left in the translation's manager vs guard nodes it produces")
    for r in rows:
        print(f"   {r['family']:32s} {r['formulas']:4d} formulas: {r['translation_nodes']:8d} vs "
              f"{r['guard_nodes']:7d} guard nodes ({r['ratio']:.1f}x)")
    total_t = sum(r["translation_nodes"] for r in rows)
    total_g = sum(r["guard_nodes"] for r in rows)
    print(f"   all: {total_t} vs {total_g} ({total_t / total_g:.1f}x)")

    from symlearn.logic.guards import _COLLECT_FROM

    # the quick run is too short to reach the default threshold: it lowers it to show the mechanism
    n, collect_from = (3000, 1 << 14) if args.quick else (12000, _COLLECT_FROM)
    runs = []
    for mode in ("on", "off"):
        out = subprocess.run([sys.executable, __file__, "--stream", mode, "--formulas", str(n),
                              "--collect-from", str(collect_from)], capture_output=True, text=True, check=True).stdout
        runs.append(json.loads(out))
    on, off = runs
    print(f"\n## {n} random formulas (12 operators, 10 of 40 propositions), each DFA dropped; "
          f"collection from {collect_from} nodes")
    for r in runs:
        print(f"   collection {'on ' if r['collect'] else 'off'}: {r['seconds']:.2f} s, table {r['final_nodes']} nodes "
              f"({r['table_mb']:.0f} MB) at the end (largest {r['largest_nodes']}), peak RSS {r['peak_rss_mb']:.0f} MB")
    print(f"   collection: {off['final_nodes'] / on['final_nodes']:.1f}x fewer nodes and "
          f"{off['table_mb'] / on['table_mb']:.1f}x less table memory at the end, "
          f"time ratio on/off {on['seconds'] / off['seconds']:.3f}")
    if args.json:
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "translation_vs_guards": rows,
                                         "stream": runs}, indent=1) + "\n")


if __name__ == "__main__":
    main()
