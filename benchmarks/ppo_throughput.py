"""Our PPO (symlearn.rl.ppo) against stable-baselines3's PPO on CartPole-v1 or SafeNav, in the same run.

Both get the same network (actor and critic: separate 64 x 64 tanh MLPs, orthogonal init), the
same ``n_envs``, ``n_steps``, minibatch size, epochs, learning rate (schedule), gamma, GAE lambda,
clip range, entropy and value coefficients, gradient clipping, Adam eps (1e-5), and one torch
thread each. Two configurations:

* ``cleanrl``: our defaults (CleanRL's): 4 envs x 128 steps, minibatch 128, 4 epochs, lr 2.5e-4
  annealed to 0, entropy 0.01;
* ``sb3``: SB3's defaults: 1 env x 2048 steps, minibatch 64, 10 epochs, lr 3e-4, entropy 0.

Per seed and configuration the two libraries run one after the other (the order alternates with
the seed, so a slow moment of the machine does not always hit the same one). Measured: environment
steps per second of the whole training call (rollouts + updates, wall clock), the mean return of
the last 20 training episodes, and the mean return of 20 deterministic evaluation episodes of
the final policy (same evaluation seeds for both). Both libraries are warmed up once before any
timed run (torch's one-time initialisation would otherwise land on whichever runs first).

``--env symlearn/safenav-point-goal-v0`` (any gymnasium id; ours are registered on import) runs
the same comparison on a continuous-action task: Box(-1, 1, (2,)) actions from a state-independent
diagonal Gaussian (log std initialised to 0) in both libraries, clipped to the bounds before the
environment sees them (SB3 clips too), float32 observations as they come (no normalisation in
either). Its evaluation uses 10 episodes (SafeNav episodes are 1,000 steps).

    python benchmarks/ppo_throughput.py                     # 3 seeds x 100k steps, both configs
    python benchmarks/ppo_throughput.py --quick             # 1 seed x 20k steps
    python benchmarks/ppo_throughput.py --json benchmarks/results/ppo_throughput.json
    python benchmarks/ppo_throughput.py --env symlearn/safenav-point-goal-v0 --configs sb3 --steps 50000 \
        --json benchmarks/results/ppo_throughput_safenav.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time

import gymnasium as gym
import numpy as np
import torch

import symlearn.envs  # noqa: F401  (registers our gymnasium ids)
from symlearn.atomic import write_text
from symlearn.rl.ppo import PPOConfig, evaluate, train_ppo

ENV_ID = "CartPole-v1"  # --env changes it
CONFIGS = {
    "cleanrl": dict(n_envs=4, n_steps=128, batch_size=128, n_epochs=4, learning_rate=2.5e-4, anneal_lr=True,
                    ent_coef=0.01),
    "sb3": dict(n_envs=1, n_steps=2048, batch_size=64, n_epochs=10, learning_rate=3e-4, anneal_lr=False,
                ent_coef=0.0),
}
# raw observations and values, log std 0: the peers' own settings (PPOConfig's defaults normalise)
SHARED = dict(gamma=0.99, gae_lambda=0.95, clip_range=0.2, vf_coef=0.5, max_grad_norm=0.5, hidden_sizes=(64, 64),
              activation="tanh", normalize_observations=False, normalize_values=False, log_std_init=0.0)
EVAL_EPISODES, EVAL_SEED, LAST_EPISODES = 20, 10_000, 20


def run_ours(config: dict, seed: int, steps: int) -> dict:
    cfg = PPOConfig(**config, **SHARED, seed=seed, torch_threads=1)
    start = time.perf_counter()
    result = train_ppo(ENV_ID, steps, cfg)
    seconds = time.perf_counter() - start
    evaluation = evaluate(result.policy, gym.make(ENV_ID), EVAL_EPISODES, seed=EVAL_SEED)
    n = min(LAST_EPISODES, len(result.episodes.returns))
    return {"steps": result.steps, "seconds": seconds, "steps_per_second": result.steps / seconds,
            "train_return": float(result.episodes.returns[-n:].mean()) if n else float("nan"),
            "eval_return": float(evaluation.returns.mean())}


def run_sb3(config: dict, seed: int, steps: int) -> dict:
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    torch.set_num_threads(1)
    lr = config["learning_rate"]
    model = PPO(
        "MlpPolicy", make_vec_env(ENV_ID, n_envs=config["n_envs"], seed=seed), n_steps=config["n_steps"],
        batch_size=config["batch_size"], n_epochs=config["n_epochs"],
        learning_rate=(lambda remaining: lr * remaining) if config["anneal_lr"] else lr,
        gamma=SHARED["gamma"], gae_lambda=SHARED["gae_lambda"], clip_range=SHARED["clip_range"],
        ent_coef=config["ent_coef"], vf_coef=SHARED["vf_coef"], max_grad_norm=SHARED["max_grad_norm"],
        policy_kwargs=dict(net_arch=dict(pi=[64, 64], vf=[64, 64]), activation_fn=torch.nn.Tanh),
        seed=seed, device="cpu", verbose=0)
    start = time.perf_counter()
    model.learn(steps)
    seconds = time.perf_counter() - start
    env = gym.make(ENV_ID)
    discrete = isinstance(env.action_space, gym.spaces.Discrete)
    returns = []
    for episode in range(EVAL_EPISODES):
        obs, _ = env.reset(seed=EVAL_SEED + episode)
        total, done = 0.0, False
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, terminated, truncated, _ = env.step(int(action) if discrete else action)
            total += float(reward)
            done = terminated or truncated
        returns.append(total)
    train_returns = [info["r"] for info in model.ep_info_buffer][-LAST_EPISODES:]
    return {"steps": int(model.num_timesteps), "seconds": seconds, "steps_per_second": model.num_timesteps / seconds,
            "train_return": float(np.mean(train_returns)) if train_returns else float("nan"),
            "eval_return": float(np.mean(returns))}


def _mean_sd(values: list[float]) -> dict:
    return {"mean": statistics.fmean(values), "sd": statistics.stdev(values) if len(values) > 1 else 0.0}


def main(argv: list[str] | None = None) -> dict:
    global ENV_ID, EVAL_EPISODES
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1 seed x 20k steps")
    parser.add_argument("--seeds", type=int, default=None, help="number of seeds (default 3, quick 1)")
    parser.add_argument("--steps", type=int, default=None, help="environment steps per run (default 100k)")
    parser.add_argument("--configs", default="cleanrl,sb3", help="comma-separated: cleanrl, sb3")
    parser.add_argument("--json", metavar="OUT", help="write every run and the summary as JSON")
    parser.add_argument("--env", default="CartPole-v1", help="gymnasium id (default CartPole-v1)")
    parser.add_argument("--eval-episodes", type=int, default=None, help="default 20 (SafeNav: 10)")
    args = parser.parse_args(argv)
    ENV_ID = args.env
    EVAL_EPISODES = args.eval_episodes or (10 if "safenav" in ENV_ID else EVAL_EPISODES)
    seeds = args.seeds or (1 if args.quick else 3)
    steps = args.steps or (20_000 if args.quick else 100_000)
    import stable_baselines3

    # warm-up: the first training call of a process pays torch's lazy initialisation (about 2 s,
    # e.g. the optimiser's first step imports torch._dynamo); neither library is timed with it
    for name in args.configs.split(","):
        run_ours(CONFIGS[name], 0, 1)
        run_sb3(CONFIGS[name], 0, 1)
    runs, summary = [], {}
    for name in args.configs.split(","):
        config = CONFIGS[name]
        for seed in range(seeds):
            order = [("symlearn", run_ours), ("sb3", run_sb3)]
            for library, run in order if seed % 2 == 0 else order[::-1]:
                row = {"config": name, "library": library, "seed": seed, **run(config, seed, steps)}
                runs.append(row)
                print(f"{name:8s} seed {seed} {library:8s} {row['steps_per_second']:8.0f} steps/s  "
                      f"train return {row['train_return']:6.1f}  eval return {row['eval_return']:6.1f}", flush=True)
        rows = {lib: [r for r in runs if r["config"] == name and r["library"] == lib] for lib in ("symlearn", "sb3")}
        ratios = [a["steps_per_second"] / b["steps_per_second"] for a, b in zip(rows["symlearn"], rows["sb3"])]
        summary[name] = {
            lib: {key: _mean_sd([r[key] for r in rs]) for key in ("steps_per_second", "train_return", "eval_return")}
            for lib, rs in rows.items()}
        summary[name]["throughput_ratio"] = _mean_sd(ratios)
    print()
    for name, s in summary.items():
        ours, peer = s["symlearn"], s["sb3"]
        print(f"{name}: symlearn {ours['steps_per_second']['mean']:.0f} steps/s vs SB3 {peer['steps_per_second']['mean']:.0f}"
              f" (ratio {s['throughput_ratio']['mean']:.2f} +- {s['throughput_ratio']['sd']:.2f}); eval return "
              f"{ours['eval_return']['mean']:.1f} +- {ours['eval_return']['sd']:.1f} vs "
              f"{peer['eval_return']['mean']:.1f} +- {peer['eval_return']['sd']:.1f}; last-{LAST_EPISODES} train return "
              f"{ours['train_return']['mean']:.1f} vs {peer['train_return']['mean']:.1f}")
    document = {
        "benchmark": "ppo_throughput", "env": ENV_ID, "seeds": seeds, "steps": steps, "eval_episodes": EVAL_EPISODES,
        "configs": {name: {**CONFIGS[name], **SHARED} for name in args.configs.split(",")},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "torch": torch.__version__, "stable_baselines3": stable_baselines3.__version__,
                    "gymnasium": gym.__version__, "torch_threads": 1, "load_average_at_end": os.getloadavg()},
        "command": " ".join(["python", "benchmarks/ppo_throughput.py", *(argv if argv is not None else sys.argv[1:])]),
        "summary": summary, "runs": runs}
    if args.json:
        write_text(args.json, json.dumps(document, indent=1) + "\n")
    return document


if __name__ == "__main__":
    main()
