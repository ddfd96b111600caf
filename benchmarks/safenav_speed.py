"""Steps per second of the SafeNav and toy environments, against gymnasium's Pendulum-v1 in the same run.

The issue asks for environments "fast enough for CPU training (thousands of steps/s)". Every
environment is stepped with random actions (drawn beforehand from its seeded action space, so
only ``step`` is timed, plus the ``reset`` at each episode end) through ``gymnasium.make`` --
i.e. with gymnasium's order-enforcing and passive-checker wrappers, as a training loop sees it
-- and also unwrapped. Pendulum-v1 (classic control, pure numpy, the cheapest continuous-control
peer gymnasium ships) is the reference; the ratio column is ours / Pendulum. Runs go round-robin
(each environment once per repeat, best kept), so load from other processes hits both alike. The scripted expert
(:mod:`symlearn.envs.safenav_expert`, a Dijkstra field per goal) is timed as well, since it is
what records demonstrations.

    .venv/bin/python benchmarks/safenav_speed.py            # 20,000 steps, best of 5 (about a minute)
    .venv/bin/python benchmarks/safenav_speed.py --quick    # 2,000 steps, best of 2

Raw results: ``benchmarks/results/safenav_speed.json``.
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

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import gymnasium  # noqa: E402

import symlearn.envs  # noqa: E402,F401  (registers the gymnasium ids)
from symlearn.envs.safenav_expert import expert_demonstrations  # noqa: E402

PEER = "Pendulum-v1"
IDS = ("symlearn/safenav-point-goal-v0", "symlearn/safenav-point-push-v0", "symlearn/safenav-car-goal-v0",
       "symlearn/safenav-car-push-v0", "symlearn/toy-navigation-v0", PEER)


def one_run(env, actions: list, seed: int) -> tuple[float, int]:
    """Steps/s of one run through ``actions`` (reset at every episode end); also the episodes ended."""
    env.reset(seed=seed)
    ended = 0
    start = time.perf_counter()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
            ended += 1
    return len(actions) / (time.perf_counter() - start), ended


def measure(ids: tuple[str, ...], steps: int, repeats: int) -> list[dict]:
    """Best steps/s per environment, made and unwrapped. The runs go round-robin (every
    environment once per repeat), so a busy moment of the machine hits ours and the peer alike."""
    envs = {gym_id: gymnasium.make(gym_id) for gym_id in ids}
    actions = {}
    for gym_id, env in envs.items():
        env.action_space.seed(0)
        actions[gym_id] = [env.action_space.sample() for _ in range(steps)]
    best = {(gym_id, form): 0.0 for gym_id in ids for form in ("make", "unwrapped")}
    episodes = {}
    for r in range(repeats):
        for gym_id, env in envs.items():
            for form, target in (("make", env), ("unwrapped", env.unwrapped)):
                rate, ended = one_run(target, actions[gym_id], seed=r)
                best[gym_id, form] = max(best[gym_id, form], rate)
                episodes[gym_id] = ended
    return [{"env": gym_id, "steps": steps, "episodes_ended": episodes[gym_id],
             "steps_per_s_make": best[gym_id, "make"], "steps_per_s_unwrapped": best[gym_id, "unwrapped"]}
            for gym_id in ids]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2,000 steps, best of 2 (default: 20,000, best of 5)")
    parser.add_argument("--steps", type=int)
    parser.add_argument("--repeats", type=int)
    parser.add_argument("--out", type=Path, default=REPO / "benchmarks" / "results" / "safenav_speed.json")
    args = parser.parse_args()
    steps = args.steps or (2_000 if args.quick else 20_000)
    repeats = args.repeats or (2 if args.quick else 5)
    machine = {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
               "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
               "gymnasium": gymnasium.__version__}
    print(f"# {machine['processor']}, {machine['cpus']} CPUs, python {machine['python']}, "
          f"numpy {machine['numpy']}, gymnasium {machine['gymnasium']}; {steps} random steps, best of {repeats}")

    rows = measure(IDS, steps, repeats)
    peer = next(r for r in rows if r["env"] == PEER)
    print(f"{'environment':<32} {'steps/s (make)':>15} {'unwrapped':>10} {'/ Pendulum':>11}")
    for row in rows:
        row["ratio_vs_pendulum_make"] = row["steps_per_s_make"] / peer["steps_per_s_make"]
        row["ratio_vs_pendulum_unwrapped"] = row["steps_per_s_unwrapped"] / peer["steps_per_s_unwrapped"]
        print(f"{row['env']:<32} {row['steps_per_s_make']:>15,.0f} {row['steps_per_s_unwrapped']:>10,.0f} "
              f"{row['ratio_vs_pendulum_make']:>11.2f}")

    experts = []
    episode_steps = 200 if args.quick else 1000
    for agent in ("point", "car"):
        for task in ("goal", "push"):
            start = time.perf_counter()
            demos = expert_demonstrations(agent, task, n=2, seed=0, max_steps=episode_steps)
            seconds = time.perf_counter() - start
            taken = sum(len(t.actions) for t in demos)
            experts.append({"env": f"symlearn/safenav-{agent}-{task}-v0", "episodes": 2, "steps": taken,
                            "seconds": seconds, "steps_per_s": taken / seconds,
                            "cost": sum(t.info["cost"] for t in demos),
                            "goals_reached": sum(t.info["goals_reached"] for t in demos),
                            "return": float(sum(t.rewards.sum() for t in demos))})
    print(f"\n{'scripted expert (2 episodes)':<32} {'steps/s':>10} {'cost':>5} {'goals':>6} {'return':>7}")
    for row in experts:
        print(f"{row['env']:<32} {row['steps_per_s']:>10,.0f} {row['cost']:>5} {row['goals_reached']:>6} "
              f"{row['return']:>7.1f}")

    document = {"command": " ".join(["benchmarks/safenav_speed.py", *sys.argv[1:]]), "machine": machine,
                "peer": PEER, "environments": rows, "experts": experts}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"\nwrote {args.out.relative_to(REPO) if args.out.is_relative_to(REPO) else args.out}")


if __name__ == "__main__":
    main()
