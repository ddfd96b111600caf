"""Does the held-out check see what the ground truth sees? (issue #25, ``--validation``)

    python benchmarks/validation_holdout.py [--json benchmarks/results/validation_holdout.json]

Logic constraint inference at the CLI's defaults (iterations 20, horizon 30, the world's reward)
on the warehouse user domain (``tests/support/warehouse_domain.py``) with n = 5, 10, 20, 60
expert deliveries, seeds 0-4, a fifth held out (``holdout(demos, 0.2, seed)``): the share of held-out
expert steps the learned rules forbid, next to the rules' FPR and FNR against the truth. The
check needs no truth; the question is whether it is positive when the FPR is.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "support"))

from symlearn.grounding import Domain  # noqa: E402
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference  # noqa: E402
from symlearn.learners.validation import forbidden_pairs_report, holdout  # noqa: E402


def main(argv=None) -> None:
    import warehouse_domain as wh

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        domain = Domain.from_folder(wh.write_warehouse(Path(tmp) / "warehouse"))
        for n in (5, 10, 20, 60):
            for seed in range(5):
                train, held = holdout(wh.expert_demonstrations(n, seed=seed), 0.2, seed=seed)
                learner = LogicConstraintInference(iterations=20, horizon=30, reward="given").fit(train, domain)
                episodes = [(e.states, e.actions) for e in domain.episodes(held)]
                report = forbidden_pairs_report(learner.rule_constraints_, episodes, 0.2, len(train))
                score = learner.score()
                rows.append({"n": n, "seed": seed, "rules": learner.rules_, "fpr": score["fpr"], "fnr": score["fnr"],
                             "held_out_steps": report.steps, "held_out_forbidden": report.forbidden,
                             "held_out_share": report.share})
            mine = [r for r in rows if r["n"] == n]
            flagged = [r for r in mine if r["held_out_forbidden"]]
            print(f"n={n:3d}  mean FPR {np.mean([r['fpr'] for r in mine]):.3f}  mean FNR "
                  f"{np.mean([r['fnr'] for r in mine]):.3f}  runs with FPR > 0: {sum(r['fpr'] > 0 for r in mine)}/5  "
                  f"flagged by the held-out check: {len(flagged)}/5 (of them FPR > 0: "
                  f"{sum(r['fpr'] > 0 for r in flagged)})  mean held-out share "
                  f"{np.mean([r['held_out_share'] for r in mine]):.3f}", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"python": platform.python_version(), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
