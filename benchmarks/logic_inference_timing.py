"""Wall time of logic constraint inference, for comparing two versions of the code in one run.

    python benchmarks/logic_inference_timing.py [--repeats 3] [--json OUT]
    python benchmarks/logic_inference_timing.py --compare OLD_CHECKOUT [--repeats 3] [--json OUT]

One measurement: ``LogicConstraintInference`` fitted on the bundled expert's demonstrations in
the lights and priority junctions (200 drives, 20 iterations) and Hanoi (10 games, 3 iterations),
seconds of ``fit`` and the rules learned. With ``--compare DIR`` every repetition runs this
script once in ``DIR`` (an older checkout, imported through ``PYTHONPATH``) and once here,
alternating, so both see the same machine load; the table gives the median seconds and the
ratio new / old per domain, and checks that both learned the same rules.

The script runs against the learner API before and after the learner contract (issue "bring
your own domain"): ``LogicConstraintInference(lm, iterations=).fit(demos)`` then,
``LogicConstraintInference(iterations=).fit(demos, lm.domain)`` now.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

CASES = (("junction-lights", "traffic-lights", 200, 20), ("junction-priority", "traffic-priority", 200, 20),
         ("hanoi", "hanoi", 10, 3))


def measure() -> list[dict]:
    """Fit every case once in this process; one row per case."""
    import inspect

    from symlearn.envs.logic_mdp import logic_mdp
    from symlearn.progress import progress_bars

    try:
        from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
    except ImportError:  # the layout before learners were grouped by family
        from symlearn.learners.logic_constraint_inference import LogicConstraintInference
    old_api = "domain" in inspect.signature(LogicConstraintInference.__init__).parameters
    rows = []
    for name, old_name, n_demos, iterations in CASES:
        try:
            lm = logic_mdp(name)
        except Exception:  # older names
            lm = logic_mdp(old_name)
        demos = lm.expert_demonstrations(n_demos, seed=0)
        with progress_bars(False):
            t0 = time.perf_counter()
            if old_api:
                learner = LogicConstraintInference(lm, iterations=iterations).fit(demos)
            else:
                learner = LogicConstraintInference(iterations=iterations).fit(demos, lm.domain)
            seconds = time.perf_counter() - t0
        rows.append({"domain": name, "demos": n_demos, "iterations": iterations, "seconds": seconds,
                     "rules": sorted(learner.rules_)})
    return rows


def compare(old: Path, repeats: int) -> dict:
    here = Path(__file__).resolve()
    runs: dict[str, list[list[dict]]] = {"old": [], "new": []}
    for _ in range(repeats):
        for label, root in (("old", old), ("new", here.parents[1])):
            env = {**os.environ, "PYTHONPATH": str(root), "CI": "1"}
            done = subprocess.run([sys.executable, str(here), "--single"], cwd=root, env=env, check=True,
                                  capture_output=True, text=True)
            runs[label].append(json.loads(done.stdout))
    table = []
    for k, (name, *_rest) in enumerate(CASES):
        old_s = statistics.median(r[k]["seconds"] for r in runs["old"])
        new_s = statistics.median(r[k]["seconds"] for r in runs["new"])
        same = all(r[k]["rules"] == runs["old"][0][k]["rules"] for r in runs["old"] + runs["new"])
        table.append({"domain": name, "old_median_s": old_s, "new_median_s": new_s, "ratio_new_over_old": new_s / old_s,
                      "same_rules": same, "rules": runs["new"][0][k]["rules"]})
    return {"repeats": repeats, "old": str(old), "runs": runs, "table": table}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--compare", type=Path, help="an older checkout to compare with")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--single", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--json", metavar="OUT")
    args = parser.parse_args()
    if args.single:
        print(json.dumps(measure()))
        return
    result = compare(args.compare, args.repeats) if args.compare else {"rows": measure()}
    result["command"] = "python benchmarks/logic_inference_timing.py " + " ".join(sys.argv[1:])
    if "table" in result:
        print("| domain | old s (median) | new s (median) | new / old | same rules |")
        print("|---|---:|---:|---:|---|")
        for row in result["table"]:
            print(f"| {row['domain']} | {row['old_median_s']:.2f} | {row['new_median_s']:.2f} | "
                  f"{row['ratio_new_over_old']:.2f} | {row['same_rules']} |")
    else:
        for row in result["rows"]:
            print(f"{row['domain']}: {row['seconds']:.2f} s, {len(row['rules'])} rules")
    if args.json:
        from symlearn.atomic import write_text

        write_text(args.json, json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
