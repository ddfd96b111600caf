"""The gridworld of thesis Fig. 2.1 through PPO with neural costs: the stochasticity sweep.

For every stochasticity p in {0, 0.1, ..., 0.5} and seed: record the constrained expert's
demonstrations (:meth:`StochasticGridworld.expert_policy`, optimal under the true constraints),
then learn, each with the same PPO budget and settings,

* **MCE-ICRL** (``NeuralMCEICRL``: causal entropy, thesis Algorithm 2.1),
* **ME-ICRL** (``NeuralMEICRL``, Malik et al. 2021: trajectory entropy, feasibility network),
* **VME-ICRL** (``NeuralVMEICRL``, Liu et al. 2023: Beta-distributed feasibility),
* **GACL** (``NeuralGACL``: a GAIL discriminator, the policy on ``r + log D``),

in the gridworld observed as coordinates ``(row, col)``
(:class:`~symlearn.envs.gridworld_coordinates.CoordinateGridworld`), and, for reference, the
exact tabular MCE-ICRL (``symlearn.learners.constraints.MCEICRL``: soft value iteration on the
known model, no PPO) on the same demonstrations. Every policy is evaluated on
``EVAL_EPISODES`` episodes in the true environment: the violation rate (fraction of an
episode's steps that end in a forbidden cell, as ``benchmarks/gridworld_stochasticity.py``
measures it) and the reward, with actions sampled from the policy (the thesis' "trajectories
sampled from the policy after training") and with its most likely action; for the neural costs
the ROC AUC of the learned cost at the 49 cell centres against the forbidden cells.

The thesis' claim checked: MCE-ICRL's violation rate below ME-ICRL's at p >= 0.2.

    nice -n 10 python benchmarks/icrl_gridworld_sweep.py              # 6 p x 5 seeds (~20 min on 2 shared cores)
    python benchmarks/icrl_gridworld_sweep.py --quick                 # p = 0, 0.3; 1 seed; small budget
    python benchmarks/icrl_gridworld_sweep.py --json out.json --figure out.png
    python benchmarks/icrl_gridworld_sweep.py --replot                # redraw the plot from the results

Settings shared by the four neural methods (CI-sized; the thesis trained far longer):
``beta = 0.05`` (PPO's entropy coefficient -- at 0.01 the nominal policy became so sure of the
straight path through the block that 40k further PPO steps on the *true* cost did not turn it
round, measured at p = 0.2), observation normalisation in PPO (without it PPO on raw
coordinates 0..6 did not learn the detour in 30k steps even from scratch), a (32, 32) cost
network, 10k nominal steps, then 8 iterations of 8k. MCE-ICRL starts from ``lambda = 1`` with
``lambda_lr = 0.2`` (see ``NeuralMCEICRL``'s ``lambda_init``: with episodes that end at the
goal, ``lambda = 0`` never moves).
"""

from __future__ import annotations

import argparse
import io
import json
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import torch

from symlearn.atomic import write_bytes, write_text
from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.gridworld_coordinates import CoordinateGridworld, expert_demonstrations
from symlearn.learners.neural import NeuralGACL, NeuralMCEICRL, NeuralMEICRL, NeuralVMEICRL
from symlearn.rl.episodes import demonstration_batch, sample_episodes
from symlearn.rl.episode_metrics import episode_metrics

ROOT = Path(__file__).resolve().parent
RESULTS = ROOT / "results" / "icrl_gridworld_sweep.json"
FIGURE = ROOT.parent / "docs" / "figures" / "icrl_gridworld_sweep.png"
PS = tuple(round(0.1 * i, 1) for i in range(6))
N_DEMOS = 20
EVAL_EPISODES = 100
SHARED = {"beta": 0.05, "n_iterations": 8, "nominal_steps": 10_000, "policy_steps": 8_000, "hidden_sizes": (32, 32),
          "ppo": {"normalize_observations": True}}
QUICK = {**SHARED, "n_iterations": 2, "nominal_steps": 2_048, "policy_steps": 2_048}
METHODS = {"MCE-ICRL": (NeuralMCEICRL, {"lambda_init": 1.0, "lambda_lr": 0.2}), "ME-ICRL": (NeuralMEICRL, {}),
           "VME-ICRL": (NeuralVMEICRL, {}), "GACL": (NeuralGACL, {})}
TABULAR = "tabular MCE-ICRL"
COLUMNS = ("expert", *METHODS, TABULAR)


def evaluate(policy, p: float, seed: int) -> dict:
    def env_fn():
        return CoordinateGridworld(p)

    sampled = episode_metrics(sample_episodes(policy, env_fn, EVAL_EPISODES, seed=seed))
    mode = episode_metrics(sample_episodes(policy, env_fn, EVAL_EPISODES, seed=seed, deterministic=True))
    return {"reward": sampled.reward, "violation_rate": sampled.violation_rate,
            "reward_mode": mode.reward, "violation_rate_mode": mode.violation_rate}


def cell_auc(cost, env: CoordinateGridworld) -> float:
    """ROC AUC of the learned cost at the cell centres against the forbidden cells."""
    from sklearn.metrics import roc_auc_score

    height, width = env.grid.shape
    centres = np.array([(r, c) for r in range(height) for c in range(width)], dtype=np.float32)
    return float(roc_auc_score(env.grid.forbidden_states, cost(centres)))


def neural_run(name: str, demos, p: float, seed: int, settings: dict) -> dict:
    method, extra = METHODS[name]
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        learner = method(**settings, **extra, random_state=seed).fit(demos, lambda: CoordinateGridworld(p))
    seconds = time.perf_counter() - started
    return {**evaluate(learner.policy_, p, 10_000 + seed), "cost_auc": cell_auc(learner.cost_, CoordinateGridworld(p)),
            "seconds": seconds, "timings": learner.result_.timings,
            "history_violation_rate": [h.violation_rate for h in learner.history_]}


def tabular_run(demos, p: float, seed: int, iterations: int) -> dict:
    """The exact tabular MCE-ICRL on the same demonstrations (cell ids), evaluated in the same way."""
    from symlearn.learners.constraints.mce_icrl import MCEICRL

    env = CoordinateGridworld(p)
    cells = Demonstrations([Trajectory(env.state_of(np.asarray(t.states)), t.actions, t.rewards) for t in demos])
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        learner = MCEICRL(n_iterations=iterations).fit(cells, env.grid.to_tabular())
    seconds = time.perf_counter() - started
    table = np.asarray(learner.policy_)

    def policy(obs, rng=np.random.default_rng(seed)):  # coordinates -> actions sampled from the table
        rows = table[env.state_of(obs)]
        return np.array([rng.choice(len(row), p=row / row.sum()) for row in rows])

    sampled = episode_metrics(sample_episodes(policy, lambda: CoordinateGridworld(p), EVAL_EPISODES,
                                              seed=10_000 + seed))
    mode = episode_metrics(sample_episodes(lambda obs, rng: table[env.state_of(obs)].argmax(1),
                                           lambda: CoordinateGridworld(p), EVAL_EPISODES, seed=10_000 + seed))
    return {"reward": sampled.reward, "violation_rate": sampled.violation_rate, "reward_mode": mode.reward,
            "violation_rate_mode": mode.violation_rate, "seconds": seconds}


def summarise(runs: list[dict], ps, columns) -> dict:
    out: dict = {}
    for p in ps:
        rows = [r for r in runs if r["p"] == p]
        out[str(p)] = {}
        for name in columns:
            block = {}
            for key in ("violation_rate", "reward", "violation_rate_mode", "reward_mode", "cost_auc"):
                values = np.array([r[name][key] for r in rows if name in r and key in r[name]])
                if values.size:
                    block[key] = float(values.mean())
                    block[key + "_se"] = float(values.std(ddof=1) / np.sqrt(values.size)) if values.size > 1 else 0.0
            out[str(p)][name] = block
    return out


def claim(summary: dict, ps) -> dict:
    """Per p >= 0.2: is MCE-ICRL's mean violation rate below ME-ICRL's (sampled actions)?"""
    return {str(p): {"mce": summary[str(p)]["MCE-ICRL"]["violation_rate"],
                     "me": summary[str(p)]["ME-ICRL"]["violation_rate"],
                     "mce_below_me": summary[str(p)]["MCE-ICRL"]["violation_rate"]
                     < summary[str(p)]["ME-ICRL"]["violation_rate"]}
            for p in ps if p >= 0.2}


def plot(summary: dict, ps, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for name in COLUMNS:
        for ax, key in zip(axes, ("reward", "violation_rate")):
            mean = np.array([summary[str(p)][name].get(key, np.nan) for p in ps])
            se = np.array([summary[str(p)][name].get(key + "_se", 0.0) for p in ps])
            style = {"linestyle": "--", "color": "black"} if name == "expert" else \
                {"linestyle": ":", "color": "grey"} if name == TABULAR else {}
            ax.plot(ps, mean, marker="o", label=name, **style)
            ax.fill_between(ps, mean - se, mean + se, alpha=0.15, color=style.get("color"))
    axes[0].set_title("reward per episode")
    axes[1].set_title("constraint violation rate")
    for ax in axes:
        ax.set_xlabel("stochasticity p")
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", fontsize=8)
    fig.suptitle("gridworld (Fig. 2.1) through PPO with neural costs; mean ± s.e. over seeds", fontsize=9)
    fig.tight_layout(rect=(0, 0, 0.83, 1))
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    plt.close(fig)
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_bytes(path, buffer.getvalue())


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="p = 0, 0.3; 1 seed; a tiny PPO budget (a smoke test)")
    parser.add_argument("--seeds", type=int, default=None, help="seeds 0..N-1 (5; --quick 1)")
    parser.add_argument("--json", type=Path, default=RESULTS, help=f"output (default {RESULTS})")
    parser.add_argument("--figure", type=Path, default=FIGURE, help=f"plot (default {FIGURE})")
    parser.add_argument("--replot", action="store_true", help="only redraw the plot from the --json results")
    args = parser.parse_args(argv)
    if args.replot:
        document = json.loads(args.json.read_text())
        print("wrote", plot(document["summary"], document["settings"]["ps"], args.figure))
        return document
    torch.set_num_threads(1)
    os.environ.setdefault("SYMLEARN_QUIET", "1")
    ps = (0.0, 0.3) if args.quick else PS
    seeds = args.seeds or (1 if args.quick else 5)
    settings = QUICK if args.quick else SHARED
    tabular_iterations = 30 if args.quick else 300
    started, load_before = time.perf_counter(), os.getloadavg()
    runs = []
    for p in ps:
        for seed in range(seeds):
            env = CoordinateGridworld(p)
            demos = expert_demonstrations(env, N_DEMOS, seed=seed)
            expert_table = env.grid.expert_policy()
            expert = evaluate(lambda obs, rng: expert_table[env.state_of(obs)], p, 10_000 + seed)
            run: dict = {"p": p, "seed": seed, "expert": expert,
                         "demonstrations": episode_metrics(demonstration_batch(demos)).as_dict()}
            for name in METHODS:
                run[name] = neural_run(name, demos, p, seed, settings)
            run[TABULAR] = tabular_run(demos, p, seed, tabular_iterations)
            runs.append(run)
            print(f"p={p} seed={seed}: " + ", ".join(f"{name} {run[name]['violation_rate']:.3f}" for name in COLUMNS)
                  + f" ({time.perf_counter() - started:.0f} s)", flush=True)
    summary = summarise(runs, ps, COLUMNS)
    document = {
        "benchmark": "icrl_gridworld_sweep",
        "command": "python benchmarks/icrl_gridworld_sweep.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "settings": {"ps": list(ps), "seeds": seeds, "n_demos": N_DEMOS, "eval_episodes": EVAL_EPISODES,
                     "neural": {k: (list(v) if isinstance(v, tuple) else v) for k, v in settings.items()},
                     "method_settings": {name: extra for name, (_, extra) in METHODS.items()},
                     "tabular_iterations": tabular_iterations, "env": "CoordinateGridworld(p) (7x7, Fig. 2.1 layout)"},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "numpy": np.__version__, "torch": torch.__version__,
                    "load_average_before": load_before, "load_average_after": os.getloadavg()},
        "summary": summary, "claim_mce_below_me_at_p_ge_0.2": claim(summary, ps),
        "runs": runs, "seconds": round(time.perf_counter() - started, 1)}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.json, json.dumps(document, indent=1) + "\n")
    figure = plot(summary, ps, args.figure)
    print("\nviolation rate (sampled actions), mean over seeds\n")
    print("| p | " + " | ".join(COLUMNS) + " |")
    print("|---|" + "---|" * len(COLUMNS))
    for p in ps:
        print(f"| {p} | " + " | ".join(f"{summary[str(p)][n]['violation_rate']:.3f}" for n in COLUMNS) + " |")
    print(f"\nwrote {args.json} and {figure} ({document['seconds']:.0f} s)")
    return document


if __name__ == "__main__":
    main()
