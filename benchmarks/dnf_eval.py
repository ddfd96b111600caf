"""DNF evaluation speed: ``DNF.evaluate`` against plain numpy on the same array, same run.

The issue's target: evaluating a DNF of 100 conjunctions on 10^6 points should take at most 5x
one plain numpy comparison pass over the same ``[N, k]`` array (``X > 0.5``). We also time the
formula written directly in numpy (one comparison per atom on the columns, ``&`` inside a
conjunction, ``|`` across), which is what one would write by hand, and check that both give
the same answer.

Formulas look like pruned one-class-tree output: each conjunction bounds 2-5 random features
from below and above, thresholds are data-like floats (one case rounds them to 2 decimals, as
printed in the thesis' tables). "wide" boxes cover almost all points; "narrow" ones (width
0.02-0.12 per feature) flag a minority, as a learned constraint does on expert-like data.
Points are uniform in ``[0, 1]^k``, float64, C order.
Times are medians over ``--repeats`` rounds in which the contenders take turns, after one
warm-up (which compiles the formula's lookup tables once; compile time is reported apart).
The slow plain-numpy evaluation gets fewer rounds and is scaled by the one-pass time of its
own rounds.

    .venv/bin/python benchmarks/dnf_eval.py [--quick] [--repeats 7] [--out benchmarks/results/dnf_eval.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from symlearn.logic.dnf import DNF, Atom, Conjunction


def make_formula(k: int, m: int, rng: np.random.Generator, rounded: bool, sparse: bool = False) -> DNF:
    names = [f"x{i}" for i in range(k)]
    conjunctions = []
    for _ in range(m):
        chosen = rng.choice(k, size=int(rng.integers(2, min(5, k) + 1)), replace=False)
        atoms = []
        for j in chosen:
            if sparse:            # narrow boxes: most points are safe, as in a learned constraint
                width = rng.uniform(0.02, 0.12)
                lo = rng.uniform(0, 1 - width)
                hi = lo + width
            else:                 # wide boxes: almost every point is in one
                lo, hi = np.sort(rng.random(2))
            if rounded:
                lo, hi = round(float(lo), 2), round(float(hi), 2)
            atoms += [Atom(names[j], ">" if rng.random() < 0.5 else ">=", float(lo)),
                      Atom(names[j], "<=" if rng.random() < 0.5 else "<", float(hi))]
        conjunctions.append(Conjunction(tuple(atoms)))
    return DNF(tuple(conjunctions))


def plain_numpy(formula: DNF, X: np.ndarray, names: list[str]) -> np.ndarray:
    index = {n: i for i, n in enumerate(names)}
    ops = {"<": np.less, "<=": np.less_equal, ">": np.greater, ">=": np.greater_equal}
    result = np.zeros(len(X), dtype=bool)
    for c in formula.conjunctions:
        hold = np.ones(len(X), dtype=bool)
        for a in c.atoms:
            hold &= ops[a.op](X[:, index[a.feature]], a.value)
        result |= hold
    return result


def timed(functions: dict, repeats: int) -> dict[str, float]:
    """Median wall time of each function; the functions take turns in every round, so a busy
    machine slows them alike."""
    for fn in functions.values():
        fn()
    times: dict[str, list[float]] = {name: [] for name in functions}
    for _ in range(repeats):
        for name, fn in functions.items():
            start = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(values) for name, values in times.items()}


def run_case(n: int, k: int, m: int, rounded: bool, sparse: bool, repeats: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    names = [f"x{i}" for i in range(k)]
    formula = make_formula(k, m, rng, rounded, sparse)
    X = rng.random((n, k))
    start = time.perf_counter()
    fresh = DNF(formula.conjunctions)
    fresh.evaluate(X[:1], names)
    compile_s = time.perf_counter() - start
    ours = formula.evaluate(X, names)
    same = bool(np.array_equal(ours, plain_numpy(formula, X, names)))
    per = formula.evaluate(X, names, per_conjunction=True)
    same = same and bool(np.array_equal(per.any(axis=1), ours))
    fast = timed({"one_pass": lambda: X > 0.5, "evaluate": lambda: formula.evaluate(X, names),
                  "per_conjunction": lambda: formula.evaluate(X, names, per_conjunction=True)}, repeats)
    base, ours_s, per_s = fast["one_pass"], fast["evaluate"], fast["per_conjunction"]
    slow = timed({"one_pass": lambda: X > 0.5, "plain": lambda: plain_numpy(formula, X, names)}, max(1, repeats // 3))
    plain_s = slow["plain"] * base / slow["one_pass"]       # scaled to the same one-pass time
    modes = [step.mode for step in formula._plan.steps]
    return {
        "n": n, "k": k, "conjunctions": m, "atoms": sum(len(c) for c in formula), "rounded": rounded,
        "boxes": "narrow" if sparse else "wide",
        "true_fraction": float(ours.mean()), "same_result": same, "lookup_modes": sorted(set(modes)),
        "compile_s": compile_s, "one_pass_s": base, "evaluate_s": ours_s, "per_conjunction_s": per_s,
        "plain_numpy_s": plain_s,
        "evaluate_over_one_pass": ours_s / base, "per_conjunction_over_one_pass": per_s / base,
        "plain_numpy_over_one_pass": plain_s / base, "plain_numpy_over_evaluate": plain_s / ours_s,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="10^5 points, fewer cases")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "dnf_eval.json"))
    args = parser.parse_args()
    n = 10**5 if args.quick else 10**6
    ks = (4, 10) if args.quick else (2, 4, 10, 20)
    cases = [(k, 100, False, sparse) for sparse in (False, True) for k in ks]
    cases += [] if args.quick else [(10, 100, True, False), (10, 10, False, False)]
    rows = []
    for k, m, rounded, sparse in cases:
        row = run_case(n, k, m, rounded, sparse, args.repeats, args.seed)
        rows.append(row)
        print(f"N={n:>8} k={k:>2} m={m:>3} atoms={row['atoms']:>4} {row['boxes']:6} rounded={rounded!s:5} "
              f"true={row['true_fraction']:.3f} "
              f"one pass {row['one_pass_s'] * 1e3:7.2f} ms | evaluate {row['evaluate_s'] * 1e3:7.2f} ms "
              f"({row['evaluate_over_one_pass']:5.1f}x) | per-conj {row['per_conjunction_s'] * 1e3:7.2f} ms "
              f"({row['per_conjunction_over_one_pass']:5.1f}x) | plain numpy {row['plain_numpy_s'] * 1e3:8.2f} ms "
              f"({row['plain_numpy_over_one_pass']:6.1f}x; {row['plain_numpy_over_evaluate']:5.1f}x ours) "
              f"same={row['same_result']}", flush=True)
    doc = {"benchmark": "dnf_eval", "command": "benchmarks/dnf_eval.py" + (" --quick" if args.quick else ""),
           "machine": {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
                       "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__},
           "repeats": args.repeats, "seed": args.seed, "cases": rows}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    from symlearn.atomic import write_text

    write_text(args.out, json.dumps(doc, indent=2) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
