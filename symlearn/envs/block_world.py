"""A simulated block world for learning sub-goal orderings (thesis, section 6.5.1), numpy only.

Blocks start in a tray and are moved, one at a time, to target places. A *task* is a list of
placements (block -> place) with precedences (a block can go on top of another only after it)
and a preference weight per placement. A scripted demonstrator picks the next placement among
those whose precedences are met with probability proportional to its weight (a Plackett-Luce
ordering: the weights' order is the preferred ordering), carries the block along a randomised
arc and leaves it there for a few frames. A camera sees every block's xyz with Gaussian noise
and misses a block now and then (its coordinates are NaN in that frame).

Tasks: :func:`place_task` (``k`` blocks to ``k`` places, any order, 2 <= k <= 6),
:func:`stack_task` (build a stack of three, rebuild it elsewhere upside down, ...: ``3 *
rounds`` sub-goals in one forced order), :func:`sequence_task` (``n`` sub-goals spread over
``m`` objects, forced order). Each gives its ground truth: :meth:`BlockTask.truth_subgoals`
(a :class:`~symlearn.grounding.subgoals.SubGoalSet` over the frames' columns) and
:meth:`BlockTask.truth_pdfa` (the demonstrator's exact ordering distribution as a PDFA over the
same sub-goal names; its probabilities are what a learner should recover).

:class:`BlockWorld` executes plans: ``controller(subgoals)`` moves a sub-goal's block to its
centre and reports failure when the block is not detected; ``reachable`` checks detection.
Blocks can be hidden until ``n`` moves have been made (``hidden={block: n}``), to test replanning.

>>> task = place_task(3)
>>> frames, order = Demonstrator(task, seed=0).demonstration()
>>> frames.shape[1], sorted(order) == [0, 1, 2]
(9, True)
>>> round(task.truth_pdfa().most_probable_accepted()[1], 9) == round(task.preferred_probability(), 9)
True
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from symlearn.envs.ordering_truth import available, draw_order, preference_pdfa, preferred_order
from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet
from symlearn.progress import progress

COLOURS = ("red", "green", "blue", "yellow", "orange", "purple", "cyan", "pink")
BLOCK = 0.05  # edge of a block, m
TRUTH_RADIUS = 0.02  # radius of a ground-truth sub-goal, m


@dataclass(frozen=True)
class Placement:
    block: int
    place: tuple[float, float, float]


@dataclass(frozen=True)
class BlockTask:
    """Blocks, their start positions, placements, precedences and preference weights."""

    name: str
    start: tuple[tuple[float, float, float], ...]  # per block
    placements: tuple[Placement, ...]
    requires: tuple[frozenset[int], ...]  # per placement: placements that must come first
    weights: tuple[float, ...]  # per placement: Plackett-Luce preference
    blocks: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        if not self.blocks:
            object.__setattr__(self, "blocks", COLOURS[:len(self.start)])
        if not (len(self.placements) == len(self.requires) == len(self.weights)):
            raise DataError("a block task needs one precedence set and one weight per placement")
        if any(w <= 0 for w in self.weights):
            raise DataError("preference weights must be positive")

    @property
    def n_blocks(self) -> int:
        return len(self.start)

    @property
    def n_features(self) -> int:
        return 3 * self.n_blocks

    def subsets(self) -> dict[str, list[int]]:
        """The candidate feature subsets: each block's xyz."""
        return {name: [3 * b, 3 * b + 1, 3 * b + 2] for b, name in enumerate(self.blocks)}

    def subsets_text(self) -> str:
        return ";".join(f"{n}={','.join(map(str, c))}" for n, c in self.subsets().items())

    def subgoal_name(self, j: int) -> str:
        p = self.placements[j]
        same = [i for i in range(j) if self.placements[i].block == p.block]
        return f"{self.blocks[p.block]}_at_{len(same)}"

    def truth_subgoals(self) -> SubGoalSet:
        goals = [SubGoal(self.subgoal_name(j), self.blocks[p.block], (3 * p.block, 3 * p.block + 1, 3 * p.block + 2),
                         p.place, TRUTH_RADIUS) for j, p in enumerate(self.placements)]
        return SubGoalSet(goals, feature_names=self.feature_names())

    def feature_names(self) -> tuple[str, ...]:
        return tuple(f"{b}_{axis}" for b in self.blocks for axis in "xyz")

    def available(self, done: frozenset[int]) -> list[int]:
        return available(done, self.requires)

    def preferred_order(self) -> list[int]:
        """Always the heaviest available placement next (the greedy plan of the truth)."""
        return preferred_order(self.weights, self.requires)

    def preferred_probability(self) -> float:
        done: frozenset[int] = frozenset()
        p = 1.0
        for j in self.preferred_order():
            p *= self.weights[j] / sum(self.weights[i] for i in self.available(done))
            done |= {j}
        return p

    def truth_pdfa(self):
        """The demonstrator's distribution over orderings as a PDFA (states = sets done)."""
        return preference_pdfa([self.subgoal_name(j) for j in range(len(self.placements))], self.weights,
                               self.requires)


def _tray(n: int) -> tuple[tuple[float, float, float], ...]:
    return tuple((-0.25 + 0.1 * b, -0.3, BLOCK / 2) for b in range(n))


def place_task(k: int, preferred: Sequence[int] | None = None, ratio: float = 2.0,
               requires: Mapping[int, Sequence[int]] | None = None) -> BlockTask:
    """``k`` blocks to ``k`` places; ``preferred`` (default ``0..k-1``) is the preferred ordering
    of the blocks, each next one ``ratio`` times likelier than the one after it. ``requires``
    (``{block: [blocks placed before it]}``, default none: any order) limits the orderings."""
    if not 1 <= k <= len(COLOURS):
        raise DataError(f"place_task takes 1..{len(COLOURS)} blocks, got {k}")
    preferred = list(range(k)) if preferred is None else list(preferred)
    if sorted(preferred) != list(range(k)):
        raise DataError(f"preferred must be an ordering of 0..{k - 1}, got {preferred}")
    places = [(-0.2 + 0.4 * (b % 3) / 2, 0.1 + 0.15 * (b // 3), BLOCK / 2) for b in range(k)]
    weights = [0.0] * k
    for rank, b in enumerate(preferred):
        weights[b] = ratio ** (k - 1 - rank)
    requires = dict(requires or {})
    if any(not 0 <= b < k or not all(0 <= a < k and a != b for a in before) for b, before in requires.items()):
        raise DataError(f"requires must map blocks 0..{k - 1} to other blocks, got {requires}")
    task = BlockTask(f"place-{k}", _tray(k), tuple(Placement(b, places[b]) for b in range(k)),
                     tuple(frozenset(requires.get(b, ())) for b in range(k)), tuple(weights))
    task.preferred_order()  # raises when the precedences are cyclic
    return task


def stack_task(rounds: int) -> BlockTask:
    """Three blocks stacked at one place, then restacked upside down at the next place, ``rounds``
    times: ``3 * rounds`` sub-goals, each placement requiring the previous one."""
    if rounds < 1:
        raise DataError(f"stack_task needs at least one round, got {rounds}")
    placements = []
    for r in range(rounds):
        place = (-0.2 + 0.2 * (r % 3), 0.1 + 0.15 * (r // 3))
        order = [0, 1, 2] if r % 2 == 0 else [2, 1, 0]
        for level, b in enumerate(order):
            placements.append(Placement(b, (place[0], place[1], BLOCK / 2 + BLOCK * level)))
    n = len(placements)
    return BlockTask(f"stack-{rounds}", _tray(3), tuple(placements),
                     tuple(frozenset([j - 1]) if j else frozenset() for j in range(n)), (1.0,) * n)


def sequence_task(n_objects: int, n_subgoals: int) -> BlockTask:
    """``n_subgoals`` placements in a forced order, spread round-robin over ``n_objects`` blocks,
    each to a place of its own on a grid."""
    if not 1 <= n_objects <= len(COLOURS) or n_subgoals < 1:
        raise DataError(f"sequence_task takes 1..{len(COLOURS)} objects and >= 1 sub-goals")
    placements = [Placement(j % n_objects, (-0.25 + 0.1 * (j % 6), 0.05 + 0.1 * (j // 6), BLOCK / 2))
                  for j in range(n_subgoals)]
    return BlockTask(f"sequence-{n_objects}x{n_subgoals}", _tray(n_objects), tuple(placements),
                     tuple(frozenset([j - 1]) if j else frozenset() for j in range(n_subgoals)),
                     (1.0,) * n_subgoals)


class Camera:
    """Noisy detection: Gaussian noise per coordinate, a block missed with probability ``drop``."""

    def __init__(self, noise: float = 0.002, drop: float = 0.05, rng=None) -> None:
        if noise < 0 or not 0 <= drop < 1:
            raise DataError("noise must be >= 0 and drop in [0, 1)")
        self.noise, self.drop = noise, drop
        self.rng = rng if rng is not None else np.random.default_rng()

    def observe(self, positions: np.ndarray, hidden: Sequence[int] = ()) -> np.ndarray:
        """``(T, n_blocks, 3)`` or ``(n_blocks, 3)`` true positions -> flat noisy frames."""
        positions = np.asarray(positions, dtype=np.float64)
        single = positions.ndim == 2
        frames = positions[None] if single else positions
        seen = frames + self.rng.normal(0.0, self.noise, frames.shape) if self.noise else frames.copy()
        missed = self.rng.random(frames.shape[:2]) < self.drop
        missed[:, list(hidden)] = True
        seen[missed] = np.nan
        flat = seen.reshape(len(seen), -1)
        return flat[0] if single else flat


class Demonstrator:
    """The scripted demonstrator of a task (see the module doc); seeded."""

    def __init__(self, task: BlockTask, *, noise: float = 0.002, drop: float = 0.05, carry_frames: int = 8,
                 dwell: tuple[int, int] = (4, 10), seed: int | None = None) -> None:
        self.task = task
        self.rng = np.random.default_rng(seed)
        self.camera = Camera(noise, drop, self.rng)
        self.carry_frames = carry_frames
        self.dwell = dwell

    def ordering(self) -> list[int]:
        """A Plackett-Luce draw of the placements, respecting precedences."""
        return draw_order(self.task.weights, self.task.requires, self.rng)

    def demonstration(self, order: Sequence[int] | None = None) -> tuple[np.ndarray, list[int]]:
        """``(frames (T, 3 * blocks), ordering of placements)``."""
        task = self.task
        order = list(self.ordering() if order is None else order)
        position = np.asarray(task.start, dtype=np.float64)
        states = [position.copy() for _ in range(int(self.rng.integers(*self.dwell)))]
        for j in order:
            placement = task.placements[j]
            a, b = position[placement.block].copy(), np.asarray(placement.place)
            # a random arc: height and sideways bulge drawn per move, so transit frames of many
            # demonstrations spread out instead of piling up on one path
            height = self.rng.uniform(0.05, 0.25)
            side = self.rng.uniform(-0.08, 0.08)
            horizontal = (b - a)[:2]
            normal = np.array([-horizontal[1], horizontal[0], 0.0]) / (np.linalg.norm(horizontal) + 1e-12)
            for s in np.arange(1, self.carry_frames + 1) / (self.carry_frames + 1):
                bump = math.sin(math.pi * s)
                position[placement.block] = (1 - s) * a + s * b + bump * (height * np.array([0, 0, 1.0]) + side * normal)
                states.append(position.copy())
            position[placement.block] = b
            states += [position.copy() for _ in range(int(self.rng.integers(*self.dwell)))]
        states += [position.copy() for _ in range(int(self.rng.integers(*self.dwell)))]
        return self.camera.observe(np.asarray(states)), order

    def demonstrations(self, n: int) -> tuple[list[np.ndarray], list[list[int]]]:
        runs, orders = [], []
        for _ in progress(range(n), total=n, desc="block-world demonstrations"):
            frames, order = self.demonstration()
            runs.append(frames)
            orders.append(order)
        return runs, orders


class BlockWorld:
    """The world a plan is executed in: true block positions, a camera, hidden blocks."""

    def __init__(self, task: BlockTask, *, noise: float = 0.002, drop: float = 0.0, place_error: float = 0.003,
                 hidden: Mapping[int, int] | None = None, seed: int | None = None) -> None:
        self.task = task
        self.rng = np.random.default_rng(seed)
        self.camera = Camera(noise, drop, self.rng)
        self.place_error = place_error
        self.positions = np.asarray(task.start, dtype=np.float64).copy()
        self.hidden = dict(hidden or {})  # block -> moves it stays hidden for
        self.frames: list[np.ndarray] = []

    def observe(self) -> np.ndarray:
        hidden = [b for b, n in self.hidden.items() if n > 0]
        frame = self.camera.observe(self.positions, hidden)
        self.frames.append(frame)
        return frame

    def _block(self, goal: SubGoal) -> int:
        if len(goal.features) != 3 or goal.features[0] % 3 or list(goal.features) != list(
                range(goal.features[0], goal.features[0] + 3)):
            raise DataError(f"sub-goal {goal.name} is not the xyz of one block")
        return goal.features[0] // 3

    def reachable(self, subgoals: SubGoalSet):
        """``reachable(name)``: the sub-goal's block is detected in a fresh observation."""
        def check(name: str) -> bool:
            return not np.isnan(self.observe()[list(subgoals[name].features)]).any()
        return check

    def controller(self, subgoals: SubGoalSet):
        """``controller(name) -> bool``: look, and if the block is seen, put it at the sub-goal's centre."""
        def move(name: str) -> bool:
            goal = subgoals[name]
            block = self._block(goal)
            if np.isnan(self.observe()[3 * block:3 * block + 3]).any():
                return False
            self.positions[block] = np.asarray(goal.centre) + self.rng.normal(0, self.place_error, 3)
            for b in self.hidden:  # a hidden block shows up after that many moves of other blocks
                self.hidden[b] = max(0, self.hidden[b] - 1)
            return True
        return move

    def task_done(self, tolerance: float = TRUTH_RADIUS) -> bool:
        """Every block whose last placement in the task is its place ends within ``tolerance`` of it."""
        last: dict[int, tuple[float, float, float]] = {}
        for p in self.task.placements:
            last[p.block] = p.place
        return all(np.linalg.norm(self.positions[b] - np.asarray(place)) <= tolerance for b, place in last.items())
