"""Driving (thesis Fig. 4.5 in shape): a learned DNF cost vs plain PPO vs an engineered penalty.

    nice -n 5 .venv/bin/python benchmarks/driving.py                 # the recorded run
    nice -n 5 .venv/bin/python benchmarks/driving.py --quick         # smoke run (~3 min; *_quick files)
    nice -n 5 .venv/bin/python benchmarks/driving.py --speed-only    # steps/s only

Environment: ``symlearn/driving-v0`` (highway-env's highway, continuous action; the
``highway`` extra). Steps, in one run:

1. **Speed**: steps/s of our environment and of highway-env's own ``highway-fast-v0`` configured
   the same way (continuous action, 5 Hz, 3 lanes, 20 cars) stepped through its ``step``, with
   the same actions, round-robin (best of ``--repeats``): the same-run ratio. Also our
   environment driven by the IDM/MOBIL demonstrator (what recording demonstrations costs).
2. **Constraint**: ``--demos`` IDM/MOBIL episodes (action noise ``--noise``, unsafe episodes
   replaced) -> :class:`OneClassTreeConstraint` (``--depth``) -> a DNF over the 10 features. It
   is checked on 10 *held-out* demonstrator episodes: the share of their states it calls unsafe
   and their mean cost per episode under it. That cost is PPO-Lagrangian's ``cost_limit``: the
   agent may do what the demonstrator does, by the learned formula's own measure.
3. **Agents**, ``--seeds`` seeds each, ``--steps`` environment steps, one PPO configuration:
   ``ppo`` (the environment's reward: progress, 0 on the crash step; the episode ends on a
   collision or off the road), ``ppo-penalty`` (reward minus ``--penalty`` on a collision or
   leaving the road: the "RL with an engineered reward" of the thesis, after Wang et al.) and
   ``ppo-lag-dnf`` (PPO-Lagrangian with the learned DNF as its cost; it never sees the true
   events). During training every episode's true collision / off-road and its environment
   reward (without penalty) are logged: the curves of Fig. 4.5. After training: ``--eval``
   greedy episodes on fixed seeds, and the demonstrator on the same seeds.

Results: ``benchmarks/results/driving.json`` (everything, raw per-episode logs included) and
``docs/figures/driving.png`` (reward, collision ratio, off-road ratio during training).
"""

from __future__ import annotations

import argparse
from dataclasses import asdict
import io
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(Path(__file__).resolve().parent))  # safenav_speed's timing loop

import gymnasium  # noqa: E402

from safenav_speed import one_run as _steps_per_second  # noqa: E402  (same timing loop as SafeNav's)
from symlearn.atomic import write_bytes, write_text  # noqa: E402
from symlearn.optional import require  # noqa: E402

METHODS = ("ppo", "ppo-penalty", "ppo-lag-dnf")
EVAL_SEED = 10_000


# --- 1. speed ---------------------------------------------------------------------------------


def measure_speed(steps: int, repeats: int) -> dict:
    import highway_env  # noqa: F401  (registers highway-fast-v0)

    from symlearn.envs.driving import DrivingEnv
    from symlearn.envs.driving.expert import IdmMobilExpert

    ours = DrivingEnv()
    peer = gymnasium.make("highway-fast-v0", config={
        "action": {"type": "ContinuousAction", "steering_range": (-ours.steering_range, ours.steering_range)},
        "policy_frequency": ours.frequency, "simulation_frequency": ours.simulation_frequency,
        "lanes_count": ours.lanes, "vehicles_count": ours.n_vehicles, "duration": ours.duration}).unwrapped
    rng = np.random.default_rng(0)
    # two action sets: "straight" (gentle throttle, no steering: long episodes, mostly ended by a
    # collision with the car ahead) and "random" (an untrained Gaussian policy: episodes of ~10
    # steps, so resets weigh in)
    action_sets = {"straight": np.tile([0.2, 0.0], (steps, 1)),
                   "random": np.clip(rng.normal(0.0, 1.0, (steps, 2)), -1, 1)}
    best: dict[str, float] = {}
    ended: dict[str, int] = {}
    for _ in range(repeats):  # round-robin: a busy moment of the machine hits every row alike
        for kind, actions in action_sets.items():
            for name, env in (("ours", ours), ("highway-env", peer)):
                rate, n = _steps_per_second(env, actions, seed=0)
                key = f"{name}/{kind}"
                if rate > best.get(key, 0.0):
                    best[key], ended[key] = rate, n
        expert = IdmMobilExpert(ours, target_speed=27.0)
        ours.reset(seed=1)
        expert.reset()
        start, n_steps = time.perf_counter(), min(steps, 600)
        for _ in range(n_steps):
            _, _, terminated, truncated, _ = ours.step(expert())
            if terminated or truncated:
                ours.reset()
                expert.reset()
        best["ours/idm-expert"] = max(best.get("ours/idm-expert", 0.0), n_steps / (time.perf_counter() - start))
    rows = [{"env": key.split("/")[0], "actions": key.split("/")[1], "steps_per_s": round(rate, 1),
             "episodes_ended": ended.get(key)} for key, rate in best.items()]
    ratios = {kind: round(best[f"ours/{kind}"] / best[f"highway-env/{kind}"], 2) for kind in action_sets}
    return {"steps": steps, "repeats": repeats, "rows": rows, "ours_over_highway_env": ratios}


# --- 2. constraint ----------------------------------------------------------------------------


def learn_constraint(n_demos: int, depth: int, noise: float, seed: int) -> dict:
    from symlearn.envs.driving.expert import expert_demonstrations
    from symlearn.envs.driving.features import FEATURE_NAMES
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    names = list(FEATURE_NAMES)
    start = time.perf_counter()
    train = expert_demonstrations(n_demos, seed=seed, noise=noise)
    held_out = expert_demonstrations(10, seed=seed + 1, noise=noise)
    demo_seconds = time.perf_counter() - start
    learner = OneClassTreeConstraint(max_depth=depth, random_state=seed).fit(train, names)
    dnf = learner.dnf_
    states = np.concatenate([t.states for t in held_out])
    # cost per episode as the wrapper counts it: the states each step reached (not the reset's)
    per_episode = [float(dnf.evaluate(t.states[1:], names).sum()) for t in held_out]
    per_rule = dnf.evaluate(states, names, per_conjunction=True).mean(axis=0)
    return {"dnf": dnf, "n_demos": n_demos, "depth": depth, "noise": noise, "n_states": int(learner.n_samples_),
            "replaced_unsafe": train.metadata["replaced_unsafe"], "demo_seconds": round(demo_seconds, 1),
            "fit_seconds": round(learner.result_.timings["total"], 3), "n_rules": len(dnf.conjunctions),
            "held_out_flagged": float(dnf.evaluate(states, names).mean()),
            "held_out_cost_per_episode": float(np.mean(per_episode)),
            "rules_flagging_held_out": [{"rule": str(c), "share": round(float(s), 4)}
                                        for c, s in zip(dnf.conjunctions, per_rule) if s > 0]}


# --- 3. agents --------------------------------------------------------------------------------


class EpisodeLog(gymnasium.Wrapper):
    """Logs every finished episode's true events and environment reward (before any penalty).

    All copies of one training run share ``log`` and ``clock`` (total steps), so an entry's
    ``step`` is the training step at which the episode ended."""

    def __init__(self, env, log: list, clock: list) -> None:
        super().__init__(env)
        self.log, self.clock = log, clock
        self._return = 0.0
        self._length = 0

    def reset(self, **kwargs):
        self._return, self._length = 0.0, 0
        return self.env.reset(**kwargs)

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        self.clock[0] += 1
        self._return += float(reward)
        self._length += 1
        if terminated or truncated:
            self.log.append({"step": self.clock[0], "return": self._return, "length": self._length,
                             "collision": bool(info["collision"]), "offroad": bool(info["offroad"])})
        return observation, reward, terminated, truncated, info


class EngineeredPenalty(gymnasium.Wrapper):
    """``reward - penalty`` on a step with a collision or leaving the road (the true events)."""

    def __init__(self, env, penalty: float) -> None:
        super().__init__(env)
        self.penalty = float(penalty)

    def step(self, action):
        observation, reward, terminated, truncated, info = self.env.step(action)
        return observation, reward - self.penalty * float(info["cost"]), terminated, truncated, info


def ppo_config(seed: int):
    from symlearn.rl.ppo import PPOConfig

    # CleanRL's continuous-control settings, except 4 copies x 256 steps per rollout and a
    # smaller starting action noise: with log std 0 almost every early episode leaves the road
    # within ten steps (steering saturates), which teaches all three agents little
    return PPOConfig(n_envs=4, n_steps=256, batch_size=256, n_epochs=10, learning_rate=3e-4, ent_coef=0.0,
                     log_std_init=-0.5, seed=seed, torch_threads=1, normalize_observations=False,
                     normalize_values=False)  # the settings of the recorded tables


def train_one(method: str, seed: int, steps: int, dnf_text: str | None, cost_limit: float, penalty: float,
              n_eval: int) -> dict:
    import torch

    torch.set_num_threads(1)
    from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
    from symlearn.envs.driving import DrivingEnv
    from symlearn.envs.driving.features import FEATURE_NAMES
    from symlearn.logic.dnf import parse
    from symlearn.rl.ppo import LEGACY_LAGRANGIAN, LagrangianConfig, evaluate, train_ppo

    log: list = []
    clock = [0]
    stats = lagrangian = None
    if method == "ppo-lag-dnf":
        dnf = parse(dnf_text)
        stats = RuleStats(dnf, FEATURE_NAMES)
        lagrangian = LagrangianConfig(cost_limit=cost_limit, **LEGACY_LAGRANGIAN)

    def make():
        env = EpisodeLog(DrivingEnv(), log, clock)
        if method == "ppo-penalty":
            return EngineeredPenalty(env, penalty)
        if method == "ppo-lag-dnf":
            return DnfCostWrapper(env, stats.dnf, FEATURE_NAMES, stats=stats)
        return env

    start = time.perf_counter()
    result = train_ppo(make, steps, ppo_config(seed), lagrangian=lagrangian)
    seconds = time.perf_counter() - start
    eval_log: list = []
    episodes = evaluate(result.policy, EpisodeLog(DrivingEnv(), eval_log, [0]), n_eval, seed=EVAL_SEED)
    row = {"method": method, "seed": seed, "steps": int(result.steps), "seconds": round(seconds, 1),
           "steps_per_s": round(result.steps / seconds, 1), "eval": _summary(eval_log),
           "eval_mean_length": float(np.mean(episodes.lengths)), "training_episodes": log,
           "multipliers": [float(m) for m in np.atleast_1d(result.multipliers)]}
    if stats is not None:
        _, verdicts = stats.prune(1e-3)
        row["pruning"] = {"kept": sum(v.kept for v in verdicts), "dropped": sum(not v.kept for v in verdicts)}
    return row


def _summary(episodes: list[dict]) -> dict:
    return {"episodes": len(episodes), "collision_ratio": float(np.mean([e["collision"] for e in episodes])),
            "offroad_ratio": float(np.mean([e["offroad"] for e in episodes])),
            "reward": float(np.mean([e["return"] for e in episodes])),
            "length": float(np.mean([e["length"] for e in episodes]))}


def evaluate_expert(n_eval: int) -> dict:
    from symlearn.envs.driving import DrivingEnv
    from symlearn.envs.driving.expert import IdmMobilExpert

    log: list = []
    env = EpisodeLog(DrivingEnv(), log, [0])
    expert = IdmMobilExpert(env.unwrapped, target_speed=27.0)
    for i in range(n_eval):
        env.reset(seed=EVAL_SEED + i)
        expert.reset()
        done = False
        while not done:
            _, _, terminated, truncated, _ = env.step(expert())
            done = terminated or truncated
    return _summary(log)


def curves(runs: list[dict], steps: int, bins: int) -> dict:
    """Per method: for each bin of training steps, the mean over seeds of the bin's collision
    ratio, off-road ratio and reward per episode (and their min/max over seeds)."""
    edges = np.linspace(0, steps, bins + 1)
    out = {}
    for method in METHODS:
        per_seed = []
        for run in (r for r in runs if r["method"] == method):
            rows = []
            for lo, hi in zip(edges[:-1], edges[1:]):
                eps = [e for e in run["training_episodes"] if lo < e["step"] <= hi]
                rows.append([np.mean([e[k] for e in eps]) if eps else np.nan
                             for k in ("return", "collision", "offroad")])
            per_seed.append(rows)
        if not per_seed:
            continue
        a = np.array(per_seed, dtype=np.float64)  # seeds x bins x 3
        out[method] = {name: {"mean": np.nanmean(a[:, :, i], axis=0).tolist(),
                              "min": np.nanmin(a[:, :, i], axis=0).tolist(),
                              "max": np.nanmax(a[:, :, i], axis=0).tolist()}
                       for i, name in enumerate(("reward", "collision_ratio", "offroad_ratio"))}
    return {"bin_ends": edges[1:].tolist(), "methods": out}


def figure(curve: dict, expert: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = {"ppo": "PPO", "ppo-penalty": "PPO, engineered penalty", "ppo-lag-dnf": "PPO-Lagrangian, learned DNF"}
    fig, axes = plt.subplots(3, 1, figsize=(6.4, 7.6), sharex=True)
    x = np.array(curve["bin_ends"]) / 1000
    for ax, key, title in zip(axes, ("reward", "collision_ratio", "offroad_ratio"),
                              ("reward per episode", "collision ratio", "off-road ratio")):
        for method, data in curve["methods"].items():
            line, = ax.plot(x, data[key]["mean"], label=labels[method])
            ax.fill_between(x, data[key]["min"], data[key]["max"], color=line.get_color(), alpha=0.15)
        ax.axhline(expert[{"reward": "reward", "collision_ratio": "collision_ratio",
                           "offroad_ratio": "offroad_ratio"}[key]], color="grey", ls="--", lw=1,
                   label="IDM/MOBIL demonstrator")
        ax.set_ylabel(title)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("training steps (thousands)")
    fig.suptitle("Driving (highway-env): training episodes, mean and range over seeds", fontsize=10)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


# --- main -------------------------------------------------------------------------------------


def table(runs: list[dict], expert: dict) -> str:
    lines = ["| agent | collision ratio | off-road ratio | reward per episode | episode length |",
             "|---|---|---|---|---|"]
    for method in METHODS:
        rows = [r["eval"] for r in runs if r["method"] == method]
        if not rows:
            continue
        cells = []
        for key, fmt in (("collision_ratio", "{:.2f}"), ("offroad_ratio", "{:.2f}"), ("reward", "{:.1f}"),
                         ("length", "{:.0f}")):
            values = [r[key] for r in rows]
            cells.append(fmt.format(np.mean(values)) + " (" + ", ".join(fmt.format(v) for v in values) + ")")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    lines.append(f"| IDM/MOBIL demonstrator | {expert['collision_ratio']:.2f} | {expert['offroad_ratio']:.2f} | "
                 f"{expert['reward']:.1f} | {expert['length']:.0f} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=50_000, help="environment steps per training run")
    parser.add_argument("--demos", type=int, default=60, help="demonstrator episodes the tree is fitted to")
    parser.add_argument("--depth", type=int, default=1, help="one-class tree max_depth")
    parser.add_argument("--noise", type=float, default=0.1, help="demonstrator action noise (std)")
    parser.add_argument("--penalty", type=float, default=10.0, help="engineered penalty per collision/off-road")
    parser.add_argument("--eval", type=int, default=20, help="greedy evaluation episodes per run")
    parser.add_argument("--bins", type=int, default=12, help="training-curve bins")
    parser.add_argument("--speed-steps", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--workers", type=int, default=2, help="training runs side by side (processes)")
    parser.add_argument("--quick", action="store_true", help="a smoke run: 1 seed, 6k steps, 20 demos")
    parser.add_argument("--speed-only", action="store_true")
    parser.add_argument("--json", type=Path, default=REPO / "benchmarks" / "results" / "driving.json")
    parser.add_argument("--figure", type=Path, default=REPO / "docs" / "figures" / "driving.png")
    args = parser.parse_args()
    require("highway", "the driving benchmark")
    if args.quick:  # never over the recorded results
        args.seeds, args.steps, args.demos, args.eval, args.speed_steps, args.repeats = 1, 6_000, 20, 5, 600, 1
        args.bins = 4
        args.json = args.json.with_name(args.json.stem + "_quick.json")
        args.figure = args.json.with_suffix(".png")
    started = time.perf_counter()
    doc: dict = {"command": " ".join([Path(sys.executable).name, *sys.argv]), "machine": {
        "python": platform.python_version(), "cpus": os.cpu_count(), "platform": platform.platform()}}
    import highway_env

    doc["highway_env"] = highway_env.__version__
    print("speed ...", flush=True)
    doc["speed"] = measure_speed(args.speed_steps, args.repeats)
    for row in doc["speed"]["rows"]:
        print(f"  {row['env']:12} {row['actions']:10} {row['steps_per_s']:8.1f} steps/s")
    print("  ours / highway-env:", doc["speed"]["ours_over_highway_env"], flush=True)
    if args.speed_only:
        write_text(args.json.with_name("driving_speed.json"), json.dumps(doc, indent=1) + "\n")
        return

    print("demonstrations and tree ...", flush=True)
    constraint = learn_constraint(args.demos, args.depth, args.noise, seed=0)
    dnf = constraint.pop("dnf")
    constraint["formula"] = str(dnf)
    cost_limit = constraint["held_out_cost_per_episode"]
    doc["constraint"] = constraint
    print(f"  {constraint['n_rules']} rules from {constraint['n_states']} states; held-out demonstrator states "
          f"flagged: {constraint['held_out_flagged']:.3f}; cost limit {cost_limit:.2f}", flush=True)
    doc["settings"] = {"seeds": args.seeds, "steps": args.steps, "penalty": args.penalty, "eval_episodes": args.eval,
                       "cost_limit": cost_limit, "ppo": {k: v for k, v in asdict(ppo_config(0)).items() if k != "seed"}}
    jobs = [(m, s) for s in range(args.seeds) for m in METHODS]
    runs: list[dict] = []

    def done(row: dict) -> None:
        runs.append(row)
        e = row["eval"]
        print(f"  {row['method']:12} seed {row['seed']}: collision {e['collision_ratio']:.2f} off-road "
              f"{e['offroad_ratio']:.2f} reward {e['reward']:.1f} ({row['seconds']:.0f} s, "
              f"{row['steps_per_s']:.0f} steps/s)", flush=True)

    print(f"training {len(jobs)} runs of {args.steps} steps ...", flush=True)
    arguments = [(m, s, args.steps, str(dnf), cost_limit, args.penalty, args.eval) for m, s in jobs]
    if args.workers > 1:
        from concurrent.futures import ProcessPoolExecutor, as_completed

        with ProcessPoolExecutor(args.workers) as pool:
            for future in as_completed([pool.submit(train_one, *a) for a in arguments]):
                done(future.result())
    else:
        for a in arguments:
            done(train_one(*a))
    runs.sort(key=lambda r: (METHODS.index(r["method"]), r["seed"]))
    doc["expert"] = evaluate_expert(args.eval)
    doc["runs"] = runs
    doc["curves"] = curves(runs, args.steps, args.bins)
    doc["table"] = table(runs, doc["expert"])
    doc["seconds"] = round(time.perf_counter() - started, 1)
    args.json.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.json, json.dumps(doc, indent=1) + "\n")
    args.figure.parent.mkdir(parents=True, exist_ok=True)
    figure(doc["curves"], doc["expert"], args.figure)
    print(doc["table"])
    print(f"wrote {args.json} and {args.figure} ({doc['seconds']:.0f} s)")


if __name__ == "__main__":
    main()
