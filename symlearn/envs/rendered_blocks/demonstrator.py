"""A scripted demonstrator: one video per ordering of a task's placements, seen by both cameras.

Each demonstration waits at the start for a while, then per placement lifts the block, carries it
along an arc (random height and number of frames) and lowers it onto its goal with a small
placement error, and waits again. Waiting is what makes sub-goals dense in feature space (the
thesis' premise: sub-goals are visited more often than the states between them). Every frame is
rendered by the front camera (what a learner infers the machine from) and the top-down camera
(the policy's view, for the place network's prototypes), with independent lighting jitter and
noise drawn from ``seed``. Frames carry the ground-truth proposition (none while a block moves) as
their label, for measuring a learner, never for learning.

>>> demos = demonstrations("stack-2", seed=0)
>>> len(demos.front), demos.front.state_kind, demos.front[0].states.shape[1:]
(1, 'image', (64, 64, 3))
>>> sorted(set().union(*demos.front[0].labels))
['at_red', 'at_start']
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.rendered_blocks.render import PALETTE, TABLE, WALL, Lighting, front_view, top_down_view
from symlearn.envs.rendered_blocks.tasks import TASKS, BlockTask
from symlearn.envs.rendered_blocks.world import BLOCK
from symlearn.errors import DataError


@dataclass(frozen=True)
class Script:
    """Timing of the scripted demonstrator (frames)."""

    wait: tuple[int, int] = (10, 14)  # frames at the start and after each placement, low..high
    carry: tuple[int, int] = (6, 9)  # frames in the air per placement
    arc: tuple[float, float] = (1.2, 2.2)  # arc height, in blocks
    placement_error: float = 0.005  # table units (standard deviation): a precise scripted robot


@dataclass(frozen=True)
class Cameras:
    """How the frames are drawn (sizes, colours, jitter)."""

    front_size: int = 64
    top_size: int = 48
    lighting: Lighting = field(default_factory=Lighting)
    palette: dict = field(default_factory=lambda: dict(PALETTE))
    table: tuple = TABLE
    wall: tuple = WALL


@dataclass(frozen=True)
class BlockDemonstrations:
    """The same demonstrations seen by the front camera and from above (same frames, same labels)."""

    task: BlockTask
    front: Demonstrations
    top: Demonstrations
    configurations: tuple[np.ndarray, ...]  # per demonstration: configuration index per frame, -1 in the air


def _episode(task: BlockTask, order, rng: np.random.Generator, script: Script):
    """Positions ``(T, n, 3)`` (level may be fractional in the air), lifts ``(T, n)``."""
    world = task.world()
    positions, lifts = [], []

    def wait():
        for _ in range(rng.integers(script.wait[0], script.wait[1] + 1)):
            positions.append(world.positions())
            lifts.append(np.zeros(len(task.blocks)))

    wait()
    for p in order:
        placement = task.placements[p]
        i = placement.block
        start = world.state[i].copy()
        goal = np.array(placement.goal, dtype=float)
        goal[:2] += rng.normal(0.0, script.placement_error, size=2)
        steps = int(rng.integers(script.carry[0], script.carry[1] + 1))
        height = rng.uniform(*script.arc) * BLOCK
        for k in range(1, steps + 1):
            t = k / (steps + 1)
            smooth = t * t * (3 - 2 * t)
            frame = world.positions()
            frame[i, :2] = (1 - smooth) * start[:2] + smooth * goal[:2]
            frame[i, 2] = (1 - smooth) * start[2] + smooth * goal[2]
            lift = np.zeros(len(task.blocks))
            lift[i] = height * np.sin(np.pi * t)
            positions.append(frame)
            lifts.append(lift)
        world.state[i] = goal
        wait()
    return np.asarray(positions), np.asarray(lifts)


def demonstrations(task: str | BlockTask, seed: int = 0, *, orderings=None, script: Script = Script(),
                   cameras: Cameras = Cameras()) -> BlockDemonstrations:
    """One demonstration per ordering of ``task`` (Table 7.1's counts), rendered with ``seed``'s noise."""
    if isinstance(task, str):
        if task not in TASKS:
            raise DataError(f"unknown block task {task!r}", hint="tasks: " + ", ".join(TASKS))
        task = TASKS[task]
    rng = np.random.default_rng(seed)
    front, top, configs = [], [], []
    for order in (task.orderings() if orderings is None else orderings):
        positions, lifts = _episode(task, order, rng, script)
        names = [name for name, _, _ in task.blocks]
        front_frames, top_frames, labels, config = [], [], [], []
        for pos, lift in zip(positions, lifts):
            raised = {i: float(h) for i, h in enumerate(lift) if h > 0}
            front_frames.append(front_view(names, pos, size=cameras.front_size, lift=raised, palette=cameras.palette,
                                           table=cameras.table, wall=cameras.wall, lighting=cameras.lighting, rng=rng))
            top_frames.append(top_down_view(names, pos, size=cameras.top_size, lift=raised, palette=cameras.palette,
                                            table=cameras.table, lighting=cameras.lighting, rng=rng))
            effective = pos.copy()
            effective[:, 2] += lift / BLOCK
            k = task.configuration_of(effective) if not raised else None
            labels.append([] if k is None else [task.proposition(task.configurations()[k])])
            config.append(-1 if k is None else k)
        info = {"task": task.name, "ordering": [int(p) for p in order], "seed": int(seed)}
        front.append(Trajectory(np.asarray(front_frames), labels=labels, info={**info, "view": "front"}))
        top.append(Trajectory(np.asarray(top_frames), labels=labels, info={**info, "view": "top"}))
        configs.append(np.asarray(config))
    meta = {"env": f"rendered-blocks-{task.name}", "task": task.name, "seed": int(seed)}
    return BlockDemonstrations(task, Demonstrations(front, metadata={**meta, "view": "front"}),
                               Demonstrations(top, metadata={**meta, "view": "top"}), tuple(configs))


__all__ = ["BlockDemonstrations", "Cameras", "Script", "demonstrations"]
