"""Learning curves on the rendered block tasks (thesis Fig. 7.5 in shape): DQRM vs DQN.

Per task and seed, in the same run and with the same settings:

* ``dqrm-inferred``  DQRM on the machine inferred from the task's image demonstrations;
* ``dqrm-truth``     DQRM on the ground-truth machine (propositions from the blocks' positions);
* ``dqn-shaped``     one pair of networks, the inferred machine's shaped reward, no machine state;
* ``dqn-sparse``     one pair of networks, the environment's reward (1 when the task is done).

Every ``eval_every`` episodes a greedy episode records the machine return, task success and the
final placement error. All methods get the demonstrator's transitions in their buffers.
Defaults are CPU-sized: Adam 1e-3 (the thesis' 1e-4 learns the same, only slower than our budget
allows), 8 updates of batch 16 per episode, epsilon 0.7 -> 0.1; the rest is ``DQRMConfig``'s
defaults (target networks copied every 16 updates with double Q-learning, no coordinate channels).

    nice -n 10 .venv/bin/python benchmarks/dqrm_blocks.py --quick      # Stack-2 + Place-2, 1 seed
    nice -n 10 .venv/bin/python benchmarks/dqrm_blocks.py --seeds 5 --episodes 60
    nice -n 10 .venv/bin/python benchmarks/dqrm_blocks.py --tasks pyramid-3,stack-3,place-3 --seeds 1 \
        --episodes 80 --output benchmarks/results/dqrm_blocks_three.json     # slow

Raw results: ``--output`` (default ``benchmarks/results/dqrm_blocks.json``, written when the run is
complete; the runs done so far go to ``*.partial.json`` as they finish), with the command, seeds,
load averages and wall and CPU seconds per run; figure ``docs/figures/<output name>.png``.
``--merge a.json b.partial.json --output c.json`` joins the runs of several files (one long benchmark
split over processes, or cut short) into one file and figure without training.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import platform
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

METHODS = {"dqrm-inferred": ("inferred", "dqrm"), "dqrm-truth": ("truth", "dqrm"),
           "dqn-shaped": ("inferred", "dqn-shaped"), "dqn-sparse": ("inferred", "dqn-sparse")}


def main() -> None:
    from symlearn.atomic import write_bytes, write_text
    from symlearn.recipes.block_rewards import block_setup
    from symlearn.rl.dqrm import DQRMConfig, train_dqrm

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="1 seed, 60 episodes")
    parser.add_argument("--tasks", default="stack-2,place-2")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--first-seed", type=int, default=0, help="seeds are first-seed, first-seed + 1, ...")
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--learning-rate", type=float, default=1e-3)
    parser.add_argument("--output", type=Path, default=REPO / "benchmarks" / "results" / "dqrm_blocks.json")
    parser.add_argument("--figures", type=Path, default=REPO / "docs" / "figures")
    parser.add_argument("--merge", type=Path, nargs="+", metavar="RESULTS",
                        help="no training: merge these results files (complete or .partial.json) into --output and draw it")
    args = parser.parse_args()
    if args.merge:
        merge(args.merge, args.output, args.figures)
        return
    seeds = [args.first_seed] if args.quick else list(range(args.first_seed, args.first_seed + args.seeds))
    tasks = args.tasks.split(",")
    episodes = 60 if args.quick else args.episodes
    config = DQRMConfig(episodes=episodes, learning_rate=args.learning_rate, updates_per_episode=8)
    started, load_before = time.perf_counter(), os.getloadavg()
    runs = []
    args.output.parent.mkdir(parents=True, exist_ok=True)
    partial = args.output.with_name(args.output.stem + ".partial.json")

    def document(complete: bool) -> dict:
        return {"benchmark": "dqrm_blocks", "command": "benchmarks/dqrm_blocks.py " + " ".join(sys.argv[1:]),
                "machine": {"platform": platform.platform(), "cpus": os.cpu_count(), "python": platform.python_version(),
                            "load_average_before": load_before, "load_average_after": os.getloadavg()},
                "config": asdict(config), "tasks": tasks, "seeds": seeds, "complete": complete,
                "seconds": time.perf_counter() - started, "runs": runs}

    for task in tasks:
        setups = {}
        for seed in seeds:
            for name, (machine, method) in METHODS.items():
                key = (machine, seed)
                if key not in setups:
                    setups[key] = block_setup(task, machine, seed=seed)
                s = setups[key]
                tick, cpu, load = time.perf_counter(), time.process_time(), os.getloadavg()[0]
                result = train_dqrm(s.env_fn, s.machine, s.labeling, s.prototypes, method=method,
                                    demonstrations=s.demonstrations, config=config, seed=seed)
                history = [h.as_dict() for h in result.history]
                first = next((h["episode"] for h in history if h["success"] == 1.0), None)
                reward = next((h["episode"] for h in history if h["machine_return"] >= 0.9), None)
                runs.append({"task": task, "seed": seed, "method": name, "machine": s.source,
                             "seconds": time.perf_counter() - tick, "cpu_seconds": time.process_time() - cpu,
                             "load_average": [load, os.getloadavg()[0]],
                             "first_success_episode": first, "first_reward_episode": reward,
                             "final_success": float(np.mean([h["success"] for h in history[-3:]])),
                             "history": history})
                print(f"{task} seed {seed} {name:14s} first success at {first} final {runs[-1]['final_success']:.2f} "
                      f"({runs[-1]['seconds']:.0f} s, {runs[-1]['cpu_seconds']:.0f} CPU s)", flush=True)
                # runs so far, beside the results: a long run cut short still leaves its numbers
                write_text(partial, json.dumps(document(False), indent=1, default=float) + "\n")
    doc = document(True)
    write_text(args.output, json.dumps(doc, indent=1, default=float) + "\n")
    partial.unlink(missing_ok=True)

    args.figures.mkdir(parents=True, exist_ok=True)
    print("wrote", args.output, write_bytes(args.figures / (args.output.stem + ".png"), figure(runs, tasks)))


def figure(runs: list[dict], tasks: list[str]) -> bytes:
    """PNG: greedy machine return and placement error per task, mean and range over the seeds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(tasks), figsize=(5 * len(tasks), 6), squeeze=False)
    for c, task in enumerate(tasks):
        for name in METHODS:
            mine = [r for r in runs if r["task"] == task and r["method"] == name]
            if not mine:
                continue
            x = [h["episode"] for h in mine[0]["history"]]
            for row, key in ((0, "machine_return"), (1, "placement_error")):
                values = np.array([[h[key] for h in r["history"]] for r in mine])
                axes[row, c].plot(x, values.mean(axis=0), label=name)
                if len(mine) > 1:
                    axes[row, c].fill_between(x, values.min(axis=0), values.max(axis=0), alpha=0.2)
        seeds = len({r["seed"] for r in runs if r["task"] == task})
        axes[0, c].set_title(f"{task}: greedy reward ({seeds} seed{'s' * (seeds > 1)})")
        axes[1, c].set_title(f"{task}: placement error")
        axes[1, c].set_xlabel("episode")
        axes[0, c].legend(fontsize=7)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90)
    return buffer.getvalue()


def merge(files: list[Path], output: Path, figures: Path) -> None:
    """One results file (and its figure) from several runs' files, complete or ``*.partial.json``:
    a long benchmark split over processes, or cut short, still gets its table and figure."""
    from symlearn.atomic import write_bytes, write_text

    docs = [json.loads(f.read_text()) for f in files]
    runs = [r for d in docs for r in d["runs"]]
    tasks = list(dict.fromkeys(r["task"] for r in runs))
    sources = []
    for f, d in zip(files, docs):  # a merged file brings its own sources
        sources += d.get("merged_from") or [{"file": str(f), "command": d["command"], "machine": d["machine"],
                                             "complete": d.get("complete", True), "seconds": d["seconds"]}]
    merged = {"benchmark": "dqrm_blocks", "merged_from": sources,
              "config": docs[0]["config"], "tasks": tasks, "seeds": sorted({r["seed"] for r in runs}), "runs": runs}
    write_text(output, json.dumps(merged, indent=1, default=float) + "\n")
    figures.mkdir(parents=True, exist_ok=True)
    print("wrote", output, write_bytes(figures / (output.stem + ".png"), figure(runs, tasks)))


if __name__ == "__main__":
    main()
