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


def run(name, world, demos, reward, rationality=None) -> dict:
    t0 = time.perf_counter()
    setting = {} if rationality is None else {"rationality": rationality}
    learner = LogicConstraintInference(iterations=20, horizon=30, reward=reward, **setting).fit(demos, world)
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
            "rationality": "default" if rationality is None else rationality,
            "rationality_used": getattr(learner, "rationality_", None),
            "seconds": round(seconds, 2)}


def likelihoods(world, demos, reward, betas) -> dict:
    """Mean log-probability per demonstrated step under the unconstrained nominal model, per beta
    (what ``rationality="auto"`` maximises), and the same with the world's truth rules known."""
    from symlearn.learners.constraints.ml_constraint_inference import MaxEntVisitation
    from symlearn.learners.constraints.rationality_fit import demonstration_log_likelihood

    episodes = world.episodes(demos)
    planner = MaxEntVisitation(world.mdp, [], reward, 30, 1.0)
    out = {}
    for label, forbidden in (("unconstrained", world.unavailable),
                             ("truth known", world.unavailable | world.truth_forbidden)):
        out[label] = {str(b): round(demonstration_log_likelihood(world.mdp, episodes, planner._reward, b, 30,
                                                                 ~forbidden), 4) for b in betas}
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json")
    parser.add_argument("--rationality", default=None,
                        help="comma-separated settings to run each world at (numbers or 'auto'); default: the "
                             "learner's default only")
    parser.add_argument("--likelihood", default=None,
                        help="comma-separated betas: also print each world's demonstration log-likelihood at them")
    parser.add_argument("--worlds", default=None, help="comma-separated world names (default: all)")
    args = parser.parse_args(argv)
    settings = [None] if args.rationality is None else [
        v if v == "auto" else float(v) for v in args.rationality.split(",")]
    rows, curves = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, world, demos, reward in _worlds(Path(tmp)):
            if args.worlds and name not in args.worlds.split(","):
                continue
            demonstrations = demos(world)
            if args.likelihood:
                domain = getattr(world, "domain", world)
                curves[name] = likelihoods(domain, demonstrations, reward, [float(b) for b in args.likelihood.split(",")])
                print(f"{name:18s} log-likelihood per step: {curves[name]}", flush=True)
            for setting in settings:
                row = run(name, world, demonstrations, reward, setting)
                rows.append(row)
                print(f"{name:18s} rationality {row['rationality']} ({row['rationality_used']})  "
                      f"iterations {row['iterations']:2d} (rules final from {row['converged_at']:2d})  "
                      f"stop {row['stop_reason']:15s} rules {row['rules']:2d}  FPR {row['fpr']:.3f}  "
                      f"FNR {row['fnr']:.3f}  (reach: FPR {row['reach_fpr']:.3f} FNR {row['reach_fnr']:.3f})  "
                      f"unexplained {len(row['unexplained']):3d}  {row['seconds']:.1f} s", flush=True)
    if args.json:
        doc = {"python": platform.python_version(), "command": " ".join(sys.argv), "rows": rows}
        if curves:
            doc["log_likelihood"] = curves
        Path(args.json).write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
