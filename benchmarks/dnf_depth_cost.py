"""PPO-Lagrangian on a learned DNF: 1 per unsafe step against ``1 + W x depth`` (``train --depth-weight``).

    python benchmarks/dnf_depth_cost.py --seeds 0 1 2 --weights 0 3 --json benchmarks/results/dnf_depth_cost.json

Every task's formula is learned first, as a user would (`symlearn learn dnf`, default settings):
the thesis' toy from 20 scripted-expert episodes, SafeNav PointGoal/CarGoal from the scripted
experts, and 20 demonstrations recorded in four environments written as users would
(`benchmarks/plain_ppo_user_envs.py`: the lander, the robot that goes round a disk; the tests'
rover; CartPole with a hand-written controller). Then one `symlearn train --cost F.dnf` process
per cell at the defaults (ppo-lag, 50k steps, limit 0) with `--depth-weight W`; greedy return and
true cost per episode (`info["cost"]`; CartPole has none) over 10 evaluation episodes.
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

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TASKS = {  # name -> (env id, how its formula is learned, extra train flags)
    "toy-navigation (README recipe)": ("toy-navigation", ["--n-demos", "20"], ["--prune"]),
    "disk robot (user module)": ("plain_ppo_user_envs:Sorter-v0", "sorter", []),
    "lander (user module)": ("plain_ppo_user_envs:Lander-v0", "lander", []),
    "rover (user module)": ("rover_env:Rover-v0", "rover", []),
    "CartPole-v1 (hand-written controller)": ("CartPole-v1", "cartpole", []),
    "safenav-point-goal": ("safenav-point-goal", [], []),
    "safenav-car-goal": ("safenav-car-goal", [], []),
}


def _env() -> dict:
    paths = [str(ROOT / "benchmarks"), str(ROOT / "tests" / "support"), os.environ.get("PYTHONPATH", "")]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(paths)}


def record(kind: str, path: Path) -> None:
    """20 demonstrations of a scripted controller (what a user would have logged)."""
    sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT / "tests" / "support")]
    import gymnasium as gym

    import plain_ppo_user_envs as own
    import rover_env
    from symlearn.data import record as run

    rng = np.random.default_rng(0)

    def cartpole(o):
        return int(o[2] + 0.5 * o[3] + 0.05 * o[1] + 0.01 * o[0] > 0) if rng.random() > 0.05 else int(rng.integers(2))

    env, policy = {"sorter": ("Sorter-v0", own.sorter_expert()), "lander": ("Lander-v0", own.lander_expert()),
                   "rover": ("Rover-v0", rover_env.expert), "cartpole": ("CartPole-v1", cartpole)}[kind]
    run(gym.make(env), policy, 20, seed=0).save(path)


def learn(task: str, workdir: Path) -> Path:
    env, how, _ = TASKS[task]
    formula = workdir / (env.replace(":", "_").replace("/", "_") + ".dnf")
    flags = list(how) if isinstance(how, list) else []
    if isinstance(how, str):
        demos = workdir / f"{how}.npz"
        record(how, demos)
        flags = ["--demos", str(demos)]
    subprocess.run([sys.executable, "-m", "symlearn", "learn", "dnf", "--env", env, *flags, "-o", str(formula),
                    "--quiet"], check=True, cwd=workdir, env=_env(), capture_output=True)
    return formula


def run_cell(task: str, formula: Path, weight: float, seed: int, workdir: Path, more: tuple[str, ...] = ()) -> dict:
    env, _, extra = TASKS[task]
    command = [sys.executable, "-m", "symlearn", "train", "--env", env, "--cost", str(formula), "--seed", str(seed),
               "--depth-weight", str(weight), "--json", *extra, *more]
    done = subprocess.run(command, capture_output=True, text=True, cwd=workdir, env=_env())
    row = {"task": task, "weight": weight, "seed": seed}
    if done.returncode:
        return {**row, "error": done.stderr.strip().splitlines()[-1:]}
    doc = json.loads(done.stdout)
    return {**row, "return": doc["return"], "cost": doc["cost"], "violation_rate": doc["violation_rate"],
            "multipliers": doc["multipliers"], "seconds": doc["seconds"], "warnings": doc["warnings"],
            "actor_resets": doc.get("actor_resets"), "actor_restored": doc.get("actor_restored"),
            "train_args": list(more)}


def table(rows: list[dict], weights: list[float]) -> str:
    head = " | ".join(f"W = {w:g}: return / true cost" for w in weights)
    lines = [f"| task | {head} |", "|---|" + "---|" * len(weights)]
    for task in dict.fromkeys(r["task"] for r in rows):
        cells = []
        for w in weights:
            done = [r for r in rows if r["task"] == task and r["weight"] == w and "return" in r]
            if not done:
                cells.append("error")
                continue
            returns = [r["return"] for r in done]
            costs = [r["cost"] for r in done if r["cost"] is not None]
            cost = f"{np.mean(costs):.3g}" if costs else "n/a"
            per_seed = ", ".join(f"{r['return']:.3g}/" + ("n/a" if r["cost"] is None else f"{r['cost']:.3g}")
                                 for r in done)
            cells.append(f"{np.mean(returns):.3g} / {cost} ({per_seed})")
        lines.append(f"| {task} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--weights", type=float, nargs="+", default=[0.0, 3.0])
    parser.add_argument("--tasks", nargs="+", default=list(TASKS))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--train-args", default="", help="more flags for every `symlearn train`, e.g. '--reset-actor never'")
    args = parser.parse_args()
    more = tuple(args.train_args.split())
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(tmp)
        formulas = {task: learn(task, workdir) for task in args.tasks}
        cells = [(t, formulas[t], w, s) for t in args.tasks for s in args.seeds for w in args.weights]
        with ThreadPoolExecutor(args.workers) as pool:
            rows = list(pool.map(lambda cell: run_cell(*cell, workdir, more), cells))
        rules = {task: sum(1 for line in f.read_text().splitlines() if line.strip() and not line.startswith("#"))
                 for task, f in formulas.items()}
    for row in rows:
        print(json.dumps(row), flush=True)
    print(table(rows, args.weights))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"command": " ".join(sys.argv), "rules": rules, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
