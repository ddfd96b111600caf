"""A point-mass "drone" that visits three locations in a preferred order (thesis, section 6.5.2).

The world is a 10 m x 10 m x 4 m box with two box obstacles between the locations. Paths come
from a small RRT (:func:`rrt_path`: goal-biased tree over collision-free segments, then
shortcuts), flown by a point mass with a PD controller on the path's waypoints (acceleration
and speed limits). A state is the drone's xyz, observed with Gaussian noise at ``frame_every``
simulation steps (a 2 Hz position sensor by default); the only feature subset is all three
coordinates (C(F) = {F}).

The scripted demonstrator takes off at ``HOME``, visits the three ``LOCATIONS`` in a
Plackett-Luce order (weights 4 : 2 : 1 by default, so the preferred order is A, B, C) and hovers
at each for a few frames. Ground truth: :func:`truth_subgoals`, :func:`truth_pdfa`.

:class:`DroneWorld` executes plans: ``controller(subgoals)`` plans an RRT path to a sub-goal's
centre and flies it; a location can be *closed* for its first ``n`` attempts (a temporary
no-fly zone: the controller reports failure), to test replanning.

>>> frames, order = DroneDemonstrator(seed=0).demonstration()
>>> frames.shape[1], sorted(order)
(3, [0, 1, 2])
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from symlearn.envs.ordering_truth import draw_order, preference_pdfa, preferred_order
from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet
from symlearn.progress import progress

BOUNDS = (np.array([0.0, 0.0, 0.0]), np.array([10.0, 10.0, 4.0]))
OBSTACLES = ((np.array([4.0, 3.5, 0.0]), np.array([6.0, 6.5, 4.0])),  # a tower in the middle
             (np.array([7.0, 4.5, 0.0]), np.array([10.0, 5.5, 3.0])))  # a wall between A and B
HOME = (1.0, 1.0, 0.5)
LOCATIONS = ((8.5, 2.0, 2.0), (8.5, 8.0, 2.0), (2.0, 8.0, 1.5))
NAMES = ("A", "B", "C")
TRUTH_RADIUS = 0.3
DT = 0.1


def collides(point: np.ndarray, margin: float = 0.2) -> bool:
    if (point < BOUNDS[0]).any() or (point > BOUNDS[1]).any():
        return True
    return any(((point > lo - margin) & (point < hi + margin)).all() for lo, hi in OBSTACLES)


def segment_free(a: np.ndarray, b: np.ndarray, step: float = 0.1) -> bool:
    n = max(2, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)
    return not any(collides(a + s * (b - a)) for s in np.linspace(0.0, 1.0, n))


def rrt_path(start: Sequence[float], goal: Sequence[float], rng, *, step: float = 0.8, goal_bias: float = 0.15,
             max_nodes: int = 3000) -> list[np.ndarray] | None:
    """A collision-free path of waypoints from ``start`` to ``goal`` (None if none is found
    within ``max_nodes`` tree nodes, or if ``goal`` itself is blocked)."""
    start, goal = np.asarray(start, dtype=np.float64), np.asarray(goal, dtype=np.float64)
    if collides(goal) or collides(start):
        return None
    nodes = [start]
    parent = [-1]
    for _ in range(max_nodes):
        sample = goal if rng.random() < goal_bias else rng.uniform(BOUNDS[0], BOUNDS[1])
        near = int(np.argmin(np.linalg.norm(np.asarray(nodes) - sample, axis=1)))
        direction = sample - nodes[near]
        length = np.linalg.norm(direction)
        if length < 1e-9:
            continue
        new = nodes[near] + direction * min(1.0, step / length)
        if not segment_free(nodes[near], new):
            continue
        nodes.append(new)
        parent.append(near)
        if np.linalg.norm(new - goal) <= step and segment_free(new, goal):
            path = [goal]
            i = len(nodes) - 1
            while i >= 0:
                path.append(nodes[i])
                i = parent[i]
            return _shortcut(path[::-1], rng)
    return None


def _shortcut(path: list[np.ndarray], rng, tries: int = 60) -> list[np.ndarray]:
    """Random shortcuts: drop the waypoints between two that see each other."""
    for _ in range(tries):
        if len(path) <= 2:
            break
        i, j = sorted(rng.choice(len(path), 2, replace=False))
        if j - i > 1 and segment_free(path[i], path[j]):
            path = path[:i + 1] + path[j:]
    return path


def fly(position: np.ndarray, path: Sequence[np.ndarray], *, max_speed: float = 1.5, max_accel: float = 3.0,
        tolerance: float = 0.15, max_steps: int = 4000) -> list[np.ndarray]:
    """Point-mass PD flight along the waypoints; the positions of every simulation step."""
    x, v = np.asarray(position, dtype=np.float64).copy(), np.zeros(3)
    trace = []
    for k, waypoint in enumerate(path):
        last = k == len(path) - 1
        for _ in range(max_steps):
            error = waypoint - x
            if np.linalg.norm(error) < (tolerance if last else 0.4) and (not last or np.linalg.norm(v) < 0.1):
                break
            a = 2.0 * error - 2.5 * v
            a *= min(1.0, max_accel / (np.linalg.norm(a) + 1e-12))
            v = v + a * DT
            v *= min(1.0, max_speed / (np.linalg.norm(v) + 1e-12))
            x = x + v * DT
            trace.append(x.copy())
    return trace


def truth_subgoals() -> SubGoalSet:
    return SubGoalSet([SubGoal(n, "all", (0, 1, 2), c, TRUTH_RADIUS) for n, c in zip(NAMES, LOCATIONS)],
                      feature_names=("x", "y", "z"))


def truth_pdfa(weights: Sequence[float] = (4.0, 2.0, 1.0)):
    return preference_pdfa(NAMES, weights, [frozenset()] * 3)


def preferred(weights: Sequence[float] = (4.0, 2.0, 1.0)) -> list[str]:
    return [NAMES[j] for j in preferred_order(weights, [frozenset()] * 3)]


class DroneDemonstrator:
    """Scripted surveillance flights (see the module doc); seeded."""

    def __init__(self, *, weights: Sequence[float] = (4.0, 2.0, 1.0), noise: float = 0.03, frame_every: int = 5,
                 hover: tuple[int, int] = (6, 12), seed: int | None = None) -> None:
        if len(weights) != 3 or min(weights) <= 0:
            raise DataError("the drone needs three positive preference weights")
        self.weights = tuple(weights)
        self.noise, self.frame_every, self.hover = noise, frame_every, hover
        self.rng = np.random.default_rng(seed)

    def demonstration(self) -> tuple[np.ndarray, list[int]]:
        order = draw_order(self.weights, [frozenset()] * 3, self.rng)
        x = np.asarray(HOME, dtype=np.float64)
        frames = [x.copy() for _ in range(int(self.rng.integers(*self.hover)))]
        for j in order:
            path = rrt_path(x, LOCATIONS[j], self.rng)
            if path is None:  # the map is open enough that this does not happen; say so if it does
                raise DataError(f"RRT found no path to location {NAMES[j]}")
            trace = fly(x, path)
            frames += trace[self.frame_every - 1::self.frame_every]
            x = trace[-1] if trace else x
            frames += [x.copy() for _ in range(int(self.rng.integers(*self.hover)))]
        frames = np.asarray(frames)
        return frames + self.rng.normal(0.0, self.noise, frames.shape), order

    def demonstrations(self, n: int) -> tuple[list[np.ndarray], list[list[int]]]:
        pairs = [self.demonstration() for _ in progress(range(n), total=n, desc="drone demonstrations")]
        return [p[0] for p in pairs], [p[1] for p in pairs]


class DroneWorld:
    """Executing a plan: RRT + PD flight to each sub-goal; locations may be closed for a while."""

    def __init__(self, *, closed: Mapping[str, int] | None = None, seed: int | None = None) -> None:
        self.rng = np.random.default_rng(seed)
        self.position = np.asarray(HOME, dtype=np.float64)
        self.closed = dict(closed or {})  # location name -> attempts it stays closed for
        self.flown = 0.0

    def controller(self, subgoals: SubGoalSet):
        def go(name: str) -> bool:
            goal = subgoals[name]
            if len(goal.features) != 3:
                raise DataError(f"sub-goal {name} is not a drone position (x, y, z)")
            for location, n in self.closed.items():
                if n > 0 and np.linalg.norm(np.subtract(LOCATIONS[NAMES.index(location)], goal.centre)) <= 1.0:
                    self.closed[location] = n - 1
                    return False  # a no-fly zone around it for now
            path = rrt_path(self.position, goal.centre, self.rng)
            if path is None:
                return False
            trace = fly(self.position, path)
            if trace:
                self.flown += float(np.sum(np.linalg.norm(np.diff(np.vstack([self.position, trace]), axis=0), axis=1)))
                self.position = trace[-1]
            return bool(np.linalg.norm(self.position - np.asarray(goal.centre)) <= goal.radius)
        return go
