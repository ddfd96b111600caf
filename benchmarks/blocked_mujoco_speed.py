"""Raw steps per second of the blocked MuJoCo environments against the bare v5 robots, same run.

Per task (``symlearn.envs.blocked_mujoco_tasks.TASKS`` and the broken ant), three variants step
the same random actions (drawn beforehand from the seeded action space, reset at every episode
end, as training steps them):

* ``bare``: ``gymnasium.make("<Robot>-v5", <the task's robot kwargs>, max_episode_steps=<the
  task's>)``: the robot as gymnasium gives it (TimeLimit, order and passive checkers), the peer;
* ``blocked``: the ``make_*`` factory (what the registry's ``make_env`` and ``symlearn learn icrl``
  build): the task's reward, the wall's cost, ``info["features"]``, our own truncation;
* ``blocked+gym``: ``gymnasium.make("symlearn/<name>-v0")``: the same with gymnasium's wrappers.

Variants go round-robin, ``--repeats`` times, medians kept; the ratio is ``variant / bare``
steps per second from the same run (wall clock and process CPU time).

    nice -n 10 .venv/bin/python benchmarks/blocked_mujoco_speed.py [--steps 5000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import gymnasium  # noqa: E402

from symlearn.atomic import write_text  # noqa: E402
from symlearn.envs import blocked_mujoco as bm  # noqa: E402
from symlearn.envs.gym_registration import register_gymnasium_envs  # noqa: E402
from symlearn.envs.blocked_mujoco_tasks import TASKS  # noqa: E402

RESULTS = REPO / "benchmarks" / "results" / "blocked_mujoco_speed.json"
# registry name -> (task row, factory, extra kwargs of the bare robot matching the factory's defaults)
CASES = {
    "blocked-half-cheetah": ("half-cheetah", bm.make_blocked_half_cheetah, {}),
    "blocked-ant": ("ant", bm.make_blocked_ant, {"include_cfrc_ext_in_observation": False}),
    "broken-ant": ("ant", bm.make_broken_ant, {"include_cfrc_ext_in_observation": False}),
    "blocked-walker2d": ("walker2d", bm.make_blocked_walker2d, {}),
    "blocked-swimmer": ("swimmer", bm.make_blocked_swimmer, {}),
    "biased-inverted-pendulum": ("inverted-pendulum", bm.make_biased_inverted_pendulum, {}),
}
VARIANTS = ("bare", "blocked", "blocked+gym")


def make(name: str, variant: str):
    task_name, factory, extra = CASES[name]
    task = TASKS[task_name]
    if variant == "bare":
        return gymnasium.make(task.gym_id, **task.robot_kwargs, **extra, max_episode_steps=task.max_episode_steps)
    return factory() if variant == "blocked" else gymnasium.make(f"symlearn/{name}-v0")


def one_run(env, actions, seed: int) -> tuple[float, float, int]:
    """Wall and CPU seconds per step over ``actions`` (resets at episode ends included), episodes."""
    env.reset(seed=seed)
    episodes = 0
    start, cpu = time.perf_counter(), time.process_time()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
            episodes += 1
    return (time.perf_counter() - start) / len(actions), (time.process_time() - cpu) / len(actions), episodes


def measure(name: str, steps: int, repeats: int, seed: int) -> dict:
    envs = {variant: make(name, variant) for variant in VARIANTS}
    space = envs["bare"].action_space
    space.seed(seed)
    actions = [space.sample() for _ in range(steps)]
    for env in envs.values():  # warm-up
        one_run(env, actions[: min(200, steps)], seed)
    wall: dict[str, list[float]] = {v: [] for v in VARIANTS}
    cpu: dict[str, list[float]] = {v: [] for v in VARIANTS}
    episodes = {}
    for _ in range(repeats):
        for variant, env in envs.items():
            w, c, episodes[variant] = one_run(env, actions, seed)
            wall[variant].append(w)
            cpu[variant].append(c)
    for env in envs.values():
        env.close()
    steps_per_s = {v: 1.0 / statistics.median(wall[v]) for v in VARIANTS}
    cpu_steps_per_s = {v: 1.0 / statistics.median(cpu[v]) for v in VARIANTS}
    return {"env": name, "robot": TASKS[CASES[name][0]].gym_id,
            "observation_size": int(envs["blocked"].observation_space.shape[0]),
            "steps_per_s": steps_per_s, "cpu_steps_per_s": cpu_steps_per_s,
            "ratio": {v: steps_per_s[v] / steps_per_s["bare"] for v in VARIANTS[1:]},
            "cpu_ratio": {v: cpu_steps_per_s[v] / cpu_steps_per_s["bare"] for v in VARIANTS[1:]},
            "episodes_per_run": episodes,
            "runs_us": {v: [x * 1e6 for x in wall[v]] for v in VARIANTS}}


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=5000, help="steps per run (5000)")
    parser.add_argument("--repeats", type=int, default=5, help="runs per variant, round-robin (5)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--envs", default=",".join(CASES), help="comma-separated registry names (all)")
    parser.add_argument("--out", default=str(RESULTS))
    args = parser.parse_args(argv)
    names = [n.strip() for n in args.envs.split(",") if n.strip()]
    unknown = [n for n in names if n not in CASES]
    if unknown:
        parser.error(f"unknown environment {unknown[0]!r}; known: {', '.join(CASES)}")
    register_gymnasium_envs()
    bm.route_mujoco_warnings()  # before the bare robots load (else MuJoCo writes MUJOCO_LOG.TXT here)
    warnings.filterwarnings("ignore", message="MuJoCo: compiler attribute", category=RuntimeWarning)
    load_before = os.getloadavg()
    started = time.perf_counter()
    rows = []
    for name in names:
        row = measure(name, args.steps, args.repeats, args.seed)
        rows.append(row)
        rate = row["steps_per_s"]
        print(f"{name:26} bare {rate['bare']:8.0f} steps/s | blocked {rate['blocked']:8.0f} "
              f"({row['ratio']['blocked']:.2f}x, CPU {row['cpu_ratio']['blocked']:.2f}x) | via gymnasium.make "
              f"{rate['blocked+gym']:8.0f} ({row['ratio']['blocked+gym']:.2f}x)", flush=True)
    doc = {"benchmark": "blocked_mujoco_speed",
           "command": "nice -n 10 .venv/bin/python benchmarks/blocked_mujoco_speed.py"
                      + ("" if argv is None and len(sys.argv) == 1 else " " + " ".join(argv if argv is not None
                                                                                         else sys.argv[1:])),
           "machine": {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
                       "cpus": os.cpu_count(), "python": platform.python_version(), "numpy": np.__version__,
                       "gymnasium": gymnasium.__version__, "mujoco": _version("mujoco"),
                       "load_average_before": load_before, "load_average_after": os.getloadavg()},
           "steps": args.steps, "repeats": args.repeats, "seed": args.seed,
           "seconds": time.perf_counter() - started, "cases": rows}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_text(args.out, json.dumps(doc, indent=2) + "\n")
    print(f"wrote {args.out}")
    return doc


def _version(module: str) -> str:
    from importlib.metadata import version

    return version(module)


if __name__ == "__main__":
    main()
