"""SafeNav against Safety-Gymnasium (issue 24, section 4): task difficulty and the DNF pipeline.

Safety-Gymnasium is a *peer*, never a dependency: version 1.0.0 does not import on the project's
Python 3.11, so its episodes are recorded by ``benchmarks/safety_gym_record.py`` under a separate
Python 3.10 interpreter (``--python``) into NPZ files, and everything else runs here:

    /root/.pyenv/versions/3.10.13/bin/python -m venv /work/peers/sg310
    /work/peers/sg310/bin/pip install safety-gymnasium          # 1.0.0; pulls mujoco 2.3.3, no torch
    OMP_NUM_THREADS=1 nice -n 10 .venv/bin/python benchmarks/safety_gym_crosscheck.py \
        --python /work/peers/sg310/bin/python

Without that interpreter (or with one that cannot import safety_gymnasium) the script says so and
exits 0 having done nothing.

1. **Recording** (Point and Car, Goal level 1; SafeNav's ``point-goal`` / ``car-goal`` alike):
   ``--demos`` scripted-expert episodes to learn from (episode seeds from seed 0), ``--held-out``
   more expert episodes (seed 1), ``--random`` uniform-random-policy episodes (seed 2) and as many
   *straight* episodes (seed 3: the expert's steering aimed straight at the goal, hazards ignored,
   so that both simulators have states with cost), 1,000 steps each, on both simulators. The
   recorder writes SafeNav's 20 features; the check below recomputes their lidar part here with
   SafeNav's own ``pseudo_lidar`` from the recorded poses.
2. **Difficulty table**: random-policy cost per 1,000 steps, the scripted experts' return, cost and
   goals per episode, the simulated time per step, motion and hazard-lidar statistics.
3. **The DNF pipeline through the CLI, as a user runs it**: the expert episodes are written as a
   symlearn demonstrations NPZ (``metadata["feature_names"]``), ``symlearn learn dnf --demos
   demos.npz -o F.dnf`` at the defaults and with ``--max-depth 3`` (the SafeNav benchmarks' depth),
   then ``symlearn dnf eval F.dnf --points P.npz --json`` on the held-out expert, random and
   straight states of *both* simulators: the share flagged unsafe, the recall on the states with
   true cost (cost > 0; from the random and straight policies) and the false alarms on their safe
   states. SafeNav's formulas go through the same commands on SafeNav's data, so
   the diagonal compares like with like and the off-diagonal is the cross-transfer.

Writes ``--json`` (default ``benchmarks/results/safety_gym_crosscheck.json``, with the command and
the versions) and the learned formulas into ``--rules-dir``; prints the tables as Markdown. The
recordings stay in ``--work-dir`` (not committed; reused when their settings match, unless
``--rerecord``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
RECORDER = ROOT / "benchmarks" / "safety_gym_record.py"
SG_IDS = {"point": "SafetyPointGoal1-v0", "car": "SafetyCarGoal1-v0"}
ROBOTS = ("point", "car")
SIMS = ("safenav", "safety-gym")
SIM_LABEL = {"safenav": "SafeNav", "safety-gym": "Safety-Gymnasium"}
ROLE_SEEDS = {"demos": 0, "heldout": 1, "random": 2, "straight": 3}
ROLE_POLICY = {"demos": "expert", "heldout": "expert", "random": "random", "straight": "straight"}
EVAL_ROLES = ("heldout", "random", "straight")  # the points `dnf eval` sees, in this order
NEAR = 0.88  # the lidar threshold the SafeNav formulas learn (`d_k > 0.88`, BENCHMARKS.md)


@dataclass
class Episodes:
    """Concatenated states of several episodes, with the per-state true cost."""

    states: np.ndarray  # (N, 20), the reset state of every episode included
    costs: np.ndarray  # (N,)
    actions: np.ndarray  # (N - episodes, 2)
    rewards: np.ndarray  # (N - episodes,)
    lengths: np.ndarray  # states per episode
    returns: np.ndarray
    episode_costs: np.ndarray
    goals: np.ndarray
    dt: float
    meta: dict

    def split(self, column: np.ndarray, per_step: bool = False) -> list[np.ndarray]:
        sizes = self.lengths - 1 if per_step else self.lengths
        return np.split(column, np.cumsum(sizes)[:-1])


# --------------------------------------------------------------------------------------------------
# Safety-Gymnasium, through the peer interpreter


def peer_problem(python: str) -> str | None:
    """Why the peer interpreter cannot record (None when it can)."""
    if not Path(python).exists():
        return f"{python} does not exist"
    probe = subprocess.run([python, "-c", "import safety_gymnasium, numpy"], capture_output=True, text=True)
    if probe.returncode != 0:
        last = (probe.stderr.strip().splitlines() or ["?"])[-1]
        return f"{python} cannot import safety_gymnasium ({last})"
    return None


def record_sg(python: str, robot: str, role: str, episodes: int, work: Path, rerecord: bool) -> Episodes:
    path = work / f"sg_{robot}_{role}.npz"
    policy = ROLE_POLICY[role]
    seed = ROLE_SEEDS[role]
    if path.exists() and not rerecord:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
        if (meta["episodes"], meta["seed"], meta["policy"]) != (episodes, seed, policy):
            rerecord = True
    if rerecord or not path.exists():
        command = [python, str(RECORDER), "--env", SG_IDS[robot], "--policy", policy,
                   "--episodes", str(episodes), "--seed", str(seed), "-o", str(path)]
        print(f"recording {SG_IDS[robot]} {policy} x{episodes} ...", file=sys.stderr, flush=True)
        start = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True, env={**os.environ, "OMP_NUM_THREADS": "1"})
        if done.returncode != 0:
            raise SystemExit(f"the recorder failed:\n{done.stderr[-3000:]}")
        print(f"  {time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
    with np.load(path, allow_pickle=False) as z:
        meta = json.loads(str(z["meta"]))
        check_features(z, meta)
        return Episodes(z["states"], z["costs"], z["actions"], z["rewards"], z["lengths"], z["returns"],
                        z["episode_costs"], z["goals"], float(meta["dt"]), meta)


def check_features(z, meta: dict) -> None:
    """The recorded lidar is SafeNav's: recompute it with ``symlearn.envs.safenav.lidar.pseudo_lidar``
    from the recorded poses and hazards. Also check Safety-Gym's own lidar (centre distances, its
    body frame) and cost (centre within 0.2 of a hazard centre) against the same poses."""
    from symlearn.envs.safenav.lidar import pseudo_lidar

    poses, hazards, lengths = z["poses"], z["hazards"], z["lengths"]
    episode = np.repeat(np.arange(len(lengths)), lengths)
    offset = float(meta["sg_lidar_heading_offset"])
    ours = np.array([pseudo_lidar(x, y, h, hazards[e], 0.2) for (x, y, h), e in zip(poses, episode)])
    theirs = np.array([pseudo_lidar(x, y, h + offset, hazards[e], 0.0) for (x, y, h), e in zip(poses, episode)])
    nearest = np.array([np.hypot(*(hazards[e] - (x, y)).T).min() for (x, y, _), e in zip(poses, episode)])
    sg_difference = np.abs(theirs - z["lidar_sg"]).max(axis=1)
    meta["check"] = {"max_lidar_difference_to_safenav": float(np.abs(ours - z["states"][:, 4:]).max()),
                     "max_difference_to_sg_lidar": float(sg_difference.max()),
                     "median_difference_to_sg_lidar": float(np.median(sg_difference)),
                     "share_states_sg_lidar_differs_by_0.01": float(np.mean(sg_difference > 0.01)),
                     "cost_disagreements": int(np.sum((nearest <= 0.2) != (z["costs"] > 0)))}
    # Safety-Gym's ego frame is the body's full 3-D rotation, and the Car rocks (pitch and roll;
    # under the random policy's bang-bang wheels enough to move a reading by 0.2, in about 8 % of
    # its states by more than 0.01), so its own lidar differs from the planar one where it tilts;
    # the Point stays flat and agrees to rounding. A wrong ray order or frame would differ by
    # tenths in most states, so the typical (median) difference is what is checked.
    if (meta["check"]["max_lidar_difference_to_safenav"] > 1e-9
            or meta["check"]["median_difference_to_sg_lidar"] > 0.01):
        raise SystemExit(f"{meta['env_id']} {meta['policy']}: the recorded lidar disagrees: {meta['check']}")


# --------------------------------------------------------------------------------------------------
# SafeNav, here


def safenav_episodes(robot: str, role: str, episodes: int) -> Episodes:
    from symlearn.envs.safenav.agents import DT
    from symlearn.envs.safenav.env import SafeNavEnv
    from symlearn.envs.safenav_expert import expert_demonstrations

    seed = ROLE_SEEDS[role]
    if ROLE_POLICY[role] == "expert":
        demos = expert_demonstrations(robot, "goal", episodes, seed=seed)
        states = [np.asarray(t.states) for t in demos]
        costs = [np.array([1.0 if "hazard" in lab else 0.0 for lab in t.labels]) for t in demos]
        actions = [np.asarray(t.actions) for t in demos]
        rewards = [np.asarray(t.rewards, dtype=np.float64) for t in demos]
        goals = [t.info["goals_reached"] for t in demos]
    else:  # the uniform random policy of safenav_common.probe_points, or straight at the goal
        env = SafeNavEnv(robot, "goal")
        rng = np.random.default_rng(seed)
        states, costs, actions, rewards, goals = [], [], [], [], []
        for episode_seed in np.random.SeedSequence(seed).generate_state(episodes).tolist():
            _, info = env.reset(seed=int(episode_seed))
            xs, cs, acts, rs, done = [info["features"]], [info["cost"]], [], [], False
            while not done:
                action = rng.uniform(-1.0, 1.0, size=2) if role == "random" else straight_at_goal(env)
                _, reward, terminated, truncated, info = env.step(action)
                done = terminated or truncated
                xs.append(info["features"])
                cs.append(info["cost"])
                acts.append(action)
                rs.append(reward)
            states.append(np.array(xs))
            costs.append(np.array(cs, dtype=np.float64))
            actions.append(np.array(acts))
            rewards.append(np.array(rs))
            goals.append(env.goals_reached)
    return Episodes(np.vstack(states), np.concatenate(costs), np.vstack(actions), np.concatenate(rewards),
                    np.array([len(s) for s in states]), np.array([r.sum() for r in rewards]),
                    np.array([c.sum() for c in costs]), np.array(goals), DT, {"env": f"safenav-{robot}-goal"})


def straight_at_goal(env) -> np.ndarray:
    """The scripted expert's steering law (``SafeNavExpert._drive``) aimed straight at the goal at
    full speed, hazards ignored: the ``straight`` policy of the recorder, here."""
    state = env.state
    error = (math.atan2(env.task.goal[1] - state.y, env.task.goal[0] - state.x) - state.heading + math.pi) % (2 * math.pi) - math.pi
    forward = max(0.0, math.cos(error)) ** 3
    if env.agent_name == "point":
        return np.array([forward, np.clip(2.0 * error, -1.0, 1.0)])
    turn = float(np.clip(1.5 * error - 0.3 * state.yaw_rate, -1.0, 1.0))
    return np.clip(np.array([forward - turn, forward + turn]), -1.0, 1.0)


# --------------------------------------------------------------------------------------------------
# the difficulty table


def mean_sd(values) -> dict:
    values = np.asarray(values, dtype=np.float64)
    return {"mean": float(values.mean()), "sd": float(values.std(ddof=1)) if len(values) > 1 else 0.0}


def lidar_stats(states: np.ndarray) -> dict:
    d = states[:, 4:]
    top = d.max(axis=1)
    return {"mean": float(d.mean()), "mean_max_bin": float(top.mean()), "share_any_above_0.88": float(np.mean(top > NEAR)),
            "share_any_at_1": float(np.mean(top >= 1.0 - 1e-12)), "share_all_zero": float(np.mean(top <= 0.0))}


def motion_stats(states: np.ndarray) -> dict:
    a, v = states[:, :2], states[:, 2:4]
    return {"mean_forward_speed": float(v[:, 0].mean()), "p99_forward_speed": float(np.quantile(v[:, 0], 0.99)),
            "share_reversing": float(np.mean(v[:, 0] < 0)), "mean_abs_sideways_speed": float(np.abs(v[:, 1]).mean()),
            "share_sideways_above_1e-6": float(np.mean(np.abs(v[:, 1]) > 1e-6)),
            "p99_abs_accel": [float(np.quantile(np.abs(a[:, 0]), 0.99)), float(np.quantile(np.abs(a[:, 1]), 0.99))]}


def difficulty(expert: Episodes, random: Episodes, straight: Episodes) -> dict:
    steps = random.lengths - 1
    return {"dt": expert.dt, "episode_steps": int(np.median(expert.lengths - 1)),
            "episode_seconds": float(np.median(expert.lengths - 1) * expert.dt),
            "random_cost_per_1000_steps": mean_sd(1000 * random.episode_costs / steps),
            "random_return": mean_sd(random.returns), "random_share_states_in_hazard": float(np.mean(random.costs > 0)),
            "straight_cost_per_1000_steps": mean_sd(1000 * straight.episode_costs / (straight.lengths - 1)),
            "straight_return": mean_sd(straight.returns),
            "expert_episodes": int(len(expert.lengths)), "expert_return": mean_sd(expert.returns),
            "expert_cost": mean_sd(expert.episode_costs), "expert_goals": mean_sd(expert.goals),
            "expert_episodes_with_cost": int(np.sum(expert.episode_costs > 0)),
            "lidar_random": lidar_stats(random.states), "lidar_expert": lidar_stats(expert.states),
            "motion_random": motion_stats(random.states), "motion_expert": motion_stats(expert.states)}


def concat(a: Episodes, b: Episodes) -> Episodes:
    return Episodes(np.vstack([a.states, b.states]), np.concatenate([a.costs, b.costs]),
                    np.vstack([a.actions, b.actions]), np.concatenate([a.rewards, b.rewards]),
                    np.concatenate([a.lengths, b.lengths]), np.concatenate([a.returns, b.returns]),
                    np.concatenate([a.episode_costs, b.episode_costs]), np.concatenate([a.goals, b.goals]), a.dt, a.meta)


# --------------------------------------------------------------------------------------------------
# the DNF pipeline, through the CLI


def cli(*args: str, cwd: Path = ROOT) -> dict:
    """``symlearn ARGS --json --quiet`` in a fresh process (this checkout's package first), in ``cwd``."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)}
    done = subprocess.run([sys.executable, "-m", "symlearn", *args, "--json", "--quiet"], capture_output=True,
                          text=True, env=env, cwd=cwd)
    if done.returncode != 0:
        raise SystemExit(f"symlearn {' '.join(args)} failed ({done.returncode}):\n{done.stderr[-3000:]}")
    return json.loads(done.stdout)


def display(path: Path) -> str:
    """``path`` relative to the checkout where it lies inside it (the JSON is committed)."""
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def write_demos(episodes: Episodes, path: Path, source: str) -> None:
    """The expert episodes as a symlearn demonstrations NPZ (docs/FORMATS.md), states named by
    ``metadata["feature_names"]``, the true cost as the label ``hazard``."""
    from symlearn.data import Demonstrations, Trajectory
    from symlearn.envs.safenav.observation import FEATURE_NAMES

    states = episodes.split(episodes.states)
    costs = episodes.split(episodes.costs)
    actions = episodes.split(episodes.actions, per_step=True)
    rewards = episodes.split(episodes.rewards, per_step=True)
    trajectories = [Trajectory(s, a, r, [("hazard",) if c > 0 else () for c in cost],
                               info={"cost": float(cost.sum())})
                    for s, a, r, cost in zip(states, actions, rewards, costs)]
    Demonstrations(trajectories, metadata={"feature_names": list(FEATURE_NAMES), "source": source}).save(path)


def formula_rates(unsafe: np.ndarray, d: dict[str, Episodes]) -> dict:
    """Shares over the evaluation points, laid out as :data:`EVAL_ROLES` (see ``points_of``)."""
    parts = np.split(unsafe, np.cumsum([len(d[role].states) for role in EVAL_ROLES])[:-1])
    flagged = dict(zip(EVAL_ROLES, parts))
    costly = {role: d[role].costs > 0 for role in EVAL_ROLES}
    hit = np.concatenate([flagged[r][costly[r]] for r in ("random", "straight")])
    safe = np.concatenate([flagged[r][~costly[r]] for r in ("random", "straight")])
    return {"expert_flagged": float(flagged["heldout"].mean()), "random_flagged": float(flagged["random"].mean()),
            "straight_flagged": float(flagged["straight"].mean()),
            "recall_on_cost_states": float(hit.mean()) if hit.size else None,
            "false_alarm_on_safe_states": float(safe.mean()),
            "cost_states": int(hit.size), "expert_cost_states": int(costly["heldout"].sum())}


def dnf_pipeline(data: dict, work: Path, rules_dir: Path, depths: list[int | None]) -> dict:
    from safenav_common import unsafe_breakdown  # a sibling: this runs as a script from benchmarks/
    from symlearn.envs.safenav.observation import FEATURE_NAMES
    from symlearn.logic.dnf import load as load_dnf

    points = {}
    for (sim, robot), d in data.items():
        path = work / f"points_{sim}_{robot}.npz"
        np.savez_compressed(path, points=np.vstack([d[role].states for role in EVAL_ROLES]),
                            features=np.array(FEATURE_NAMES))
        points[sim, robot] = path
    formulas = []
    for (sim, robot), d in data.items():
        demos_path = work / f"demos_{sim}_{robot}.npz"
        write_demos(d["demos"], demos_path, f"{len(d['demos'].lengths)} scripted-expert episodes of "
                                            f"{SIM_LABEL[sim]} {robot.capitalize()}Goal1")
        for depth in depths:
            name = f"{sim}_{robot}_goal.{'default' if depth is None else f'd{depth}'}.dnf"
            out = rules_dir / name
            # From the work folder, so the formula's header names the demonstrations file, not /tmp/...
            args = ["learn", "dnf", "--demos", demos_path.name, "-o", str(out.resolve())]
            if depth is not None:
                args += ["--max-depth", str(depth)]
            learned = cli(*args, cwd=work)
            row = {"source": sim, "robot": robot, "max_depth": depth, "file": display(out),
                   "command": "symlearn " + shlex.join(args).replace(str(rules_dir.resolve()), display(rules_dir)),
                   "conjunctions": len(learned["conjunctions"]), "samples": learned["samples"],
                   "fit_seconds": learned["seconds"], "unsafe_share_of_box": learned["unsafe_share"],
                   "warnings": learned["warnings"], "on": {}}
            for target in SIMS:
                evaluated = cli("dnf", "eval", str(out), "--points", str(points[target, robot]))
                unsafe = np.asarray(evaluated["unsafe"], dtype=bool)
                row["on"][target] = formula_rates(unsafe, data[target, robot])
                # Which rules call the target's held-out expert unsafe (the SafeNav sections' diagnosis).
                row["on"][target]["expert_breakdown"] = unsafe_breakdown(load_dnf(out), data[target, robot]["heldout"].states)
            formulas.append(row)
    return {"formulas": formulas}


# --------------------------------------------------------------------------------------------------
# report


def pm(stat: dict, digits: int = 1) -> str:
    return f"{stat['mean']:.{digits}f} ± {stat['sd']:.{digits}f}"


def pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f} %"


def markdown(result: dict) -> str:
    rows = result["difficulty"]
    cols = [(robot, sim) for robot in ROBOTS for sim in SIMS]
    head = "| | " + " | ".join(f"{SIM_LABEL[s]} {r.capitalize()}Goal1" for r, s in cols) + " |"
    lines = [head, "|---|" + "---:|" * len(cols)]

    def line(label, fn):
        lines.append(f"| {label} | " + " | ".join(fn(rows[f"{s}/{r}"]) for r, s in cols) + " |")

    line("seconds per step (steps per episode)", lambda d: f"{d['dt']:.2f} ({d['episode_steps']})")
    line("random policy: cost per 1,000 steps", lambda d: pm(d["random_cost_per_1000_steps"]))
    line("random policy: return per episode", lambda d: pm(d["random_return"], 2))
    line("straight at the goal: cost per 1,000 steps", lambda d: pm(d["straight_cost_per_1000_steps"]))
    line("straight at the goal: return per episode", lambda d: pm(d["straight_return"], 2))
    line("expert: return per episode", lambda d: pm(d["expert_return"], 2))
    line("expert: goals per episode", lambda d: pm(d["expert_goals"]))
    line("expert: cost per episode (episodes with cost)",
         lambda d: f"{pm(d['expert_cost'])} ({d['expert_episodes_with_cost']}/{d['expert_episodes']})")
    for who in ("random", "expert"):
        line(f"{who}: lidar mean (all 16 bins)", lambda d, w=who: f"{d['lidar_' + w]['mean']:.3f}")
        line(f"{who}: mean of the largest bin", lambda d, w=who: f"{d['lidar_' + w]['mean_max_bin']:.3f}")
        line(f"{who}: states with a bin > 0.88", lambda d, w=who: pct(d["lidar_" + w]["share_any_above_0.88"]))
        line(f"{who}: states with a bin = 1 (touching)", lambda d, w=who: pct(d["lidar_" + w]["share_any_at_1"]))
    for who in ("random", "expert"):
        line(f"{who}: mean forward speed v_x (m/s)", lambda d, w=who: f"{d['motion_' + w]['mean_forward_speed']:.3f}")
        line(f"{who}: states reversing (v_x < 0)", lambda d, w=who: pct(d["motion_" + w]["share_reversing"]))
        line(f"{who}: mean abs sideways speed v_y", lambda d, w=who: f"{d['motion_' + w]['mean_abs_sideways_speed']:.3f}")
        line(f"{who}: 99th percentile abs a_x, a_y",
             lambda d, w=who: "{:.1f}, {:.1f}".format(*d["motion_" + w]["p99_abs_accel"]))
    out = ["\n".join(lines), ""]
    table = ["| formula (learned on) | depth | conjunctions | on | held-out expert flagged | random flagged | "
             "straight flagged | recall on cost states (n) | false alarms on safe random/straight states |",
             "|---|---|---:|---|---:|---:|---:|---:|---:|"]
    for f in result["dnf"]["formulas"]:
        for target in SIMS:
            r = f["on"][target]
            table.append(f"| {SIM_LABEL[f['source']]} {f['robot'].capitalize()}Goal | "
                         f"{'5 (default)' if f['max_depth'] is None else f['max_depth']} | {f['conjunctions']} | "
                         f"{SIM_LABEL[target]} | {pct(r['expert_flagged'])} | {pct(r['random_flagged'])} | "
                         f"{pct(r['straight_flagged'])} | {pct(r['recall_on_cost_states'])} ({r['cost_states']}) | "
                         f"{pct(r['false_alarm_on_safe_states'])} |")
    out.append("\n".join(table))
    why = ["| formula (depth 3) | on held-out expert of | flagged | by a one-atom a_* rule | v_* rule | d_* rule | "
           "only by multi-atom rules |", "|---|---|---:|---:|---:|---:|---:|"]
    for f in result["dnf"]["formulas"]:
        if f["max_depth"] != 3:
            continue
        for target in SIMS:
            b = f["on"][target]["expert_breakdown"]
            g = b["one_atom_share_by_group"]
            why.append(f"| {SIM_LABEL[f['source']]} {f['robot'].capitalize()}Goal | {SIM_LABEL[target]} | "
                       f"{pct(b['unsafe_share'])} | {pct(g.get('acceleration', 0.0))} | {pct(g.get('velocity', 0.0))} | "
                       f"{pct(g.get('lidar', 0.0))} | {pct(b['only_multi_atom_share'])} |")
    out += ["", "\n".join(why)]
    return "\n".join(out)


def versions(sg_meta: dict) -> dict:
    import symlearn

    return {"python": platform.python_version(), "numpy": np.__version__, "symlearn": symlearn.__version__,
            "peer_python": sg_meta.get("python"), "safety_gymnasium": sg_meta.get("safety_gymnasium"),
            "mujoco": sg_meta.get("mujoco"), "peer_numpy": sg_meta.get("numpy"), "machine": platform.machine(),
            "cpus": os.cpu_count()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--python", default="/work/peers/sg310/bin/python",
                        help="a Python that imports safety_gymnasium (3.10 for safety-gymnasium 1.0.0)")
    parser.add_argument("--demos", type=int, default=20, help="expert episodes to learn from (20)")
    parser.add_argument("--held-out", type=int, default=10, help="more expert episodes to evaluate on (10)")
    parser.add_argument("--random", type=int, default=10,
                        help="random-policy episodes, and as many straight-at-the-goal ones (10)")
    parser.add_argument("--work-dir", default="/tmp/symlearn-safety-gym", help="recordings, demos and points")
    parser.add_argument("--rules-dir", default=str(ROOT / "benchmarks/results/safety_gym_rules"))
    parser.add_argument("--json", default=str(ROOT / "benchmarks/results/safety_gym_crosscheck.json"))
    parser.add_argument("--rerecord", action="store_true", help="record again even when the files match")
    args = parser.parse_args(argv)

    problem = peer_problem(args.python)
    if problem:
        print(f"safety_gym_crosscheck: skipped: {problem}. Make the peer with\n"
              "  /root/.pyenv/versions/3.10.13/bin/python -m venv /work/peers/sg310 && "
              "/work/peers/sg310/bin/pip install safety-gymnasium\nand pass --python /work/peers/sg310/bin/python.")
        return 0
    from symlearn.atomic import write_text

    start = time.perf_counter()
    work, rules_dir = Path(args.work_dir), Path(args.rules_dir)
    work.mkdir(parents=True, exist_ok=True)
    rules_dir.mkdir(parents=True, exist_ok=True)
    counts = {"demos": args.demos, "heldout": args.held_out, "random": args.random, "straight": args.random}
    data = {}
    for robot in ROBOTS:
        data["safety-gym", robot] = {role: record_sg(args.python, robot, role, n, work, args.rerecord)
                                     for role, n in counts.items()}
        data["safenav", robot] = {role: safenav_episodes(robot, role, n) for role, n in counts.items()}
    recorded = time.perf_counter() - start
    result = {"command": "python benchmarks/safety_gym_crosscheck.py " + shlex.join(argv if argv is not None else sys.argv[1:]),
              "versions": versions(data["safety-gym", "point"]["demos"].meta),
              "episodes": counts, "seeds": "episode seeds: numpy SeedSequence(role seed) with demos 0, held-out 1, random 2",
              "recording_checks": {f"{robot}/{role}": data["safety-gym", robot][role].meta["check"]
                                   for robot in ROBOTS for role in counts},
              "difficulty": {f"{sim}/{robot}": difficulty(concat(data[sim, robot]["demos"], data[sim, robot]["heldout"]),
                                                          data[sim, robot]["random"], data[sim, robot]["straight"])
                             for sim in SIMS for robot in ROBOTS},
              "dnf": dnf_pipeline(data, work, rules_dir, [None, 3])}
    result["seconds"] = {"recording_and_safenav": recorded, "total": time.perf_counter() - start}
    write_text(args.json, json.dumps(result, indent=1) + "\n")
    print(markdown(result))
    print(f"\nwrote {args.json} ({result['seconds']['total']:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
