"""Cost transfer to the broken ant (thesis section 2.5.4, Fig. 2.4 in shape), at a reduced budget.

For every seed: the PPO-Lagrangian expert of blocked Ant (``x < -3`` forbidden) records the
demonstrations (cached, :mod:`symlearn.rl.lagrangian_expert`); MCE-ICRL learns a cost
on blocked Ant reading only ``x``; the cost file is saved and loaded back against the broken ant
(``NeuralCost.load(path, env)``: the check a user's transfer goes through -- same observation
layout and names). Then three fresh PPO agents learn on the broken ant (two legs' actuators off)
with the same budget and settings:

* **transferred cost**: the reward ``r - C(s)`` with the learned ``C``;
* **unconstrained PPO**: the reward alone;
* **PPO-Lagrangian on the true cost** (cost limit 0, the expert's settings).

Each is evaluated on ``EVAL_EPISODES`` mean-action episodes of the broken ant: reward, violation
rate, feasible reward.

    nice -n 10 python benchmarks/icrl_transfer_broken_ant.py --seeds 1      # ~1 h per seed on a free core
    python benchmarks/icrl_transfer_broken_ant.py --smoke                    # the plumbing only

Needs the ``mujoco`` extra. Writes ``benchmarks/results/icrl_transfer_broken_ant.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import torch

from icrl_common import write_document
from symlearn.envs.blocked_mujoco import make_blocked_ant, make_broken_ant
from symlearn.learners.neural import NeuralCost, NeuralMCEICRL
from symlearn.rl.episodes import sample_episodes
from symlearn.learners.neural.icrl_metrics import recovery
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.rl.lagrangian_expert import EXPERT_LAGRANGIAN, EXPERT_PPO, lagrangian_expert
from symlearn.learners.neural.mce_icrl import action_bound_penalty, penalised
from symlearn.learners.neural.neural_cost import space_spec
from symlearn.rl.ppo import LagrangianConfig, PPOConfig, train_ppo

ROOT = Path(__file__).resolve().parent
RESULTS = ROOT / "results" / "icrl_transfer_broken_ant.json"
CACHE = ROOT / "results" / "cache"
EVAL_EPISODES = 5
NAMES = ("transferred cost", "unconstrained", "ppo-lagrangian true cost")


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--expert-steps", type=int, default=1_000_000)
    parser.add_argument("--steps", type=int, default=1_000_000, help="MCE-ICRL's PPO steps in all")
    parser.add_argument("--iterations", type=int, default=5)
    parser.add_argument("--target-steps", type=int, default=1_000_000, help="PPO steps of each broken-ant agent")
    parser.add_argument("--demos", type=int, default=10)
    parser.add_argument("--learner", type=json.loads, default={"reset_actor": "last"}, metavar="JSON",
                        help="more NeuralMCEICRL arguments (default '{\"reset_actor\": \"last\"}')")
    parser.add_argument("--smoke", action="store_true", help="tiny budgets, short episodes, no cache")
    parser.add_argument("--json", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    episode_steps = 500
    if args.smoke:
        args.expert_steps = args.steps = args.target_steps = 4096
        args.iterations, args.demos, episode_steps = 2, 2, 50
    torch.set_num_threads(1)
    started, load_before = time.perf_counter(), os.getloadavg()

    def source():
        return make_blocked_ant(max_episode_steps=episode_steps)

    def target():
        return make_broken_ant(max_episode_steps=episode_steps)

    penalty = action_bound_penalty(space_spec(target().action_space, bounds=True), 1.0)
    runs = []
    for seed in range(args.seeds):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            demos, expert = lagrangian_expert(source, args.demos, steps=args.expert_steps, seed=seed, ppo=EXPERT_PPO,
                                              key={"env": "blocked-ant", "kwargs": {"max_episode_steps": episode_steps}},
                                              cache_dir=None if args.smoke else CACHE)
        expert["warnings"] = [str(w.message) for w in caught if "expert violates" in str(w.message)]
        nominal = args.steps // 8
        t0 = time.perf_counter()
        learner = NeuralMCEICRL(n_iterations=args.iterations, nominal_steps=nominal,
                                policy_steps=max((args.steps - nominal) // args.iterations, 1), obs_dims=[0],
                                ppo=EXPERT_PPO, random_state=seed, **args.learner).fit(demos, source)
        learn_seconds = time.perf_counter() - t0
        states = np.concatenate([np.asarray(t.states) for t in demos])
        probe = source()
        rec = recovery(learner.cost_, probe.is_unsafe, states, seed=seed, margin="auto").as_dict()
        probe.close()

        def evaluate(policy, env_fn) -> dict:
            return episode_metrics(sample_episodes(policy, env_fn, EVAL_EPISODES, seed=70_000 + seed,
                                                   deterministic=True)).as_dict()

        with tempfile.TemporaryDirectory() as folder:
            cost = NeuralCost.load(learner.save(Path(folder) / "cost.safetensors"), target())
        config = PPOConfig(**EXPERT_PPO, seed=seed)
        agents = {
            "transferred cost": lambda: train_ppo(target, args.target_steps, config, reward_fn=penalised(cost, penalty)),
            "unconstrained": lambda: train_ppo(target, args.target_steps, config, reward_fn=penalised(None, penalty)),
            "ppo-lagrangian true cost": lambda: train_ppo(target, args.target_steps, config,
                                                          LagrangianConfig(**EXPERT_LAGRANGIAN),
                                                          reward_fn=penalised(None, penalty)),
        }
        run: dict = {"seed": seed, "expert": expert,
                     "source mce-icrl": {**evaluate(learner.policy_, source), "recovery": rec, "seconds": learn_seconds,
                                         "history": [h.as_dict() for h in learner.history_]}}
        for name, train in agents.items():
            t0 = time.perf_counter()
            result = train()
            run[name] = {**evaluate(result.policy, target), "seconds": time.perf_counter() - t0}
        runs.append(run)
        print(f"seed {seed}: expert (blocked ant) {expert['reward']:.1f} / {expert['violation_rate']:.3f}; MCE-ICRL "
              f"(blocked ant) {run['source mce-icrl']['reward']:.1f} / {run['source mce-icrl']['violation_rate']:.3f} "
              f"AUC {rec['auc']}; broken ant: " + "; ".join(
                  f"{name} {run[name]['reward']:.1f} / {run[name]['violation_rate']:.3f}" for name in NAMES), flush=True)
    summary = {name: {key: float(np.mean([r[name][key] for r in runs]))
                      for key in ("reward", "violation_rate", "feasible_reward")}
               for name in ("expert", "source mce-icrl", *NAMES)}
    settings = vars(args) | {"episode_steps": episode_steps, "ppo": EXPERT_PPO, "expert_lagrangian": EXPERT_LAGRANGIAN,
                             "eval_episodes": EVAL_EPISODES, "cost_inputs": ["x"], "source": "blocked-ant",
                             "target": "broken-ant"}
    document = write_document(args.json, "icrl_transfer_broken_ant", argv, settings, runs, summary, started, load_before)
    return document


if __name__ == "__main__":
    main()
