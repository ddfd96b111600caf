"""The one table of bundled environments, domains and tasks, and what can be learned in each.

Every bundled name lives here once: the CLI (``symlearn envs``, ``--env``), the logic domains
(:mod:`~symlearn.envs.logic_domains`), the specification tasks (:mod:`~symlearn.envs.spec_tasks`),
the constraint settings and the gymnasium ids all look their names up in :data:`ENTRIES`.

An :class:`Entry` has one or more :class:`Kind`:

* ``constraints`` -- tabular constraint learning (``symlearn learn constraints --env NAME``);
* ``rules`` -- it also has ASP facts for every state-action pair, so rules can be induced
  (``--method logic``); such an entry names the factory of its
  :class:`~symlearn.envs.logic_domains.LogicDomain`;
* ``spec`` -- a task specification with its ground-truth LTLf formula
  (``symlearn learn spec --env NAME``);
* ``continuous`` -- a continuous-state gymnasium environment whose ground-truth cost
  (``info["cost"]``) is a region of its named features (``info["features"]``): constraints are
  learned there as DNF formulas over features (thesis chapter 4);
* ``machine`` -- a rendered block task whose image demonstrations give a reward machine;
* ``subgoals`` -- a block-world task whose frames of object positions give sub-goals and the
  probabilistic automaton of their orderings (``symlearn learn pdfa``; no gymnasium environment).

An entry also names its **expert** (``expert(n, seed=0, env_kwargs=None)``, see
:mod:`~symlearn.envs.experts`; ``None`` where there is none, and ``trained_expert`` where a
PPO-Lagrangian expert can be trained on the true cost instead), the names of its **features**
(a ``"module:CONSTANT"`` tuple of the names of ``info["features"]``), and, for sub-goal tasks,
the block-world **task** (feature names and default subsets). Entry points never decide
anything from an entry's name: they read these fields (through :mod:`symlearn.recipes`).

Factories are ``"module:attribute"`` strings resolved only when called, so importing this
module loads neither gymnasium nor numpy; the same strings are the gymnasium entry points
(:mod:`~symlearn.envs.gym_registration`).

>>> get("junction-lights").gym_id
'symlearn/junction-lights-v0'
>>> names(Kind.RULES)
('hanoi', 'junction-lights', 'junction-priority', 'junction-combined')
>>> get("office-1").formula, get("office-1").gym_name
('(f T g) & G !n', 'office')
>>> get("junction-light")  # doctest: +ELLIPSIS
Traceback (most recent call last):
symlearn.errors.UnknownNameError: unknown environment 'junction-light' (hint: did you mean 'junction-lights'? ...)
"""

from __future__ import annotations

import importlib
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from difflib import get_close_matches
from enum import StrEnum
from typing import Any

from symlearn.errors import DataError, UnknownNameError


class Kind(StrEnum):
    """What can be learned in an entry (the value is what ``symlearn envs --json`` prints)."""

    CONSTRAINTS = "constraints"
    RULES = "rules"
    SPEC = "spec"
    CONTINUOUS = "continuous"
    MACHINE = "machine"
    SUBGOALS = "subgoals"

    @property
    def label(self) -> str:
        return {"constraints": "constraint-learning environment", "rules": "logic domain",
                "spec": "specification task", "continuous": "continuous-constraint environment",
                "machine": "reward-machine task (image demonstrations)",
                "subgoals": "sub-goal task (frames of object positions)"}[self.value]


@dataclass(frozen=True)
class Factory:
    """``target`` (``"module:attribute"``) called with ``kwargs`` (and the caller's arguments);
    imported only when called."""

    target: str
    kwargs: Mapping[str, Any] = field(default_factory=dict, hash=False)

    def resolve(self) -> Any:
        module, _, attribute = self.target.partition(":")
        return getattr(importlib.import_module(module), attribute)

    def __call__(self, *args: Any, **overrides: Any) -> Any:
        return self.resolve()(*args, **{**self.kwargs, **overrides})


@dataclass(frozen=True)
class Entry:
    """One bundled environment, domain or task.

    ``env`` builds its gymnasium environment (registered as ``gym_id``), ``domain`` its logic
    domain (``rules`` entries), ``formula`` is the ground truth of a ``spec`` entry, ``methods``
    what it can be learned with (``--method`` of ``symlearn learn constraints``; ``spec`` is
    ``symlearn learn spec``).
    """

    name: str
    kinds: frozenset[Kind]
    description: str
    methods: tuple[str, ...]
    gym_id: str | None = None
    env: Factory | None = None
    domain: Factory | None = None
    formula: str | None = None
    expert: Factory | None = None
    features: str | None = None
    task: Factory | None = None
    trained_expert: bool = False

    def __post_init__(self) -> None:
        # A wrong row is a bug of ours, found by the import of this module (and its tests).
        problems = []
        if not self.kinds & {Kind.CONSTRAINTS, Kind.SPEC, Kind.CONTINUOUS, Kind.MACHINE, Kind.SUBGOALS}:
            problems.append("is no constraint environment, specification task, continuous-constraint environment, "
                            "reward-machine task or sub-goal task")
        if Kind.SUBGOALS in self.kinds and (self.expert is None or self.task is None):
            problems.append("is a sub-goal task without an expert or a block-world task")
        if self.expert is not None and self.trained_expert:
            problems.append("has a scripted expert and a trained one")
        if self.features is not None and ":" not in self.features:
            problems.append(f"names its features {self.features!r}, not 'module:CONSTANT'")
        if self.kinds & {Kind.CONTINUOUS, Kind.MACHINE} and self.env is None:
            problems.append("is a continuous-constraint environment or reward-machine task without an environment")
        if Kind.RULES in self.kinds and (Kind.CONSTRAINTS not in self.kinds or self.domain is None):
            problems.append("has rules but no constraint kind or no domain factory")
        if Kind.SPEC in self.kinds and (self.formula is None or self.env is None):
            problems.append("is a specification task without a formula or an environment")
        if (self.gym_id is None) != (self.env is None):
            problems.append("needs both a gymnasium id and an environment factory, or neither")
        if self.gym_id is not None and not _GYM_ID.fullmatch(self.gym_id):
            problems.append(f"has gymnasium id {self.gym_id!r}, not 'symlearn/<name>-v<version>'")
        if problems:
            raise ValueError(f"registry entry {self.name!r} " + "; ".join(problems))

    @property
    def gym_name(self) -> str | None:
        """The gymnasium id without namespace and version (``office`` for ``symlearn/office-v0``)."""
        return None if self.gym_id is None else _GYM_ID.fullmatch(self.gym_id)["name"]

    def feature_names(self) -> tuple[str, ...] | None:
        """The names of the entry's features (``info["features"]``, or a sub-goal task's frame
        columns), or ``None`` where the entry names none."""
        if self.task is not None:
            return tuple(self.task().feature_names())
        if self.features is None:
            return None
        return tuple(Factory(self.features).resolve())

    def make_env(self, **kwargs: Any) -> Any:
        """The gymnasium environment, built directly (without ``gymnasium.make``'s wrappers)."""
        if self.env is None:
            raise DataError(f"{self.name} has no gymnasium environment",
                                   hint="environments: " + ", ".join(e.name for e in ENTRIES if e.env))
        return self.env(**kwargs)


_GYM_ID = re.compile(r"symlearn/(?P<name>[a-z0-9-]+?)-v\d+")

_CONSTRAINT_RULES = frozenset({Kind.CONSTRAINTS, Kind.RULES})
_LOGIC_METHODS = ("logic", "ml")  # mce-icrl needs the environment's reward, which these lack


def _junction(variant: str, description: str) -> Entry:
    name = f"junction-{variant}"
    return Entry(name, _CONSTRAINT_RULES, description, _LOGIC_METHODS, f"symlearn/{name}-v0",
                 Factory("symlearn.envs.junction_env:JunctionEnv", {"variant": variant}),
                 Factory("symlearn.envs.logic_domains:junction_domain", {"variant": variant}))


def _spec(name: str, world: str, formula: str, description: str) -> Entry:
    # One gymnasium environment per world: the task is not part of the environment (it pays no
    # reward); the formula says what the agent should achieve there.
    factory = Factory(f"symlearn.envs.{world}_world:make_{world}_world")
    return Entry(name, frozenset({Kind.SPEC}), description, ("spec",), f"symlearn/{world}-v0", factory,
                 formula=formula, expert=Factory("symlearn.envs.experts:spec_task", {"task": name}))


_DNF_METHODS = ("dnf",)  # one-class tree -> DNF over the environment's info["features"]
_ICRL_METHODS = ("mce-icrl",)  # neural ICRL on the environment's observations (symlearn learn icrl)
_BLOCK_TASKS = {"stack-2": "stack red on green", "place-2": "two blocks to their places",
                "pyramid-3": "a three-block pyramid", "stack-3": "a three-block stack",
                "place-3": "three blocks to their places"}

# Thesis section 2.5.2's blocked MuJoCo robots and section 2.5.4's broken ant (gymnasium v5; the
# `mujoco` extra): name, factory in symlearn.envs.blocked_mujoco, description.
_BLOCKED_MUJOCO = (
    ("blocked-half-cheetah", "make_blocked_half_cheetah",
     "HalfCheetah-v5 paid for speed either way; x < -3 forbidden (needs symlearn[mujoco])"),
    ("blocked-ant", "make_blocked_ant",
     "Ant-v5 paid for its distance from the origin; x < -3 forbidden (needs symlearn[mujoco])"),
    ("blocked-walker2d", "make_blocked_walker2d",
     "Walker2d-v5 paid for speed either way; x < -3 forbidden (needs symlearn[mujoco])"),
    ("blocked-swimmer", "make_blocked_swimmer",
     "Swimmer-v5 paid for speed either way; x > 0.5 forbidden (needs symlearn[mujoco])"),
    ("biased-inverted-pendulum", "make_biased_inverted_pendulum",
     "InvertedPendulum-v5 paid more left of its start; x < -0.015 forbidden (needs symlearn[mujoco])"),
    ("broken-ant", "make_broken_ant",
     "blocked ant with two legs disabled, same observations (cost-transfer target; needs symlearn[mujoco])"),
)


def _safenav(agent: str, task: str, description: str) -> Entry:
    name = f"safenav-{agent}-{task}"
    return Entry(name, frozenset({Kind.CONTINUOUS}), description, _DNF_METHODS, f"symlearn/{name}-v0",
                 Factory("symlearn.envs.safenav.env:SafeNavEnv", {"agent": agent, "task": task}),
                 expert=Factory("symlearn.envs.experts:safenav", {"agent": agent, "task": task}),
                 features="symlearn.envs.safenav.observation:FEATURE_NAMES")


def _blocks(kind: str, size: int) -> Entry:
    # Thesis chapter 6's block world: frames of block positions, no gymnasium environment.
    what = (f"{size} blocks placed in a preferred order" if kind == "place"
            else f"{size} round(s) of three blocks stacked")
    spec = {"kind": kind, "size": size}
    return Entry(f"blocks-{kind}-{size}", frozenset({Kind.SUBGOALS}), f"block world: {what} (sub-goal PDFA)",
                 ("pdfa",), expert=Factory("symlearn.envs.experts:block_world", spec),
                 task=Factory("symlearn.envs.experts:block_world_task", spec))


#: Every bundled entry, in listing order. The formulas are those of the thesis, Table 5.1
#: (``T`` is "then": ``a T b`` = ``F(a & X F b)``).
ENTRIES: tuple[Entry, ...] = (
    # No gymnasium environment exists for Hanoi: it is a finite model learned on as a tabular MDP.
    Entry("hanoi", _CONSTRAINT_RULES, "Towers of Hanoi, 3 disks: no disk on a smaller one", _LOGIC_METHODS,
          domain=Factory("symlearn.envs.logic_domains:hanoi_domain")),
    _junction("lights", "5x5 junction with a traffic light, two-way roads"),
    _junction("priority", "5x5 junction with priority to the right, one-way roads"),
    _junction("combined", "7x7 junction: light + priority + one-way roads (transfer target)"),
    Entry("gridworld", frozenset({Kind.CONSTRAINTS}),
          "7x7 stochastic gridworld with a forbidden block (--stochasticity p)", ("ml", "mce-icrl"),
          "symlearn/gridworld-v0", Factory("symlearn.envs.gridworld:StochasticGridworld")),
    _spec("office-1", "office", "(f T g) & G !n", "fetch coffee, then deliver it to g, never touching a decoration"),
    _spec("office-2", "office", "(e T g) & G !n", "fetch mail, then deliver it to g, never touching a decoration"),
    _spec("office-3", "office", "(f T g) & (e T g) & G !n",
          "fetch coffee and mail (any order), then deliver both to g, avoiding decorations"),
    _spec("office-4", "office", "(a T b) & (b T c) & (c T d) & G !n",
          "visit offices a, b, c, d in this order, avoiding decorations"),
    _spec("craft-1", "craft", "a T c", "get a, then use it at c"),
    _spec("craft-2", "craft", "(a T e) & (f T e)", "get a and f, then use both at e"),
    _spec("craft-3", "craft", "(a T b) & (f T b) & (c T b)", "get a, f and c, then use them at b"),
    _spec("craft-4", "craft", "(a T e) & (f T e) & (e T g)", "get a and f, use them at e, then go to g"),
    # Continuous constraints (thesis chapter 4): the toy of section 4.3.1 and SafeNav, a numpy
    # re-creation of Safety-Gym's Point/Car x Goal1/Push1 (section 4.4.1).
    Entry("toy-navigation", frozenset({Kind.CONTINUOUS}),
          "point in [0,1]^2 from (0.1,0.1) to (0.9,0.9) along an L-shaped safe set (features x, y)",
          _DNF_METHODS, "symlearn/toy-navigation-v0", Factory("symlearn.envs.toy_navigation:ToyNavigationEnv"),
          expert=Factory("symlearn.envs.experts:toy_navigation"), features="symlearn.envs.toy_navigation:FEATURE_NAMES"),
    _safenav("point", "goal", "Safety-Gym PointGoal1 in numpy: reach goals, avoid 8 hazards (20 features)"),
    _safenav("point", "push", "Safety-Gym PointPush1 in numpy: push a box to the goal, avoid 8 hazards"),
    _safenav("car", "goal", "Safety-Gym CarGoal1 in numpy: differential drive, reach goals, avoid hazards"),
    _safenav("car", "push", "Safety-Gym CarPush1 in numpy: differential drive, push a box, avoid hazards"),
    # Section 4.4.2's highway (highD there, licensed): highway-env's highway, continuous action,
    # IDM/MOBIL demonstrator; building it needs the `highway` extra.
    Entry("driving", frozenset({Kind.CONTINUOUS}),
          "highway-env highway, continuous action: avoid collisions and leaving the road (10 features; "
          "needs symlearn[highway])", _DNF_METHODS, "symlearn/driving-v0",
          Factory("symlearn.envs.driving.env:DrivingEnv"), expert=Factory("symlearn.envs.experts:driving"),
          features="symlearn.envs.driving.features:FEATURE_NAMES"),
    # Section 2.5.3's realistic traffic (highD there): the same highway with a speed cap or a
    # minimum gap as the constraint neural ICRL recovers; IDM/MOBIL demonstrators that obey it.
    *(Entry(f"driving-{kind}", frozenset({Kind.CONTINUOUS}),
            f"highway-env highway, continuous action, {what} (neural ICRL; needs symlearn[highway])",
            _ICRL_METHODS, f"symlearn/driving-{kind}-v0",
            Factory("symlearn.envs.driving.env:DrivingEnv", {"constraint": kind}),
            expert=Factory("symlearn.envs.experts:driving_constrained", {"constraint": kind}),
            features="symlearn.envs.driving.features:FEATURE_NAMES")
      for kind, what in (("velocity", "speed along the road at most 20 m/s"),
                         ("distance", "a gap of at least 10 m to the car ahead"))),
    # Neural MCE-ICRL (thesis chapter 2) at CPU size: a numpy stand-in for the blocked MuJoCo robots
    # (section 2.5.2) and the kinematic point of the transfer experiment (section 2.5.4).
    Entry("blocked-point", frozenset({Kind.CONTINUOUS}),
          "point mass paid for moving along x; the easy direction is forbidden behind a wall at x = wall (-3)",
          _ICRL_METHODS, "symlearn/blocked-point-v0", Factory("symlearn.envs.blocked_point:BlockedPoint"),
          expert=Factory("symlearn.envs.experts:blocked_point"), features="symlearn.envs.blocked_point:FEATURE_NAMES"),
    Entry("point-circle", frozenset({Kind.CONTINUOUS}),
          "kinematic point paid for running a circle of radius 10, wall at x = -3 (cost-transfer target)",
          _ICRL_METHODS, "symlearn/point-circle-v0", Factory("symlearn.envs.point_circle:PointCircle"),
          trained_expert=True, features="symlearn.envs.blocked_point:FEATURE_NAMES"),
    # No scripted expert for the robots: a PPO-Lagrangian one is trained on the true cost.
    *(Entry(name, frozenset({Kind.CONTINUOUS}), description, _ICRL_METHODS, f"symlearn/{name}-v0",
            Factory(f"symlearn.envs.blocked_mujoco:{factory}"), trained_expert=True,
            features="symlearn.envs.blocked_mujoco:FEATURE_NAMES")
      for name, factory, description in _BLOCKED_MUJOCO),
    # Thesis chapter 7 (Table 7.1): numpy rendered block world, image demonstrations, pick-and-place pixels.
    *(Entry(f"blockworld-{task.replace('-', '')}", frozenset({Kind.MACHINE}),
            f"rendered block world, {text} (top-down 48 px policy view, front camera for demos)",
            ("rm", "dqrm", "dqn"), f"symlearn/blockworld-{task.replace('-', '')}-v0",
            Factory("symlearn.envs.rendered_blocks.env:RenderedBlocksEnv", {"task": task}),
            expert=Factory("symlearn.envs.experts:rendered_blocks", {"task": task}))
      for task, text in _BLOCK_TASKS.items()),
    # Thesis chapter 6 (section 6.4.1): sub-goals and preferred orderings from object positions.
    *(_blocks("place", k) for k in range(2, 7)),
    *(_blocks("stack", r) for r in range(1, 5)),
)

# Names used before the registry gave the junction one name everywhere (hints only).
_FORMER_NAMES = {f"traffic-{variant}": f"junction-{variant}" for variant in ("lights", "priority", "combined")}

_BY_NAME: dict[str, Entry] = {entry.name: entry for entry in ENTRIES}
if len(_BY_NAME) != len(ENTRIES):
    raise ValueError("registry names must be unique")


def entries(kind: Kind | None = None) -> tuple[Entry, ...]:
    """Every entry (of ``kind``), in listing order."""
    return tuple(e for e in ENTRIES if kind is None or kind in e.kinds)


def names(kind: Kind | None = None) -> tuple[str, ...]:
    return tuple(e.name for e in entries(kind))


def get(name: str, kind: Kind | None = None, *, what: str | None = None) -> Entry:
    """The entry called ``name`` (case-insensitive) that has ``kind``.

    Anything else raises :class:`~symlearn.errors.UnknownNameError` whose hint lists the names
    of that kind (and the closest one). ``what`` names the thing in the message (default: the
    kind's label, or "environment").
    """
    key = str(name).strip().lower()
    known = names(kind)
    if key in known:
        return _BY_NAME[key]
    what = what or (kind.label if kind else "environment")
    close = [_FORMER_NAMES[key]] if _FORMER_NAMES.get(key) in known else get_close_matches(key, known, n=1)
    hint = (f"did you mean {close[0]!r}? " if close else "") + f"known {_plural(kind)}: " + ", ".join(known)
    if key in _BY_NAME:  # a real entry, just not of this kind: say what it is instead
        kinds = ", ".join(sorted(k.value for k in _BY_NAME[key].kinds))
        raise UnknownNameError(f"{key!r} is no {what} (it is: {kinds})", hint=hint)
    raise UnknownNameError(f"unknown {what} {name!r}", hint=hint)


def _plural(kind: Kind | None) -> str:
    return f"{kind.label}s" if kind else "environments"


def gym_entries() -> dict[str, Factory]:
    """Gymnasium id -> environment factory, one per id (the spec tasks of a world share one)."""
    found: dict[str, Factory] = {}
    for entry in ENTRIES:
        if entry.gym_id is None:
            continue
        if found.setdefault(entry.gym_id, entry.env) != entry.env:
            raise ValueError(f"gymnasium id {entry.gym_id} has two different factories")
    return found


def formulas(world: str) -> dict[str, str]:
    """Task name -> ground-truth formula of the specification tasks in ``world`` (``office``)."""
    return {e.name: e.formula for e in entries(Kind.SPEC) if e.gym_name == world}


__all__ = ["ENTRIES", "Entry", "Factory", "Kind", "entries", "formulas", "get", "gym_entries", "names"]
