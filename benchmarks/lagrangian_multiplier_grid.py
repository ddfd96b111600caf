"""PPO-Lagrangian settings on two tasks where the default is safe but not useful: the README's toy
recipe (the DNF learned from 20 expert episodes) and a user's rover (``tests/support/rover_env.py``,
its own ``info["cost"]``), cost limit 0, 50k steps, greedy evaluation on 10 episodes.

    python benchmarks/lagrangian_multiplier_grid.py --json benchmarks/results/lagrangian_multiplier_grid.json

Each variant changes the library defaults (``LagrangianConfig``/``PPOConfig`` as ``symlearn train
--algo ppo-lag`` uses them) in one or two places; reported: greedy return, true cost per episode,
final multiplier, the policy's entropy at the end.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
# Every variant is spelled out in full: the library's defaults moved with this benchmark (the first
# rows were measured on the previous ones, gradient 0.05 with PPO's 2.5e-4 and log std 0).
_PREVIOUS = {"lag": {"update": "gradient", "lr": 0.05}, "ppo": {"learning_rate": 2.5e-4, "log_std_init": 0.0}}


def _on_previous(lag: dict | None = None, ppo: dict | None = None) -> dict:
    return {"lag": {**_PREVIOUS["lag"], **(lag or {})}, "ppo": {**_PREVIOUS["ppo"], **(ppo or {})}}


VARIANTS = {
    "previous defaults (gradient 0.05, PPO 2.5e-4, log std 0)": _on_previous(),
    "previous, cost_estimate='episodes'": _on_previous({"cost_estimate": "episodes"}),
    "previous, adam 0.035": _on_previous({"update": "adam", "lr": 0.035}),
    "previous, adam 0.1": _on_previous({"update": "adam", "lr": 0.1}),
    "previous, adam 0.035, init 1, log_std_init -1": _on_previous({"update": "adam", "lr": 0.035, "init": 1.0},
                                                                  {"log_std_init": -1.0}),
    "previous, max_multiplier 10": _on_previous({"max_multiplier": 10.0}),
    "previous, advantage_scale='raw'": _on_previous({"advantage_scale": "raw"}),
    "previous, pid": _on_previous({"update": "pid"}),
    "previous, log_std_init -1": _on_previous(ppo={"log_std_init": -1.0}),
    "adam 0.035, learning rate 1e-3, log_std_init -1": {"lag": {"update": "adam", "lr": 0.035},
                                                        "ppo": {"learning_rate": 1e-3, "log_std_init": -1.0}},
    "adam 0.1, learning rate 1e-3, log_std_init -1 (the new defaults)": {
        "lag": {"update": "adam", "lr": 0.1}, "ppo": {"learning_rate": 1e-3, "log_std_init": -1.0}},
    "adam 0.1 with beta2 0.99, learning rate 1e-3, log_std_init -1": {
        "lag": {"update": "adam", "lr": 0.1, "adam_beta2": 0.99}, "ppo": {"learning_rate": 1e-3, "log_std_init": -1.0}},
}
TASKS = ("toy-navigation (learned DNF)", "rover (user module, true cost)", "blocked-point (true cost)",
         "hazard robot (user module, DNF)")


def _target(task: str, folder: Path):
    from symlearn.cli.train_costs import training_cost
    from symlearn.recipes.environments import resolve_env

    if task.startswith("toy"):
        target = resolve_env("toy-navigation").as_numeric()
        cost = training_cost(str(folder / "toy.dnf"), target, features=None, per_rule=False)
        env_fn = target.env_fn if cost.wrap is None else (lambda: cost.wrap(target.make()))
        return target, env_fn, cost.rollout_cost
    if task.startswith("hazard"):
        target = resolve_env("point_robot_env:HazardRobot-v0").as_numeric()
        cost = training_cost(str(folder / "hazard.dnf"), target, features=None, per_rule=False)
        env_fn = target.env_fn if cost.wrap is None else (lambda: cost.wrap(target.make()))
        return target, env_fn, cost.rollout_cost
    target = resolve_env("rover_env:Rover-v0" if task.startswith("rover") else "blocked-point").as_numeric()
    return target, target.env_fn, None


def run(task: str, variant: str, seed: int, folder: Path, steps: int) -> dict:
    from symlearn.progress import progress_bars
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, evaluate, train_ppo

    spec = VARIANTS[variant]
    target, env_fn, cost_fn = _target(task, folder)
    started = time.perf_counter()
    with progress_bars(False):
        result = train_ppo(env_fn, steps, PPOConfig(seed=seed, **spec.get("ppo", {})),
                           # init 0: the start every recorded row of this grid had (the default until 2026-12-07)
                           lagrangian=LagrangianConfig(cost_limit=0.0, **{"init": 0.0, **spec.get("lag", {})}),
                           cost_fn=cost_fn)
    episodes = evaluate(result.policy, target.make(), 10, seed=seed + 10_000)
    return {"task": task, "variant": variant, "seed": seed, "return": float(np.mean(episodes.returns)),
            "true_cost": float(episodes.costs.sum(axis=1).mean()),
            "multipliers": [float(m) for m in result.multipliers], "entropy": result.history[-1].entropy,
            "seconds": time.perf_counter() - started}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tasks", nargs="+", choices=TASKS, default=list(TASKS))
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--steps", type=int, default=50_000, help="per run (the hazard robot: 30k, as "
                        "train_lagrangian_defaults.py)")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args(argv)
    import subprocess

    sys.path.insert(0, str(ROOT / "tests" / "support"))
    folder = Path(tempfile.mkdtemp(prefix="multiplier-grid-"))
    subprocess.run([sys.executable, "-m", "symlearn", "learn", "dnf", "--env", "toy-navigation", "--n-demos", "20",
                    "-o", "toy.dnf"], cwd=folder, check=True, capture_output=True)
    (folder / "hazard.dnf").write_text("x > 0.4 & x < 0.6 & y < 0.6\n")  # as train_lagrangian_defaults.py
    rows = []
    for task in args.tasks:
        for variant in args.variants:
            for seed in args.seeds:
                row = run(task, variant, seed, folder, 30_000 if task.startswith("hazard") else args.steps)
                rows.append(row)
                print(f"{task:32s} {variant:45s} seed {seed}: return {row['return']:7.3f}  true cost "
                      f"{row['true_cost']:6.1f}  multiplier {row['multipliers'][0]:8.2f}  entropy {row['entropy']:.2f}",
                      flush=True)
                if args.json:  # after every run: a killed sweep keeps what it finished
                    args.json.write_text(json.dumps({"command": "python benchmarks/lagrangian_multiplier_grid.py "
                                                     + " ".join(argv or sys.argv[1:]), "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
