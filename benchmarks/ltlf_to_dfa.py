"""LTLf -> minimal DFA: symlearn's symbolic progression versus LTLf2DFA + MONA, in one run.

For every formula of every family we measure

* ``ours``      symlearn.logic.ltlf.translate (best of 3 runs), minimal complete DFA;
* ``ltlf2dfa``  LTLf2DFA's own ``to_dfa`` (parse, MONA program, MONA, DOT with sympy guards):
                the peer as its users run it;
* ``mona``      the same MONA program run by us and its table read back without sympy
                (the fastest way to use MONA through LTLf2DFA);

and check that the two minimal DFAs have the same language and the same number of states
(MONA's automaton has one extra start state; see symlearn/logic/ltlf/mona.py).

Families: conjunctions of n ``F``; chains of n ``T``; task templates ``G(!x) & (a T b) & ...``;
Dwyer specification patterns (the 9 flie formulas and the classic scoped patterns); random
formulas with k operators (k <= 30); and, separately, the 201 formulas of the public LTLf
learning benchmark (Spot dialect; includes formulas far beyond 30 operators).

    .venv/bin/python benchmarks/ltlf_to_dfa.py            # full run (a few minutes)
    .venv/bin/python benchmarks/ltlf_to_dfa.py --quick    # smaller families
"""

from __future__ import annotations

import argparse
import json
import platform
import random
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "tests" / "support"))

from symlearn.logic.ltlf import operator_count, parse, translate  # noqa: E402
from symlearn.logic.ltlf.ast import (  # noqa: E402
    FALSE, TRUE, Always, And, Eventually, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until, WeakNext,
)
from symlearn.logic.ltlf.mona import ltlf2dfa_dot, mona_dfa  # noqa: E402

FORMULAS_TXT = REPO.parent / "shared" / "benchmarks" / "ltlf_learning" / "formulas.txt"

DWYER = [  # the 9 flie / samples2LTL formulas, then classic scoped patterns (Dwyer et al.)
    "F(p)", "G(p)", "G(!(p))", "G(q -> G(p))", "G(q -> G(!(p)))", "F(q) -> (p U q)", "F(p) -> (!(p) U q)",
    "G(!(p)) | F(p & F(q))", "G(p & (!(q) -> (!q) U (r & !(q))))",
    "F r -> (!p U r)", "G(q -> G !p)", "G(q & !r & F r -> (!p U r))", "G(q & !r -> (!p W r))",
    "!r W (p & !r)", "G(q & !r -> (!r W (p & !r)))", "G(p -> F s)", "F r -> (p -> (!r U (s & !r))) U r",
    "G(q & !r -> ((p -> (!r U (s & !r))) W r))", "!p W s", "F r -> (!p U (s | r))",
    "G((q & F r) -> (!p U (s | r)))", "G(p -> F(s & F t))", "G(q -> G(p -> F s))",
]


def conjunctions_of_f(n_max):
    return [" & ".join(f"F p{i}" for i in range(n)) for n in range(1, n_max + 1)]


def chains_of_t(n_max):
    return [" T ".join(f"p{i}" for i in range(n)) for n in range(2, n_max + 1)]


def task_templates(n_max):
    out = []
    for n in range(1, n_max + 1):
        parts = [f"G(!x{i})" for i in range(max(1, n // 2))]
        parts += [f"(a{i} T b{i})" for i in range(n)]
        out.append(" & ".join(parts))
        out.append(" & ".join(parts + ["G(a0 -> X !a0)", "F goal"]))
    return out


def random_formula(rng: random.Random, operators: int, props=("p0", "p1", "p2", "p3")):
    if operators == 0:
        return Prop(rng.choice(props)) if rng.random() > 0.05 else rng.choice([TRUE, FALSE])
    kind = rng.random()
    if kind < 0.4:
        op = rng.choice([Not, Next, WeakNext, Eventually, Always])
        return op(random_formula(rng, operators - 1, props))
    op = rng.choice([And, Or, Implies, Iff, Until, Release, Until, And, Or, Then])
    left = rng.randint(0, operators - 1)
    return op(random_formula(rng, left, props), random_formula(rng, operators - 1 - left, props))


def random_family(sizes, per_size, seed):
    rng = random.Random(seed)
    return [str(random_formula(rng, k)) for k in sizes for _ in range(per_size)]


PEER_TIMEOUT = 60


class _PeerTimeout(Exception):
    pass


def _ltlf2dfa_seconds(f, limit: int) -> tuple[float, bool]:
    """LTLf2DFA's end-to-end time; stopped after ``limit`` s (its sympy guard step can take minutes),
    in which case the limit is recorded as a lower bound."""
    import signal

    def stop(signum, frame):
        raise _PeerTimeout

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(limit)
    try:
        _, seconds = ltlf2dfa_dot(f)
        return seconds, False
    except _PeerTimeout:
        return float(limit), True
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def measure(text: str, dialect: str, peer: bool) -> dict:
    import sys as _sys

    sys.path.insert(0, str(REPO / "tests" / "support"))
    from ltlf_oracle import compare

    f = parse(text, dialect)
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        dfa = translate(f, max_states=500_000)
        best = min(best, time.perf_counter() - start)
    row = {"formula": text, "operators": operator_count(f), "states": dfa.n_states, "edges": dfa.count_edges(),
           "symbolic": dfa.is_symbolic(), "ours_s": best}
    mona = mona_dfa(f)
    row["mona_s"] = mona.seconds
    row["mona_states"] = len(mona.word_states())
    row["identical"] = not compare(dfa, mona)
    if peer:
        row["ltlf2dfa_s"], row["ltlf2dfa_timeout"] = _ltlf2dfa_seconds(f, PEER_TIMEOUT)
    del _sys
    return row


def summarise(name: str, rows: list[dict]) -> dict:
    ours = [r["ours_s"] for r in rows]
    summary = {"family": name, "formulas": len(rows), "max_operators": max(r["operators"] for r in rows),
               "max_states": max(r["states"] for r in rows),
               "identical": sum(r["identical"] for r in rows),
               "median_ours_ms": 1000 * statistics.median(ours),
               "median_mona_ms": 1000 * statistics.median(r["mona_s"] for r in rows),
               "speedup_vs_mona_median": statistics.median(r["mona_s"] / r["ours_s"] for r in rows)}
    if all("ltlf2dfa_s" in r for r in rows):
        summary["median_ltlf2dfa_ms"] = 1000 * statistics.median(r["ltlf2dfa_s"] for r in rows)
        summary["speedup_vs_ltlf2dfa_median"] = statistics.median(r["ltlf2dfa_s"] / r["ours_s"] for r in rows)
        summary["speedup_vs_ltlf2dfa_min"] = min(r["ltlf2dfa_s"] / r["ours_s"] for r in rows)
    summary["slower_than_mona"] = [r["formula"] for r in rows if r["ours_s"] > r["mona_s"]]
    summary["ltlf2dfa_timeouts"] = sum(r.get("ltlf2dfa_timeout", False) for r in rows)
    return summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smaller families")
    parser.add_argument("--no-benchmark-file", action="store_true", help="skip the 201 benchmark formulas")
    parser.add_argument("--json", help="also write every measurement to this JSON file")
    parser.add_argument("--verbose", action="store_true", help="print every formula's times")
    parser.add_argument("--peer-timeout", type=int, default=60, help="seconds before LTLf2DFA is stopped")
    args = parser.parse_args()
    global PEER_TIMEOUT
    PEER_TIMEOUT = args.peer_timeout

    q = args.quick
    families = {
        "conjunctions of n F": (conjunctions_of_f(5 if q else 8), "ours"),
        "chains of n T": (chains_of_t(6 if q else 10), "ours"),
        "task templates": (task_templates(3 if q else 6), "ours"),
        "Dwyer patterns": (DWYER[:9] if q else DWYER, "ours"),
        "random, k <= 30 operators": (random_family([5, 10, 20, 30] if q else [5, 10, 15, 20, 25, 30],
                                                    3 if q else 8, seed=2026), "ours"),
    }
    if not args.no_benchmark_file and FORMULAS_TXT.is_file():
        lines = [l.strip() for l in FORMULAS_TXT.read_text().splitlines() if l.strip()]
        families["LTLf learning benchmark (201, spot)"] = (lines[::10] if q else lines, "spot")

    print(f"# {' '.join(sys.argv)}")
    print(f"# machine: {platform.machine()}, {platform.python_implementation()} {platform.python_version()}")
    results, all_rows = [], {}
    for name, (texts, dialect) in families.items():
        rows = []
        for t in texts:
            rows.append(measure(t, dialect, peer=True))
            if args.verbose:
                r = rows[-1]
                print(f"   {r['ours_s'] * 1000:8.2f} ms  LTLf2DFA {r['ltlf2dfa_s'] * 1000:8.1f} ms  "
                      f"{r['states']:4d} states  {t[:70]}", flush=True)
        all_rows[name] = rows
        s = summarise(name, rows)
        results.append(s)
        print(f"\n## {name}: {s['formulas']} formulas, <= {s['max_operators']} operators, <= {s['max_states']} states")
        print(f"   identical minimal DFAs (language and state count): {s['identical']}/{s['formulas']}")
        print(f"   median time: ours {s['median_ours_ms']:.3f} ms | LTLf2DFA {s['median_ltlf2dfa_ms']:.1f} ms | "
              f"MONA only {s['median_mona_ms']:.1f} ms")
        print(f"   per-formula speed-up, median: {s['speedup_vs_ltlf2dfa_median']:.0f}x vs LTLf2DFA, "
              f"{s['speedup_vs_mona_median']:.0f}x vs MONA only; worst {s['speedup_vs_ltlf2dfa_min']:.1f}x vs LTLf2DFA")
        if s["ltlf2dfa_timeouts"]:
            print(f"   LTLf2DFA stopped after {PEER_TIMEOUT} s on {s['ltlf2dfa_timeouts']} formulas "
                  f"(counted as {PEER_TIMEOUT} s: speed-ups there are lower bounds)")
        if s["slower_than_mona"]:
            print(f"   slower than MONA only on: {s['slower_than_mona']}")
        sys.stdout.flush()
    small = [r for rows in all_rows.values() for r in rows if r["operators"] <= 30]
    overall = statistics.median(r["ltlf2dfa_s"] for r in small) / statistics.median(r["ours_s"] for r in small)
    overall_mona = statistics.median(r["mona_s"] for r in small) / statistics.median(r["ours_s"] for r in small)
    print(f"\n## all formulas with <= 30 operators ({len(small)}): median-time ratio "
          f"{overall:.0f}x vs LTLf2DFA, {overall_mona:.0f}x vs MONA only; identical "
          f"{sum(r['identical'] for r in small)}/{len(small)}")
    if args.json:
        Path(args.json).write_text(json.dumps({"summary": results, "rows": all_rows}, indent=1))


if __name__ == "__main__":
    main()
