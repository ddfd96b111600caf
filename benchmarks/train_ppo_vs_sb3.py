"""``symlearn train --algo ppo`` against ``--algo sb3-ppo`` on CartPole-v1: the two PPOs a user gets
from the command line, in the same run.

Both routes build the same network (separate 64 x 64 tanh actor and critic), 4 copies x 128 steps,
minibatch 128, 4 epochs, learning rate 2.5e-4 annealed to 0, entropy 0.01, one torch thread.
Each seed runs the two one after the other, the order alternating with the seed; both are warmed
up once first. Measured: environment steps per second of training (the ``steps`` and ``seconds``
of the command's JSON: the training call only, not building or evaluation) and the greedy
evaluation return the command reports (10 episodes).

    python benchmarks/train_ppo_vs_sb3.py --json benchmarks/results/train_ppo_vs_sb3.json
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import platform
import statistics
import sys

from symlearn.atomic import write_text
from symlearn.cli.main import main as symlearn


def train(algo: str, steps: int, seed: int) -> dict:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = symlearn(["train", "--env", "CartPole-v1", "--algo", algo, "--steps", str(steps),
                         "--seed", str(seed), "--quiet", "--json"])
    if code != 0:
        raise SystemExit(f"train --algo {algo} failed with exit code {code}")
    doc = json.loads(out.getvalue())
    return {"algo": algo, "seed": seed, "steps": doc["steps"], "seconds": doc["seconds"],
            "steps_per_second": doc["steps"] / doc["seconds"], "return": doc["return"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--json", metavar="OUT")
    args = parser.parse_args()
    for algo in ("ppo", "sb3-ppo"):   # warm-up: torch's one-time initialisation lands here
        train(algo, 1024, 99)
    runs = []
    for seed in range(args.seeds):
        order = ("ppo", "sb3-ppo") if seed % 2 == 0 else ("sb3-ppo", "ppo")
        for algo in order:
            runs.append(train(algo, args.steps, seed))
            print(json.dumps(runs[-1]), file=sys.stderr)
    summary = {}
    for algo in ("ppo", "sb3-ppo"):
        mine = [r for r in runs if r["algo"] == algo]
        summary[algo] = {"steps_per_second": statistics.mean(r["steps_per_second"] for r in mine),
                         "return": statistics.mean(r["return"] for r in mine)}
    ratios = [a["steps_per_second"] / b["steps_per_second"]
              for a, b in zip([r for r in runs if r["algo"] == "ppo"], [r for r in runs if r["algo"] == "sb3-ppo"],
                              strict=True)]
    summary["ours_over_sb3"] = {"mean": statistics.mean(ratios), "per_seed": ratios}
    print(json.dumps(summary, indent=1))
    if args.json:
        import stable_baselines3
        import torch

        document = {"benchmark": "train_ppo_vs_sb3", "env": "CartPole-v1", "steps": args.steps,
                    "python": platform.python_version(), "torch": torch.__version__,
                    "stable_baselines3": stable_baselines3.__version__, "runs": runs, "summary": summary}
        write_text(args.json, json.dumps(document, indent=1) + "\n")


if __name__ == "__main__":
    main()
