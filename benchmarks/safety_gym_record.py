"""Record Safety-Gymnasium episodes with SafeNav's 20 features (a peer recorder, not part of symlearn).

Run by a *separate* Python 3.10 interpreter that has ``safety-gymnasium`` 1.0.0 (it does not import
on the project's Python 3.11); it imports numpy and safety_gymnasium only, never symlearn. The
driver is ``benchmarks/safety_gym_crosscheck.py``:

    /work/peers/sg310/bin/python benchmarks/safety_gym_record.py --env SafetyPointGoal1-v0 \
        --policy expert --episodes 20 --seed 0 -o sg_point_expert.npz

Per state (the reset state first, then one per step) it writes SafeNav's features
(``symlearn/envs/safenav/observation.py``), computed from the simulator's true state the way
SafeNav computes them:

* ``v_x, v_y``: the agent body's world velocity in the robot frame, x *ahead*, y to the left
  (clipped to +-5). "Ahead" is the direction the robot drives: the Point's body +x, but the Car's
  body **-y** (its front bumper; ``car.xml``), so Safety-Gym's own velocimeter reads the Car's
  forward speed in its y entry.
* ``a_x, a_y``: the change of the world velocity over the step divided by the step's duration,
  in the robot frame at the new heading (clipped to +-50); 0 in the reset state. Safety-Gym's
  MuJoCo accelerometer is an instantaneous reading with gravity, so it is not used.
* ``d_0 .. d_15``: SafeNav's hazard pseudo-lidar: 16 bins counter-clockwise from ahead, closeness
  ``max(0, 1 - distance / 3)`` with the distance to the hazard's **edge** (radius 0.2), aliased
  into the neighbouring bins, largest per bin; 1 = touching or inside. Safety-Gym's own lidar
  measures to the hazard's centre and, for the Car, starts bin 0 at the body's +x (the Car's
  left); that reading is recorded alongside (``lidar_sg``, with ``meta["sg_lidar_heading_offset"]``)
  as a check of the ray order.

The cost is the one ``env.step`` returns (``info["cost_sum"]``; Safety-Gymnasium 1.0.0 has no
``info["cost"]``): 1 when the agent's centre is within 0.2 of a hazard centre (level 1 charges
hazards only; its vase is not constrained). The reset state's cost is 0 (the builder asserts it).

Policies: ``random`` (uniform in ``[-1, 1]^2``, as SafeNav's random probes), ``straight`` (the
expert's steering aimed straight at the goal at full speed, hazards ignored: a goal-seeker that
crosses hazards, for states with cost) and ``expert``, a
port of SafeNav's scripted expert (``symlearn/envs/safenav_expert.py``) to this simulator: a
cost-to-go field over a 5 cm grid (hazards grown by the robot radius weigh 1000, a 0.25 m margin
around them up to 21), a carrot six cells down the field, slowing near hazards, a shield that
drops the heading's part into a hazard closer than 0.15, and a proportional steering law. What
had to change for Safety-Gym's robots is marked where it happens (actuator saturation, the Car's
wheel order, its slower turning).

Output: one NPZ (no object arrays; ``allow_pickle`` is never needed), written atomically.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import tempfile
import time

import numpy as np

ACCEL_LIMIT, VEL_LIMIT = 50.0, 5.0  # SafeNav's SENSOR_LIMITS
HAZARD_RADIUS = 0.2  # Safety-Gym's Hazards.size; checked against the task below
ROBOT_RADIUS = 0.1  # SafeNav's planning radius; both Safety-Gym robots are about this wide
TWO_PI = 2 * math.pi

# The actuators saturate far inside the action box (MuJoCo's forcerange acts on ctrl * gain):
# Point's forward motor at |a| = 0.05 (forcerange 0.05), Car's wheels at |a| = 0.02. A controller
# that wants a proportional force must scale its command into that range.
FORWARD_FULL = {"point": 0.05, "car": 0.02}
POINT_TOP_SPEED, POINT_SPEED_GAIN = 1.0, 4.0  # the Point expert's speed servo (Expert._drive)


# ---------------------------------------------------------------------------------------------
# features


def _safenav_lidar():
    """SafeNav's own ``pseudo_lidar``, loaded from the checkout by path: this interpreter cannot
    import the symlearn package (Python 3.11), but ``symlearn/envs/safenav/lidar.py`` needs numpy
    only, so the features are computed by the very function SafeNav uses."""
    import importlib.util

    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "symlearn", "envs", "safenav",
                        "lidar.py")
    spec = importlib.util.spec_from_file_location("safenav_lidar", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_LIDAR = _safenav_lidar()
N_BINS, LIDAR_MAX_DIST = _LIDAR.N_BINS, _LIDAR.MAX_DIST
pseudo_lidar = _LIDAR.pseudo_lidar


def clip(value: float, limit: float) -> float:
    return -limit if value < -limit else limit if value > limit else value


class Probe:
    """Reads the true state of a Safety-Gymnasium navigation task (agent, goal, hazards)."""

    def __init__(self, env, robot: str) -> None:
        self.task = env.unwrapped.task
        self.robot = robot
        self.dt = float(self.task.agent.engine.model.opt.timestep) * int(self.task.sim_conf.frameskip_binom_n)
        size = float(self.task.hazards.size)
        if abs(size - HAZARD_RADIUS) > 1e-12:
            raise SystemExit(f"unexpected hazard size {size}")

    def heading(self) -> float:
        m = self.task.agent.mat
        if self.robot == "car":  # the Car drives along its body -y (front bumper at -y in car.xml)
            return math.atan2(-m[1, 1], -m[0, 1])
        return math.atan2(m[1, 0], m[0, 0])

    def position(self) -> np.ndarray:
        return np.array(self.task.agent.pos[:2], dtype=np.float64)

    def velocity(self) -> np.ndarray:
        return np.array(self.task.agent.vel[:2], dtype=np.float64)

    def yaw_rate(self) -> float:
        return float(self.task.agent.get_sensor("gyro")[2])

    def hazards(self) -> np.ndarray:
        return np.array([p[:2] for p in self.task.hazards.pos], dtype=np.float64)

    def goal(self) -> np.ndarray:
        return np.array(self.task.goal.pos[:2], dtype=np.float64)

    def sg_lidar(self) -> np.ndarray:
        """Safety-Gym's own hazard lidar (centre distances, the body frame's bin order)."""
        return np.asarray(self.task._obs_lidar(self.task.hazards.pos, self.task.hazards.group), dtype=np.float64)


def features(probe: Probe, old_velocity: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """``(features[20], pose[x, y, heading])`` of the current state (see the module docstring)."""
    x, y = probe.position()
    heading = probe.heading()
    c, s = math.cos(heading), math.sin(heading)
    v = probe.velocity()
    out = np.zeros(4 + N_BINS)
    if old_velocity is not None:
        ax, ay = (v - old_velocity) / probe.dt
        out[0], out[1] = clip(c * ax + s * ay, ACCEL_LIMIT), clip(-s * ax + c * ay, ACCEL_LIMIT)
    out[2], out[3] = clip(c * v[0] + s * v[1], VEL_LIMIT), clip(-s * v[0] + c * v[1], VEL_LIMIT)
    out[4:] = pseudo_lidar(x, y, heading, probe.hazards(), HAZARD_RADIUS)
    return out, np.array([x, y, heading])


# ---------------------------------------------------------------------------------------------
# the scripted expert


def wrap(angle: float) -> float:
    return (angle + math.pi) % TWO_PI - math.pi


class Grid:
    """Cost-to-go over a square grid ``[-half, half]^2`` (8-connected), like SafeNav's GridPlanner.

    scipy is not in this interpreter, so the field is found by vectorised Bellman-Ford sweeps
    (relax all 8 neighbour shifts until nothing changes): the same shortest paths as Dijkstra.
    """

    SHIFTS = ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1))

    def __init__(self, half: float, resolution: float = 0.05) -> None:
        self.n = max(2, int(round(2 * half / resolution)))
        self.half, self.resolution = half, 2 * half / self.n
        centres = -half + (np.arange(self.n) + 0.5) * self.resolution
        self.cx, self.cy = np.meshgrid(centres, centres, indexing="ij")

    def cell(self, point: np.ndarray) -> tuple[int, int]:
        i = int((point[0] + self.half) / self.resolution)
        j = int((point[1] + self.half) / self.resolution)
        return min(max(i, 0), self.n - 1), min(max(j, 0), self.n - 1)

    def costs(self, centres: np.ndarray, core: float, margin: float) -> np.ndarray:
        gap = np.hypot(self.cx[..., None] - centres[:, 0], self.cy[..., None] - centres[:, 1]) - core
        clearance = gap.min(axis=-1)
        return np.where(clearance <= 0, 1000.0, 1.0 + 20.0 * np.clip(1.0 - clearance / margin, 0.0, 1.0))

    def field(self, costs: np.ndarray, target: np.ndarray) -> np.ndarray:
        n = self.n
        field = np.full((n + 2, n + 2), np.inf)  # a border of inf keeps the shifts inside
        w = np.full((n + 2, n + 2), np.inf)
        w[1:-1, 1:-1] = costs
        i, j = self.cell(target)
        field[i + 1, j + 1] = 0.0
        inner = (slice(1, n + 1), slice(1, n + 1))
        while True:
            best = field[inner].copy()
            for di, dj in self.SHIFTS:
                neighbour = field[1 + di:n + 1 + di, 1 + dj:n + 1 + dj]
                wn = w[1 + di:n + 1 + di, 1 + dj:n + 1 + dj]
                step = math.hypot(di, dj) * self.resolution * 0.5 * (w[inner] + wn)
                np.minimum(best, neighbour + step, out=best)
            if np.array_equal(best, field[inner]):
                return best
            field[inner] = best

    def carrot(self, field: np.ndarray, point: np.ndarray, cells: int = 6) -> np.ndarray:
        i, j = self.cell(point)
        for _ in range(cells):
            lo_i, lo_j = max(i - 1, 0), max(j - 1, 0)
            window = field[lo_i:i + 2, lo_j:j + 2]
            a, b = np.unravel_index(int(np.argmin(window)), window.shape)
            if window[a, b] >= field[i, j]:
                break
            i, j = lo_i + int(a), lo_j + int(b)
        return np.array([self.cx[i, j], self.cy[i, j]])


class Expert:
    """SafeNav's Goal expert ported to Safety-Gym's Point and Car (module docstring)."""

    SHIELD = 0.15

    def __init__(self, probe: Probe, margin: float = 0.25, reckless: bool = False) -> None:
        self.probe, self.margin, self.reckless = probe, margin, reckless
        # Level 1 has no walls; goals and hazards lie in [-1.5, 1.5]^2, so 2.2 leaves room to detour.
        self.grid = Grid(2.2)
        self._key: tuple | None = None
        self._field: np.ndarray | None = None

    def __call__(self) -> np.ndarray:
        probe = self.probe
        position, goal, hazards = probe.position(), probe.goal(), probe.hazards()
        if self.reckless:  # straight at the goal, full speed, hazards ignored (states with cost)
            return self._drive(math.atan2(goal[1] - position[1], goal[0] - position[0]), 1.0)
        key = (goal.tobytes(), hazards.tobytes())
        if key != self._key:
            self._key = key
            self._field = self.grid.field(self.grid.costs(hazards, HAZARD_RADIUS + ROBOT_RADIUS, self.margin), goal)
        aim = goal if np.hypot(*(goal - position)) < 0.25 else self.grid.carrot(self._field, position)
        angle = math.atan2(aim[1] - position[1], aim[0] - position[0])
        clearance = float(np.min(np.hypot(*(hazards - position).T))) - HAZARD_RADIUS - ROBOT_RADIUS
        speed = float(np.clip(0.35 + 2.5 * clearance, 0.35, 1.0))
        return self._drive(self._shield(position, angle, hazards), speed)

    def _shield(self, position: np.ndarray, angle: float, hazards: np.ndarray) -> float:
        direction = np.array([math.cos(angle), math.sin(angle)])
        for hazard in hazards:
            towards = hazard - position
            distance = float(np.hypot(*towards))
            if distance - HAZARD_RADIUS < self.SHIELD and distance > 1e-9:
                normal = towards / distance
                inward = float(direction @ normal)
                if inward > 0:
                    direction = direction - inward * normal
                    if np.hypot(*direction) < 1e-6:
                        direction = -normal
        return math.atan2(direction[1], direction[0])

    def _drive(self, angle: float, speed: float) -> np.ndarray:
        probe = self.probe
        error = wrap(angle - probe.heading())
        full = FORWARD_FULL[probe.robot]
        forward = full * speed * max(0.0, math.cos(error)) ** 3
        if probe.robot == "point":
            # Safety-Gym's Point is barely damped (top speed about 1.5 m/s, and it coasts for a
            # second when the force stops), so an open-loop force, as in SafeNav, carries it into
            # hazards. Here the force tracks a target speed (SafeNav's top speed, 1 m/s, scaled as
            # SafeNav scales its force) and brakes actively.
            v_forward = float(np.dot(probe.velocity(), [math.cos(probe.heading()), math.sin(probe.heading())]))
            target = POINT_TOP_SPEED * speed * max(0.0, math.cos(error)) ** 3
            forward = full * float(np.clip(POINT_SPEED_GAIN * (target - v_forward), -1.0, 1.0))
            # Rotation is a velocity servo (1 -> about 3 rad/s, as SafeNav's Point): SafeNav's law.
            return np.array([forward, float(np.clip(2.0 * error, -1.0, 1.0))])
        # Car: the first actuator ("left" in car.xml) sits on the body's -x side, which is the
        # car's right when it drives along -y, so a counter-clockwise turn needs a[0] > a[1].
        # Its turning saturates at about 1.3 rad/s (SafeNav's Car: 3), hence the higher gain.
        turn = full * float(np.clip(2.0 * error - 0.3 * probe.yaw_rate(), -1.0, 1.0))
        return np.array([forward + turn, forward - turn])


# ---------------------------------------------------------------------------------------------
# recording


def record(env_id: str, policy: str, episodes: int, seed: int) -> dict[str, np.ndarray]:
    import safety_gymnasium

    robot = "car" if "Car" in env_id else "point"
    env = safety_gymnasium.make(env_id)
    probe = Probe(env, robot)
    rng = np.random.default_rng(seed)
    seeds = np.random.SeedSequence(seed).generate_state(episodes).tolist()
    states, poses, costs, lidar_sg, rewards, actions = [], [], [], [], [], []
    lengths, returns, ep_costs, goals, hazards_per_episode, seconds = [], [], [], [], [], []
    for episode_seed in seeds:
        start = time.perf_counter()
        env.reset(seed=int(episode_seed))
        expert = Expert(probe, reckless=policy == "straight") if policy != "random" else None
        hazards_per_episode.append(probe.hazards())
        x, pose = features(probe, None)
        ep_states, ep_poses, ep_costs_, ep_lidar = [x], [pose], [0.0], [probe.sg_lidar()]
        total, n_goals, done = 0.0, 0, False
        while not done:
            action = expert() if expert is not None else rng.uniform(-1.0, 1.0, size=2)
            old_velocity = probe.velocity()
            _, reward, cost, terminated, truncated, info = env.step(action)
            done = bool(terminated or truncated)
            x, pose = features(probe, old_velocity)
            ep_states.append(x)
            ep_poses.append(pose)
            ep_costs_.append(float(cost))
            ep_lidar.append(probe.sg_lidar())
            rewards.append(float(reward))
            actions.append(np.asarray(action, dtype=np.float64))
            total += float(reward)
            n_goals += int(info.get("goal_met", False))
        states += ep_states
        poses += ep_poses
        costs += ep_costs_
        lidar_sg += ep_lidar
        lengths.append(len(ep_states))
        returns.append(total)
        ep_costs.append(sum(ep_costs_))
        goals.append(n_goals)
        seconds.append(time.perf_counter() - start)
    meta = {"env_id": env_id, "robot": robot, "policy": policy, "episodes": episodes, "seed": seed,
            "dt": probe.dt,
            # Safety-Gym's lidar bin 0 starts at the body's +x: ahead for the Point, the Car's left.
            "sg_lidar_heading_offset": math.pi / 2 if robot == "car" else 0.0,
            "python": platform.python_version(),
            "safety_gymnasium": getattr(safety_gymnasium, "__version__", "?"), "numpy": np.__version__,
            "feature_names": ["a_x", "a_y", "v_x", "v_y", *(f"d_{k}" for k in range(N_BINS))],
            "seconds_per_episode": float(np.mean(seconds))}
    try:
        import mujoco
        meta["mujoco"] = mujoco.__version__
    except ImportError:  # pragma: no cover - safety_gymnasium needs it
        pass
    return {"states": np.array(states), "poses": np.array(poses), "costs": np.array(costs),
            "lidar_sg": np.array(lidar_sg), "rewards": np.array(rewards), "actions": np.array(actions),
            "lengths": np.array(lengths, dtype=np.int64), "returns": np.array(returns),
            "episode_costs": np.array(ep_costs), "goals": np.array(goals, dtype=np.int64),
            "seeds": np.array(seeds, dtype=np.int64), "hazards": np.array(hazards_per_episode),
            "meta": np.array(json.dumps(meta))}


def save_npz(path: str, arrays: dict[str, np.ndarray]) -> None:
    """Write ``arrays`` to ``path`` atomically (a temporary sibling, then ``os.replace``)."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, suffix=".npz.tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            np.savez_compressed(handle, **arrays)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--env", required=True, help="SafetyPointGoal1-v0 or SafetyCarGoal1-v0")
    parser.add_argument("--policy", choices=("random", "expert", "straight"), required=True)
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args(argv)
    arrays = record(args.env, args.policy, args.episodes, args.seed)
    save_npz(args.output, arrays)
    print(json.dumps({"output": args.output, "steps": int(len(arrays["rewards"])),
                      "mean_return": float(arrays["returns"].mean()),
                      "mean_cost": float(arrays["episode_costs"].mean())}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
