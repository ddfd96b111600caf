"""Gymnasium's Reacher (v5, MuJoCo) as a sub-goal task (thesis, section 6.5.3), with an IK + PD controller.

Four sub-goals for the fingertip: ``+x``, ``+y``, ``-x``, ``-y`` at :data:`RADIUS` from the
arm's base. A scripted demonstrator starts with the arm stretched along +x, goes to ``+x``
and then round the circle counter-clockwise (``+y``, ``-x``, ``-y``) with probability ``p_ccw``,
clockwise otherwise, holding each sub-goal for a few frames. A state is the fingertip's
``(x, y)`` (C(F) = {F}); the thesis uses an RL policy as the low-level controller, here an
analytic two-link inverse kinematics (link lengths read from the model) with a PD law on the
joint angles, clipped to Reacher's torque range, drives the fingertip to a sub-goal.

Needs the ``mujoco`` extra (``pip install symlearn[mujoco]``); without it
:class:`~symlearn.errors.MissingDependencyError` says so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet
from symlearn.progress import progress

RADIUS = 0.12
NAMES = ("px", "py", "nx", "ny")
CENTRES = ((RADIUS, 0.0), (0.0, RADIUS), (-RADIUS, 0.0), (0.0, -RADIUS))
CCW = (0, 1, 2, 3)
CW = (0, 3, 2, 1)
TRUTH_RADIUS = 0.02


def make_reacher(seed: int | None = None):
    """An unwrapped ``Reacher-v5`` reset with ``seed`` (no time limit: plans take longer than 50 steps)."""
    from symlearn.optional import require

    require("mujoco", "the Reacher sub-goal task")
    import gymnasium as gym

    env = gym.make("Reacher-v5").unwrapped
    env.reset(seed=seed)
    return env


def fingertip(env) -> np.ndarray:
    return np.array(env.get_body_com("fingertip")[:2], dtype=np.float64)  # a copy: MuJoCo reuses the buffer


def link_lengths(env) -> tuple[float, float]:
    """Upper arm = body1's offset from body0; forearm = the fingertip's offset from body1."""
    model = env.model
    import mujoco

    body1 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "body1")
    tip = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "fingertip")
    return float(np.linalg.norm(model.body_pos[body1][:2])), float(np.linalg.norm(model.body_pos[tip][:2]))


def inverse_kinematics(point: Sequence[float], lengths: tuple[float, float], elbow: float = 1.0) -> tuple[float, float]:
    """Joint angles putting a two-link arm's tip at ``point`` (``elbow`` = +1 or -1 picks the branch)."""
    x, y = point
    l1, l2 = lengths
    d2 = x * x + y * y
    c = (d2 - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    if not -1.0 <= c <= 1.0:
        raise DataError(f"({x:.3f}, {y:.3f}) is out of the arm's reach ({abs(l1 - l2):.3f} .. {l1 + l2:.3f})")
    q2 = elbow * math.acos(c)
    q1 = math.atan2(y, x) - math.atan2(l2 * math.sin(q2), l1 + l2 * math.cos(q2))
    return q1, q2


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def reach(env, point: Sequence[float], *, hold: int = 0, tolerance: float = 0.01, max_steps: int = 150,
          kp: float = 3.0, kd: float = 0.15, lengths: tuple[float, float] | None = None) -> tuple[bool, list[np.ndarray]]:
    """Drive the fingertip to ``point`` with IK + PD, then hold it ``hold`` steps.

    Returns ``(reached, fingertip positions of every step)``. The target joint angles nearest the
    current ones (both elbow branches tried) avoid a needless swing of the elbow.
    """
    lengths = lengths or link_lengths(env)
    q = env.data.qpos[:2].copy()
    options = [inverse_kinematics(point, lengths, e) for e in (1.0, -1.0)]
    goal = min(options, key=lambda o: abs(_wrap(o[0] - q[0])) + abs(_wrap(o[1] - q[1])))
    trace, settled = [], 0
    for _ in range(max_steps + hold):
        q, dq = env.data.qpos[:2], env.data.qvel[:2]
        error = np.array([_wrap(goal[0] - q[0]), _wrap(goal[1] - q[1])])
        torque = np.clip(kp * error - kd * dq, -1.0, 1.0)
        env.do_simulation(torque, env.frame_skip)
        trace.append(fingertip(env))
        if np.linalg.norm(trace[-1] - np.asarray(point)) <= tolerance:
            settled += 1
            if settled > hold:
                return True, trace
    return False, trace


def truth_subgoals() -> SubGoalSet:
    return SubGoalSet([SubGoal(n, "all", (0, 1), c, TRUTH_RADIUS) for n, c in zip(NAMES, CENTRES)],
                      feature_names=("x", "y"))


def truth_pdfa(p_ccw: float = 0.7):
    """Both circuits start at +x; the second sub-goal decides the direction (states = sets done)."""
    from symlearn.logic.automata.pdfa import PDFA
    from symlearn.logic.guards import Guard

    letter = {n: Guard.cube({m: m == n for m in NAMES}) for n in NAMES}
    states = [frozenset()]
    transitions: dict[int, list] = {}
    for order, p in ((CCW, p_ccw), (CW, 1 - p_ccw)):
        done: frozenset[int] = frozenset()
        for step, j in enumerate(order):
            nxt = done | {j}
            if nxt not in states:
                states.append(nxt)
            source, target = states.index(done), states.index(nxt)
            row = transitions.setdefault(source, [])
            if all(t != target for _, t, _ in row):
                row.append((letter[NAMES[j]], target, p if step == 1 else 1.0))
            done = nxt
    termination = [1.0 if len(s) == 4 else 0.0 for s in states]
    names = ["{" + ",".join(NAMES[j] for j in sorted(s)) + "}" for s in states]
    return PDFA(NAMES, len(states), 0, transitions, termination, None, names)


class ReacherDemonstrator:
    """Circuits of the four sub-goals, counter-clockwise with probability ``p_ccw``."""

    def __init__(self, *, p_ccw: float = 0.7, hold: tuple[int, int] = (5, 10), noise: float = 0.001,
                 seed: int | None = None) -> None:
        if not 0 < p_ccw < 1:
            raise DataError(f"p_ccw must be in (0, 1), got {p_ccw}")
        self.p_ccw, self.hold, self.noise = p_ccw, hold, noise
        self.rng = np.random.default_rng(seed)
        self.env = make_reacher(int(self.rng.integers(2**31)))
        self.lengths = link_lengths(self.env)

    def demonstration(self) -> tuple[np.ndarray, tuple[int, ...]]:
        env = self.env
        env.reset(seed=int(self.rng.integers(2**31)))
        env.set_state(np.r_[self.rng.normal(0, 0.05, 2), env.data.qpos[2:]], np.zeros(env.model.nv))
        order = CCW if self.rng.random() < self.p_ccw else CW
        frames = [fingertip(env)] * int(self.rng.integers(*self.hold))
        for j in order:
            ok, trace = reach(env, CENTRES[j], hold=int(self.rng.integers(*self.hold)), lengths=self.lengths)
            if not ok:
                raise DataError(f"the demonstrator's controller did not reach {NAMES[j]}")
            frames += trace
        frames = np.asarray(frames)
        return frames + self.rng.normal(0, self.noise, frames.shape), order

    def demonstrations(self, n: int) -> tuple[list[np.ndarray], list[tuple[int, ...]]]:
        pairs = [self.demonstration() for _ in progress(range(n), total=n, desc="Reacher demonstrations")]
        return [p[0] for p in pairs], [p[1] for p in pairs]
