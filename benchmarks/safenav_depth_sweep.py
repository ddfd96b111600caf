"""Thesis Fig. 4.4 on SafeNav: rules, ground-truth cost and reward against the one-class tree's max_depth.

On one task (``--task``, default point-goal: the thesis used CarPush, but at our budget no
agent earns Push reward to speak of -- see docs/BENCHMARKS.md), a tree of each depth in
``--depths`` is fitted to the same ``--n-demos`` scripted-expert episodes; its DNF is the
cost of a PPO-Lagrangian agent (cost limit ``--cost-limit``), ``--seeds`` seeds each.
Reported per depth: conjunctions (and how many survive the thesis' pruning at 0.001 given each
run's rule counts), the formula cost the scripted expert pays on unseen layouts (how often
the rules fire on behaviour the tree never saw: the overfitting of deep trees), and the
agent's reward and ground-truth cost on 10 unseen layouts (mean +- sd over seeds).

    .venv/bin/python benchmarks/safenav_depth_sweep.py                  # depths 1-6, 2 seeds (~15 min on 2 workers)
    .venv/bin/python benchmarks/safenav_depth_sweep.py --quick          # smoke test (/tmp)

Runs go to ``--jsonl`` (rewritten atomically per run; finished runs are skipped on restart);
``--reuse`` takes runs with identical settings from the transfer benchmark's log. Raw results:
``benchmarks/results/safenav_depth_sweep.json``; figure: ``docs/figures/safenav_depth_sweep.png``.
"""

from __future__ import annotations

import argparse
import io
import json
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

from safenav_common import (  # noqa: E402
    FastRules, ResultLog, clean, expert_rows, learn_rules, parse_key, probe_points, prune_counts, run_all,
)

from symlearn.atomic import write_bytes, write_text  # noqa: E402


def spec_id(task: str, depth: int, seed: int, args: argparse.Namespace) -> str:
    # the transfer benchmark's id format, so its same-task runs can be reused
    return f"lag-dnf|{task}>{task}|d{depth}|n{args.n_demos}|s{seed}|{args.steps}|L{args.cost_limit:g}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="point-goal")
    parser.add_argument("--depths", default="1,2,3,4,5,6")
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--steps", type=int, default=250_000)
    parser.add_argument("--n-demos", type=int, default=20)
    parser.add_argument("--demo-seed", type=int, default=0)
    parser.add_argument("--cost-limit", type=float, default=25.0)
    parser.add_argument("--multiplier-lr", type=float, default=0.035)
    parser.add_argument("--eval-episodes", type=int, default=10)
    parser.add_argument("--prune-threshold", type=float, default=1e-3)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--jsonl", default=str(REPO / "benchmarks/results/safenav_depth_sweep.runs.jsonl"))
    parser.add_argument("--reuse", default=str(REPO / "benchmarks/results/safenav_transfer.runs.jsonl"),
                        help="a log whose runs with the same id are taken over ('' for none)")
    parser.add_argument("--json", default=str(REPO / "benchmarks/results/safenav_depth_sweep.json"))
    parser.add_argument("--figure", default=str(REPO / "docs/figures/safenav_depth_sweep.png"))
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument("--quick", action="store_true", help="depths 1 and 3, 2048 steps, 1 seed, /tmp")
    args = parser.parse_args()
    if args.quick:
        args.depths, args.seeds, args.steps, args.eval_episodes = "1,3", 1, 2048, 1
        args.jsonl, args.json, args.reuse = "/tmp/safenav_depth_quick.jsonl", "/tmp/safenav_depth_quick.json", ""
        args.figure = "/tmp/safenav_depth_sweep_quick.png"
    depths = [int(d) for d in args.depths.split(",")]
    agent, task = parse_key(args.task)
    started = time.perf_counter()

    from symlearn.envs.safenav.observation import FEATURE_NAMES

    rules, infos = {}, {}
    for depth in depths:
        dnf, info = learn_rules(agent, task, depth, args.n_demos, args.demo_seed)
        FastRules(dnf, FEATURE_NAMES).check(probe_points(agent, task, args.n_demos, args.demo_seed, 1500))
        rules[depth], infos[depth] = dnf, info
        print(f"depth {depth}: {info['conjunctions']} conjunctions, {info['leaves']} leaves, "
              f"{info['atoms']} atoms ({info['fit_seconds']:.2f} s)", flush=True)
    expert = expert_rows(args.task, {f"d{d}": rules[d] for d in depths}, args.eval_episodes)
    print("expert formula cost on unseen layouts:",
          {k: round(v["mean"], 1) for k, v in expert["dnf_cost"].items()}, flush=True)

    log = ResultLog(args.jsonl)
    specs = []
    for seed in range(args.seeds):
        for depth in depths:
            specs.append({"id": spec_id(args.task, depth, seed, args), "seed": seed,
                          "budget": {"steps": args.steps, "eval_episodes": args.eval_episodes},
                          "n_demos": args.n_demos, "demo_seed": args.demo_seed, "cost_limit": args.cost_limit,
                          "multiplier_lr": args.multiplier_lr, "algo": "ppo-lag", "target": args.task, "cost": "dnf",
                          "source": args.task, "depth": depth})
    if args.reuse and Path(args.reuse).exists():
        other = ResultLog(args.reuse)
        for s in specs:
            if not log.done(s["id"]) and other.done(s["id"]):
                row = dict(other.rows[s["id"]])
                row["reused_from"] = args.reuse
                log.add(row)
                print(f"reused {s['id']} from {args.reuse}", flush=True)
    if not args.report_only:
        run_all(specs, log, args.workers)

    per_depth = []
    for depth in depths:
        rows = [log.rows[s["id"]] for s in specs if s["depth"] == depth and log.done(s["id"])]
        if not rows:
            continue
        after = [len(prune_counts(rules[depth], r["rule_counts"]["evaluated"], r["rule_counts"]["fired"],
                                  args.prune_threshold)[0].conjunctions) for r in rows]

        def ms(values):
            v = np.array([x for x in values if x is not None], dtype=float)
            return {"mean": float(v.mean()), "sd": float(v.std()), "n": int(len(v))} if len(v) else None

        ev = [r["eval"]["stochastic"] for r in rows]
        per_depth.append({
            "depth": depth, "conjunctions": infos[depth]["conjunctions"], "leaves": infos[depth]["leaves"],
            "atoms": infos[depth]["atoms"], "after_pruning": ms(after),
            "expert_formula_cost": expert["dnf_cost"][f"d{depth}"],
            "reward": ms(e["return"]["mean"] for e in ev), "true_cost": ms(e["true_cost"]["mean"] for e in ev),
            "formula_cost": ms(e["dnf_cost"]["mean"] for e in ev),
            "greedy_reward": ms(r["eval"]["greedy"]["return"]["mean"] for r in rows),
            "greedy_true_cost": ms(r["eval"]["greedy"]["true_cost"]["mean"] for r in rows),
            "steps_per_second": ms(r["steps_per_second"] for r in rows), "seeds": len(rows)})

    def f(cell, d=1):
        return "–" if not cell else f"{cell['mean']:.{d}f} ± {cell['sd']:.{d}f}"

    table = ["| max_depth | leaves | conjunctions | after pruning (0.001) | expert's formula cost (unseen) | "
             "reward | ground-truth cost | formula cost | steps/s |", "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for p in per_depth:
        table.append(f"| {p['depth']} | {p['leaves']} | {p['conjunctions']} | {f(p['after_pruning'])} | "
                     f"{f(p['expert_formula_cost'])} | {f(p['reward'], 2)} | {f(p['true_cost'])} | "
                     f"{f(p['formula_cost'])} | {p['steps_per_second']['mean']:.0f} |")
    print("\n".join(table), flush=True)
    plot(per_depth, [log.rows[s["id"]] for s in specs if log.done(s["id"])], expert, args, Path(args.figure))
    document = {
        "benchmark": "safenav_depth_sweep",
        "command": "python benchmarks/safenav_depth_sweep.py " + " ".join(sys.argv[1:]),
        "machine": {"node": platform.node(), "python": platform.python_version()},
        "settings": {k: v for k, v in vars(args).items() if k not in ("jsonl", "json", "figure")},
        "expert": expert, "per_depth": per_depth, "table": "\n".join(table),
        # per-rule counts stay in the JSONL log (up to 1554 rules per run); the table has what they give
        "runs": [{k: v for k, v in log.rows[s["id"]].items() if k != "rule_counts"} for s in specs if log.done(s["id"])],
        "report_seconds": time.perf_counter() - started,
    }
    write_text(args.json, json.dumps(clean(document), indent=1, allow_nan=False) + "\n")
    print(f"wrote {args.json} and {args.figure} ({(time.perf_counter() - started) / 60:.1f} min)", flush=True)


def plot(per_depth, rows, expert, args, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5))
    cmap = plt.get_cmap("viridis")
    depths = sorted({r["depth"] for r in rows})
    for k, depth in enumerate(depths):
        rs = [r for r in rows if r["depth"] == depth]
        color = cmap(k / max(1, len(depths) - 1))
        steps = np.array(rs[0]["curve"]["steps"]) / 1000
        for ax, key in ((axes[0, 0], "return"), (axes[0, 1], "true_cost")):
            Y = np.array([[np.nan if v is None else v for v in r["curve"][key]] for r in rs], dtype=float)
            with warnings.catch_warnings():  # a bin without finished episodes is NaN
                warnings.simplefilter("ignore", RuntimeWarning)
                ax.plot(steps, np.nanmean(Y, axis=0), color=color, label=f"depth {depth}")
    axes[0, 0].axhline(expert["return"]["mean"], color="k", ls="--", lw=1, label="scripted expert")
    axes[0, 0].set(title="reward during training", xlabel="environment steps (thousands)", ylabel="episode reward")
    axes[0, 1].set(title="ground-truth cost during training (the limit bounds the formula cost)", xlabel="environment steps (thousands)",
                   ylabel="episode cost")
    axes[0, 0].legend(fontsize=7)
    axes[0, 1].legend(fontsize=7)
    d = [p["depth"] for p in per_depth]
    ax = axes[1, 0]
    ax.plot(d, [p["conjunctions"] for p in per_depth], "o-", label="conjunctions")
    ax.errorbar(d, [p["after_pruning"]["mean"] for p in per_depth], [p["after_pruning"]["sd"] for p in per_depth],
                fmt="s-", label="after pruning (0.001)")
    ax.plot(d, [p["expert_formula_cost"]["mean"] for p in per_depth], "^--",
            label="scripted expert's formula cost (unseen)")
    ax.set_yscale("log")
    ax.set(title="rules and false alarms", xlabel="max_depth")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    ax.errorbar(d, [p["reward"]["mean"] for p in per_depth], [p["reward"]["sd"] for p in per_depth], fmt="o-",
                color="tab:blue", label="reward")
    ax.set(title="after training (10 unseen layouts)", xlabel="max_depth")
    ax.set_ylabel("episode reward", color="tab:blue")
    twin = ax.twinx()
    twin.errorbar(d, [p["true_cost"]["mean"] for p in per_depth], [p["true_cost"]["sd"] for p in per_depth],
                  fmt="s-", color="tab:red", label="ground-truth cost")
    twin.set_ylabel("ground-truth episode cost", color="tab:red")
    fig.suptitle(f"{args.task}: PPO-Lagrangian on one-class-tree DNFs of growing depth "
                 f"({args.steps // 1000}k steps, cost limit {args.cost_limit:g}, mean over {args.seeds} seeds)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


if __name__ == "__main__":
    main()
