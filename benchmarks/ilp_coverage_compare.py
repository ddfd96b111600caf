"""``symlearn ilp check --coverage`` before and after a change, on generated hypothesis files over
the bundled tasks (issue 26, ninth round): are stdout, stderr and the exit code identical?

Each case draws rules at random (fixed seeds) from templates over the task's own predicates:
constraints that exclude some examples and not others, rules whose head the background reads
(``onRoad``, ``moved``, ``after``), rules with a new head, negation in the body, choices, pools,
aggregates and odd loops, so that every way the new code decides a (rule, example) pair, and its
exact check of the rest, is compared with the old one-grounding-per-rule answer. ``--before``
is a checkout of the code before the change (the old way costs about 0.2 s a rule here).

``python benchmarks/ilp_coverage_compare.py --before /path/to/old [--rules 40] [--seeds 0 1 2]``
writes ``benchmarks/results/ilp_coverage_compare.json``.
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
KB = REPO / "background_kb"

HANOI = [
    ":- move(D, P), D = {d}.",
    ":- move(D, P), at(E, P, _), E > D, D != {d}.",
    ":- on(D1, D2), D1 < D2, D2 != {d}.",
    "c{i}(D) :- moved(D), D >= {d}.",
    "c{i}(D) :- disk(D), not c{i}(D), D = {d}.",
    "moved(D) :- disk(D), D = {d}.",
    "{{ moved(D) }} :- disk(D), D > {d}.",
    "{{ w{i}(D) : disk(D) }} 0 :- move(D, _), D > {d}.",
    "v{i}(1;2) :- move(_, P), P > {d}.",
    ":- move(D, P), #count {{ E : at(E, P, _) }} > {d}.",
    "after(D, 9, 9) :- move(D, _), D = {d}.",
    ":- not moved({d}).",
]
TRAFFIC = [
    ":- go({dir}).",
    ":- go(D), onRoad(D), D != {dir}.",
    ":- go({dir}), not onRoad({dir}).",
    ":- go(D), beforeJunction(D), tls0.",
    "onRoad({dir}) :- at({x}, {y}).",
    "seen{i}(D) :- go(D), onRoad(D).",
    "stop{i} :- go({dir}), not stop{i}.",
    "{{ tls0 }} :- at({x}, _).",
    ":- go(D), not onRoad(D) : dir(D).",
    "go({dir}) :- at({x}, {y}).",
]
TASKS = {"hanoi": (KB / "hanoi" / "tasks" / "hanoi.las", HANOI),
         "lights": (KB / "traffic" / "tasks" / "lights.las", TRAFFIC),
         "priority": (KB / "traffic" / "tasks" / "priority.las", TRAFFIC)}
DIRECTIONS = ["zero", "north", "east", "south", "west"]


def hypothesis(templates: list[str], n: int, seed: int) -> str:
    pick = random.Random(seed)
    rules = [pick.choice(templates).format(i=i, d=pick.randrange(4), dir=pick.choice(DIRECTIONS),
                                           x=pick.randrange(1, 6), y=pick.randrange(1, 6)) for i in range(n)]
    return "\n".join(rules) + "\n"


def _run(checkout: Path, task: Path, rules: Path, folder: Path):
    sys.path.insert(0, str(REPO / "tests" / "support"))
    from hostile import run_command

    return run_command(["ilp", "check", task, rules, "--coverage", "--timeout", "inf", "--max-memory", "0"],
                       cwd=folder, timeout=600, memory_mb=4096,
                       env={"PYTHONPATH": str(checkout), "OMP_NUM_THREADS": "1"})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True, help="checkout of the code before the change")
    parser.add_argument("--rules", type=int, default=40)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--output", type=Path, default=HERE / "results" / "ilp_coverage_compare.json")
    args = parser.parse_args(argv)
    results: dict = {"command": "python -m symlearn ilp check TASK HYP.lp --coverage --timeout inf --max-memory 0",
                     "rules": args.rules, "cases": []}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, (task, templates) in TASKS.items():
            for seed in args.seeds:
                rules = folder / f"{name}_{seed}.lp"
                rules.write_text(hypothesis(templates, args.rules, seed))
                runs = {label: _run(tree, task, rules, folder)
                        for label, tree in (("before", args.before.resolve()), ("after", REPO))}
                same = len({(r.returncode, r.stdout, r.stderr) for r in runs.values()}) == 1
                excluded = runs["after"].stdout.count(" -- excluded by ")
                case = {"task": name, "seed": seed, "same_output": same, "exit": runs["after"].returncode,
                        "lines_naming_excluding_rules": excluded,
                        **{f"{label}_seconds": round(r.seconds, 2) for label, r in runs.items()}}
                results["cases"].append(case)
                print(json.dumps(case), flush=True)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(results, indent=1) + "\n")
    print(f"wrote {args.output}")
    return 0 if all(c["same_output"] for c in results["cases"]) else 1


if __name__ == "__main__":
    raise SystemExit(main())
