"""Neural MCE-ICRL on BlockedPoint: issue 12's CI-sized targets, against peers in the same run.

For every seed: record the scripted expert's demonstrations, then

* **MCE-ICRL** (``NeuralMCEICRL`` at its defaults: the cost's candidate inputs are the entries
  BlockedPoint declares its constraint to be about, its ``feature_names`` ``x, y``, and the input
  selection keeps the fewest of them that tell expert from nominal states; 240k PPO steps in all),
* **ME-ICRL** (``NeuralMEICRL``, Malik et al. 2021: feasibility network, PPO-Lagrangian forward
  step with cost limit 0, its multiplier stepped once per iteration by MCE-ICRL's rule,
  importance-weighted backward step with KL early stopping; same defaults and budget),
* **VME-ICRL** (``NeuralVMEICRL``, Liu et al. 2023: ME-ICRL with a Beta-distributed
  feasibility and a KL regulariser toward a prior; same inputs and budget),
* **GACL**: a GAIL discriminator between expert and policy pairs, the policy learning from
  ``r + log D`` (same inputs and budget),
* **MCE-ICRL, the inputs' ablations**: ``x, y`` without the selection (``select_inputs=0``); the
  whole observation, velocities too (``obs_dims="all"``) without the selection (the default
  before), with it, and with the group-sparsity penalty on the inputs instead
  (``input_sparsity=0.01``, :mod:`symlearn.learners.neural.input_sparsity`),
* **ME-ICRL / VME-ICRL, per-rollout multiplier**: the two baselines with ``lambda_lr=None``
  (the PPO-Lagrangian's own Adam step of 0.035 per rollout, their behaviour before), and both
  rules again on a cost reading ``(x, y)`` (no selection),
* **unconstrained PPO**: the nominal policy of the MCE-ICRL run (PPO on the reward alone),
* **PPO-Lagrangian on the true cost** (cost limit 0, as many steps as MCE-ICRL's policy phases):
  what a learner told the constraint reaches with the same budget,

and evaluate each policy on 20 episodes (mean action) against the ground truth: reward,
violation rate per step, feasible reward (before the first violation); for the learned costs the
recovery AUC/IoU of the unsafe set on states sampled around the expert's, and the time split of
an iteration (policy update vs cost update). The targets of issue 12 are checked per seed.

    python benchmarks/icrl_blocked_point.py                 # seeds 0-2
    python benchmarks/icrl_blocked_point.py --seeds 1 --no-peers
    python benchmarks/icrl_blocked_point.py --json out.json
    python benchmarks/icrl_blocked_point.py --ablations      # beta sweep and pre-training off (MCE-ICRL only)
    python benchmarks/icrl_blocked_point.py --wall 2 --json benchmarks/results/icrl_blocked_point_wall2.json
    python benchmarks/icrl_blocked_point.py --peers me-icrl,vme-icrl    # only these rows after MCE-ICRL
    python benchmarks/icrl_blocked_point.py --no-figures --peers "me-icrl x,y no selection,me-icrl x,y no selection (per-rollout multiplier),vme-icrl x,y no selection,vme-icrl x,y no selection (per-rollout multiplier)" --json benchmarks/results/icrl_blocked_point_multiplier.json

``--wall W`` moves the wall (BlockedPoint's ``wall``; a positive one forbids ``x > W`` and turns
the expert round): the defaults were chosen at ``wall=-3`` and are checked at others.

``--ablations`` writes ``benchmarks/results/icrl_blocked_point_ablations.json``: MCE-ICRL with
``beta`` in {0.001, 0.01, 0.1, 0.5} (the thesis' inverted U of reward over beta, Table 2.1) and
with the autoencoder pre-training switched off, same seeds and budget.

Figures (unless ``--no-figures``): ``docs/figures/icrl_blocked_point_iterations.png`` (reward,
violation rate and lambda / Lagrange multiplier over the iterations per method, mean and range
over seeds) and ``docs/figures/icrl_blocked_point_cost_map.png`` (seed 0's learned costs over
``(x, y)`` with the wall and the expert's positions), drawn by
:mod:`symlearn.demo.blockedpoint_pipeline`.

Timings are wall-clock on a shared machine: the load average is recorded before and after.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import torch

from symlearn.atomic import write_text
from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.learners.neural import NeuralMCEICRL
from symlearn.rl.episodes import demonstration_batch, sample_episodes
from symlearn.learners.neural.icrl_metrics import recovery
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.learners.neural.gacl import NeuralGACL
from symlearn.learners.neural.me_icrl import NeuralMEICRL
from symlearn.learners.neural.vme_icrl import NeuralVMEICRL
from symlearn.rl.ppo import LEGACY_LAGRANGIAN, LagrangianConfig, PPOConfig, train_ppo

RESULTS = Path(__file__).resolve().parent / "results" / "icrl_blocked_point.json"
ABLATIONS = RESULTS.with_name("icrl_blocked_point_ablations.json")
FIGURES = Path(__file__).resolve().parent.parent / "docs" / "figures"
LEARNED = ("mce-icrl", "me-icrl", "vme-icrl", "gacl")
#: every row after MCE-ICRL's: (method, settings); the true-cost peer last
PEER_SETTINGS = {
    "me-icrl": (NeuralMEICRL, {}), "vme-icrl": (NeuralVMEICRL, {}), "gacl": (NeuralGACL, {}),
    "mce-icrl x,y, no selection": (NeuralMCEICRL, {"select_inputs": 0.0}),
    "mce-icrl all inputs, no selection": (NeuralMCEICRL, {"obs_dims": "all", "select_inputs": 0.0}),
    "mce-icrl all inputs, selected": (NeuralMCEICRL, {"obs_dims": "all"}),
    "mce-icrl all inputs, sparse": (NeuralMCEICRL, {"obs_dims": "all", "select_inputs": 0.0, "input_sparsity": 0.01}),
    "me-icrl per-rollout multiplier": (NeuralMEICRL, {"lambda_lr": None}),
    "vme-icrl per-rollout multiplier": (NeuralVMEICRL, {"lambda_lr": None}),
    # the multiplier rules on a cost that reads (x, y), where they differed before the selection
    "me-icrl x,y no selection": (NeuralMEICRL, {"select_inputs": 0.0}),
    "me-icrl x,y no selection (per-rollout multiplier)": (NeuralMEICRL, {"select_inputs": 0.0, "lambda_lr": None}),
    "vme-icrl x,y no selection": (NeuralVMEICRL, {"select_inputs": 0.0}),
    "vme-icrl x,y no selection (per-rollout multiplier)": (NeuralVMEICRL, {"select_inputs": 0.0, "lambda_lr": None}),
    "ppo-lagrangian true cost": (None, {}),
}
PEERS = tuple(PEER_SETTINGS)  # the methods with a learned cost and a history
BETAS = (0.001, 0.01, 0.1, 0.5)
N_DEMOS = 20
EVAL_EPISODES = 20
STEPS = 240_000  # as `symlearn learn icrl`'s default: 1/8 nominal, the rest over the iterations
ITERATIONS = 10
ENV = BlockedPoint  # the environment factory; --wall replaces it
TARGETS = {"violation_rate": 0.05, "unconstrained_violation_rate": 0.5, "reward_share": 0.7, "recovery_auc": 0.9,
           "cost_share_of_policy_time": 0.10, "seconds": 120.0}


def evaluate(policy, seed: int) -> dict:
    return episode_metrics(sample_episodes(policy, ENV, EVAL_EPISODES, seed=seed,
                                           deterministic=True)).as_dict()


def icrl_run(demos, seed: int, method=NeuralMCEICRL, **settings) -> tuple[dict, NeuralMCEICRL]:
    nominal = STEPS // 8
    started = time.perf_counter()
    learner = method(n_iterations=ITERATIONS, nominal_steps=nominal, policy_steps=(STEPS - nominal) // ITERATIONS,
                     random_state=seed, **settings).fit(demos, ENV)
    seconds = time.perf_counter() - started
    states = np.concatenate([np.asarray(t.states) for t in demos])
    rec = recovery(learner.cost_, ENV().is_unsafe, states, seed=seed)
    timings = learner.result_.timings
    return {"seconds": seconds, **evaluate(learner.policy_, 50_000 + seed), "recovery": rec.as_dict(),
            "lambda": [float(x) for x in learner.cost_.lambdas.numpy()], "timings": timings,
            "cost_inputs": learner.result_.metrics["cost_inputs"],
            "cost_share_of_policy_time": timings["cost"] / timings["policy"],
            "history": [h.as_dict() for h in learner.history_]}, learner


def lagrangian_run(seed: int) -> dict:
    config = PPOConfig(n_envs=4, n_steps=256, batch_size=256, learning_rate=1e-3, anneal_lr=False,
                       normalize_values=True, normalize_observations=False, log_std_init=0.0, ent_coef=0.01,
                       seed=seed)
    started = time.perf_counter()  # the recorded table's multiplier settings (the library's defaults then)
    result = train_ppo(ENV, STEPS, config, LagrangianConfig(cost_limit=0.0, **LEGACY_LAGRANGIAN))
    return {"seconds": time.perf_counter() - started, **evaluate(result.policy, 50_000 + seed),
            "multiplier": float(result.multipliers[0])}


def peer_names(text: str) -> tuple[str, ...]:
    """The rows a ``--peers`` list names: split at commas, pieces joined again where a name holds
    commas itself ("mce-icrl x,y, no selection"); what matches no name is returned as it is."""
    names, current = [], ""
    for piece in text.split(","):
        current = piece if not current else current + "," + piece
        if current.strip() in PEER_SETTINGS:
            names.append(current.strip())
            current = ""
    return (*names, current.strip()) if current.strip() else tuple(names)


def check_targets(run: dict, expert_reward: float) -> dict:
    icrl = run["mce-icrl"]
    return {"violation_rate <= 0.05": icrl["violation_rate"] <= TARGETS["violation_rate"],
            "unconstrained violation_rate >= 0.5":
                run["unconstrained"]["violation_rate"] >= TARGETS["unconstrained_violation_rate"],
            "reward >= 0.7 x expert": icrl["reward"] >= TARGETS["reward_share"] * expert_reward,
            "recovery AUC >= 0.9": (icrl["recovery"]["auc"] or 0) >= TARGETS["recovery_auc"],
            "cost update <= 10% of policy update": icrl["cost_share_of_policy_time"] <= TARGETS[
                "cost_share_of_policy_time"],
            "<= 2 minutes": icrl["seconds"] <= TARGETS["seconds"]}


def ablations(args: argparse.Namespace, argv: list[str] | None) -> dict:
    """MCE-ICRL over beta and without pre-training (same seeds, budget and evaluation)."""
    started, load_before = time.perf_counter(), os.getloadavg()
    variants = {f"beta={b:g}": {"beta": b} for b in BETAS}
    variants["no pre-training (beta=0.01)"] = {"pretrain": False}
    runs = []
    for seed in range(args.seeds):
        demos = expert_demonstrations(N_DEMOS, seed=seed, env=ENV())
        for name, settings in variants.items():
            result, _ = icrl_run(demos, seed, obs_dims=[0, 1], select_inputs=0.0, **settings)
            result.pop("history")
            runs.append({"seed": seed, "variant": name, **result})
            print(f"seed {seed} {name}: reward {result['reward']:.1f} violations {result['violation_rate']:.3f} "
                  f"AUC {result['recovery']['auc']:.3f} ({result['seconds']:.0f} s)", flush=True)
    summary = {name: {key: float(np.mean([r[key] if key in r else r["recovery"][key.split("_")[1]]
                                          for r in runs if r["variant"] == name]))
                      for key in ("reward", "violation_rate", "feasible_reward", "recovery_auc", "recovery_iou")}
               for name in variants}
    document = {
        "benchmark": "icrl_blocked_point_ablations",
        "command": "python benchmarks/icrl_blocked_point.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "settings": {"n_demos": N_DEMOS, "eval_episodes": EVAL_EPISODES, "steps": STEPS, "iterations": ITERATIONS,
                     "seeds": args.seeds, "env": f"BlockedPoint(wall={ENV().wall:g})", "cost_inputs": ["x", "y"]},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "torch": torch.__version__, "load_average_before": load_before,
                    "load_average_after": os.getloadavg()},
        "summary": summary, "runs": runs, "seconds": round(time.perf_counter() - started, 1)}
    write_text(ABLATIONS, json.dumps(document, indent=1) + "\n")
    print(f"\nwrote {ABLATIONS} ({document['seconds']:.0f} s)")
    return document


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1 (3)")
    parser.add_argument("--no-peers", action="store_true", help="skip the all-inputs ablation and PPO-Lagrangian")
    parser.add_argument("--json", type=Path, default=RESULTS, help=f"output (default {RESULTS})")
    parser.add_argument("--ablations", action="store_true", help=f"beta sweep and no pre-training -> {ABLATIONS.name}")
    parser.add_argument("--figures", type=Path, default=FIGURES, help=f"directory of the plots (default {FIGURES})")
    parser.add_argument("--no-figures", action="store_true", help="write no plots")
    parser.add_argument("--wall", type=float, default=-3.0, help="BlockedPoint's wall (-3)")
    parser.add_argument("--peers", help="comma-separated rows to run after MCE-ICRL (default all: "
                        + ", ".join(PEERS) + ")")
    args = parser.parse_args(argv)
    peers = () if args.no_peers else PEERS if not args.peers else peer_names(args.peers)
    unknown = [p for p in peers if p not in PEER_SETTINGS]
    if unknown:
        parser.error(f"unknown --peers {unknown}; choose from {list(PEERS)}")
    global ENV
    ENV = functools.partial(BlockedPoint, wall=args.wall)
    torch.set_num_threads(1)
    if args.ablations:
        return ablations(args, argv)
    started = time.perf_counter()
    load_before = os.getloadavg()
    runs = []
    seed0_costs: dict = {}  # seed 0's learned costs, for the cost-map figure
    for seed in range(args.seeds):
        demos = expert_demonstrations(N_DEMOS, seed=seed, env=ENV())
        expert = episode_metrics(demonstration_batch(demos)).as_dict()
        if seed == 0:
            seed0_states = np.concatenate([np.asarray(t.states) for t in demos])
        run: dict = {"seed": seed, "expert": expert}
        run["mce-icrl"], learner = icrl_run(demos, seed)
        run["unconstrained"] = evaluate(learner.nominal_policy_, 50_000 + seed)
        learners = {"mce-icrl": learner}
        for name in peers:
            method, settings = PEER_SETTINGS[name]
            if method is None:
                run[name] = lagrangian_run(seed)
            else:
                run[name], fitted = icrl_run(demos, seed, method=method, **settings)
                if name in LEARNED:
                    learners[name] = fitted
        run["targets"] = check_targets(run, expert["reward"])
        runs.append(run)
        if seed == 0:
            seed0_costs = {name.upper(): fitted.cost_ for name, fitted in learners.items()}
        icrl = run["mce-icrl"]
        print(f"seed {seed}: expert reward {expert['reward']:.1f}; MCE-ICRL reward {icrl['reward']:.1f} violations "
              f"{icrl['violation_rate']:.3f} AUC {icrl['recovery']['auc']:.3f} IoU {icrl['recovery']['iou']:.3f} "
              f"({icrl['seconds']:.0f} s, cost/policy time {icrl['cost_share_of_policy_time']:.3f}); unconstrained "
              f"violations {run['unconstrained']['violation_rate']:.3f}", flush=True)
        for name in PEERS:
            if name in run:
                r = run[name]
                extra = f" AUC {r['recovery']['auc']:.3f}" if "recovery" in r else ""
                print(f"  {name}: reward {r['reward']:.1f} violations {r['violation_rate']:.3f}{extra} "
                      f"({r['seconds']:.0f} s)", flush=True)
        print("  targets: " + ", ".join(f"{k}: {'met' if v else 'NOT met'}" for k, v in run["targets"].items()),
              flush=True)

    def mean(method: str, key: str) -> float | None:
        values = [r[method][key] for r in runs if method in r]
        return float(np.mean(values)) if values else None

    summary = {method: {key: mean(method, key) for key in ("reward", "violation_rate", "feasible_reward")}
               for method in ("expert", "mce-icrl", "unconstrained", *PEERS) if any(method in r for r in runs)}
    for method in ("mce-icrl", *PEERS[:-1]):
        if method in summary:
            # MCE-ICRL's multipliers are the cost's lambda; the others' the PPO-Lagrangian's (GACL: none)
            summary[method]["multiplier"] = float(np.mean([
                r[method]["history"][-1].get("multiplier", sum(r[method]["lambda"])) if not method.startswith("gacl")
                else float("nan") for r in runs if method in r]))
            summary[method]["recovery_auc"] = float(np.mean([r[method]["recovery"]["auc"] for r in runs]))
            summary[method]["recovery_iou"] = float(np.mean([r[method]["recovery"]["iou"] for r in runs]))
            summary[method]["seconds"] = mean(method, "seconds")
            summary[method]["cost_share_of_policy_time"] = mean(method, "cost_share_of_policy_time")
    document = {
        "benchmark": "icrl_blocked_point",
        "command": "python benchmarks/icrl_blocked_point.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "settings": {"n_demos": N_DEMOS, "eval_episodes": EVAL_EPISODES, "steps": STEPS, "iterations": ITERATIONS,
                     "seeds": args.seeds, "env": f"BlockedPoint(wall={ENV().wall:g})", "targets": TARGETS,
                     "peers": list(peers)},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "numpy": np.__version__, "torch": torch.__version__,
                    "load_average_before": load_before, "load_average_after": os.getloadavg()},
        "summary": summary,
        "targets_met": {k: all(r["targets"][k] for r in runs) for k in runs[0]["targets"]},
        "runs": runs, "seconds": round(time.perf_counter() - started, 1)}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.json, json.dumps(document, indent=1) + "\n")
    print(f"\nwrote {args.json} ({document['seconds']:.0f} s)")
    if not args.no_figures:
        for path in figures(runs, seed0_costs, seed0_states, args.figures):
            print(f"wrote {path}")
    return document


def figures(runs: list[dict], costs: dict, expert_states: np.ndarray, directory: Path) -> list[Path]:
    """The per-iteration curves of every learned method over the seeds, and seed 0's cost maps."""
    from symlearn.demo.blockedpoint_pipeline import plot_cost_maps, plot_iterations

    directory.mkdir(parents=True, exist_ok=True)
    curves, maps = directory / "icrl_blocked_point_iterations.png", directory / "icrl_blocked_point_cost_map.png"
    plot_iterations(curves, {name.upper(): [r[name]["history"] for r in runs if name in r] for name in LEARNED})
    plot_cost_maps(maps, costs, ENV().wall, expert_states)
    return [curves, maps]


if __name__ == "__main__":
    main()
