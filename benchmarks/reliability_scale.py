"""Time against input size for the large-input cases of issue 26, with log-log slopes.

Each case is the real command in a child process (start-up included, as a user sees it), once per
size, with a 60 s limit; ``--before CHECKOUT`` also runs the same commands with ``PYTHONPATH`` set
to another checkout (the code before the change) at sizes that finish:

* ``dnf show RULES.dnf --json`` of N conjunctions (3 atoms each): the DNF text reader;
* ``automaton show CHAIN.json`` and ``automaton convert CHAIN.json out.hoa`` of an N-state chain
  (minimisation, printing, export);
* ``ltl dfa --file F.ltl`` of a conjunction of N literals ``p0 & ... & pN``, and of N safety
  conjuncts ``G(!a0p | a0q) & ...`` (each conjunct's names sorting together);
* refusals, timed the same way (exit 2 expected): ``F p0 & ... & F pN`` (2^N states, refused
  from the bound on independent conjuncts) and ``G(!p0 | q0) & ...`` (every ``p`` sorting before
  every ``q``: the first transition's BDD is exponential in name order).

Every run is under a 4 GB address-space cap; its peak resident memory is recorded too.

``python benchmarks/reliability_scale.py [--quick] [--before /path/to/old/checkout]`` writes
``benchmarks/results/reliability_scale.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
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


def _run(checkout: Path, args: list[str], folder: Path, codes: tuple[int, ...] = (0,)) -> tuple | None:
    """``(seconds, peak MB, exit code)`` of ``python -m symlearn ARGS`` with ``checkout`` first on
    the path, under a 4 GB address-space cap; None when it ran past :data:`LIMIT_S`, or stopped
    with an exit code not in ``codes`` (killed at the cap, a crash)."""
    sys.path.insert(0, str(REPO / "tests" / "support"))
    from hostile import run_command

    result = run_command(args, cwd=folder, timeout=LIMIT_S, memory_mb=4096,
                         env={"PYTHONPATH": str(checkout), "OMP_NUM_THREADS": "1"})
    if result.timed_out or result.returncode not in codes:
        return None
    return result.seconds, round(result.max_rss_mb), result.returncode


def _slope(points: list[tuple[int, float]]) -> float | None:
    """Least-squares slope of log(seconds) against log(size): 1 is linear, 2 quadratic."""
    if len(points) < 2:
        return None
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(max(t, 1e-9)) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def _conjunction(conjunct: str):
    return lambda n: ("f.ltl", " & ".join(conjunct.format(i=i) for i in range(n)) + "\n")


_LTL_DFA = lambda f: ["ltl", "dfa", "--file", f]  # noqa: E731

CASES = {  # name: (input of size n, command, exit codes that count as handled)
    "dnf show": (lambda n: ("rules.dnf", _rules(n)), lambda f: ["dnf", "show", f, "--json"], (0,)),
    "automaton show": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "show", f], (0,)),
    "automaton convert": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "convert", f, "out.hoa"],
                          (0,)),
    "ltl dfa: p0 & ... & pN": (_conjunction("p{i}"), _LTL_DFA, (0,)),
    "ltl dfa: G(!a0p | a0q) & ...": (_conjunction("G(!a{i}p | a{i}q)"), _LTL_DFA, (0,)),
    "ltl dfa refused: F p0 & ... & F pN": (_conjunction("F p{i}"), _LTL_DFA, (2,)),
    "ltl dfa refused: G(!p0 | q0) & ...": (_conjunction("G(!p{i} | q{i})"), _LTL_DFA, (2,)),
}


def curve(case: str, checkout: Path, sizes: list[int]) -> dict:
    """``{"points": [[n, seconds], ...], "slope": ..., "timed_out_at": n or None}`` (stops at
    the first size past the limit)."""
    make, command, codes = CASES[case]
    points, peaks, timed_out = [], [], None
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            name, text = make(n)
            (Path(folder) / name).write_text(text)
            run = _run(checkout, command(name), Path(folder), codes)
            if run is None:
                timed_out = n
                break
            points.append([n, round(run[0], 3)])
            peaks.append([n, run[1]])
    # the slope over all points is flattened by the start-up (~0.4 s); the last two show the growth
    return {"points": points, "peak_mb": peaks, "slope": _slope([tuple(p) for p in points]),
            "slope_last_two": _slope([tuple(p) for p in points[-2:]]), "timed_out_at": timed_out}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes")
    parser.add_argument("--before", type=Path, help="another checkout to time the same commands with")
    parser.add_argument("--only", help="only the cases whose name contains this text")
    args = parser.parse_args(argv)
    sizes = {"dnf show": [1000, 10000, 100000, 1000000], "automaton show": [1000, 10000, 100000],
             "automaton convert": [1000, 10000, 100000],
             "ltl dfa: p0 & ... & pN": [1000, 10000, 50000], "ltl dfa: G(!a0p | a0q) & ...": [1000, 5000, 20000],
             "ltl dfa refused: F p0 & ... & F pN": [100, 2000, 20000],
             "ltl dfa refused: G(!p0 | q0) & ...": [100, 2000, 20000]}
    before_sizes = {"dnf show": [1000, 10000, 100000], "automaton show": [1000, 2000, 4000, 8000, 16000],
                    "automaton convert": [1000, 2000, 4000, 8000, 16000],
                    "ltl dfa: p0 & ... & pN": [500, 1000, 2000, 4000], "ltl dfa: G(!a0p | a0q) & ...": [250, 500, 1000, 2000],
                    "ltl dfa refused: F p0 & ... & F pN": [100, 2000], "ltl dfa refused: G(!p0 | q0) & ...": [100, 2000]}
    if args.quick:
        sizes = {k: v[:-1] for k, v in sizes.items()}
        before_sizes = {k: v[:3] for k, v in before_sizes.items()}
    result = {"command": "python benchmarks/reliability_scale.py" + (" --quick" if args.quick else "")
              + (f" --before {args.before}" if args.before else ""), "limit_s": LIMIT_S, "after": {}, "before": {}}
    out = HERE / "results" / "reliability_scale.json"
    if args.only and out.exists():  # a partial run keeps the other cases' figures
        kept = json.loads(out.read_text())
        result["after"], result["before"] = kept.get("after", {}), kept.get("before", {})
        result["command"] = kept.get("command", "") + "; then " + result["command"] + f" --only {args.only!r}"
    for case in CASES:
        if args.only and args.only not in case:
            continue
        result["after"][case] = curve(case, REPO, sizes[case])
        print(case, "after", json.dumps(result["after"][case]), flush=True)
        if args.before:
            result["before"][case] = curve(case, args.before, before_sizes[case])
            print(case, "before", json.dumps(result["before"][case]), flush=True)
    out.write_text(json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
