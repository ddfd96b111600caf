"""Time against input size for the large-input cases of issue 26, with log-log slopes.

Each case is the real command in a child process (start-up included, as a user sees it), once per
size, with a 60 s limit; ``--before CHECKOUT`` also runs the same commands with ``PYTHONPATH`` set
to another checkout (the code before the change) at sizes that finish:

* ``dnf show RULES.dnf --json`` of N conjunctions (3 atoms each): the DNF text reader;
* ``automaton show CHAIN.json`` and ``automaton convert CHAIN.json out.hoa`` of an N-state chain
  (minimisation, printing, export).

``python benchmarks/reliability_scale.py [--quick] [--before /path/to/old/checkout]`` writes
``benchmarks/results/reliability_scale.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
LIMIT_S = 60.0


def _rules(n: int) -> str:
    return "".join(f"x{i % 7} > {i * 0.001:.3f} & y < {i % 97}.5 & z >= -{i % 13}\n" for i in range(n))


def _chain(n: int) -> str:
    edges = [e for i in range(n - 1) for e in ({"source": i, "target": i + 1, "guard": "a"},
                                             {"source": i, "target": i, "guard": "!a"})]
    edges.append({"source": n - 1, "target": n - 1, "guard": "true"})
    return json.dumps({"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a"],
                       "states": n, "initial": 0, "accepting": [n - 1], "state_names": None, "transitions": edges})


def _run(checkout: Path, args: list[str], folder: Path) -> float | None:
    """Wall-clock seconds of ``python -m symlearn ARGS`` with ``checkout`` first on the path;
    None when it ran past :data:`LIMIT_S` or failed."""
    env = dict(os.environ, PYTHONPATH=str(checkout), SYMLEARN_QUIET="1", OMP_NUM_THREADS="1")
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "symlearn", *args], cwd=folder, env=env, timeout=LIMIT_S,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    except subprocess.TimeoutExpired:
        return None
    if done.returncode != 0:
        raise RuntimeError(f"{args} failed: {done.stderr[-500:]}")
    return time.perf_counter() - start


def _slope(points: list[tuple[int, float]]) -> float | None:
    """Least-squares slope of log(seconds) against log(size): 1 is linear, 2 quadratic."""
    if len(points) < 2:
        return None
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(max(t, 1e-9)) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


CASES = {
    "dnf show": (lambda n: ("rules.dnf", _rules(n)), lambda f: ["dnf", "show", f, "--json"]),
    "automaton show": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "show", f]),
    "automaton convert": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "convert", f, "out.hoa"]),
}


def curve(case: str, checkout: Path, sizes: list[int]) -> dict:
    """``{"points": [[n, seconds], ...], "slope": ..., "timed_out_at": n or None}`` (stops at
    the first size past the limit)."""
    make, command = CASES[case]
    points, timed_out = [], None
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            name, text = make(n)
            (Path(folder) / name).write_text(text)
            seconds = _run(checkout, command(name), Path(folder))
            if seconds is None:
                timed_out = n
                break
            points.append([n, round(seconds, 3)])
    # the slope over all points is flattened by the start-up (~0.4 s); the last two show the growth
    return {"points": points, "slope": _slope([tuple(p) for p in points]),
            "slope_last_two": _slope([tuple(p) for p in points[-2:]]), "timed_out_at": timed_out}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes")
    parser.add_argument("--before", type=Path, help="another checkout to time the same commands with")
    args = parser.parse_args(argv)
    sizes = {"dnf show": [1000, 10000, 100000, 1000000], "automaton show": [1000, 10000, 100000],
             "automaton convert": [1000, 10000, 100000]}
    before_sizes = {"dnf show": [1000, 10000, 100000], "automaton show": [1000, 2000, 4000, 8000, 16000],
                    "automaton convert": [1000, 2000, 4000, 8000, 16000]}
    if args.quick:
        sizes = {k: v[:-1] for k, v in sizes.items()}
        before_sizes = {k: v[:3] for k, v in before_sizes.items()}
    result = {"command": "python benchmarks/reliability_scale.py" + (" --quick" if args.quick else "")
              + (f" --before {args.before}" if args.before else ""), "limit_s": LIMIT_S, "after": {}, "before": {}}
    for case in CASES:
        result["after"][case] = curve(case, REPO, sizes[case])
        print(case, "after", json.dumps(result["after"][case]), flush=True)
        if args.before:
            result["before"][case] = curve(case, args.before, before_sizes[case])
            print(case, "before", json.dumps(result["before"][case]), flush=True)
    out = HERE / "results" / "reliability_scale.json"
    out.write_text(json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
