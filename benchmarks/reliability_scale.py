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

* ``ilp check TASK.las HYP.lp`` of N rules ``rI :- p(X), X > I.`` (the bundled Hanoi task), and
  ``--coverage`` of the same files (which rule excludes or misses each example);
* ``ltl dfa`` of ``F(a & X F(a & ...))`` nested N deep: at least N ``a``, an (N + 2)-state chain
  DFA (deep nesting through the parser and the translation).

Every run is under a 4 GB address-space cap; its peak resident memory is recorded too.
``--mona`` also runs MONA (``mona -q -u -w``, the program LTLf2DFA writes for the formula, written
before the clock starts) on the ``ltl dfa`` cases' formulas, same cap and limit: the automata
peer the issue names. ``--figure PNG`` draws time against size on log-log axes (a dashed line per
MONA curve, the slope over the two largest sizes in the legend); ``--figure-only`` redraws it from
the recorded JSON.

``python benchmarks/reliability_scale.py [--quick] [--before /path/to/old/checkout] [--mona]
[--figure docs/figures/reliability_scale.png]`` writes ``benchmarks/results/reliability_scale.json``.
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


def _nested_eventually(n: int) -> tuple[str, str]:
    text = "F(a & X " * (n - 1) + "F a" + ")" * (n - 1)
    return "f.ltl", text + "\n"


def _hypothesis(n: int) -> tuple[str, str]:
    sys.path.insert(0, str(HERE))
    from ilp_check_scale import issue26_rules

    return "hyp.lp", issue26_rules(n)


_LTL_DFA = lambda f: ["ltl", "dfa", "--file", f]  # noqa: E731
_TASK = str(REPO / "background_kb" / "hanoi" / "tasks" / "hanoi.las")
_ILP = ["--timeout", "inf", "--max-memory", "0"]

CASES = {  # name: (input of size n, command, exit codes that count as handled: ilp check exits 2
    # when examples stay uncovered, which these generated hypotheses leave)
    "dnf show": (lambda n: ("rules.dnf", _rules(n)), lambda f: ["dnf", "show", f, "--json"], (0,)),
    "automaton show": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "show", f], (0,)),
    "automaton convert": (lambda n: ("chain.json", _chain(n)), lambda f: ["automaton", "convert", f, "out.hoa"],
                          (0,)),
    "ltl dfa: p0 & ... & pN": (_conjunction("p{i}"), _LTL_DFA, (0,)),
    "ltl dfa: G(!a0p | a0q) & ...": (_conjunction("G(!a{i}p | a{i}q)"), _LTL_DFA, (0,)),
    "ltl dfa refused: F p0 & ... & F pN": (_conjunction("F p{i}"), _LTL_DFA, (2,)),
    "ltl dfa refused: G(!p0 | q0) & ...": (_conjunction("G(!p{i} | q{i})"), _LTL_DFA, (2,)),
    "ltl dfa: F(a & X F(a & ...)) nested N deep": (_nested_eventually, _LTL_DFA, (0,)),
    "ilp check: N rules": (_hypothesis, lambda f: ["ilp", "check", _TASK, f, *_ILP], (0, 2)),
    "ilp check --coverage: N rules": (_hypothesis, lambda f: ["ilp", "check", _TASK, f, "--coverage", *_ILP],
                                      (0, 2)),
}


def _mona(text: str, folder: Path) -> tuple[float | None, str]:
    """MONA's time on the formula ``text`` (the program LTLf2DFA writes for it, written before the
    clock starts; 4 GB cap, :data:`LIMIT_S`): ``(seconds, "ok")``, or ``(None, why)``."""
    import resource
    import subprocess

    from symlearn.logic.ltlf import parse
    from symlearn.logic.ltlf.mona import _program

    written: dict = {}

    def write() -> None:  # LTLf2DFA's lark parser and printer recurse once per nesting level
        try:
            written["program"] = _program(parse(text), printed=False)[0]
        except RecursionError:
            written["error"] = "LTLf2DFA cannot write the program (recursion depth)"

    import threading

    limit, stack = sys.getrecursionlimit(), threading.stack_size()
    sys.setrecursionlimit(1_000_000)
    threading.stack_size(1 << 30)
    try:
        worker = threading.Thread(target=write)
        worker.start()
        worker.join()
    finally:
        sys.setrecursionlimit(limit)
        threading.stack_size(stack)
    if "program" not in written:
        return None, written.get("error", "LTLf2DFA failed")
    program = written["program"]
    path = folder / "f.mona"
    path.write_text(program)

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    started = time.perf_counter()
    try:
        done = subprocess.run(["mona", "-q", "-u", "-w", str(path)], capture_output=True, text=True,
                              timeout=LIMIT_S, preexec_fn=cap)
    except subprocess.TimeoutExpired:
        return None, "timeout"
    seconds = time.perf_counter() - started
    if done.returncode != 0 or "Automaton has" not in done.stdout:
        return None, "memory or error: " + (done.stderr or done.stdout)[-120:].strip()
    return seconds, "ok"


def curve(case: str, checkout: Path, sizes: list[int], mona: bool = False) -> dict:
    """``{"points": [[n, seconds], ...], "slope": ..., "timed_out_at": n or None}`` (stops at
    the first size past the limit); with ``mona``, MONA's curve on the same formulas instead."""
    make, command, codes = CASES[case]
    points, peaks, timed_out, why = [], [], None, None
    with tempfile.TemporaryDirectory() as folder:
        for n in sizes:
            name, text = make(n)
            (Path(folder) / name).write_text(text)
            if mona:
                seconds, why = _mona(text.strip(), Path(folder))
                if seconds is None:
                    timed_out = n
                    break
                points.append([n, round(seconds, 3)])
                why = None
                continue
            run = _run(checkout, command(name), Path(folder), codes)
            if run is None:
                timed_out = n
                break
            points.append([n, round(run[0], 3)])
            peaks.append([n, run[1]])
    # the slope over all points is flattened by the start-up (~0.4 s); the last two show the growth
    doc = {"points": points, "peak_mb": peaks, "slope": _slope([tuple(p) for p in points]),
           "slope_last_two": _slope([tuple(p) for p in points[-2:]]), "timed_out_at": timed_out}
    if why:
        doc["stopped"] = why
    return doc


def figure(result: dict, path: Path) -> None:
    """Time against size on log-log axes, one panel per family of cases; MONA dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = {"readers and automata": ["dnf show", "automaton show", "automaton convert"],
              "ltl dfa": [c for c in CASES if c.startswith("ltl dfa")],
              "ilp check": [c for c in CASES if c.startswith("ilp check")]}
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 6.4))
    for ax, (title, cases) in zip(axes, panels.items()):
        for index, case in enumerate(cases):
            colour = f"C{index}"
            for key, style, who in (("after", "-o", ""), ("mona", "--s", "MONA: ")):
                data = result.get(key, {}).get(case)
                if not data or not data["points"]:
                    continue
                xs, ys = zip(*data["points"])
                slope = data.get("slope_last_two")
                label = f"{who}{case}" + (f" (slope {slope:.2f})" if slope is not None else "")
                if data.get("timed_out_at"):
                    label += f"; stopped at {data['timed_out_at']:,}"
                ax.plot(xs, ys, style, color=colour, label=label, markersize=4)
        lines = [line for line in ax.get_lines() if len(line.get_xdata())]
        if lines:  # a slope-1 guide through the panel's median point: what linear work looks like
            xs = sorted(x for line in lines for x in line.get_xdata())
            ys = sorted(y for line in lines for y in line.get_ydata())
            x0, y0 = xs[len(xs) // 2], ys[len(ys) // 2]
            ax.plot([xs[0], xs[-1]], [y0 * xs[0] / x0, y0 * xs[-1] / x0], ":", color="grey", label="slope 1 (linear)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("input size N")
        ax.set_ylabel("wall seconds, whole process")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14))
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes")
    parser.add_argument("--before", type=Path, help="another checkout to time the same commands with")
    parser.add_argument("--only", help="only the cases whose name contains this text")
    parser.add_argument("--mona", action="store_true", help="MONA on the ltl dfa cases' formulas too")
    parser.add_argument("--figure", type=Path, help="draw the log-log figure to this PNG")
    parser.add_argument("--json", type=Path, default=HERE / "results" / "reliability_scale.json",
                        help="where the results go (default: benchmarks/results/reliability_scale.json)")
    parser.add_argument("--figure-only", action="store_true", help="redraw --figure from the recorded JSON")
    args = parser.parse_args(argv)
    out = args.json
    if args.figure_only:
        figure(json.loads(out.read_text()), args.figure)
        return 0
    sizes = {"dnf show": [1000, 10000, 100000, 1000000], "automaton show": [1000, 10000, 100000],
             "automaton convert": [1000, 10000, 100000],
             "ltl dfa: p0 & ... & pN": [1000, 10000, 50000], "ltl dfa: G(!a0p | a0q) & ...": [1000, 5000, 20000],
             "ltl dfa refused: F p0 & ... & F pN": [100, 2000, 20000],
             "ltl dfa refused: G(!p0 | q0) & ...": [100, 2000, 20000],
             "ltl dfa: F(a & X F(a & ...)) nested N deep": [10, 30, 100, 300, 1000, 2000],
             "ilp check: N rules": [1000, 4000, 16000], "ilp check --coverage: N rules": [100, 1000, 4000, 10000]}
    # MONA reads LTLf2DFA's program, which holds the formula on one line: its lexer stops at
    # YYLMAX ("token too large") near a thousand operators, so its curves are shorter
    mona_sizes = {"ltl dfa: p0 & ... & pN": [10, 30, 100, 300], "ltl dfa: G(!a0p | a0q) & ...": [10, 30, 100, 300],
                  "ltl dfa refused: F p0 & ... & F pN": [5, 10, 15, 20, 25],
                  "ltl dfa refused: G(!p0 | q0) & ...": [5, 10, 15, 20, 25],
                  "ltl dfa: F(a & X F(a & ...)) nested N deep": [10, 30, 100, 300]}
    before_sizes = {"dnf show": [1000, 10000, 100000], "automaton show": [1000, 2000, 4000, 8000, 16000],
                    "automaton convert": [1000, 2000, 4000, 8000, 16000],
                    "ltl dfa: p0 & ... & pN": [500, 1000, 2000, 4000], "ltl dfa: G(!a0p | a0q) & ...": [250, 500, 1000, 2000],
                    "ltl dfa refused: F p0 & ... & F pN": [100, 2000], "ltl dfa refused: G(!p0 | q0) & ...": [100, 2000]}
    if args.quick:
        sizes = {k: v[:-1] for k, v in sizes.items()}
        before_sizes = {k: v[:3] for k, v in before_sizes.items()}
    result = {"command": "python benchmarks/reliability_scale.py" + (" --quick" if args.quick else "")
              + (f" --before {args.before}" if args.before else "") + (" --mona" if args.mona else "") + f" --json {args.json}",
              "limit_s": LIMIT_S, "after": {}, "before": {}, "mona": {}}
    if args.only and out.exists():  # a partial run keeps the other cases' figures
        kept = json.loads(out.read_text())
        result["after"], result["before"] = kept.get("after", {}), kept.get("before", {})
        result["mona"] = kept.get("mona", {})
        result["command"] = kept.get("command", "") + "; then " + result["command"] + f" --only {args.only!r}"
    for case in CASES:
        if args.only and args.only not in case:
            continue
        result["after"][case] = curve(case, REPO, sizes[case])
        print(case, "after", json.dumps(result["after"][case]), flush=True)
        if args.before and case in before_sizes:
            result["before"][case] = curve(case, args.before, before_sizes[case])
            print(case, "before", json.dumps(result["before"][case]), flush=True)
        if args.mona and case in mona_sizes:
            result["mona"][case] = curve(case, REPO, mona_sizes[case], mona=True)
            print(case, "MONA", json.dumps(result["mona"][case]), flush=True)
    out.write_text(json.dumps(result, indent=1) + "\n")
    if args.figure:
        figure(result, args.figure)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
