"""Neural MCE-ICRL on blocked HalfCheetah (gymnasium v5, x < -3 forbidden): the reduced-budget run.

Issue 12's slow experiment (thesis section 2.5.2 at a fraction of its budget). For every seed:

1. **expert**: PPO-Lagrangian on the true cost (cost limit 0, :data:`EXPERT_LAGRANGIAN`) for ``--expert-steps``; its
   ``--demos`` mean-action episodes are the demonstrations, cached as
   ``benchmarks/results/cache/blocked-half-cheetah_s{seed}_{steps}_{hash of the settings}.npz`` (generated from the
   seed, never downloaded; delete the file to regenerate);
2. **MCE-ICRL** (``NeuralMCEICRL``, the cost reading only ``x``; ``--steps`` PPO steps in all, 1/8
   nominal, the rest over ``--iterations``); its nominal policy is the **unconstrained PPO** peer;
3. evaluation: ``EVAL_EPISODES`` mean-action episodes of each policy against the ground truth --
   reward, violation rate per step, feasible reward -- and the learned cost's recovery AUC.

The issue's target: MCE-ICRL's violation rate <= 0.1 with reward >= 0.5 x the expert's.

    nice -n 10 python benchmarks/icrl_blocked_half_cheetah.py                       # 3 seeds, 1M + 1M steps (hours)
    python benchmarks/icrl_blocked_half_cheetah.py --seeds 1 --steps 200000 --expert-steps 300000
    python benchmarks/icrl_blocked_half_cheetah.py --smoke                          # seconds: checks the plumbing only

Needs the ``mujoco`` extra. Timings are wall-clock on a shared machine (load recorded).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import torch

from symlearn.atomic import write_text
from symlearn.data import Demonstrations
from symlearn.envs.blocked_mujoco import make_blocked_half_cheetah
from symlearn.learners.neural import NeuralMCEICRL
from symlearn.learners.neural import lagrangian_expert as lagrangian_expert_module
from symlearn.learners.neural.lagrangian_expert import lagrangian_expert
from symlearn.learners.neural.episodes import sample_episodes
from symlearn.learners.neural.icrl_metrics import episode_metrics, recovery

ROOT = Path(__file__).resolve().parent
RESULTS = ROOT / "results" / "icrl_blocked_half_cheetah.json"
CACHE = ROOT / "results" / "cache"
EVAL_EPISODES = 5
#: PPO for the cheetah (every phase: expert, nominal, ICRL) and the expert's PPO-Lagrangian: the library's
#: expert settings (symlearn.learners.neural.lagrangian_expert says why they are what they are)
EXPERT_LAGRANGIAN = dict(lagrangian_expert_module.EXPERT_LAGRANGIAN)
CHEETAH_PPO = dict(lagrangian_expert_module.EXPERT_PPO)


def expert(seed: int, steps: int, n_demos: int, episode_steps: int, cache: Path | None) -> tuple[Demonstrations, dict]:
    """The PPO-Lagrangian expert's demonstrations (:func:`lagrangian_expert`, cached under ``cache``)."""
    return lagrangian_expert(lambda: make_blocked_half_cheetah(max_episode_steps=episode_steps), n_demos, steps=steps,
                             seed=seed, ppo=CHEETAH_PPO, lagrangian=EXPERT_LAGRANGIAN,
                             key={"env": "blocked-half-cheetah", "kwargs": {"max_episode_steps": episode_steps}},
                             cache_dir=cache)


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=1_000_000, help="MCE-ICRL's PPO steps in all")
    parser.add_argument("--expert-steps", type=int, default=1_000_000)
    parser.add_argument("--iterations", type=int, default=10)
    parser.add_argument("--demos", type=int, default=10)
    parser.add_argument("--episode-steps", type=int, default=1000, help="episode length (v5: 1000)")
    parser.add_argument("--smoke", action="store_true", help="tiny budgets, no cache: the plumbing only")
    parser.add_argument("--mce", type=json.loads, default={}, metavar="JSON",
                        help="more NeuralMCEICRL arguments, e.g. '{\"reset_actor\": true}'")
    parser.add_argument("--json", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    if args.smoke:
        args.seeds, args.steps, args.expert_steps, args.iterations, args.demos, args.episode_steps = 1, 4096, 4096, 2, 2, 100
    torch.set_num_threads(1)
    started, load_before = time.perf_counter(), os.getloadavg()

    def env_fn():
        return make_blocked_half_cheetah(max_episode_steps=args.episode_steps)

    def evaluate(policy, seed: int) -> dict:
        return episode_metrics(sample_episodes(policy, env_fn, EVAL_EPISODES, seed=seed, deterministic=True)).as_dict()

    runs = []
    for seed in range(args.seeds):
        demos, expert_metrics = expert(seed, args.expert_steps, args.demos, args.episode_steps,
                                       None if args.smoke else CACHE)
        nominal = args.steps // 8
        t0 = time.perf_counter()
        learner = NeuralMCEICRL(n_iterations=args.iterations, nominal_steps=nominal,
                                policy_steps=max((args.steps - nominal) // args.iterations, 1), obs_dims=[0],
                                ppo=CHEETAH_PPO, random_state=seed, **args.mce).fit(demos, env_fn)
        seconds = time.perf_counter() - t0
        states = np.concatenate([np.asarray(t.states) for t in demos])
        probe = env_fn()
        rec = recovery(learner.cost_, probe.is_unsafe, states, seed=seed)
        probe.close()
        run = {"seed": seed, "expert": expert_metrics,
               "mce-icrl": {**evaluate(learner.policy_, 50_000 + seed), "recovery": rec.as_dict(),
                            "seconds": seconds, "timings": learner.result_.timings,
                            "history": [h.as_dict() for h in learner.history_]},
               "unconstrained": evaluate(learner.nominal_policy_, 50_000 + seed)}
        icrl = run["mce-icrl"]
        run["targets"] = {"violation_rate <= 0.1": icrl["violation_rate"] <= 0.1,
                          "reward >= 0.5 x expert": icrl["reward"] >= 0.5 * expert_metrics["reward"]}
        runs.append(run)
        print(f"seed {seed}: expert reward {expert_metrics['reward']:.1f} violations "
              f"{expert_metrics['violation_rate']:.3f}; MCE-ICRL reward {icrl['reward']:.1f} violations "
              f"{icrl['violation_rate']:.3f} AUC {rec.as_dict()['auc']}; unconstrained reward "
              f"{run['unconstrained']['reward']:.1f} violations {run['unconstrained']['violation_rate']:.3f} "
              f"({seconds:.0f} s)", flush=True)
    document = {
        "benchmark": "icrl_blocked_half_cheetah",
        "command": "python benchmarks/icrl_blocked_half_cheetah.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "settings": {k: v for k, v in vars(args).items() if k != "json"} | {"ppo": CHEETAH_PPO,
                                                                             "expert_lagrangian": EXPERT_LAGRANGIAN,
                                                                             "eval_episodes": EVAL_EPISODES},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "torch": torch.__version__, "load_average_before": load_before,
                    "load_average_after": os.getloadavg()},
        "runs": runs, "seconds": round(time.perf_counter() - started, 1)}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.json, json.dumps(document, indent=1) + "\n")
    print(f"wrote {args.json} ({document['seconds']:.0f} s)")
    return document


if __name__ == "__main__":
    main()
