"""When logic constraint inference stops, and what it learns, at the command line's defaults (issue #25).

    python benchmarks/logic_convergence.py [--json OUT]

For Hanoi (10 expert games), the traffic-light junction (100 demonstrations), the priority
junction (30) and the warehouse user domain of ``tests/support/warehouse_domain.py`` (200
deliveries, the world's own reward as ``symlearn learn constraints --domain`` picks) and a
seven-rule variant of it written by :func:`seven_rule_warehouse` (its expert plans with all seven), one run of
:class:`LogicConstraintInference` with ``iterations=20`` (the CLI default, a cap) and horizon 30.
Per run: iterations used, the iteration after which the rules stopped changing ("converged at"),
the stop reason, the number of rules, FPR/FNR over every pair and over the pairs a rule-abiding
agent reaches from the start ("reach"), and the pairs reported as unexplained. The script runs
on code without ``stop_reason_`` too (the "before" column of
docs/BENCHMARKS.md was measured with it on commit 9d87179).
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
    yield "warehouse-7", Domain.from_folder(seven_rule_warehouse(folder / "warehouse7")), \
        lambda d: obeying_expert(d, 200, seed=0), "given"


def seven_rule_warehouse(folder: Path) -> Path:
    """The warehouse with five more rules nobody tuned on, written here: no picking when loaded or
    away from the pick station, no dropping when empty or away from the drop station, no waiting
    without an alarm. The same expert obeys them (it never makes a useless step), so its
    demonstrations serve; the bias names the conditions as positive atoms of the background."""
    import warehouse_domain as wh

    wh.write_warehouse(folder)
    (folder / "bk.lp").write_text(wh.BACKGROUND + "calm :- not alarm.\nempty :- not loaded.\n"
                                  "offPick :- not atStation(pick).\noffDrop :- not atStation(drop).\n")
    (folder / "bias.las").write_text("".join(f"#modeb(1, {atom}, (positive)).\n" for atom in (
        "alarm", "calm", "loaded", "empty", "offPick", "offDrop", "move(var(dir))", "blocked(var(dir))", "wait",
        "pick", "drop")) + "#maxv(1).\n")
    (folder / "truth.lp").write_text(wh.TRUTH + ":- pick, loaded.\n:- pick, offPick.\n:- drop, empty.\n"
                                     ":- drop, offDrop.\n:- wait, calm.\n")
    return folder


def obeying_expert(domain: Domain, n: int, seed: int = 0):
    """``n`` deliveries by a shortest-route expert that obeys the domain's truth rules (ties among
    optimal actions broken at random), like ``warehouse_domain.expert_demonstrations``."""
    from symlearn.data import Demonstrations, Trajectory

    mdp = domain.mdp
    P, R = mdp.transitions, mdp.rewards
    forbidden = domain.truth_forbidden | domain.unavailable
    V = np.zeros(mdp.n_states)
    for _ in range(500):
        Q = np.where(forbidden, -np.inf, R + 0.95 * P @ V)
        Q[mdp.terminal] = 0.0
        V = Q.max(axis=1)
    rng = np.random.default_rng(seed)
    trajectories = []
    for _ in range(n):
        s = int(np.argmax(mdp.initial))
        states, actions = [s], []
        for _ in range(100):
            a = int(rng.choice(np.flatnonzero(Q[s] >= Q[s].max() - 1e-9)))
            s = int(rng.choice(mdp.n_states, p=P[s, a]))
            actions.append(a)
            states.append(s)
            if mdp.terminal[s]:
                break
        trajectories.append(Trajectory(states=states, actions=actions))
    return Demonstrations(trajectories)


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
    from symlearn.learners.constraints.constraint_metrics import constraint_metrics, reachable_pairs

    # over the pairs a rule-abiding agent meets (as benchmarks/logic_constraints.py's "reach")
    reach = reachable_pairs(world.mdp, world.truth_forbidden) & ~world.unavailable
    on_reach = constraint_metrics(final, world.truth_forbidden, reach)
    return {"world": name, "reach_fpr": on_reach["fpr"], "reach_fnr": on_reach["fnr"],
            "iterations": len(learner.history_), "converged_at": converged,
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
                  f"FNR {row['fnr']:.3f}  (reach: FPR {row['reach_fpr']:.3f} FNR {row['reach_fnr']:.3f})  "
                  f"unexplained {len(row['unexplained']):3d}  {row['seconds']:.1f} s", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps({"python": platform.python_version(), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
