"""The thesis' toy (section 4.3, Fig. 4.1/4.2, pruning of 4.3.4) end to end.

An expert goes from (0.1, 0.1) along the bottom and up the right-hand side to (0.9, 0.9); the
safe set is [0.1, 0.7] x [0.1, 0.3] U [0.7, 0.9] x [0.1, 0.9] (``symlearn.envs.toy_navigation``).

(a) **Boxes.** A one-class tree (``max_depth=3``) on 30 expert episodes, for ``--tree-seeds``
    seeds: the leaf boxes, the first split, and each box's largest distance (on any side) to the
    true rectangle it covers.
(b) **Formula = complement.** On a 201 x 201 grid of [0, 1]^2: the share of points where the DNF
    agrees with "outside every learned box" (must be 1) and with the true unsafe set; and how much
    of the goal circle is safe under each.
(c) **RL.** For ``--seeds`` seeds (each with its own demonstrations and formula): plain PPO, and
    PPO-Lagrangian on the learned DNF (cost 1 per step in the learned unsafe set, cost limit 0),
    both with the toy's PPO settings (``symlearn.demo.dnf_pipeline.toy_ppo_config``), plus
    PPO-Lagrangian with the settings the demo used before (PPO defaults, raw advantages, no goal
    reward). Reported: greedy and stochastic return, goal rate, true cost (steps outside the true
    safe set) and learned cost per episode; training curves (return, true cost, multiplier).
(d) **Pruning** (threshold 0.001, rules evaluated in ascending number of atoms): the rule counts
    over the whole PPO-Lagrangian training (the thesis' procedure), over its last quarter, and over
    50 episodes of the trained (stochastic) agent; a fresh agent trained on the formula pruned by
    the whole-training counts, with its true cost.
``--ablation``: the toy's settings with one change at a time (3 seeds).

    .venv/bin/python benchmarks/toy_dnf.py                  # (a)-(d), 5 seeds x 100k steps (~15 min on 2 workers)
    .venv/bin/python benchmarks/toy_dnf.py --ablation       # adds the ablation (~+10 min)
    .venv/bin/python benchmarks/toy_dnf.py --quick          # smoke test (tiny budget, results in /tmp)

Raw results: ``benchmarks/results/toy_dnf.json``; figures ``docs/figures/toy_dnf_safe_set.png``
(true and learned safe sets, trajectories of the trained agents) and
``docs/figures/toy_dnf_training.png`` (return, true cost and multiplier during training).
"""

from __future__ import annotations

import argparse
import io
import json
import math
import os
import platform
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from symlearn.atomic import write_bytes, write_text  # noqa: E402

FEATURES = ["x", "y"]
N_DEMOS = 30
DEPTH = 3
THRESHOLD = 1e-3
EVAL_EPISODES = 50
GRID = 201

#: ablations: (name, PPO overrides, Lagrangian overrides, environment arguments)
ABLATIONS = [
    ("normalize_observations=False", {"normalize_observations": False}, {}, {}),
    ("normalize_values=False", {"normalize_values": False}, {}, {}),
    ("advantage_scale='raw'", {}, {"advantage_scale": "raw"}, {}),
    ("goal_reward=0", {}, {}, {"goal_reward": 0.0}),
    ("log_std_init=0", {"log_std_init": 0.0}, {}, {}),
    ("learning_rate=2.5e-4", {"learning_rate": 2.5e-4}, {}, {}),
    ("ent_coef=0", {"ent_coef": 0.0}, {}, {}),
    ("init=0", {}, {"init": 0.0}, {}),
]


# --------------------------------------------------------------------------------------------------
# (a), (b): the tree and the formula


def learn(seed: int, n_demos: int = N_DEMOS):
    from symlearn.envs.toy_navigation import expert_demonstrations
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    demos = expert_demonstrations(n_demos, seed=seed)
    return demos, OneClassTreeConstraint(max_depth=DEPTH).fit(demos, FEATURES)


def grid_points(n: int = GRID) -> np.ndarray:
    axis = np.linspace(0.0, 1.0, n)
    xs, ys = np.meshgrid(axis, axis)
    return np.stack([xs.ravel(), ys.ravel()], axis=1)


def truly_unsafe(points: np.ndarray) -> np.ndarray:
    from symlearn.envs.toy_navigation import SAFE_RECTANGLES

    x, y = points[:, 0], points[:, 1]
    safe = np.zeros(len(points), dtype=bool)
    for x0, x1, y0, y1 in SAFE_RECTANGLES:
        safe |= (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)
    return ~safe


def tree_report(seed: int) -> dict[str, Any]:
    from symlearn.envs.toy_navigation import GOAL, SAFE_RECTANGLES, START

    demos, learner = learn(seed)
    boxes = [[*b.lower, *b.upper] for b in learner.safe_boxes_]  # x0, y0, x1, y1
    truth = [(x0, y0, x1, y1) for x0, x1, y0, y1 in SAFE_RECTANGLES]
    errors = []
    for box in boxes:  # the true rectangle with the largest overlap, and the largest side difference
        def overlap(t):
            w = min(box[2], t[2]) - max(box[0], t[0])
            h = min(box[3], t[3]) - max(box[1], t[1])
            return max(w, 0) * max(h, 0)
        best = max(truth, key=overlap)
        errors.append(float(max(abs(a - b) for a, b in zip(box, best))))
    points = grid_points()
    dnf_unsafe = learner.dnf_.evaluate(points, FEATURES)
    outside_boxes = ~np.any([b.contains(points) for b in learner.safe_boxes_], axis=0)
    goal = np.hypot(points[:, 0] - GOAL[0], points[:, 1] - GOAL[1]) <= 0.05
    return {
        "seed": seed, "n_points": int(sum(len(t.states) for t in demos)), "leaves": len(boxes), "boxes": boxes,
        "first_split": learner.history_[0].feature if learner.history_ else None,
        "box_error": errors, "rules": len(learner.dnf_), "formula": str(learner.dnf_),
        "agree_with_boxes": float(np.mean(dnf_unsafe == outside_boxes)),
        "agree_with_truth": float(np.mean(dnf_unsafe == truly_unsafe(points))),
        "start_safe": not bool(learner.dnf_.evaluate(np.array([START]), FEATURES)[0]),
        "goal_circle_safe_learned": float(np.mean(~dnf_unsafe[goal])),
        "goal_circle_safe_true": float(np.mean(~truly_unsafe(points)[goal])),
    }


# --------------------------------------------------------------------------------------------------
# (c), (d): one training run (in a worker process)


class EpisodeLog(gym.Wrapper):
    """Wraps the cost-wrapped toy: logs every finished training episode as ``[end step (all copies),
    return, true cost, learned cost, goal reached, length]``."""

    def __init__(self, env, log: list, clock: list) -> None:
        super().__init__(env)
        self.log, self.clock = log, clock
        self.total = [0.0, 0.0, 0.0, 0]

    def reset(self, **kwargs):
        self.total = [0.0, 0.0, 0.0, 0]
        return self.env.reset(**kwargs)

    def step(self, action):
        o, r, te, tr, info = self.env.step(action)
        self.clock[0] += 1
        self.total[0] += r
        self.total[1] += info.get("env_cost", 0.0)
        self.total[2] += info["cost"]
        self.total[3] += 1
        if te or tr:
            self.log.append([self.clock[0], *self.total[:3], bool(te), self.total[3]])
        return o, r, te, tr, info


def rollouts(policy, dnf, n: int, *, deterministic: bool, seed: int, env_kwargs: dict, keep: int = 0):
    """``n`` episodes of ``policy`` on the toy, counted by a fresh RuleStats: per-episode metrics,
    the first ``keep`` trajectories, and the stats."""
    from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
    from symlearn.envs.toy_navigation import ToyNavigationEnv

    stats = RuleStats(dnf, FEATURES)
    env = DnfCostWrapper(ToyNavigationEnv(**env_kwargs), dnf, FEATURES, stats=stats)
    rng = np.random.default_rng(seed)
    rows, paths = [], []
    for episode in range(n):
        o, info = env.reset(seed=seed + episode)
        path, total, true_cost, learned, done = [info["features"].tolist()], 0.0, 0.0, 0.0, False
        terminated = False
        while not done:
            o, r, terminated, truncated, info = env.step(policy.act(o, deterministic=deterministic, rng=rng))
            total, true_cost, learned = total + r, true_cost + info["env_cost"], learned + info["cost"]
            path.append(info["features"].tolist())
            done = terminated or truncated
        rows.append((total, true_cost, learned, bool(terminated), len(path) - 1))
        if episode < keep:
            paths.append([[round(v, 4) for v in point] for point in path])
    a = np.array(rows, dtype=np.float64)
    summary = {"return": float(a[:, 0].mean()), "true_cost": float(a[:, 1].mean()),
               "learned_cost": float(a[:, 2].mean()),
               "goal_rate": float(a[:, 3].mean()), "length": float(a[:, 4].mean()),
               "safe_rate": float(np.mean(a[:, 1] == 0)), "episodes": n}
    return summary, paths, stats


def verdicts(stats) -> dict[str, Any]:
    pruned, rows = stats.prune(THRESHOLD)
    return {"kept": [str(c) for c in pruned.conjunctions], "formula": str(pruned),
            "rules": [v.as_dict() for v in rows]}


def train_run(spec: dict[str, Any]) -> dict[str, Any]:
    import torch

    from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
    from symlearn.demo.dnf_pipeline import toy_lagrangian, toy_ppo_config
    from symlearn.envs.toy_navigation import ToyNavigationEnv
    from symlearn.logic.dnf import parse
    from symlearn.rl.ppo import LEGACY_LAGRANGIAN, LagrangianConfig, PPOConfig, train_ppo

    torch.set_num_threads(1)
    started = time.perf_counter()
    seed = spec["seed"]
    dnf = parse(spec["formula"]) if spec.get("formula") else learn(seed)[1].dnf_
    stats = RuleStats(dnf, FEATURES)
    log: list = []
    clock = [0]
    env_kwargs = spec.get("env", {})

    def env_fn():
        return EpisodeLog(DnfCostWrapper(ToyNavigationEnv(**env_kwargs), dnf, FEATURES, stats=stats), log, clock)

    if spec["settings"] == "before":  # what the demo ran before: PPO defaults, raw advantages
        config = PPOConfig(**{"seed": seed, "normalize_observations": False, "normalize_values": False,
                              "learning_rate": 2.5e-4, "log_std_init": 0.0, **spec.get("ppo", {})})
        lagrangian = LagrangianConfig(**{"cost_limit": 0.0, **LEGACY_LAGRANGIAN}) if spec["lagrangian"] else None
    else:
        config = toy_ppo_config(seed, **spec.get("ppo", {}))
        lagrangian = toy_lagrangian(**spec.get("lag", {})) if spec["lagrangian"] else None
    snapshots: list = []
    curve: list = []

    def callback(record, _policy):
        snapshots.append(stats.snapshot())
        if record.iteration % 4 == 1:  # every 4th iteration is enough for the plots
            curve.append({"steps": record.steps,
                          "multiplier": round(record.multipliers[0], 4) if record.multipliers else None,
                          "scales": [round(x, 4) for x in record.return_scales], "entropy": round(record.entropy, 4)})

    result = train_ppo(env_fn, spec["steps"], config, lagrangian=lagrangian, callback=callback)
    train_seconds = time.perf_counter() - started
    greedy, greedy_paths, _ = rollouts(result.policy, dnf, 1, deterministic=True, seed=1000, env_kwargs=env_kwargs,
                                       keep=1)
    stochastic, paths, agent_stats = rollouts(result.policy, dnf, spec.get("eval_episodes", EVAL_EPISODES),
                                              deterministic=False, seed=2000, env_kwargs=env_kwargs,
                                              keep=5 if seed == 0 else 0)  # the figure shows seed 0
    late = stats.since(snapshots[(3 * len(snapshots)) // 4 - 1]) if len(snapshots) >= 4 else stats
    return {**spec, "formula": str(dnf), "rules": len(dnf), "steps_done": result.steps,
            "train_seconds": round(train_seconds, 1), "seconds": round(time.perf_counter() - started, 1),
            "multipliers": [float(m) for m in result.multipliers],
            "greedy": greedy, "stochastic": stochastic, "greedy_path": greedy_paths[0], "paths": paths,
            "training_curve": training_curve(log, spec["steps"]), "training_episodes": len(log), "curve": curve,
            "pruning": {"training": verdicts(stats), "late_training": verdicts(late),
                        "trained_agent": verdicts(agent_stats)}}


# --------------------------------------------------------------------------------------------------
# the report


def mean_sd(values) -> dict[str, float | None]:
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=np.float64)
    return {"mean": float(v.mean()) if len(v) else None, "sd": float(v.std()) if len(v) else None, "n": int(len(v))}


def fmt(stat: dict, digits: int = 2) -> str:
    if stat["mean"] is None:
        return "-"
    return f"{stat['mean']:.{digits}f} ± {stat['sd']:.{digits}f}"


def summarise(runs: list[dict]) -> dict[str, Any]:
    out = {}
    for key in ("greedy", "stochastic"):
        out[key] = {m: mean_sd(r[key][m] for r in runs)
                    for m in ("return", "true_cost", "learned_cost", "goal_rate", "length", "safe_rate")}
    out["solved"] = sum(1 for r in runs if r["greedy"]["goal_rate"] == 1 and r["greedy"]["true_cost"] == 0)
    out["seeds"] = len(runs)
    out["train_seconds"] = mean_sd(r["train_seconds"] for r in runs)
    return out


def table(rows: list[tuple[str, dict]]) -> str:
    lines = ["| agent | greedy: return | goal | true cost | stochastic: return | goal rate | true cost | "
             "learned cost | solved seeds |", "|---|---|---|---|---|---|---|---|---|"]
    for name, s in rows:
        g, st = s["greedy"], s["stochastic"]
        lines.append(f"| {name} | {fmt(g['return'])} | {fmt(g['goal_rate'])} | {fmt(g['true_cost'], 1)} | "
                     f"{fmt(st['return'])} | {fmt(st['goal_rate'])} | {fmt(st['true_cost'], 1)} | "
                     f"{fmt(st['learned_cost'], 1)} | {s['solved']}/{s['seeds']} |")
    return "\n".join(lines)


def training_curve(episodes: list, total: int, bins: int = 25) -> dict[str, list]:
    """Means of the training episodes that ended in each of ``bins`` step ranges (None: none ended)."""
    rows = np.array(episodes, dtype=np.float64).reshape(-1, 6)
    edges = np.linspace(0, total, bins + 1)
    out: dict[str, list] = {"steps": [int(e) for e in edges[1:]], "episodes": []}
    for lo, hi in zip(edges[:-1], edges[1:]):
        out["episodes"].append(int(((rows[:, 0] > lo) & (rows[:, 0] <= hi)).sum()))
    for key, col in (("return", 1), ("true_cost", 2), ("learned_cost", 3), ("goal_rate", 4)):
        values = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            chosen = rows[(rows[:, 0] > lo) & (rows[:, 0] <= hi), col]
            values.append(float(chosen.mean()) if len(chosen) else None)
        out[key] = values
    return out


def plot_safe_set(path: Path, tree_rows: list[dict], main: dict[str, list[dict]]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Rectangle

    from symlearn.envs.toy_navigation import GOAL, SAFE_RECTANGLES

    fig, axes = plt.subplots(1, 2, figsize=(9.6, 4.6), dpi=110)
    demos, learner = learn(0)
    for ax in axes:
        ax.add_patch(Rectangle((0, 0), 1, 1, color="#f2c4c4", zorder=0))
        for x0, x1, y0, y1 in SAFE_RECTANGLES:
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="white", zorder=1))
        ax.add_patch(Circle(GOAL, 0.05, fill=False, ec="#d08a00", lw=1.2, zorder=4))
        ax.set(xlim=(0, 1), ylim=(0, 1), xlabel="x", ylabel="y", aspect="equal")
    ax = axes[0]
    for k, row in enumerate(tree_rows):
        for j, (x0, y0, x1, y1) in enumerate(row["boxes"]):
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=0.8, ec="#2a7f3f", alpha=0.6, zorder=3,
                                   label="learned boxes (all seeds)" if k == j == 0 else None))
    for k, t in enumerate(demos):
        xy = np.asarray(t.states)
        ax.plot(xy[:, 0], xy[:, 1], color="#3060a0", lw=0.5, alpha=0.5, zorder=2,
                label="demonstrations (seed 0)" if k == 0 else None)
    ax.set_title(f"true unsafe set (red), boxes of {len(tree_rows)} seeds", fontsize=9)
    ax.legend(loc="upper left", fontsize=7, framealpha=0.9)
    ax = axes[1]
    for x0, y0, x1, y1 in tree_rows[0]["boxes"]:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=1.5, ec="#2a7f3f", zorder=3))
    colours = {"ppo": "#c05000", "ppo-lag": "#106030", "before": "#7030a0"}
    labels = {"ppo": "PPO", "ppo-lag": "PPO-Lagrangian (learned DNF)", "before": "PPO-Lag., previous settings"}
    for name, runs in main.items():
        seed0 = [r for r in runs if r["seed"] == 0]
        if not seed0:
            continue
        run = seed0[0]
        for k, p in enumerate(run["paths"][:3]):
            xy = np.asarray(p)
            ax.plot(xy[:, 0], xy[:, 1], color=colours[name], lw=0.6, alpha=0.35, zorder=4)
        xy = np.asarray(run["greedy_path"])
        ax.plot(xy[:, 0], xy[:, 1], color=colours[name], lw=2.0, zorder=5, label=labels[name] + " (greedy)")
    ax.set_title("learned boxes (seed 0), trained agents: greedy (thick), sampled (thin)", fontsize=9)
    ax.legend(loc="upper left", fontsize=7, framealpha=0.9)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


def plot_training(path: Path, main: dict[str, list[dict]], steps: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 4, figsize=(14, 3.4), dpi=110)
    colours = {"ppo": "#c05000", "ppo-lag": "#106030", "before": "#7030a0"}
    labels = {"ppo": "PPO", "ppo-lag": "PPO-Lagrangian", "before": "PPO-Lag., previous settings"}
    for name, runs in main.items():
        x = np.array(runs[0]["training_curve"]["steps"])
        for ax, key, title in ((axes[0], "return", "episode return"), (axes[1], "true_cost", "true cost / episode"),
                               (axes[2], "goal_rate", "goal rate")):
            data = np.array([[math.nan if v is None else v for v in r["training_curve"][key]] for r in runs])
            for row in data:
                ax.plot(x, row, color=colours[name], lw=0.5, alpha=0.3)
            with np.errstate(all="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # bins without a finished episode
                ax.plot(x, np.nanmean(data, axis=0), color=colours[name], lw=1.8, label=labels[name])
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("environment steps")
        if runs[0]["lagrangian"]:
            for k, r in enumerate(runs):
                xs = [c["steps"] for c in r["curve"]]
                axes[3].plot(xs, [c["multiplier"] for c in r["curve"]], color=colours[name], lw=0.8, alpha=0.7,
                             label=labels[name] if k == 0 else None)
    axes[1].set_yscale("symlog", linthresh=1.0)
    axes[3].set_title("multiplier lambda", fontsize=9)
    axes[3].set_xlabel("environment steps")
    axes[0].legend(fontsize=7)
    axes[3].legend(fontsize=7)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


def pruning_report(runs: list[dict]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key in ("training", "late_training", "trained_agent"):
        kept = [len(r["pruning"][key]["kept"]) for r in runs]
        # how often each kind of rule survives: bounds (one atom) vs the inner rules
        out[key] = {"kept_rules": kept, "rules": [r["rules"] for r in runs],
                    "kept_bounds": [sum(1 for k in r["pruning"][key]["kept"] if "&" not in k) for r in runs],
                    "kept_inner": [sum(1 for k in r["pruning"][key]["kept"] if "&" in k) for r in runs]}
    return out


def main(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--tree-seeds", type=int, default=10)
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--ablation", action="store_true", help="also the toy's settings with one change at a time")
    parser.add_argument("--ablation-seeds", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="2 seeds, 8k steps, results in /tmp")
    parser.add_argument("--json", type=Path, default=REPO / "benchmarks" / "results" / "toy_dnf.json")
    parser.add_argument("--figures", type=Path, default=REPO / "docs" / "figures")
    args = parser.parse_args(argv)
    if args.quick:
        args.seeds, args.tree_seeds, args.steps, args.ablation_seeds = 2, 3, 8192, 1
        args.json = Path("/tmp/toy_dnf_quick.json")
        args.figures = Path("/tmp/toy_dnf_quick_figures")
    started = time.perf_counter()

    trees = [tree_report(seed) for seed in range(args.tree_seeds)]
    print(f"(a, b) trees: leaves {[t['leaves'] for t in trees]}, agreement with the boxes "
          f"{min(t['agree_with_boxes'] for t in trees):.4f}, with the truth "
          f"{min(t['agree_with_truth'] for t in trees):.3f}-{max(t['agree_with_truth'] for t in trees):.3f}",
          flush=True)

    specs = []
    for seed in range(args.seeds):
        specs += [{"name": "ppo", "settings": "toy", "lagrangian": False, "seed": seed, "steps": args.steps},
                  {"name": "ppo-lag", "settings": "toy", "lagrangian": True, "seed": seed, "steps": args.steps},
                  {"name": "before", "settings": "before", "lagrangian": True, "seed": seed, "steps": args.steps,
                   "env": {"goal_reward": 0.0}}]
    if args.ablation:
        for name, ppo, lag, env in ABLATIONS:
            specs += [{"name": f"ablation: {name}", "settings": "toy", "lagrangian": True, "seed": seed,
                       "steps": args.steps, "ppo": ppo, "lag": lag, "env": env} for seed in range(args.ablation_seeds)]
    results: list[dict] = []
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        for r in pool.map(train_run, specs):
            results.append(r)
            print(f"  {r['name']} seed {r['seed']}: greedy return {r['greedy']['return']:.2f} goal "
                  f"{r['greedy']['goal_rate']:.0f} true cost {r['greedy']['true_cost']:.0f}; stochastic goal rate "
                  f"{r['stochastic']['goal_rate']:.2f} true cost {r['stochastic']['true_cost']:.1f} "
                  f"({r['seconds']:.0f} s)", flush=True)
        # (d) a fresh agent on the formula pruned by the whole training's counts
        retrain = [{"name": "ppo-lag on the pruned formula", "settings": "toy", "lagrangian": True, "seed": r["seed"],
                    "steps": args.steps, "formula": r["pruning"]["training"]["formula"]}
                   for r in results if r["name"] == "ppo-lag" and r["pruning"]["training"]["kept"]
                   and len(r["pruning"]["training"]["kept"]) < r["rules"]]  # else the same run again
        for r in pool.map(train_run, retrain):
            results.append(r)
            print(f"  {r['name']} seed {r['seed']}: true cost {r['greedy']['true_cost']:.0f} (greedy), "
                  f"{r['stochastic']['true_cost']:.1f} (stochastic)", flush=True)

    groups: dict[str, list[dict]] = {}
    for r in results:
        groups.setdefault(r["name"], []).append(r)
    summaries = {name: summarise(runs) for name, runs in groups.items()}
    main_runs = {k: groups[k] for k in ("ppo", "ppo-lag", "before") if k in groups}
    args.figures.mkdir(parents=True, exist_ok=True)
    plot_safe_set(args.figures / "toy_dnf_safe_set.png", trees, main_runs)
    plot_training(args.figures / "toy_dnf_training.png", main_runs, args.steps)

    names = {"ppo": "PPO (toy settings)", "ppo-lag": "PPO-Lagrangian, learned DNF, limit 0",
             "before": "PPO-Lagrangian, previous settings", "ppo-lag on the pruned formula": "PPO-Lag., pruned formula"}
    print()
    print(table([(names.get(n, n), s) for n, s in summaries.items()]))
    document = {
        "benchmark": "toy_dnf", "command": "python benchmarks/toy_dnf.py " + " ".join(argv or sys.argv[1:]),
        "settings": {"n_demos": N_DEMOS, "max_depth": DEPTH, "steps": args.steps, "seeds": args.seeds,
                     "threshold": THRESHOLD, "eval_episodes": EVAL_EPISODES, "grid": GRID},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "numpy": np.__version__, "torch": __import__("torch").__version__},
        "trees": trees, "summaries": summaries,
        "pruning": pruning_report(groups.get("ppo-lag", [])),
        "runs": results, "seconds": round(time.perf_counter() - started, 1),
    }
    write_text(args.json, json.dumps(document, indent=1) + "\n")
    print(f"\nwrote {args.json} and the figures in {args.figures} ({document['seconds']:.0f} s)")
    return document


if __name__ == "__main__":
    main()
