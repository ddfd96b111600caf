"""Issue 24, fresh user modules: constrained RL at the defaults on tasks nobody tuned on.

Writes gymnasium user modules to a temporary folder -- round 1 (the default): a conveyor arm, a
drone with a no-fly disc, a boiler, an arm with an angle limit; round 2 (``--round 2``): a grid
with a lava column, a cart under a speed limit, a point mass round a hazard bar, a rover whose
boost overdraws a low battery -- and runs, per task and seed, the commands a user would, at their
defaults:

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
    python benchmarks/fresh_user_crl.py --round 2 --seeds 0 1 2 --workers 2

Every train reports its greedy evaluation (return and the environment's info["cost"] per
episode); our runs also write ``--log`` (which changes nothing in training) and keep its
per-iteration history (``history``: what train's warnings read). The results go to
benchmarks/results/fresh_user_crl.json (round 1) or fresh_user_crl_round2.json (round 2).
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

# Round 2 (--round 2): four more kinds -- a discrete grid with lava, a speed limit, a point with
# inertia round a hazard bar, a battery whose cost is an action -- written for the second pass.
MODULES_ROUND2 = {
    "lava_grid": '''
"""A 7 x 7 grid walk from (0, 3) to (6, 3) across a lava column at x = 3, y = 1..5.

Actions: 0 left, 1 right, 2 down, 3 up (one cell; off the grid stays). Every step costs 0.5
reward, reaching the goal pays 10 and ends the episode (40 steps at most). Stepping on lava does
not end the episode but is forbidden: info["cost"] = 1 on every step that ends on a lava cell.
The straight route (6 steps, one of them on lava) earns 7.0; the detour through (3, 0) or (3, 6)
(12 steps) earns 4.0. Observation and features: (x, y).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

MOVES = ((-1, 0), (1, 0), (0, -1), (0, 1))
GOAL = (6, 3)


class LavaGrid(gym.Env):
    feature_names = ("x", "y")

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 6.0, (2,), np.float32)
        self.action_space = spaces.Discrete(4)

    def _obs(self):
        return np.array([self.x, self.y], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.y = 0, 3
        return self._obs(), {"features": self._obs(), "cost": 0.0}

    def step(self, action):
        dx, dy = MOVES[int(action)]
        self.x, self.y = min(6, max(0, self.x + dx)), min(6, max(0, self.y + dy))
        done = (self.x, self.y) == GOAL
        cost = float(self.x == 3 and 1 <= self.y <= 5)
        reward = -0.5 + (10.0 if done else 0.0)
        return self._obs(), reward, done, False, {"features": self._obs(), "cost": cost}


if "LavaGrid-v0" not in gym.registry:
    gym.register("LavaGrid-v0", entry_point=LavaGrid, max_episode_steps=40)
''',
    "speed_cart": '''
"""A cart driven from x = 0 to a dock at x = 1 under a speed limit of 0.04 per step.

Action: a throttle in [-1, 1]: v += 0.01 a (v clipped to [-0.1, 0.1]), x += v. Every step costs
0.2 reward, reaching x >= 1 pays 10 and ends the episode (100 steps at most). Driving faster than
0.04 per step is forbidden: info["cost"] = 1 on every step with v > 0.04. Full throttle docks in
16 steps (7.0 at cost 11); held at the limit it takes 28 (4.7 at cost 0).
Observation and features: (x, v).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class SpeedCart(gym.Env):
    feature_names = ("x", "v")

    def __init__(self):
        self.observation_space = spaces.Box(np.array([-0.5, -0.1], np.float32), np.array([1.0, 0.1], np.float32))
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)

    def _obs(self):
        return np.array([self.x, self.v], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.v = float(self.np_random.uniform(0.0, 0.05)), 0.0
        return self._obs(), {"features": self._obs(), "cost": 0.0}

    def step(self, action):
        throttle = float(np.clip(np.asarray(action).reshape(-1)[0], -1.0, 1.0))
        self.v = float(np.clip(self.v + 0.01 * throttle, -0.1, 0.1))
        self.x = float(max(-0.5, self.x + self.v))
        done = self.x >= 1.0
        reward = -0.2 + (10.0 if done else 0.0)
        cost = float(self.v > 0.04)
        return self._obs(), reward, done, False, {"features": self._obs(), "cost": cost}


if "SpeedCart-v0" not in gym.registry:
    gym.register("SpeedCart-v0", entry_point=SpeedCart, max_episode_steps=100)
''',
    "hazard_point": '''
"""A point mass with inertia from (0, -0.8) to a goal at (0, 0.8); a hazard bar lies between.

Action: a force in [-1, 1]^2: v = 0.8 v + 0.02 a, position += v (clipped to [-1, 1]^2). Reward:
minus the distance to the goal every step (80 steps, no early end), so every step spent on a
detour costs. The bar |x| < 0.6, |y| < 0.1 is a hazard: info["cost"] = 1 on every step inside it.
Straight at the goal: -17.9 at cost 2.4; a scripted detour round the bar's end -27.2 at cost 0.
Observation (x, y, vx, vy); features (x, y).
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

GOAL = np.array([0.0, 0.8])


class HazardPoint(gym.Env):
    feature_names = ("x", "y")

    def __init__(self):
        self.observation_space = spaces.Box(np.array([-1, -1, -0.2, -0.2], np.float32),
                                            np.array([1, 1, 0.2, 0.2], np.float32))
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)

    def _obs(self):
        return np.concatenate([self.pos, self.vel]).astype(np.float32)

    def _features(self):
        return self.pos.astype(np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = np.array([0.0, -0.8]) + self.np_random.uniform(-0.05, 0.05, 2)
        self.vel = np.zeros(2)
        return self._obs(), {"features": self._features(), "cost": 0.0}

    def step(self, action):
        self.vel = 0.8 * self.vel + 0.02 * np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1, 1)
        self.pos = np.clip(self.pos + self.vel, -1.0, 1.0)
        reward = -float(np.linalg.norm(self.pos - GOAL))
        cost = float(abs(self.pos[0]) < 0.6 and abs(self.pos[1]) < 0.1)
        return self._obs(), reward, False, False, {"features": self._features(), "cost": cost}


if "HazardPoint-v0" not in gym.registry:
    gym.register("HazardPoint-v0", entry_point=HazardPoint, max_episode_steps=80)
''',
    "boost_rover": '''
"""A rover with a battery driving 1.0 along a track; boosting on a low battery is forbidden.

Actions: 0 wait, 1 drive (0.02 forward, 0.015 battery), 2 boost (0.05 forward, 0.03 battery);
the battery starts at 1 and an empty one moves nothing. Reward: 10 x the progress per step, -0.3
per step, 5 on reaching the end (which ends the episode), 60 steps at most. Boosting with the
battery under 0.6 overdraws it: info["cost"] = 1 on such a step. Boosting while the battery
allows and then driving earns 6.2 at cost 0; boosting throughout 8.9 at cost 6; driving only -0.1.
Observation (x, battery); features (x, battery, boost) -- boost 1 on a boost step.
"""
import gymnasium as gym
import numpy as np
from gymnasium import spaces

MOVES = ((0.0, 0.0), (0.02, 0.015), (0.05, 0.03))


class BoostRover(gym.Env):
    feature_names = ("x", "battery", "boost")

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Discrete(3)

    def _obs(self):
        return np.array([self.x, self.battery], np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.battery = float(self.np_random.uniform(0.0, 0.02)), 1.0
        return self._obs(), {"features": np.array([self.x, self.battery, 0.0], np.float32), "cost": 0.0}

    def step(self, action):
        forward, drain = MOVES[int(action)]
        cost = float(int(action) == 2 and self.battery < 0.6)
        if self.battery >= drain:
            before = self.x
            self.x = min(1.0, self.x + forward)
            self.battery = max(0.0, self.battery - drain)
            progress = self.x - before
        else:
            progress = 0.0
        done = self.x >= 1.0
        reward = 10.0 * progress - 0.3 + (5.0 if done else 0.0)
        features = np.array([self.x, self.battery, float(int(action) == 2)], np.float32)
        return self._obs(), float(reward), bool(done), False, {"features": features, "cost": cost}


if "BoostRover-v0" not in gym.registry:
    gym.register("BoostRover-v0", entry_point=BoostRover, max_episode_steps=60)
''',
}
TASKS_ROUND2 = {"lava_grid": "lava_grid:LavaGrid-v0", "speed_cart": "speed_cart:SpeedCart-v0",
                "hazard_point": "hazard_point:HazardPoint-v0", "boost_rover": "boost_rover:BoostRover-v0"}


ALL_TASKS = {**TASKS, **TASKS_ROUND2}


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


#: the per-iteration columns kept of our runs' --log (what train's warnings read), rounded
HISTORY_COLUMNS = ("iteration", "steps", "episodes", "mean_return", "mean_length", "true_cost",
                   "cost_estimate_0", "multipliers_0", "return_scales_0")


def history(log: Path) -> dict | None:
    """The CSV log of one of our runs as columns of numbers (None for an empty cell)."""
    if not log.exists():
        return None
    import csv

    with log.open() as f:
        rows = list(csv.DictReader(f))
    return {c: [None if not r.get(c) else round(float(r[c]), 4) for r in rows] for c in HISTORY_COLUMNS}


def run_task(task: str, seed: int, folder: Path, peers: bool = True, variant: tuple[str, ...] = (),
             dnf_only: bool = False, true_only: bool = False) -> list[dict]:
    env_id, out = ALL_TASKS[task], folder / f"{task}_s{seed}{'_variant' if variant else ''}"
    out.mkdir(parents=True, exist_ok=True)
    s = ["--seed", str(seed)]
    rows = []

    def train(agent, cost_kind, extra):
        log = out / f"{agent.split()[0]}_{cost_kind.replace(' ', '_')}.csv"
        ours = agent.startswith("ours")   # --log changes nothing in training: it keeps the history train's warnings read
        mine = [*variant, "--log", str(log)] if ours else []
        rec = symlearn(["train", "--env", env_id, *s, "--json", *extra, *mine], folder)
        rec.update(task=task, seed=seed, agent=agent, cost_kind=cost_kind)
        if ours:
            rec["history"] = history(log)
        rows.append(rec)
        print(task, seed, agent, cost_kind, {k: rec.get("result", {}).get(k) for k in ("return", "cost")},
              rec["rc"], flush=True)
        return rec

    expert = out / "expert.safetensors"
    if not dnf_only:   # --dnf-only: the expert and its demonstrations of an earlier run (--keep)
        train("ours ppo-lag", "true", ["--algo", "ppo-lag", "-o", str(expert)])
        if peers:
            train("sb3-ppo-lag", "true", ["--algo", "sb3-ppo-lag"])
            train("ppo (unconstrained)", "none", ["--algo", "ppo"])
        if true_only:   # --true-only: the environment's own cost, nothing learned
            return rows
    demos, rules, cost = out / "demos.npz", out / "rules.dnf", out / "cost.safetensors"
    if not dnf_only:
        rows.append(dict(symlearn(["data", "record", "--env", env_id, "--policy", str(expert), *s,
                                   "-o", str(demos)], folder), task=task, seed=seed, agent="record"))
    learn = symlearn(["learn", "dnf", "--env", env_id, "--demos", str(demos), "-o", str(rules)], folder)
    if learn["rc"] and "--states features" in learn["stderr_tail"]:
        # the environment's features are not its observation: what the refusal tells the user to do
        demos_f = out / "demos_features.npz"
        rows.append(dict(symlearn(["data", "record", "--env", env_id, "--policy", str(expert), *s,
                                   "--states", "features", "-o", str(demos_f)], folder),
                         task=task, seed=seed, agent="record --states features"))
        learn = symlearn(["learn", "dnf", "--env", env_id, "--demos", str(demos_f), "-o", str(rules)], folder)
    learn.update(task=task, seed=seed, agent="learn dnf",
                 rules=rules.read_text() if rules.exists() else None)
    rows.append(learn)
    train("ours ppo-lag", "learned DNF", ["--cost", str(rules)])
    if peers:
        train("sb3-ppo-lag", "learned DNF", ["--algo", "sb3-ppo-lag", "--cost", str(rules)])
    if dnf_only:
        return rows
    icrl = symlearn(["learn", "icrl", "--env", env_id, "--demos", str(demos), *s, "-o", str(cost)], folder)
    icrl.update(task=task, seed=seed, agent="learn icrl")
    rows.append(icrl)
    train("ours ppo-lag", "learned neural", ["--cost", str(cost)])
    return rows


def new_warning(record: dict) -> str | None:
    """Whether :func:`symlearn.rl.ppo.limit_check`'s safe-but-not-useful check fires on one of our
    runs' recorded history (what train --log kept), with the code of today: ``"gave up"``,
    ``"nothing"`` or None -- runs made before the check existed are read with it too."""
    from symlearn.rl.ppo import PPOIteration
    from symlearn.rl.ppo.limit_check import MIN_WINDOW, _gave_up_reward

    cols, result = record.get("history"), record.get("result") or {}
    if not cols or not cols.get("multipliers_0") or cols["multipliers_0"][0] is None:
        return None
    nan = float("nan")
    rows = [PPOIteration(iteration=int(i), steps=0, episodes=int(e or 0),
                         mean_return=nan if r is None else r, mean_length=nan if n is None else n, mean_cost=(nan,),
                         multipliers=(m,), policy_loss=0.0, value_loss=0.0, cost_value_loss=(0.0,), entropy=0.0,
                         approx_kl=0.0, clip_fraction=0.0, explained_variance=0.0, epochs=0.0, stopped_early=False,
                         learning_rate=0.0, steps_per_second=0.0, seconds=0.0, cost_estimate=(c,))
            for i, e, r, n, m, c in zip(cols["iteration"], cols["episodes"], cols["mean_return"], cols["mean_length"],
                                        cols["multipliers_0"], cols["cost_estimate_0"]) if c is not None]
    window = rows[-max(MIN_WINDOW, len(rows) // 3):]
    limit = result.get("cost_limit") or 0.0
    floor = 1.0 if "--cost-scale-floor 1" in record.get("command", "") else 0.01
    found = _gave_up_reward(rows, window, [limit], floor)
    return None if not found else ("gave up" if "gave up" in found[0] else "nothing")


def table(runs: list[dict]) -> str:
    """The markdown table of the BENCHMARKS section: mean return at mean true cost, per seed; our
    runs' "safe, not useful" column is :func:`new_warning` on their recorded histories."""
    cells: dict[tuple, list] = {}
    for r in runs:
        if "cost_kind" in r and r.get("result"):
            cells.setdefault((r["task"], r["agent"], r["cost_kind"]), []).append(
                (r["seed"], r["result"]["return"], r["result"]["cost"], r["result"].get("warnings") or [],
                 (new_warning(r) if r.get("history") else "n/a") if r["agent"].startswith("ours") else None))
    lines = ["| task | agent | cost kind | return at true cost (mean) | seeds: return (true cost) | warned | "
             "safe, not useful |", "|---|---|---|---|---|---|---|"]
    for (task, agent, kind), rows in sorted(cells.items()):
        rows.sort(key=lambda x: x[0])
        ret = sum(x[1] for x in rows) / len(rows)
        cost = sum(x[2] for x in rows) / len(rows)
        per = " / ".join(f"{x[1]:.2f} ({x[2]:g})" for x in rows)
        warned = sum(bool(x[3]) for x in rows)
        # "n/a": a row recorded before histories were kept (the first pass's JSON)
        flagged = ("n/a" if all(x[4] == "n/a" for x in rows) else
                   ", ".join(f"s{x[0]} {x[4]}" for x in rows if x[4] and x[4] != "n/a")) if agent.startswith("ours") else ""
        flagged = flagged or ("-" if agent.startswith("ours") else "")
        lines.append(f"| {task} | {agent} | {kind} | **{ret:.2f}** at {cost:.1f} | {per} | {warned}/{len(rows)} | "
                     f"{flagged} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--round", type=int, choices=(1, 2), default=1,
                        help="1: the first four tasks (fresh_user_crl.json); 2: the second four (..._round2.json)")
    parser.add_argument("--tasks", nargs="+", default=None, help="some of the round's tasks (default: all)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--variant", default="", metavar="FLAGS",
                        help="flags added to every one of our train commands, the expert's too (e.g. "
                             "'--cost-scale-floor 1': what a user would get were they the default); implies --ours-only")
    parser.add_argument("--dnf-only", action="store_true",
                        help="with --keep FOLDER of an earlier run: only record (features), learn dnf and the "
                             "learned-DNF trains, from that run's experts")
    parser.add_argument("--true-only", action="store_true",
                        help="only our train on the environment's own cost (no record, learn, learned costs); "
                             "with --variant: that variant's true-cost rows")
    parser.add_argument("--ours-only", action="store_true",
                        help="skip the peers' and plain PPO's runs (a rerun of our rows; their old rows are kept)")
    parser.add_argument("--out", type=Path, default=None,
                        help="default benchmarks/results/fresh_user_crl.json (round 1) or fresh_user_crl_round2.json")
    parser.add_argument("--keep", type=Path, default=None, help="a folder to keep the modules and files in")
    parser.add_argument("--table", action="store_true", help="print the table of --out and stop")
    args = parser.parse_args()
    tasks = TASKS if args.round == 1 else TASKS_ROUND2
    args.tasks = args.tasks or list(tasks)
    unknown = [t for t in args.tasks if t not in tasks]
    if unknown:
        parser.error(f"round {args.round} has no task {unknown[0]!r} (it has {', '.join(tasks)})")
    args.out = args.out or ROOT / "benchmarks/results" / (
        "fresh_user_crl.json" if args.round == 1 else "fresh_user_crl_round2.json")
    if args.table:
        print(table(json.loads(args.out.read_text())["runs"]))
        return
    folder = args.keep or Path(tempfile.mkdtemp(prefix="fresh_user_crl_"))
    folder.mkdir(parents=True, exist_ok=True)
    for name, source in {**MODULES, **MODULES_ROUND2}.items():
        (folder / f"{name}.py").write_text(source.lstrip())
    jobs = [(t, s) for s in args.seeds for t in args.tasks]
    with ThreadPoolExecutor(args.workers) as pool:
        variant = tuple(args.variant.split())
        results = [r for rows in pool.map(lambda j: run_task(*j, folder, not (args.ours_only or variant), variant,
                                                             args.dnf_only, args.true_only), jobs)
                   for r in rows]
    previous = json.loads(args.out.read_text()) if args.out.exists() else {"runs": []}
    # a rerun replaces the rows it made (by task, seed, agent and cost); --ours-only keeps the peers' old rows
    done = {(r["task"], r["seed"], r["agent"], r.get("cost_kind")) for r in results}
    kept = [r for r in previous.get("runs", [])
            if (r["task"], r["seed"], r["agent"], r.get("cost_kind")) not in done]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"tasks": tasks, "runs": kept + results}, indent=1))
    print("wrote", args.out)


if __name__ == "__main__":
    main()
