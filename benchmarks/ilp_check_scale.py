"""``symlearn ilp check`` against the number of rules in the hypothesis file (issue 26).

The bundled Hanoi task (``background_kb/hanoi/tasks/hanoi.las``, 216 examples) is checked against
generated rule files of N rules, each run the real command in a child process (start-up and the
bounded worker included, as a user sees it), ``--timeout inf --max-memory 0`` (40,000 mixed rules
need more than the worker's default 1024 MB), under a 4 GB address-space cap:

* ``issue26``: ``rI :- p(X), X > I.`` -- the shape of the first issue 26 measurement
  (``docs/BENCHMARKS.md``, *Reliability at scale*); ``p/1`` is defined nowhere, so the report
  carries one warning;
* ``mixed``: rules over the task's own predicates with negation (also ``not not``), classical
  negation, comparisons and constraints, and every tenth rule one that the AST rewrite handles
  (a choice head, a pool), plus a misspelt predicate.

``--before CHECKOUT`` runs the same commands with ``PYTHONPATH`` set to another checkout (the
code before the change) and records whether stdout, stderr and the exit code are identical.

* ``excluding`` (for ``--coverage``): every positive uncovered, some rules excluding some of them;
* ``long``: one constraint of N body literals (N is then the number of literals);
  ``long_undefined``: the same with N - 1 predicates defined nowhere (N - 1 warnings).

``--coverage`` adds that flag to the command (which rules exclude each uncovered positive).

``python benchmarks/ilp_check_scale.py [--sizes 1000 4000 16000 40000] [--shapes ...] [--coverage]
[--before /path/to/old [--before-sizes 1000]] [--output FILE]`` writes
``benchmarks/results/ilp_check_scale.json`` unless told otherwise.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TASK = REPO / "background_kb" / "hanoi" / "tasks" / "hanoi.las"
LIMIT_S = 600.0


def issue26_rules(n: int) -> str:
    return "".join(f"r{i} :- p(X), X > {i}.\n" for i in range(n))


_MIXED = [
    ":- move(D, P), at(E, P, Y), E > D, Y > {k}.",
    "c{i}(D) :- after(D, X, Y), not moved(D), Y > {k}.",
    ":- on(D1, D2), D1 = D2 + {k}, not -done(D1).",
    "-done(D) :- disk(D), D > {k}.",
    ":- move(D, P), not not moved(D), D > {k}.",
    ":- after(D, X, Y), after(E, X, Y), D < E, Y >= {k}.",
    "s{i} :- on(D1, D2), at(D1, X, _), X = {k}.",
    ":- move(D, P), moved(E), E != D, D > {k}.",
    "u{i}(X) :- peg(X), not at(_, X, {k}).",
]
# forms the text fast path leaves to the AST rewrite. Conditional literals and aggregates are
# not among them here: clingo's grounding of thousands of such rules grows faster than linearly
# (``:- move(D, P), Y > K : at(D, P, Y).``, in-process CPU time here: 1,000 rules 4.8 s, 4,000
# rules 190 s; clingo is given the same program before and after this change), which would
# hide what is measured
_FALLBACK = [
    "{{ w{i}(D) : disk(D) }} 0 :- move(D, _), D > {k}.",
    "v{i}(1;2) :- move(_, P), P > {k}.",
]


def mixed_rules(n: int) -> str:
    lines = ["% generated: benchmarks/ilp_check_scale.py (mixed)", ":- move(D, P), blockd(D)."]  # misspelt
    for i in range(n - 1):
        k = 3 + i % 50  # constants the domain never reaches: the check's answer does not change with n
        shapes = _FALLBACK if i % 10 == 9 else _MIXED
        lines.append(shapes[i % len(shapes)].format(i=i, k=k))
    return "\n".join(lines) + "\n"


def excluding_rules(n: int) -> str:
    """For ``--coverage``: every positive uncovered (the first rule excludes them all), so each
    rule is asked about each of the 114 positives. Every 100th rule also excludes the positives
    that move one disk; every 1,000th derives an atom the background reads (``after/3``) on every
    example, which no shortcut decides (one background copy per positive in the exact check)."""
    lines = ["% generated: benchmarks/ilp_check_scale.py (excluding)", ":- move(D, P), D >= 0."]
    for i in range(n - 1):
        if i % 1000 == 999:
            lines.append(f"after(D, 9, {i}) :- move(D, _).")
        elif i % 100 == 99:
            lines.append(f":- move(D, P), D = {i // 100 % 3}, P != {i + 3}.")
        else:
            shapes = _FALLBACK if i % 10 == 9 else _MIXED
            lines.append(shapes[i % len(shapes)].format(i=i, k=3 + i % 50))
    return "\n".join(lines) + "\n"


def long_rule(n: int) -> str:
    """One constraint of ``n`` body literals (each safe on its own), true on every positive."""
    literals = ["move(D, P)"] + [f"D != {i + 3}" if i % 2 else f"not at(D, P, {i + 3})" for i in range(n - 1)]
    return ":- " + ", ".join(literals) + ".\n"


def long_undefined_rule(n: int) -> str:
    """One constraint of ``n`` body literals, ``n - 1`` of them predicates defined nowhere (one
    warning each)."""
    return ":- " + ", ".join(["move(D, P)"] + [f"not q{i}(D)" for i in range(n - 1)]) + ".\n"


SHAPES = {"issue26": issue26_rules, "mixed": mixed_rules, "excluding": excluding_rules, "long": long_rule,
          "long_undefined": long_undefined_rule}


def _run(checkout: Path, hypothesis: Path, folder: Path, extra: list[str]):
    sys.path.insert(0, str(REPO / "tests" / "support"))
    from hostile import run_command

    return run_command(["ilp", "check", TASK, hypothesis, "--timeout", "inf", "--max-memory", "0", *extra],
                       cwd=folder,
                       timeout=LIMIT_S,
                       memory_mb=4096, env={"PYTHONPATH": str(checkout), "OMP_NUM_THREADS": "1"})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 4000, 16000, 40000])
    parser.add_argument("--shapes", nargs="+", choices=sorted(SHAPES), default=["issue26", "mixed"])
    parser.add_argument("--coverage", action="store_true", help="check with --coverage")
    parser.add_argument("--before-sizes", type=int, nargs="+", metavar="N",
                        help="run --before only at these sizes (the old --coverage took minutes)")
    parser.add_argument("--before", type=Path, help="checkout of the code before the change")
    parser.add_argument("--output", type=Path, default=HERE / "results" / "ilp_check_scale.json")
    args = parser.parse_args(argv)
    trees = {"after": REPO} | ({"before": args.before.resolve()} if args.before else {})
    extra = ["--coverage"] if args.coverage else []
    results: dict = {"command": "python -m symlearn ilp check background_kb/hanoi/tasks/hanoi.las HYP.lp "
                                "--timeout inf --max-memory 0" + "".join(f" {e}" for e in extra),
                     "task": str(TASK.relative_to(REPO)), "load_average": None,
                     "cases": []}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for shape in args.shapes:
            for n in args.sizes:
                hypothesis = folder / f"{shape}_{n}.lp"
                hypothesis.write_text(SHAPES[shape](n))
                case = {"shape": shape, "rules": n}
                outputs = {}
                for name, tree in trees.items():
                    if name == "before" and args.before_sizes is not None and n not in args.before_sizes:
                        continue
                    run = _run(tree, hypothesis, folder, extra)
                    case[name] = {"seconds": round(run.seconds, 3), "max_rss_mb": round(run.max_rss_mb),
                                  "exit": run.returncode, "timed_out": run.timed_out,
                                  "stderr_last_line": (run.stderr.strip().splitlines() or [""])[-1][:200]}
                    outputs[name] = (run.returncode, run.stdout, run.stderr)
                    print(f"{shape:8s} {n:6d} rules  {name:6s} {run.seconds:7.2f} s  {run.max_rss_mb:5.0f} MB  "
                          f"exit {run.returncode}", flush=True)
                if len(outputs) == 2:
                    case["same_output"] = outputs["before"] == outputs["after"]
                results["cases"].append(case)
    results["load_average"] = [round(x, 2) for x in os.getloadavg()]
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(results, indent=1) + "\n")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
