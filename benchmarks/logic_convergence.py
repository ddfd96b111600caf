"""When logic constraint inference stops, and what it learns, at the command line's defaults (issue #25).

    python benchmarks/logic_convergence.py [--json OUT]

For Hanoi (10 expert games), the traffic-light junction (100 demonstrations), the priority
junction (30) and the warehouse user domain of ``tests/support/warehouse_domain.py`` (200
deliveries, the world's own reward as ``symlearn learn constraints --domain`` picks), one run of
:class:`LogicConstraintInference` with ``iterations=20`` (the CLI default, a cap) and horizon 30.
Per run: iterations used, the iteration after which the rules stopped changing ("converged at"),
the stop reason, the number of rules, FPR/FNR over every pair, and the pairs reported as
unexplained. The script runs on code without ``stop_reason_`` too (the "before" column of
docs/BENCHMARKS.md was measured with it on the previous commit).
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "support"))

from symlearn.envs.logic_mdp import logic_mdp  # noqa: E402
from symlearn.grounding import Domain  # noqa: E402
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference  # noqa: E402


def _worlds(folder: Path):
    import warehouse_domain as wh

    yield "hanoi", logic_mdp("hanoi"), lambda lm: lm.expert_demonstrations(10, seed=0), "sparse"
    yield "junction-lights", logic_mdp("junction-lights"), lambda lm: lm.expert_demonstrations(100, seed=0), "sparse"
    yield "junction-priority", logic_mdp("junction-priority"), lambda lm: lm.expert_demonstrations(30, seed=0), "sparse"
    yield "warehouse", Domain.from_folder(wh.write_warehouse(folder / "warehouse")), \
        lambda _: wh.expert_demonstrations(200, seed=0), "given"


def run(name, world, demos, reward) -> dict:
    t0 = time.perf_counter()
    learner = LogicConstraintInference(iterations=20, horizon=30, reward=reward).fit(demos, world)
    seconds = time.perf_counter() - t0
    masks = [world.rule_mask(list(h.rules)) if h.rules else np.zeros_like(world.unavailable)
             for h in learner.history_]
    final = learner.rule_constraints_
    # the first iteration from which the rules forbid exactly what they forbid at the end
    converged = next((i + 1 for i in range(len(masks)) if all(np.array_equal(m, final) for m in masks[i:])),
                     len(masks))
    score = learner.score()
    return {"world": name, "iterations": len(learner.history_), "converged_at": converged,
            "stop_reason": getattr(learner, "stop_reason_", learner.stopped_because_),
            "rules": len(learner.rules_), "fpr": score["fpr"], "fnr": score["fnr"],
            "forbidden_per_iteration": [h.n_constraints for h in learner.history_],
            "unexplained": [u.pair for u in getattr(learner, "unexplained_", [])],
            "seconds": round(seconds, 2)}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, world, demos, reward in _worlds(Path(tmp)):
            row = run(name, world, demos(world), reward)
            rows.append(row)
            print(f"{name:18s} iterations {row['iterations']:2d} (rules final from {row['converged_at']:2d})  "
                  f"stop {row['stop_reason']:15s} rules {row['rules']:2d}  FPR {row['fpr']:.3f}  "
                  f"FNR {row['fnr']:.3f}  unexplained {len(row['unexplained']):3d}  {row['seconds']:.1f} s", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"python": platform.python_version(), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
