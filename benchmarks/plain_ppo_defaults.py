"""Plain PPO (``symlearn train --algo ppo``, no cost) at the default settings against CleanRL's
settings, which were plain PPO's defaults before (issue #24: one default configuration).

    python benchmarks/plain_ppo_defaults.py --seeds 0 1 2 3 --json benchmarks/results/plain_ppo_defaults.json

Each cell is one ``symlearn train`` process, as a user runs it: 50k steps (the default), greedy
return over 10 evaluation episodes. "defaults": no flag, PPOConfig's resolution (normalised
observations and values, learning rate 1e-3, initial log standard deviation -1: the Lagrangian's
measured defaults). "cleanrl": ``--learning-rate 2.5e-4 --log-std-init 0 --no-normalize-observations
--no-normalize-values``. Tasks: gymnasium's classic control and MuJoCo v5 tasks, MiniGrid, the
thesis' toy, and four environments written as users would (``benchmarks/plain_ppo_user_envs.py``
and the tests' rover and hazard robot), reached as ``module:EnvId``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = {
    "defaults": [],
    "cleanrl": ["--learning-rate", "2.5e-4", "--log-std-init", "0", "--no-normalize-observations",
                "--no-normalize-values"],
}
TASKS = ["CartPole-v1", "Acrobot-v1", "Pendulum-v1", "MountainCarContinuous-v0", "InvertedPendulum-v5",
         "Reacher-v5", "Hopper-v5", "HalfCheetah-v5", "minigrid:MiniGrid-Empty-5x5-v0", "toy-navigation",
         "plain_ppo_user_envs:Lander-v0", "plain_ppo_user_envs:Sorter-v0", "plain_ppo_user_envs:Arm3-v0",
         "rover_env:Rover-v0", "point_robot_env:HazardRobot-v0"]


def run_cell(task: str, config: str, seed: int, workdir: Path) -> dict:
    command = [sys.executable, "-m", "symlearn", "train", "--env", task, "--algo", "ppo", "--seed", str(seed),
               "--json", *CONFIGS[config]]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "benchmarks"), str(ROOT / "tests" / "support"),
                                                        os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(command, capture_output=True, text=True, cwd=workdir, env=env)
    if done.returncode:
        return {"task": task, "config": config, "seed": seed, "error": done.stderr.strip().splitlines()[-1:]}
    doc = json.loads(done.stdout)
    return {"task": task, "config": config, "seed": seed, "return": doc["return"], "cost": doc["cost"],
            "seconds": doc["seconds"]}


def table(rows: list[dict]) -> str:
    import numpy as np

    lines = ["| task | defaults: return (mean ± std) | CleanRL's: return | better |", "|---|---|---|---|"]
    for task in dict.fromkeys(r["task"] for r in rows):
        cells = {}
        for config in CONFIGS:
            values = [r["return"] for r in rows if r["task"] == task and r["config"] == config and "return" in r]
            cells[config] = (float(np.mean(values)), float(np.std(values))) if values else None
        new, old = cells["defaults"], cells["cleanrl"]
        if new is None or old is None:
            lines.append(f"| {task} | {new} | {old} | error |")
            continue
        margin = 0.05 * max(abs(new[0]), abs(old[0]), 1e-9)
        better = "defaults" if new[0] > old[0] + margin else "CleanRL's" if old[0] > new[0] + margin else "even"
        lines.append(f"| {task} | {new[0]:.4g} ± {new[1]:.2g} | {old[0]:.4g} ± {old[1]:.2g} | {better} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--tasks", nargs="+", default=TASKS)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        cells = [(t, c, s) for t in args.tasks for s in args.seeds for c in CONFIGS]
        with ThreadPoolExecutor(args.workers) as pool:
            rows = list(pool.map(lambda cell: run_cell(*cell, Path(tmp)), cells))
    for row in rows:
        print(json.dumps(row), flush=True)
    print(table(rows))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
