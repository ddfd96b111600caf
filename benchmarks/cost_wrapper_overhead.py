"""Overhead of ``DnfCostWrapper`` per environment step, against the bare environment in the same run.

The issue's target: the cost wrapper adds less than 5 % to an environment step. Every
environment is made with ``gymnasium.make`` (as training sees it) and stepped with random
actions drawn beforehand from its seeded action space (reset at each episode end); the wrapped
variants step the same action sequence from the same seed:

* ``bare``: the environment alone (the peer);
* ``cost``: ``DnfCostWrapper(env, dnf, names, track=False)``: the cost only;
* ``cost+stats``: the default, with the pruning statistics (``RuleStats``) counted every step;
* ``per-rule+stats``: ``per_rule=True`` (one cost per conjunction, PPO-Lagrangian per rule);
* ``rollout+stats`` / ``rollout per-rule+stats``: what ``symlearn train`` does, ``train_ppo(...,
  cost_fn=DnfRolloutCost(...))``: every step's ``info["features"]`` is copied into the rollout's
  array (as PPO's rollout collection records it), and the cost and the rule counts are computed
  once per rollout of ``--rollout`` steps (512: PPO's default 4 x 128) over all of them.

The DNFs are learned, as in the chapter's experiments: ``OneClassTreeConstraint(max_depth=d)``
on the scripted expert's SafeNav demonstrations (``--episodes`` episodes of the environment's
agent and task, 20 features) and on the toy's expert demonstrations (2 features), at several
depths, so the formulas have realistic sizes (tens to thousands of conjunctions). Variants go
round-robin, ``--repeats`` times, medians kept; the overhead is ``wrapped / bare - 1`` with both
medians from the same run.

    .venv/bin/python benchmarks/cost_wrapper_overhead.py [--quick] [--out benchmarks/results/cost_wrapper_overhead.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import gymnasium  # noqa: E402

import symlearn.envs  # noqa: E402,F401  (registers the gymnasium ids)
from symlearn.atomic import write_text  # noqa: E402
from symlearn.backends.dnf_cost import DnfCostWrapper, DnfRolloutCost  # noqa: E402
from symlearn.rl.ppo import Rollout  # noqa: E402
from symlearn.envs import toy_navigation  # noqa: E402
from symlearn.envs.safenav_expert import expert_demonstrations  # noqa: E402
from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint  # noqa: E402

ENVS = {  # gym id -> (demonstrations, feature names)
    "symlearn/safenav-point-goal-v0": ("point", "goal"),
    "symlearn/safenav-car-push-v0": ("car", "push"),
    "symlearn/toy-navigation-v0": None,
}
VARIANTS = ("bare", "cost", "cost+stats", "per-rule+stats", "rollout+stats", "rollout per-rule+stats")
ROLLOUT = 512  # steps per PPO rollout (PPOConfig: n_envs 4 x n_steps 128)


def demonstrations(gym_id: str, episodes: int, seed: int):
    spec = ENVS[gym_id]
    if spec is None:
        demos = toy_navigation.expert_demonstrations(n=max(episodes, 10), seed=seed)
    else:
        demos = expert_demonstrations(*spec, n=episodes, seed=seed, max_steps=1000)
    return demos, list(demos.metadata["features"])


class PerRollout:
    """The bare environment plus what PPO does for ``cost_fn=DnfRolloutCost``: record each step's
    ``info["features"]``, evaluate the whole rollout at its end."""

    def __init__(self, env, dnf, names, per_rule: bool, rollout: int) -> None:
        self.env, self.rollout = env, rollout
        self.cost = DnfRolloutCost(dnf, names, per_rule=per_rule)
        self.features = np.zeros((rollout, 1, len(names)))

    def batch(self, n: int) -> None:
        X = self.features[:n]
        zeros = np.zeros((n, 1))
        self.cost(Rollout(obs=X, actions=zeros, next_obs=X, rewards=zeros, dones=zeros, info={"features": X}))


def make(gym_id: str, variant: str, dnf, names, rollout: int = ROLLOUT):
    env = gymnasium.make(gym_id)
    if variant == "bare":
        return env
    if variant.startswith("rollout"):
        return PerRollout(env, dnf, names, per_rule="per-rule" in variant, rollout=rollout)
    return DnfCostWrapper(env, dnf, names, track=variant != "cost", per_rule=variant.startswith("per-rule"))


def one_run(env, actions, seed: int) -> tuple[float, float]:
    """Wall and CPU seconds per step over ``actions`` (resets at episode ends included, as in
    training). CPU time (this process only) is what other jobs on the machine disturb least."""
    if isinstance(env, PerRollout):
        return one_rollout_run(env, actions, seed)
    env.reset(seed=seed)
    start, cpu = time.perf_counter(), time.process_time()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return (time.perf_counter() - start) / len(actions), (time.process_time() - cpu) / len(actions)


def one_rollout_run(wrapped: PerRollout, actions, seed: int) -> tuple[float, float]:
    env, features, t = wrapped.env, wrapped.features, 0
    shape = features.shape[2:]
    env.reset(seed=seed)
    start, cpu = time.perf_counter(), time.process_time()
    for action in actions:
        _, _, terminated, truncated, info = env.step(action)
        value = np.asarray(info["features"])     # PPO's per-step record of an info key
        if value.shape != shape:
            raise ValueError(f"features of shape {value.shape}")
        features[t, 0] = value
        t += 1
        if t == wrapped.rollout:
            wrapped.batch(t)
            t = 0
        if terminated or truncated:
            env.reset()
    if t:
        wrapped.batch(t)
    return (time.perf_counter() - start) / len(actions), (time.process_time() - cpu) / len(actions)


def measure(gym_id: str, dnf, names, steps: int, repeats: int, seed: int) -> dict:
    envs = {variant: make(gym_id, variant, dnf, names) for variant in VARIANTS}
    space = envs["bare"].action_space
    space.seed(seed)
    actions = [space.sample() for _ in range(steps)]
    for env in envs.values():                                  # warm-up (first evaluation loads the kernels)
        one_run(env, actions[: min(200, steps)], seed)
    times: dict[str, list[float]] = {variant: [] for variant in VARIANTS}
    cpu: dict[str, list[float]] = {variant: [] for variant in VARIANTS}
    for _ in range(repeats):
        for variant, env in envs.items():
            wall, used = one_run(env, actions, seed)
            times[variant].append(wall)
            cpu[variant].append(used)
    median = {variant: statistics.median(values) for variant, values in times.items()}
    median_cpu = {variant: statistics.median(values) for variant, values in cpu.items()}
    bare, bare_cpu = median["bare"], median_cpu["bare"]
    return {
        "step_us": {variant: value * 1e6 for variant, value in median.items()},
        "overhead": {variant: median[variant] / bare - 1 for variant in VARIANTS if variant != "bare"},
        "added_us": {variant: (median[variant] - bare) * 1e6 for variant in VARIANTS if variant != "bare"},
        "cpu_step_us": {variant: value * 1e6 for variant, value in median_cpu.items()},
        "cpu_overhead": {variant: median_cpu[variant] / bare_cpu - 1 for variant in VARIANTS if variant != "bare"},
        "runs_us": {variant: [v * 1e6 for v in values] for variant, values in times.items()},
        "cpu_runs_us": {variant: [v * 1e6 for v in values] for variant, values in cpu.items()},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps, depths and repeats")
    parser.add_argument("--steps", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=None)
    parser.add_argument("--episodes", type=int, default=10, help="expert episodes to learn from")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", default=str(REPO / "benchmarks" / "results" / "cost_wrapper_overhead.json"))
    args = parser.parse_args()
    steps = args.steps or (2000 if args.quick else 10000)
    repeats = args.repeats or (3 if args.quick else 7)
    depths = (2, 6) if args.quick else (2, 4, 6, 8)
    rows = []
    for gym_id in ENVS:
        demos, names = demonstrations(gym_id, 4 if args.quick else args.episodes, args.seed)
        for depth in depths:
            dnf = OneClassTreeConstraint(max_depth=depth).fit(demos, names).dnf_
            result = measure(gym_id, dnf, names, steps, repeats, args.seed)
            row = {"env": gym_id, "depth": depth, "conjunctions": len(dnf), "atoms": sum(len(c) for c in dnf),
                   "features": len(names), "form": dnf._plan.mode, "demonstration_steps": int(sum(len(t) for t in demos)),
                   **result}
            rows.append(row)
            step = row["step_us"]
            print(f"{gym_id:32} depth {depth} m={row['conjunctions']:>5} atoms={row['atoms']:>6} | bare "
                  f"{step['bare']:6.1f} us/step | " + " | ".join(
                      f"{v} +{row['added_us'][v]:5.1f} us ({100 * row['overhead'][v]:5.1f} %, CPU "
                      f"{100 * row['cpu_overhead'][v]:5.1f} %)" for v in VARIANTS[1:]),
                  flush=True)
    doc = {"benchmark": "cost_wrapper_overhead",
           "command": "benchmarks/cost_wrapper_overhead.py" + (" --quick" if args.quick else ""),
           "machine": {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
                       "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
                       "gymnasium": gymnasium.__version__, "load_average": os.getloadavg()},
           "steps": steps, "repeats": repeats, "seed": args.seed, "target_overhead": 0.05, "cases": rows}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_text(args.out, json.dumps(doc, indent=2) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
