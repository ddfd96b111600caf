"""A scripted SafeNav expert, and demonstrations recorded with it (the thesis' 20 features).

The thesis samples its demonstrations from a PPO-Lagrangian agent trained with the true cost.
Training one is slow, so this module scripts an expert that *knows* the true hazard positions
(it reads them from the environment, not from the observation):

* **Planning** (:class:`GridPlanner`): a 5 cm grid over the arena, every cell weighted by its
  clearance from the hazards (inside a hazard grown by the robot's radius: 1000; within
  ``margin`` of it: up to 21; elsewhere 1); Dijkstra from the target (scipy) gives each cell its
  cost-to-go. The expert aims at a *carrot* six cells down that field from where it stands, so
  it goes around hazards with a margin instead of getting stuck in front of them.
* **Driving**: the Point turns toward the carrot (turn proportional to the heading error) and
  pushes forward by ``cos(error)^3``; the Car does the same with ``left = forward - turn``,
  ``right = forward + turn``. Near a hazard it slows down, so momentum cannot carry it in, and
  within 0.15 of a hazard's edge it drops the part of its heading that points into the hazard
  (a small shield, needed mostly while pushing, when the route is the box's, not the robot's).
* **Push** tasks: a second field plans the *box's* route to the goal, keeping the box centre (and
  so the robot trailing it) clear of the hazards; the robot walks around the box (an obstacle in
  its own field) to the point behind it on that route, then pushes. The box moves along the
  contact normal (robot -> box centre), so while pushing the robot also slides around the box
  to turn that normal onto the route (``aim = n + 2.5 sin(e) t``, ``e`` the angle from the
  route to the normal ``n``, ``t`` the tangent); if ``e`` grows past 0.6 rad it walks around again.

``noise`` adds Gaussian noise (standard deviation ``noise``) to each action entry, clipped.

:func:`expert_demonstrations` records ``n`` episodes as :class:`~symlearn.data.Demonstrations`:
states are ``info["features"]`` (the 20 features, the first one of the reset), actions the
2-D actions, rewards the environment's, labels ``{"hazard"}`` on the states inside a hazard;
each trajectory's ``info`` has its seed, total cost (states inside a hazard) and goals reached.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.expert_episode import record_episode
from symlearn.envs.safenav.agents import RADIUS
from symlearn.envs.safenav.env import SafeNavEnv
from symlearn.progress import progress

CARROT_CELLS = 6
SHIELD = 0.15  # within this of a hazard's edge, the expert never heads further in


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


class GridPlanner:
    """Cost-to-go fields on a square grid over ``[-half, half]^2`` (8-connected, ``resolution`` m)."""

    def __init__(self, half: float, resolution: float = 0.05) -> None:
        n = max(2, int(round(2 * half / resolution)))
        self.n, self.half, self.resolution = n, half, 2 * half / n
        centres = -half + (np.arange(n) + 0.5) * self.resolution
        self.cx, self.cy = np.meshgrid(centres, centres, indexing="ij")  # cell [i, j] = (x_i, y_j)
        ids = np.arange(n * n).reshape(n, n)
        us, vs, lengths = [], [], []
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
            rows_a, rows_b = slice(0, n - di), slice(di, n)
            cols_a, cols_b = (slice(0, n - dj), slice(dj, n)) if dj >= 0 else (slice(-dj, n), slice(0, n + dj))
            a, b = ids[rows_a, cols_a].ravel(), ids[rows_b, cols_b].ravel()
            us.append(a)
            vs.append(b)
            lengths.append(np.full(a.size, math.hypot(di, dj) * self.resolution))
        self._u, self._v, self._length = np.concatenate(us), np.concatenate(vs), np.concatenate(lengths)

    def cell(self, point: np.ndarray) -> tuple[int, int]:
        i = int((point[0] + self.half) / self.resolution)
        j = int((point[1] + self.half) / self.resolution)
        return min(max(i, 0), self.n - 1), min(max(j, 0), self.n - 1)

    def costs(self, centres: np.ndarray, cores: np.ndarray | float, margin: float) -> np.ndarray:
        """Cell weights: 1000 within ``cores`` of a centre, rising to 21 within ``margin`` of that, else 1."""
        if not len(centres):
            return np.ones((self.n, self.n))
        gap = np.hypot(self.cx[..., None] - centres[:, 0], self.cy[..., None] - centres[:, 1]) - cores
        clearance = gap.min(axis=-1)
        return np.where(clearance <= 0, 1000.0, 1.0 + 20.0 * np.clip(1.0 - clearance / margin, 0.0, 1.0))

    def field(self, costs: np.ndarray, target: np.ndarray) -> np.ndarray:
        """Cost-to-go of every cell to ``target``'s cell (edge weight: length x mean cell weight)."""
        weights = costs.ravel()
        graph = csr_matrix((self._length * 0.5 * (weights[self._u] + weights[self._v]), (self._u, self._v)),
                           shape=(self.n * self.n, self.n * self.n))
        i, j = self.cell(target)
        return dijkstra(graph, directed=False, indices=i * self.n + j).reshape(self.n, self.n)

    def carrot(self, field: np.ndarray, point: np.ndarray, cells: int = CARROT_CELLS) -> np.ndarray:
        """The centre of the cell ``cells`` steps of steepest descent down ``field`` from ``point``."""
        i, j = self.cell(point)
        n = self.n
        for _ in range(cells):
            best, bi, bj = field[i, j], i, j
            for a in (i - 1, i, i + 1):
                for b in (j - 1, j, j + 1):
                    if 0 <= a < n and 0 <= b < n and field[a, b] < best:
                        best, bi, bj = field[a, b], a, b
            if (bi, bj) == (i, j):
                break
            i, j = bi, bj
        return np.array([self.cx[i, j], self.cy[i, j]])


class SafeNavExpert:
    """``SafeNavExpert(env, margin=0.25, noise=0.0, rng=None)``: a policy ``observation -> action``.

    ``env`` is the (unwrapped) :class:`~symlearn.envs.safenav.env.SafeNavEnv` it drives; the
    expert reads the true robot pose, hazards, goal and box from it (see the module docstring).
    """

    def __init__(self, env: Any, margin: float = 0.25, noise: float = 0.0,
                 rng: np.random.Generator | None = None) -> None:
        self.env: SafeNavEnv = getattr(env, "unwrapped", env)
        self.margin, self.noise = margin, noise
        self.rng = rng if rng is not None else np.random.default_rng()
        half = (self.env.wall if self.env.wall is not None else self.env.extent + 0.5)
        self._robot_grid = GridPlanner(half - RADIUS)
        self._box_grid = GridPlanner(half - (self.env.task.box_radius or 0.0)) if self.env.push else None
        self._cache: dict[str, tuple[Any, np.ndarray]] = {}
        self._pushing = False

    def reset(self) -> None:
        """Forget the plans of the previous episode."""
        self._cache.clear()
        self._pushing = False

    def _field(self, name: str, grid: GridPlanner, key: Any, build) -> np.ndarray:
        cached = self._cache.get(name)
        if cached is None or not _same(cached[0], key):
            self._cache[name] = (key, build())
        return self._cache[name][1]

    def __call__(self, observation: Any = None) -> np.ndarray:
        env = self.env
        position = np.array([env.state.x, env.state.y])
        if env.push:
            angle, speed = self._push(position)
        else:
            goal = env.task.goal
            field = self._field("goal", self._robot_grid, (env.hazards, goal), lambda: self._robot_grid.field(
                self._robot_grid.costs(env.hazards, env.hazard_radius + RADIUS, self.margin), goal))
            aim = goal if np.hypot(*(goal - position)) < 0.25 else self._robot_grid.carrot(field, position)
            angle, speed = math.atan2(aim[1] - position[1], aim[0] - position[0]), self._cautious(position)
        action = self._drive(self._shield(position, angle), speed)
        if self.noise > 0:
            action = action + self.rng.normal(0.0, self.noise, size=2)
        return np.clip(action, -1.0, 1.0).astype(np.float32)

    def _shield(self, position: np.ndarray, angle: float) -> float:
        """The heading ``angle`` without its part toward any hazard closer than ``SHIELD`` (edge to centre)."""
        env = self.env
        direction = np.array([math.cos(angle), math.sin(angle)])
        for hazard in env.hazards:
            towards = hazard - position
            distance = float(np.hypot(*towards))
            if distance - env.hazard_radius < SHIELD and distance > 1e-9:
                normal = towards / distance
                inward = float(direction @ normal)
                if inward > 0:
                    direction = direction - inward * normal
                    if np.hypot(*direction) < 1e-6:
                        direction = -normal
        return math.atan2(direction[1], direction[0])

    def _cautious(self, position: np.ndarray) -> float:
        """Full speed in the open, slower within ``margin`` of a hazard."""
        env = self.env
        if not len(env.hazards):
            return 1.0
        clearance = float(np.min(np.hypot(*(env.hazards - position).T))) - env.hazard_radius - RADIUS
        return float(np.clip(0.35 + 2.5 * clearance, 0.35, 1.0))

    def _push(self, position: np.ndarray) -> tuple[float, float]:
        env, task = self.env, self.env.task
        box, goal = task.box.copy(), task.goal
        grid = self._box_grid
        route_field = self._field("box", grid, (env.hazards, goal), lambda: grid.field(
            grid.costs(env.hazards, env.hazard_radius + RADIUS, 0.6 * self.margin), goal))
        ahead = goal if np.hypot(*(goal - box)) < 0.25 else grid.carrot(route_field, box, 5)
        route_angle = math.atan2(ahead[1] - box[1], ahead[0] - box[0])
        route = np.array([math.cos(route_angle), math.sin(route_angle)])
        contact = RADIUS + task.box_radius
        to_box = box - position
        offset = float(np.hypot(*to_box))
        misalignment = abs(_wrap(math.atan2(to_box[1], to_box[0]) - route_angle))
        if self._pushing:
            self._pushing = misalignment < 0.6 and offset < contact + 0.25
        else:
            self._pushing = misalignment < 0.3 and offset < contact + 0.15
        if self._pushing:
            # The box moves along the contact normal n (robot -> box centre). Push along n and slide
            # around the box (tangent t) so that n turns toward the route: error e = angle(n, route).
            normal = to_box / max(offset, 1e-9)
            tangent = np.array([-normal[1], normal[0]])
            error = _wrap(math.atan2(normal[1], normal[0]) - route_angle)
            aim = normal + 2.5 * math.sin(error) * tangent
            return math.atan2(aim[1], aim[0]), min(0.8, self._cautious(position) + 0.2)
        behind = box - route * (contact + 0.1)
        robot = self._robot_grid
        cached = self._cache.get("behind")
        if cached is None or cached[0][0] is not env.hazards or np.hypot(*(cached[0][1] - behind)) > 0.1:
            centres = np.vstack([env.hazards, box[None, :]])
            cores = np.append(np.full(len(env.hazards), env.hazard_radius + RADIUS), contact + 0.02)
            self._cache["behind"] = ((env.hazards, behind), robot.field(robot.costs(centres, cores, self.margin),
                                                                          behind))
        field = self._cache["behind"][1]
        distance = float(np.hypot(*(behind - position)))
        aim = behind if distance < 0.15 else robot.carrot(field, position)
        return math.atan2(aim[1] - position[1], aim[0] - position[0]), min(self._cautious(position), 0.3 + distance)

    def _drive(self, angle: float, speed: float) -> np.ndarray:
        state = self.env.state
        error = _wrap(angle - state.heading)
        forward = speed * max(0.0, math.cos(error)) ** 3
        if self.env.agent_name == "point":
            return np.array([forward, np.clip(2.0 * error, -1.0, 1.0)])
        turn = float(np.clip(1.5 * error - 0.3 * state.yaw_rate, -1.0, 1.0))
        return np.array([forward - turn, forward + turn])


def _same(a: tuple, b: tuple) -> bool:
    """Same hazards object and equal target (the layout is redrawn on reset, the goal on arrival)."""
    return a[0] is b[0] and np.array_equal(a[1], b[1])


def expert_demonstrations(agent: str = "point", task: str = "goal", n: int = 10, seed: int | None = 0, *,
                          max_steps: int = 1000, noise: float = 0.0, margin: float = 0.25,
                          **env_kwargs: Any) -> Demonstrations:
    """``n`` expert episodes of ``safenav-<agent>-<task>`` (see the module docstring)."""
    env = SafeNavEnv(agent, task, max_steps=max_steps, **env_kwargs)
    seeds = np.random.SeedSequence(seed).generate_state(n).tolist()
    expert = SafeNavExpert(env, margin=margin, noise=noise, rng=np.random.default_rng(seed))
    trajectories = []
    for episode_seed in progress(seeds, total=n, desc=f"safenav-{agent}-{task} expert", unit="episode"):
        states, actions, rewards, labels, _ = record_episode(env, expert, int(episode_seed), _label, start=expert.reset)
        trajectories.append(Trajectory(states, actions, rewards, labels,
                                       info={"seed": int(episode_seed), "cost": sum(bool(lab) for lab in labels),
                                             "goals_reached": env.goals_reached}))
    metadata = {"env": f"symlearn/safenav-{agent}-{task}-v0", "expert": "scripted", "seed": seed, "n_episodes": n,
                "noise": noise, "margin": margin, "max_steps": max_steps, "features": list(env.feature_names)}
    return Demonstrations(trajectories, metadata=metadata)


def _label(info: dict[str, Any]) -> tuple[str, ...]:
    return ("hazard",) if info["cost"] > 0 else ()


__all__ = ["GridPlanner", "SafeNavExpert", "expert_demonstrations"]
