"""Cost transfer (thesis section 2.5.4, Fig. 2.4 in shape): a cost learned on BlockedPoint trains
a fresh agent on PointCircle.

For every seed: MCE-ICRL learns a cost on BlockedPoint from the scripted expert, reading only the
``x`` position (a cost reading ``y`` too would be asked about ``|y|`` up to 10 on the circle,
where BlockedPoint's demonstrations, all within ``|y| < 2``, say nothing). Then three fresh PPO
agents are trained on PointCircle with the same budget and settings:

* **transferred cost**: the reward ``r - C(s)`` with the learned ``C`` (its file is saved and
  loaded back through ``NeuralCost.load(path, PointCircle())``, the check a user's transfer goes
  through);
* **unconstrained PPO**: the reward alone;
* **PPO-Lagrangian on the true cost** (cost limit 0).

Each is evaluated on 20 episodes (mean action): reward, violation rate, feasible reward.

    python benchmarks/icrl_transfer_point_circle.py             # seeds 0-2
    python benchmarks/icrl_transfer_point_circle.py --seeds 1
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import torch

from icrl_common import write_document
from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.envs.point_circle import PointCircle
from symlearn.learners.neural import NeuralCost, NeuralMCEICRL
from symlearn.rl.episodes import sample_episodes
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.learners.neural.mce_icrl import PPO_DEFAULTS, action_bound_penalty, penalised
from symlearn.learners.neural.neural_cost import space_spec
from symlearn.rl.ppo import LEGACY_LAGRANGIAN, LagrangianConfig, PPOConfig, train_ppo

RESULTS = Path(__file__).resolve().parent / "results" / "icrl_transfer_point_circle.json"
TARGET_STEPS = 100_000
EVAL_EPISODES = 20


def evaluate(policy, seed: int) -> dict:
    return episode_metrics(sample_episodes(policy, PointCircle, EVAL_EPISODES, seed=seed,
                                           deterministic=True)).as_dict()


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1 (3)")
    parser.add_argument("--steps", type=int, default=TARGET_STEPS, help=f"PPO steps on PointCircle ({TARGET_STEPS})")
    parser.add_argument("--json", type=Path, default=RESULTS, help=f"output (default {RESULTS})")
    args = parser.parse_args(argv)
    torch.set_num_threads(1)
    started, load_before = time.perf_counter(), os.getloadavg()
    penalty = action_bound_penalty(space_spec(PointCircle().action_space, bounds=True), 1.0)
    runs = []
    for seed in range(args.seeds):
        t0 = time.perf_counter()
        learner = NeuralMCEICRL(obs_dims=[0], nominal_steps=30_000, policy_steps=21_000,
                                random_state=seed).fit(expert_demonstrations(20, seed=seed), BlockedPoint)
        learn_seconds = time.perf_counter() - t0
        with tempfile.TemporaryDirectory() as folder:
            cost = NeuralCost.load(learner.save(Path(folder) / "cost.safetensors"), PointCircle())
        config = PPOConfig(**{**PPO_DEFAULTS, "ent_coef": 0.01, "seed": seed, "normalize_observations": False,
                              "log_std_init": 0.0})
        agents = {
            "transferred cost": lambda: train_ppo(PointCircle, args.steps, config, reward_fn=penalised(cost, penalty)),
            "unconstrained": lambda: train_ppo(PointCircle, args.steps, config, reward_fn=penalised(None, penalty)),
            "ppo-lagrangian true cost": lambda: train_ppo(PointCircle, args.steps, config,
                                                          LagrangianConfig(cost_limit=0.0, **LEGACY_LAGRANGIAN),
                                                          reward_fn=penalised(None, penalty)),
        }
        run: dict = {"seed": seed, "learn_seconds": learn_seconds, "lambda": [float(x) for x in learner.lambda_]}
        xs = np.zeros((13, 4), dtype=np.float32)
        xs[:, 0] = np.linspace(-10, 2, 13)
        run["cost_along_x"] = {f"{x:g}": float(c) for x, c in zip(xs[:, 0], cost(xs))}
        for name, train in agents.items():
            t0 = time.perf_counter()
            result = train()
            run[name] = {**evaluate(result.policy, 70_000 + seed), "seconds": time.perf_counter() - t0}
        runs.append(run)
        print(f"seed {seed} (cost learned in {learn_seconds:.0f} s): " + "; ".join(
            f"{name} reward {run[name]['reward']:.1f} violations {run[name]['violation_rate']:.3f} feasible "
            f"{run[name]['feasible_reward']:.1f}" for name in agents), flush=True)
    names = ("transferred cost", "unconstrained", "ppo-lagrangian true cost")
    summary = {name: {key: float(np.mean([r[name][key] for r in runs]))
                      for key in ("reward", "violation_rate", "feasible_reward")} for name in names}
    settings = {"steps": args.steps, "seeds": args.seeds, "eval_episodes": EVAL_EPISODES,
                "source": "BlockedPoint(wall=-3), MCE-ICRL, cost reads x", "target": "PointCircle(wall=-3)"}
    document = write_document(args.json, "icrl_transfer_point_circle", argv, settings, runs, summary, started,
                              load_before)
    return document


if __name__ == "__main__":
    main()
