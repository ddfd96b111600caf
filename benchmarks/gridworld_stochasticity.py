"""Constraint learning under stochastic dynamics: the gridworld stochasticity sweep.

For every stochasticity p and seed: record expert demonstrations (the expert is optimal under
the true constraints), learn with MCE-ICRL (causal entropy), ME-ICRL (trajectory entropy) and
maximum-likelihood constraint inference, then run each learned policy in the true environment
and measure the mean reward and the constraint-violation rate (fraction of an episode's steps
that end in a forbidden cell). The expert is measured in the same run as the reference.

    python benchmarks/gridworld_stochasticity.py            # p = 0, 0.1, ..., 0.5; 5 seeds
    python benchmarks/gridworld_stochasticity.py --quick    # p = 0, 0.3, 0.5; 2 seeds; fewer iterations
    python benchmarks/gridworld_stochasticity.py --json results.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
import warnings

import numpy as np

from symlearn.data import record
from symlearn.envs.gridworld import StochasticGridworld
from symlearn.learners.constraints.mce_icrl import MCEICRL, MEICRL
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.rl.tabular import sample_rollouts

METHODS = ("expert", "MCE-ICRL", "ME-ICRL", "ML-inference")


def evaluate(env: StochasticGridworld, policy: np.ndarray, episodes: int, seed: int) -> tuple[float, float]:
    rollouts = sample_rollouts(env.to_tabular(), policy, episodes, env.max_steps, np.random.default_rng(seed))
    return float(rollouts.returns().mean()), float(rollouts.fraction_in(env.forbidden_states).mean())


def recovery(env: StochasticGridworld, learner) -> dict[str, float]:
    """How the learned constraints compare with the truth.

    ML inference forbids state-action pairs: recall over the moves into the block from outside
    it (the ones an agent can actually take), false-positive rate over the pairs that are truly
    allowed. MCE/ME-ICRL learn a cost per state: recall over forbidden cells, false-positive
    rate over the other cells, a cell counting as constrained when its multiplier exceeds the
    learner's threshold."""
    if hasattr(learner, "constraints_"):
        truth = env.constraint_mask()
        entries = truth & ~env.forbidden_states[:, None]
        learned = learner.constraints_
        allowed = ~truth
        allowed[env.goal_state] = False
        return {"recall": float((learned & entries).sum() / entries.sum()),
                "fpr": float((learned & allowed).sum() / allowed.sum()), "constraints": int(learned.sum())}
    marked = learner.constraint_map_
    free = ~env.forbidden_states
    free[env.goal_state] = False
    return {"recall": float(marked[env.forbidden_states].mean()), "fpr": float(marked[free].mean()),
            "iterations": learner.n_iter_}


LEARNERS = {
    "MCE-ICRL": lambda iterations: MCEICRL(n_iterations=iterations),
    "ME-ICRL": lambda iterations: MEICRL(n_iterations=iterations),
    "ML-inference": lambda iterations: MLConstraintInference(horizon=50, rationality=3.0, max_iterations=200),
}


def demonstrations(p: float, seed: int, n_demos: int):
    env = StochasticGridworld(p)
    expert = env.expert_policy()
    demos = record(env, lambda s: int(expert[s]), n_demos, seed=seed, max_steps=env.max_steps, desc=f"p={p} seed={seed}")
    return env, expert, demos


def run_method(env: StochasticGridworld, expert: np.ndarray, demos, method: str, seed: int, *, iterations: int,
               episodes: int) -> dict[str, float]:
    """One method on one seed's demonstrations: its policy's reward and violation rate (the
    expert's own for ``expert``), learning time and recovery of the constraints."""
    mdp = env.to_tabular()
    if method == "expert":
        reward, violations = evaluate(env, np.eye(mdp.n_actions)[expert], episodes, 10_000 + seed)
        return {"reward": reward, "violation_rate": violations, "seconds": 0.0}
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        learner = LEARNERS[method](iterations).fit(demos, mdp)
    seconds = time.perf_counter() - t0
    reward, violations = evaluate(env, learner.policy_, episodes, 10_000 + seed)
    return {"reward": reward, "violation_rate": violations, "seconds": seconds, **recovery(env, learner)}


def run_one(p: float, seed: int, *, n_demos: int, iterations: int, episodes: int) -> dict[str, dict[str, float]]:
    env, expert, demos = demonstrations(p, seed, n_demos)
    return {method: run_method(env, expert, demos, method, seed, iterations=iterations, episodes=episodes)
            for method in METHODS}


def cell(p: float, method: str, seed: int, n_demos: int = 50, iterations: int = 300,
         episodes: int = 1000) -> dict[str, float]:
    """One cell of ``benchmarks/sweeps/gridworld_stochasticity*.toml``: the numbers :func:`run_one`
    gives ``method`` for this p and seed (the same demonstrations and evaluation seeds)."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r} (one of {', '.join(METHODS)})")
    env, expert, demos = demonstrations(p, seed, n_demos)
    return run_method(env, expert, demos, method, seed, iterations=iterations, episodes=episodes)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 stochasticities, 2 seeds, fewer iterations")
    parser.add_argument("--seeds", type=int, default=None)
    parser.add_argument("--demos", type=int, default=50, help="expert demonstrations per run")
    parser.add_argument("--json", default=None, help="also write the raw results to this file")
    args = parser.parse_args(argv)
    ps = [0.0, 0.3, 0.5] if args.quick else [round(0.1 * i, 1) for i in range(6)]
    seeds = args.seeds or (2 if args.quick else 5)
    iterations = 100 if args.quick else 300
    episodes = 300 if args.quick else 1000
    os.environ.setdefault("SYMLEARN_QUIET", "1")
    started = time.perf_counter()
    table: dict[float, dict[str, list[dict[str, float]]]] = {}
    for p in ps:
        table[p] = {m: [] for m in METHODS}
        for seed in range(seeds):
            for method, row in run_one(p, seed, n_demos=args.demos, iterations=iterations, episodes=episodes).items():
                table[p][method].append(row)
        print(f"p={p}: done ({time.perf_counter() - started:.0f} s)", file=sys.stderr)

    def cell(rows, key):
        values = np.array([r[key] for r in rows])
        return f"{values.mean():.3f} ± {values.std(ddof=1) / np.sqrt(len(values)):.3f}" if len(values) > 1 else f"{values[0]:.3f}"

    command = "python benchmarks/gridworld_stochasticity.py" + (" --quick" if args.quick else "")
    print(f"command: {command}")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, python {platform.python_version()}")
    print(f"{seeds} seeds, {args.demos} expert demonstrations each, {episodes} evaluation episodes; "
          f"mean ± standard error over seeds\n")
    print("violation rate (fraction of steps in a forbidden cell)\n")
    print("| p | " + " | ".join(METHODS) + " | ME / MCE |")
    print("|---|" + "---|" * (len(METHODS) + 1))
    for p in ps:
        mce = np.mean([r["violation_rate"] for r in table[p]["MCE-ICRL"]])
        me = np.mean([r["violation_rate"] for r in table[p]["ME-ICRL"]])
        ratio = f"{me / mce:.1f}" if mce > 0 else "-"
        print(f"| {p} | " + " | ".join(cell(table[p][m], "violation_rate") for m in METHODS) + f" | {ratio} |")
    print("\nreward per episode\n")
    print("| p | " + " | ".join(METHODS) + " |")
    print("|---|" + "---|" * len(METHODS))
    for p in ps:
        print(f"| {p} | " + " | ".join(cell(table[p][m], "reward") for m in METHODS) + " |")
    print("\nlearned constraints against the truth: recall / false-positive rate (see recovery())\n")
    print("| p | " + " | ".join(METHODS[1:]) + " | ML pairs forbidden |")
    print("|---|" + "---|" * len(METHODS))
    for p in ps:
        print(f"| {p} | " + " | ".join(f"{np.mean([r['recall'] for r in table[p][m]]):.2f} / "
                                       f"{np.mean([r['fpr'] for r in table[p][m]]):.2f}" for m in METHODS[1:])
              + f" | {np.mean([r['constraints'] for r in table[p]['ML-inference']]):.0f} |")
    print("\nlearning time per run, seconds (MCE / ME / ML)\n")
    for p in ps:
        print(f"p={p}: " + " / ".join(f"{np.mean([r['seconds'] for r in table[p][m]]):.1f}" for m in METHODS[1:]))
    print(f"\ntotal {time.perf_counter() - started:.0f} s")
    if args.json:
        from symlearn.atomic import write_text

        write_text(args.json, json.dumps({"command": command, "results": {str(p): v for p, v in table.items()}}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
