"""PPO-Lagrangian defaults of ``symlearn train``: the old ones (raw advantages, no normalisation)
against the new ones (scale-free advantages, normalised observations and values), with
stable-baselines3's PPO-Lagrangian as the peer, each run as a user would run it (the CLI, default
steps unless named, one seed per row: noisy, say so when you quote it).

    python benchmarks/train_lagrangian_defaults.py --seeds 0 --json benchmarks/results/train_lagrangian_defaults.json

Tasks: BlockedPoint on its true cost (``--algo ppo-lag`` without ``--cost``), the thesis' toy with
the DNF learned from 20 expert episodes (the README's recipe, ``--prune``), and a user's hazard
robot (``tests/support/point_robot_env.py``, a module outside the package) with a hand-written DNF.
Reported: greedy return and true cost per episode (10 evaluation episodes) and the final
multipliers.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OLD = ["--advantage-scale", "raw", "--no-normalize-observations", "--no-normalize-values",
       "--multiplier-update", "gradient", "--multiplier-lr", "0.05", "--learning-rate", "2.5e-4", "--log-std-init", "0"]
# the defaults of the previous commit: scale-free advantages and normalisation, but the gradient rule
# and PPO's plain-task learning rate and initial noise
GRADIENT = ["--multiplier-update", "gradient", "--multiplier-lr", "0.05", "--learning-rate", "2.5e-4",
            "--log-std-init", "0"]
TASKS = {
    "blocked-point (true cost)": ["--env", "blocked-point", "--algo", "ppo-lag"],
    "toy-navigation (learned DNF, README recipe)": ["--env", "toy-navigation", "--cost", "toy.dnf", "--prune"],
    "hazard robot (user module, DNF)": ["--env", "point_robot_env:HazardRobot-v0", "--cost", "hazard.dnf",
                                        "--steps", "30000"],
    "rover (user module, true cost)": ["--env", "rover_env:Rover-v0", "--algo", "ppo-lag"],
    "rover, 150k steps": ["--env", "rover_env:Rover-v0", "--algo", "ppo-lag", "--steps", "150000"],
}
VARIANTS = {"old defaults": OLD, "gradient 0.05, PPO 2.5e-4, log std 0": GRADIENT, "new defaults": [],
            "episodes-only multiplier updates": ["--cost-estimate", "episodes"],
            # docs/BENCHMARKS.md, "Over-cautious agents at limit 0" (issue 24, 2026-12-08): opt-in
            "zero-limit slack 0.25": ["--zero-limit-slack", "0.25"],
            "sb3-ppo-lag (peer)": ["--algo", "sb3-ppo-lag"],
            "unconstrained PPO (reference)": ["--algo", "ppo"]}


def _run(folder: Path, task: str, variant: str, seed: int) -> dict:
    args = list(TASKS[task])
    extra = list(VARIANTS[variant])
    if variant.startswith(("sb3", "unconstrained")):
        args = [a for a in args if a != "--prune"]
        if "--algo" in args:  # the true-cost task names ppo-lag itself
            i = args.index("--algo")
            del args[i:i + 2]
    command = [sys.executable, "-m", "symlearn", "train", *args, *extra, "--seed", str(seed), "--json"]
    done = subprocess.run(command, cwd=folder, capture_output=True, text=True, timeout=3600,
                          env={**os.environ, "SYMLEARN_QUIET": "1"})
    row = {"task": task, "variant": variant, "seed": seed, "command": " ".join(command[1:])}
    if done.returncode != 0:
        return {**row, "error": done.stderr.strip()[-400:]}
    doc = json.loads(done.stdout)
    return {**row, "return": doc["return"], "cost": doc["cost"], "violation_rate": doc["violation_rate"],
            "multipliers": doc.get("multipliers"), "seconds": doc["seconds"], "steps": doc["steps"]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--tasks", nargs="+", choices=list(TASKS), default=list(TASKS))
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    folder = Path(tempfile.mkdtemp(prefix="lagrangian-defaults-"))
    shutil.copy(ROOT / "tests" / "support" / "point_robot_env.py", folder)
    shutil.copy(ROOT / "tests" / "support" / "rover_env.py", folder)
    (folder / "hazard.dnf").write_text("x > 0.4 & x < 0.6 & y < 0.6\n")
    subprocess.run([sys.executable, "-m", "symlearn", "learn", "dnf", "--env", "toy-navigation", "--n-demos", "20",
                    "-o", "toy.dnf"], cwd=folder, check=True, capture_output=True)
    jobs = [(t, v, s) for t in args.tasks for v in args.variants for s in args.seeds]
    with ThreadPoolExecutor(args.workers) as pool:
        rows = list(pool.map(lambda job: _run(folder, *job), jobs))
    for row in rows:
        if "error" in row:
            print(f"{row['task']:45s} {row['variant']:20s} seed {row['seed']}: ERROR {row['error']}")
        else:
            print(f"{row['task']:45s} {row['variant']:20s} seed {row['seed']}: return {row['return']:8.3f}  "
                  f"true cost {row['cost']!s:>6}  multipliers {row['multipliers']}")
    if args.json:
        args.json.write_text(json.dumps({"command": "python benchmarks/train_lagrangian_defaults.py "
                                                    + " ".join(argv or sys.argv[1:]), "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
