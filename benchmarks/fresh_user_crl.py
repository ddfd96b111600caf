"""Issue 24, fresh user modules: constrained RL at the defaults on tasks nobody tuned on.

Writes four gymnasium user modules (a conveyor arm, a drone with a no-fly disc, a boiler, an arm
with an angle limit) to a temporary folder and runs, per task and seed, the commands a user
would, at their defaults:

    symlearn train --env MOD:ID --algo ppo-lag -o expert.safetensors       (true cost)
    symlearn train --env MOD:ID --algo sb3-ppo-lag                         (true cost, peer)
    symlearn train --env MOD:ID --algo ppo                                 (unconstrained)
    symlearn data record --env MOD:ID --policy expert.safetensors -o demos.npz
    symlearn learn dnf --env MOD:ID --demos demos.npz -o rules.dnf
    symlearn train --env MOD:ID --cost rules.dnf                           (ours, learned DNF)
    symlearn train --env MOD:ID --algo sb3-ppo-lag --cost rules.dnf        (peer, learned DNF)
    symlearn learn icrl --env MOD:ID --demos demos.npz -o cost.safetensors
    symlearn train --env MOD:ID --cost cost.safetensors                    (ours, learned neural)

    python benchmarks/fresh_user_crl.py --seeds 0 1 2 --workers 2

Every train reports its greedy evaluation (return and the environment's info["cost"] per
episode); the results go to benchmarks/results/fresh_user_crl.json.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

MODULES = {
    "conveyor_arm": '''
"""A conveyor arm carrying a part from p = 0 to p = 1; a person stands at 0.35 < p < 0.65.

Actions: 0 stop, 1 slow (0.03 per step), 2 fast (0.1 per step). Every step costs 0.5 reward,
reaching p >= 1 pays 10 and ends the episode (100 steps at most). Moving fast next to the person
is forbidden: info["cost"] = 1 when the arm is in the person's zone at fast speed.
Observation and features: (p, v), v the speed just used.
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

SPEEDS = (0.0, 0.03, 0.1)


class ConveyorArm(gym.Env):
    feature_names = ("p", "v")

    def __init__(self):
        self.observation_space = spaces.Box(np.array([0.0, 0.0], np.float32), np.array([1.0, 0.1], np.float32))
        self.action_space = spaces.Discrete(3)

    def _obs(self):
        return np.array([self.p, self.v], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.v = float(self.np_random.uniform(0.0, 0.05)), 0.0
        return self._obs(), {"features": self._obs(), "cost": 0.0}

    def step(self, action):
        self.v = SPEEDS[int(action)]
        self.p = min(1.0, self.p + self.v)
        cost = float(0.35 < self.p < 0.65 and self.v > 0.05)
        done = self.p >= 1.0
        reward = -0.5 + (10.0 if done else 0.0)
        return self._obs(), reward, done, False, {"features": self._obs(), "cost": cost}


if "ConveyorArm-v0" not in gym.registry:
    gym.register("ConveyorArm-v0", entry_point=ConveyorArm, max_episode_steps=100)
''',
    "nofly_drone": '''
"""A drone flying from (-0.8, 0) to (0.8, 0) in [-1, 1]^2; a no-fly disc of radius 0.35 at the origin.

Actions: a velocity in [-1, 1]^2, times 0.1 per step. Reward: 10 x the progress towards the goal
per step, 5 on reaching it (within 0.1, which ends the episode), 60 steps at most. The straight
line crosses the disc: info["cost"] = 1 on every step inside it. Features: (x, y).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

GOAL = np.array([0.8, 0.0])


class NoFlyDrone(gym.Env):
    feature_names = ("x", "y")

    def __init__(self):
        self.observation_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = np.array([-0.8, 0.0]) + self.np_random.uniform(-0.05, 0.05, 2)
        return self.pos.astype(np.float32), {"features": self.pos.astype(np.float32), "cost": 0.0}

    def step(self, action):
        before = np.linalg.norm(self.pos - GOAL)
        self.pos = np.clip(self.pos + 0.1 * np.clip(action, -1, 1), -1.0, 1.0)
        after = np.linalg.norm(self.pos - GOAL)
        done = after < 0.1
        reward = 10.0 * (before - after) + (5.0 if done else 0.0)
        cost = float(np.linalg.norm(self.pos) < 0.35)
        obs = self.pos.astype(np.float32)
        return obs, float(reward), bool(done), False, {"features": obs, "cost": cost}


if "NoFlyDrone-v0" not in gym.registry:
    gym.register("NoFlyDrone-v0", entry_point=NoFlyDrone, max_episode_steps=60)
''',
    "boiler": '''
"""A boiler whose pressure P earns its output: reward P per step, 50 steps.

Actions: 0 vent (-0.1), 1 hold (-0.02 drift), 2 fire (+0.08), plus noise of 0.01. Pressure above
0.8 is forbidden: info["cost"] = 1 on every step with P > 0.8 (the reward keeps rising to 1).
Observation and feature: (P,).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

MOVES = (-0.1, -0.02, 0.08)


class Boiler(gym.Env):
    feature_names = ("P",)

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(3)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.P = float(self.np_random.uniform(0.2, 0.4))
        obs = np.array([self.P], np.float32)
        return obs, {"features": obs, "cost": 0.0}

    def step(self, action):
        self.P = float(np.clip(self.P + MOVES[int(action)] + self.np_random.normal(0, 0.01), 0.0, 1.0))
        obs = np.array([self.P], np.float32)
        return obs, self.P, False, False, {"features": obs, "cost": float(self.P > 0.8)}


if "Boiler-v0" not in gym.registry:
    gym.register("Boiler-v0", entry_point=Boiler, max_episode_steps=50)
''',
    "arm_angle": '''
"""A pendulum-like arm that should point at 1.2 rad but may not go past 1.0 rad.

State (theta, omega) from about 0; action a torque in [-1, 1]: omega += (15 a - 10 sin theta) 0.05,
theta += omega 0.05; reward -|theta - 1.2| per step, 100 steps. info["cost"] = 1 on every step
with |theta| > 1.0 (the target lies past the limit). Features (theta, omega).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class ArmAngle(gym.Env):
    feature_names = ("theta", "omega")

    def __init__(self):
        high = np.array([np.pi, 8.0], np.float32)
        self.observation_space = spaces.Box(-high, high)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)

    def _obs(self):
        return np.array([self.theta, self.omega], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.theta, self.omega = float(self.np_random.uniform(-0.05, 0.05)), 0.0
        return self._obs(), {"features": self._obs(), "cost": 0.0}

    def step(self, action):
        torque = float(np.clip(np.asarray(action).reshape(-1)[0], -1.0, 1.0))
        self.omega = float(np.clip(self.omega + (15.0 * torque - 10.0 * np.sin(self.theta)) * 0.05, -8.0, 8.0))
        self.theta = float(np.clip(self.theta + self.omega * 0.05, -np.pi, np.pi))
        cost = float(abs(self.theta) > 1.0)
        return self._obs(), -abs(self.theta - 1.2), False, False, {"features": self._obs(), "cost": cost}


if "ArmAngle-v0" not in gym.registry:
    gym.register("ArmAngle-v0", entry_point=ArmAngle, max_episode_steps=100)
''',
}
TASKS = {"conveyor_arm": "conveyor_arm:ConveyorArm-v0", "nofly_drone": "nofly_drone:NoFlyDrone-v0",
         "boiler": "boiler:Boiler-v0", "arm_angle": "arm_angle:ArmAngle-v0"}


def symlearn(args: list[str], cwd: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=f"{ROOT}{os.pathsep}{cwd}", OMP_NUM_THREADS="1")
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "symlearn", *args], cwd=cwd, env=env,
                          capture_output=True, text=True)
    record = {"command": "symlearn " + " ".join(args), "rc": proc.returncode,
              "seconds": round(time.perf_counter() - start, 1),
              "stderr_tail": proc.stderr[-2000:]}
    if "--json" in args and proc.returncode == 0:
        try:
            record["result"] = json.loads(proc.stdout)
        except json.JSONDecodeError:
            record["stdout_tail"] = proc.stdout[-2000:]
    else:
        record["stdout_tail"] = proc.stdout[-2000:]
    return record


def run_task(task: str, seed: int, folder: Path) -> list[dict]:
    env_id, out = TASKS[task], folder / f"{task}_s{seed}"
    out.mkdir(parents=True, exist_ok=True)
    s = ["--seed", str(seed)]
    rows = []

    def train(agent, cost_kind, extra):
        rec = symlearn(["train", "--env", env_id, *s, "--json", *extra], folder)
        rec.update(task=task, seed=seed, agent=agent, cost_kind=cost_kind)
        rows.append(rec)
        print(task, seed, agent, cost_kind, {k: rec.get("result", {}).get(k) for k in ("return", "cost")},
              rec["rc"], flush=True)
        return rec

    expert = out / "expert.safetensors"
    train("ours ppo-lag", "true", ["--algo", "ppo-lag", "-o", str(expert)])
    train("sb3-ppo-lag", "true", ["--algo", "sb3-ppo-lag"])
    train("ppo (unconstrained)", "none", ["--algo", "ppo"])
    demos, rules, cost = out / "demos.npz", out / "rules.dnf", out / "cost.safetensors"
    rows.append(dict(symlearn(["data", "record", "--env", env_id, "--policy", str(expert), *s,
                               "-o", str(demos)], folder), task=task, seed=seed, agent="record"))
    learn = symlearn(["learn", "dnf", "--env", env_id, "--demos", str(demos), "-o", str(rules)], folder)
    learn.update(task=task, seed=seed, agent="learn dnf",
                 rules=rules.read_text() if rules.exists() else None)
    rows.append(learn)
    train("ours ppo-lag", "learned DNF", ["--cost", str(rules)])
    train("sb3-ppo-lag", "learned DNF", ["--algo", "sb3-ppo-lag", "--cost", str(rules)])
    icrl = symlearn(["learn", "icrl", "--env", env_id, "--demos", str(demos), *s, "-o", str(cost)], folder)
    icrl.update(task=task, seed=seed, agent="learn icrl")
    rows.append(icrl)
    train("ours ppo-lag", "learned neural", ["--cost", str(cost)])
    return rows


def table(runs: list[dict]) -> str:
    """The markdown table of the BENCHMARKS section: mean return at mean true cost, per seed."""
    cells: dict[tuple, list] = {}
    for r in runs:
        if "cost_kind" in r and r.get("result"):
            cells.setdefault((r["task"], r["agent"], r["cost_kind"]), []).append(
                (r["seed"], r["result"]["return"], r["result"]["cost"], r["result"].get("warnings") or []))
    lines = ["| task | agent | cost kind | return at true cost (mean) | seeds: return (true cost) | warned |",
             "|---|---|---|---|---|---|"]
    for (task, agent, kind), rows in sorted(cells.items()):
        rows.sort()
        ret = sum(x[1] for x in rows) / len(rows)
        cost = sum(x[2] for x in rows) / len(rows)
        per = " / ".join(f"{x[1]:.2f} ({x[2]:g})" for x in rows)
        warned = sum(bool(x[3]) for x in rows)
        lines.append(f"| {task} | {agent} | {kind} | **{ret:.2f}** at {cost:.1f} | {per} | {warned}/{len(rows)} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--tasks", nargs="+", default=list(TASKS))
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks/results/fresh_user_crl.json")
    parser.add_argument("--keep", type=Path, default=None, help="a folder to keep the modules and files in")
    parser.add_argument("--table", action="store_true", help="print the table of --out and stop")
    args = parser.parse_args()
    if args.table:
        print(table(json.loads(args.out.read_text())["runs"]))
        return
    folder = args.keep or Path(tempfile.mkdtemp(prefix="fresh_user_crl_"))
    folder.mkdir(parents=True, exist_ok=True)
    for name, source in MODULES.items():
        (folder / f"{name}.py").write_text(source.lstrip())
    jobs = [(t, s) for s in args.seeds for t in args.tasks]
    with ThreadPoolExecutor(args.workers) as pool:
        results = [r for rows in pool.map(lambda j: run_task(*j, folder), jobs) for r in rows]
    previous = json.loads(args.out.read_text()) if args.out.exists() else {"runs": []}
    done = {(r["task"], r["seed"]) for r in results}
    kept = [r for r in previous.get("runs", []) if (r["task"], r["seed"]) not in done]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"tasks": TASKS, "runs": kept + results}, indent=1))
    print("wrote", args.out)


if __name__ == "__main__":
    main()
