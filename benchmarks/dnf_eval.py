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
warm-up (which compiles the formula's plan once; that time is reported apart, and so is the
one-off cost of the numba kernels: compiled from scratch into an empty cache, and loaded from
the cache as every later process does, each measured in a fresh interpreter). The slow
plain-numpy evaluation gets fewer rounds and is scaled by the one-pass time of its own rounds.

    .venv/bin/python benchmarks/dnf_eval.py [--quick] [--repeats 7] [--against-head] [--out benchmarks/results/dnf_eval.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
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


CPU: dict[str, float] = {}   # the CPU-time medians of the last timed() call, by name


def timed(functions: dict, repeats: int, inner: int = 1) -> dict[str, float]:
    """Median wall time of each function (per call, ``inner`` calls a round); the functions take
    turns in every round, so a busy machine slows them alike. The median CPU time of this process
    (``time.process_time``: not counting the moments another process had the core) goes to
    ``CPU``: on a shared machine it is the steadier of the two."""
    for fn in functions.values():
        fn()
    times: dict[str, list[float]] = {name: [] for name in functions}
    cpu: dict[str, list[float]] = {name: [] for name in functions}
    for _ in range(repeats):
        for name, fn in functions.items():
            start, start_cpu = time.perf_counter(), time.process_time()
            for _ in range(inner):
                fn()
            cpu[name].append((time.process_time() - start_cpu) / inner)
            times[name].append((time.perf_counter() - start) / inner)
    CPU.clear()
    CPU.update({name: statistics.median(values) for name, values in cpu.items()})
    return {name: statistics.median(values) for name, values in times.items()}


def head_version():
    """``symlearn/logic/dnf.py`` as committed (``git show HEAD:...``), imported as a module: the
    evaluator before this one, for a same-run comparison (``--against-head``)."""
    import importlib.util

    text = subprocess.run(["git", "show", "HEAD:symlearn/logic/dnf.py"], cwd=Path(__file__).parent.parent,
                          capture_output=True, text=True, check=True).stdout
    path = Path(tempfile.mkdtemp()) / "dnf_head.py"
    path.write_text(text)
    spec = importlib.util.spec_from_file_location("dnf_head", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["dnf_head"] = module
    spec.loader.exec_module(module)
    return module


def run_case(n: int, k: int, m: int, rounded: bool, sparse: bool, repeats: int, seed: int, previous=None) -> dict:
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
    contenders = {"one_pass": lambda: X > 0.5, "evaluate": lambda: formula.evaluate(X, names),
                  "per_conjunction": lambda: formula.evaluate(X, names, per_conjunction=True)}
    if previous is not None:                 # the committed evaluator takes its turn in the same rounds
        old = previous.parse(str(formula))
        same = same and bool(np.array_equal(old.evaluate(X, names), ours))
        contenders["previous"] = lambda: old.evaluate(X, names)
    fast = timed(contenders, repeats)
    fast_cpu = dict(CPU)
    base, ours_s, per_s = fast["one_pass"], fast["evaluate"], fast["per_conjunction"]
    ev = formula.evaluator(names)
    point, batch = X[0], X[:64]
    small = timed({"evaluate_1": lambda: formula.evaluate(point, names),
                   "evaluator_1": lambda: ev(point, per_conjunction=True),
                   "evaluator_64": lambda: ev(batch)}, 5 * repeats, inner=200)
    if previous is not None:
        small_old = timed({"evaluate_1": lambda: old.evaluate(point, names, per_conjunction=True)}, 5 * repeats, inner=20)
    slow = timed({"one_pass": lambda: X > 0.5, "plain": lambda: plain_numpy(formula, X, names)}, max(1, repeats // 3))
    plain_s = slow["plain"] * base / slow["one_pass"]       # scaled to the same one-pass time
    row = {
        "n": n, "k": k, "conjunctions": m, "atoms": sum(len(c) for c in formula), "rounded": rounded,
        "boxes": "narrow" if sparse else "wide",
        "true_fraction": float(ours.mean()), "same_result": same, "form": formula._plan.mode,
        "compile_s": compile_s, "one_pass_s": base, "evaluate_s": ours_s, "per_conjunction_s": per_s,
        "plain_numpy_s": plain_s,
        "evaluate_over_one_pass": ours_s / base, "per_conjunction_over_one_pass": per_s / base,
        "plain_numpy_over_one_pass": plain_s / base, "plain_numpy_over_evaluate": plain_s / ours_s,
        "one_point_evaluate_us": small["evaluate_1"] * 1e6, "one_point_evaluator_per_conjunction_us": small["evaluator_1"] * 1e6,
        "batch_64_evaluator_us": small["evaluator_64"] * 1e6,
    }
    row.update(cpu_one_pass_s=fast_cpu["one_pass"], cpu_evaluate_s=fast_cpu["evaluate"],
               cpu_evaluate_over_one_pass=fast_cpu["evaluate"] / fast_cpu["one_pass"],
               cpu_per_conjunction_over_one_pass=fast_cpu["per_conjunction"] / fast_cpu["one_pass"])
    if previous is not None:
        row.update(previous_s=fast["previous"], previous_over_one_pass=fast["previous"] / base,
                   cpu_previous_over_one_pass=fast_cpu["previous"] / fast_cpu["one_pass"],
                   previous_over_evaluate=fast["previous"] / ours_s,
                   previous_one_point_per_conjunction_us=small_old["evaluate_1"] * 1e6)
    return row


def _numba_version() -> str:
    import numba

    return numba.__version__


def kernel_startup() -> dict:
    """Seconds for ``import numba`` plus the first evaluation in a fresh interpreter: with an
    empty numba cache (compiling the kernels), then again with that cache (loading them)."""
    code = ("import time; t = time.perf_counter()\n"
            "from symlearn.logic.dnf import parse\n"
            "f = parse('x > 0.5 & y < 0.2')\n"
            "f.evaluate([[0.0, 1.0]], ['x', 'y']); f.evaluate([[0.0, 1.0]], ['x', 'y'], per_conjunction=True)\n"
            "print(time.perf_counter() - t)")
    result = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("cold_compile_s", "cached_load_s"):
            done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            result[label] = float(done.stdout.strip())
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="10^5 points, fewer cases")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--against-head", action="store_true",
                        help="also time the evaluator of the committed symlearn/logic/dnf.py (git HEAD)")
    parser.add_argument("--out", default=str(Path(__file__).parent / "results" / "dnf_eval.json"))
    args = parser.parse_args()
    n = 10**5 if args.quick else 10**6
    ks = (4, 10) if args.quick else (2, 4, 10, 20)
    cases = [(k, 100, False, sparse) for sparse in (False, True) for k in ks]
    cases += [] if args.quick else [(10, 100, True, False), (10, 10, False, False)]
    previous = head_version() if args.against_head else None
    startup = kernel_startup()
    print(f"numba kernels: compile {startup['cold_compile_s']:.1f} s once, load from cache "
          f"{startup['cached_load_s']:.2f} s per process (import and first evaluation)", flush=True)
    rows = []
    for k, m, rounded, sparse in cases:
        row = run_case(n, k, m, rounded, sparse, args.repeats, args.seed, previous)
        rows.append(row)
        print(f"N={n:>8} k={k:>2} m={m:>3} atoms={row['atoms']:>4} {row['boxes']:6} rounded={rounded!s:5} {row['form']:5} "
              f"true={row['true_fraction']:.3f} "
              f"one pass {row['one_pass_s'] * 1e3:7.2f} ms | evaluate {row['evaluate_s'] * 1e3:7.2f} ms "
              f"({row['evaluate_over_one_pass']:5.1f}x) | per-conj {row['per_conjunction_s'] * 1e3:7.2f} ms "
              f"({row['per_conjunction_over_one_pass']:5.1f}x) | plain numpy {row['plain_numpy_s'] * 1e3:8.2f} ms "
              f"({row['plain_numpy_over_one_pass']:6.1f}x; {row['plain_numpy_over_evaluate']:5.1f}x ours) "
              f"same={row['same_result']} | CPU-time ratio {row['cpu_evaluate_over_one_pass']:.1f}x | one point {row['one_point_evaluate_us']:.1f} us"
              + (f" | HEAD {row['previous_over_one_pass']:.1f}x (CPU {row['cpu_previous_over_one_pass']:.1f}x), one point "
                 f"{row['previous_one_point_per_conjunction_us']:.0f} us"
                 if previous is not None else ""), flush=True)
    doc = {"benchmark": "dnf_eval", "command": "benchmarks/dnf_eval.py" + (" --quick" if args.quick else "")
           + (" --against-head" if args.against_head else ""),
           "machine": {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
                       "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
                       "numba": _numba_version(), "load_average": os.getloadavg()},
           "repeats": args.repeats, "seed": args.seed, "kernel_startup": startup, "cases": rows}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    from symlearn.atomic import write_text

    write_text(args.out, json.dumps(doc, indent=2) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
