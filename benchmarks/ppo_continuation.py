"""Does a continued PPO policy leave a behaviour its new reward forbids? (the ``reset_actor`` question)

The gridworld of thesis Fig. 2.1 observed as coordinates (``envs/gridworld_coordinates.py``): a
policy is trained on the reward alone (``--nominal-steps``; it learns the shortest path, through
the forbidden block), then training goes on for ``--steps`` on the reward minus 10 per step in a
forbidden cell (the *true* cost, so only the policy step is under test) in four ways:

* **continued**: the same policy (``train_ppo(policy=...)``), what the ICRL learners did before
  ``reset_actor``;
* **continued, head shrunk**: the actor's last layer scaled by 0.1 (its logits closer to uniform);
* **continued, entropy in the reward**: ``PPOConfig(entropy_mode="reward", ent_coef=0.2)``, the
  maximum-entropy objective with a temperature of 0.2 reward units instead of the bonus;
* **fresh actor** (``ActorCritic.reset_actor``): new actor weights, the critic and the observation
  statistics kept -- ``reset_actor="every"`` / ``"last"``;
* **from scratch**: a new model.

Reported per seed: the violation rate of sampled episodes (share of steps in the block) and their
reward (the detour earns about -13, the shortest path -4 without its cost).

    python benchmarks/ppo_continuation.py            # seeds 0-4, p = 0 and 0.2, ~1 min
"""

from __future__ import annotations

import argparse
import copy
import os
import time
from pathlib import Path

import gymnasium as gym
import numpy as np
import torch

from icrl_common import write_document
from symlearn.envs.gridworld_coordinates import CoordinateGridworld
from symlearn.rl.episodes import sample_episodes
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.rl.ppo import PPOConfig, train_ppo

RESULTS = Path(__file__).resolve().parent / "results" / "ppo_continuation.json"
WAYS = ("continued", "continued, head shrunk", "continued, entropy in the reward", "fresh actor", "from scratch")
COST = 10.0
SOFT_TEMPERATURE = 0.2


class TrueCost(gym.Wrapper):
    """The reward minus ``COST`` on every step that ends in a forbidden cell."""

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        return obs, reward - COST * float(info["cost"]), terminated, truncated, info


def config(seed: int, beta: float, entropy_mode: str = "bonus") -> PPOConfig:
    return PPOConfig(n_envs=4, n_steps=256, batch_size=256, n_epochs=4, learning_rate=1e-3, anneal_lr=False,
                     normalize_values=True, normalize_observations=True, ent_coef=beta, seed=seed,
                     hidden_sizes=(32, 32), entropy_mode=entropy_mode)


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--p", default="0.0,0.2", help="stochasticities (comma-separated)")
    parser.add_argument("--beta", type=float, default=0.01, help="PPO's entropy coefficient")
    parser.add_argument("--nominal-steps", type=int, default=10_000)
    parser.add_argument("--steps", type=int, default=40_000, help="PPO steps on the true cost")
    parser.add_argument("--json", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    torch.set_num_threads(1)
    started, load_before = time.perf_counter(), os.getloadavg()
    runs = []
    for p in (float(x) for x in args.p.split(",")):
        for seed in range(args.seeds):
            def plain(p=p):
                return CoordinateGridworld(p)

            def costly(p=p):
                return TrueCost(CoordinateGridworld(p))

            def evaluate(policy, p=p) -> dict:
                m = episode_metrics(sample_episodes(policy, plain, 50, seed=999 + seed))
                return {"violation_rate": m.violation_rate, "reward": m.reward}

            nominal = train_ppo(plain, args.nominal_steps, config(seed, args.beta)).policy
            run = {"p": p, "seed": seed, "nominal": evaluate(nominal)}
            for way in WAYS:
                policy = None if way == "from scratch" else copy.deepcopy(nominal)
                if way == "continued, head shrunk":
                    with torch.no_grad():
                        policy.actor[-1].weight.mul_(0.1)
                        policy.actor[-1].bias.mul_(0.1)
                elif way == "fresh actor":
                    policy.reset_actor(torch.Generator().manual_seed(seed))
                t0 = time.perf_counter()
                soft = way == "continued, entropy in the reward"
                settings = config(seed + 1, SOFT_TEMPERATURE, "reward") if soft else config(seed + 1, args.beta)
                trained = train_ppo(costly, args.steps, settings, policy=policy).policy
                run[way] = {**evaluate(trained), "seconds": time.perf_counter() - t0}
            runs.append(run)
            print(f"p {p} seed {seed}: " + "; ".join(f"{w} {run[w]['violation_rate']:.3f}" for w in WAYS), flush=True)
    summary = {f"p={p}": {way: {"mean_violation_rate": float(np.mean([r[way]["violation_rate"] for r in runs
                                                                       if r["p"] == p])),
                                "turned": int(sum(r[way]["violation_rate"] < 0.1 for r in runs if r["p"] == p))}
                          for way in ("nominal", *WAYS)}
               for p in sorted({r["p"] for r in runs})}
    return write_document(args.json, "ppo_continuation", argv, vars(args), runs, summary, started, load_before)


if __name__ == "__main__":
    main()
