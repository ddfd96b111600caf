"""Before/after timing of in-process ILP (task loading, hypothesis space, learning) in two source trees.

Runs the same workload alternately in a child process per tree (``--rounds`` times each, so load
on the machine hits both alike) and compares per-task best CPU times of
``learn(load_task(path), timeout=120)`` on the bundled tasks and the FastLAS test tasks that
solve in seconds. Scores must agree.

Make the "before" tree from a commit without touching the working copy, e.g.::

    mkdir -p /tmp/ab/before && git archive HEAD symlearn grammars background_kb | tar -x -C /tmp/ab/before
    .venv/bin/python benchmarks/ilp_ab.py /tmp/ab/before . --rounds 5
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
from pathlib import Path

FASTLAS = Path(__file__).resolve().parents[2] / "shared" / "benchmarks" / "ilp" / "fastlas"
FASTLAS_QUICK = ["fastlas__testing__aaai_presentation_task.las", "fastlas__testing__agent_abduction.las",
                 "fastlas__testing__arithmetic2.las", "fastlas__testing__simple_agent.las",
                 "fastlas__testing__negative_examples.las"]
TASKS = ["hanoi/tasks/hanoi.las", "hanoi/tasks/hanoi_demos.las", "traffic/tasks/lights.las",
         "traffic/tasks/lights_demos.las", "traffic/tasks/priority.las", "traffic/tasks/priority_demos.las"]

_CHILD = r"""
import json, sys, time
from pathlib import Path
sys.path.insert(0, sys.argv[1])
import symlearn
from symlearn.logic.ilp import learn, load_task
root, fastlas, names, quick = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), json.loads(sys.argv[4])
assert Path(symlearn.__file__).resolve().is_relative_to(Path(root).resolve()), symlearn.__file__
result = {}
jobs = [(Path(root) / "background_kb" / n, "ilasp") for n in names] + [(Path(fastlas) / n, "fastlas") for n in quick]
for path, dialect in jobs:
    cpu = time.process_time()
    r = learn(load_task(path, dialect=dialect), timeout=120)
    result[path.name] = [time.process_time() - cpu, r.score]
print(json.dumps(result))
"""


def _round(tree: Path, quick: list[str]) -> dict:
    env = dict(os.environ, SYMLEARN_QUIET="1")
    done = subprocess.run([sys.executable, "-c", _CHILD, str(tree.resolve()), str(FASTLAS), json.dumps(TASKS),
                           json.dumps(quick)], capture_output=True, text=True, env=env, check=False,
                          cwd=tree.resolve())
    if done.returncode != 0:
        raise SystemExit(f"{tree}: {done.stderr.strip()[-2000:]}")
    return json.loads(done.stdout)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    quick = FASTLAS_QUICK if FASTLAS.exists() else []
    print(f"command: python benchmarks/ilp_ab.py {args.before} {args.after} --rounds {args.rounds}")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cpus, python {platform.python_version()}, "
          f"load average {' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    runs: dict[str, list[dict]] = {"before": [], "after": []}
    for _ in range(args.rounds):
        for name, tree in (("before", args.before), ("after", args.after)):
            runs[name].append(_round(tree, quick))
    print(f"{'task':44} {'before cpu s':>12} {'after cpu s':>11} {'ratio':>6} {'score':>5}")
    ratios = []
    for task in runs["before"][0]:
        before = min(r[task][0] for r in runs["before"])
        after = min(r[task][0] for r in runs["after"])
        scores = {r[task][1] for side in runs.values() for r in side}
        if len(scores) != 1:
            raise SystemExit(f"{task}: scores differ: {scores}")
        ratios.append(after / before)
        print(f"{task:44} {before:>12.3f} {after:>11.3f} {after / before:>6.2f} {scores.pop()!s:>5}")
    print(f"geometric mean after / before: {statistics.geometric_mean(ratios):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
