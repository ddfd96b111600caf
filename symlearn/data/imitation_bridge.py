"""The ``imitation`` library's trajectories in memory, both ways, by duck typing.

imitation (``imitation.data.types.Trajectory`` / ``TrajectoryWithRew``) pins older gymnasium and
stable-baselines3 releases than symlearn, so symlearn never imports it to read its objects: any
object with ``obs`` (one more row than ``acts``), ``acts``, ``terminal`` and, optionally,
``rews`` is a trajectory. ``obs`` may be an array or a dict of arrays (imitation's ``DictObs``,
read through its ``_d`` dict or ``dict_len``-free ``keys``/``get``), which is flattened into one
vector per step (:mod:`symlearn.data.flat_observations`). Per-step ``infos`` are not kept
(symlearn holds one JSON info per trajectory); the trajectory's info says ``terminated`` and
``truncated`` (its opposite).

:func:`to_imitation` builds imitation's own classes when imitation is installed, and otherwise
frozen dataclasses with the same fields (:class:`PlainTrajectory`,
:class:`PlainTrajectoryWithRew`), which code that reads those fields accepts alike.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

from symlearn.data import kinds
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.flat_observations import flatten_leaves, leaf_name, ordered_keys
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError


@dataclasses.dataclass(frozen=True, eq=False)
class PlainTrajectory:
    """imitation's ``Trajectory`` fields, for when imitation is not installed."""

    obs: np.ndarray
    acts: np.ndarray
    infos: np.ndarray | None
    terminal: bool

    def __len__(self) -> int:
        return len(self.acts)


@dataclasses.dataclass(frozen=True, eq=False)
class PlainTrajectoryWithRew(PlainTrajectory):
    rews: np.ndarray


def _observation_dict(obs: Any) -> Mapping[str, Any] | None:
    if isinstance(obs, Mapping):
        return obs
    inner = getattr(obs, "_d", None)  # imitation's DictObs keeps its arrays in _d
    return inner if isinstance(inner, Mapping) else None


def _flat_leaves(tree: Mapping[str, Any], prefix: tuple[str, ...] = ()) -> list[tuple[str, np.ndarray]]:
    leaves = []
    odd = [key for key in tree.keys() if not isinstance(key, str)]
    if odd:
        raise DataError(f"observation keys must be strings, got {odd[0]!r}")
    for key in ordered_keys(tree.keys()):
        nested = _observation_dict(tree[key])
        if nested is not None:
            leaves += _flat_leaves(nested, prefix + (key,))
        else:
            leaves.append((leaf_name(prefix + (key,)), np.asarray(tree[key])))
    return leaves


def from_imitation(trajectories: Iterable[Any], *, metadata: Mapping[str, Any] | None = None) -> Demonstrations:
    """Demonstrations from imitation ``Trajectory``/``TrajectoryWithRew`` objects (or look-alikes)."""
    result, feature_names = [], None
    for i, traj in enumerate(trajectories):
        missing = [field for field in ("obs", "acts") if not hasattr(traj, field)]
        if missing:
            raise DataError(f"trajectory {i} ({type(traj).__name__}) has no {', '.join(missing)}: not an imitation "
                            "trajectory", hint="pass imitation.data.types.Trajectory objects")
        tree = _observation_dict(traj.obs)
        names = None
        try:
            if tree is not None:
                states, names = flatten_leaves(_flat_leaves(tree), f"trajectory {i} obs")
            else:
                states = np.asarray(traj.obs)
            actions = np.asarray(traj.acts)
            if states.ndim == 0 or actions.ndim == 0 or len(states) != len(actions) + 1:
                raise DataError(f"{len(states) if states.ndim else 0} observations for "
                                f"{len(actions) if actions.ndim else 0} actions; imitation trajectories have one "
                                "more observation than actions")
            rews = getattr(traj, "rews", None)
            terminal = bool(getattr(traj, "terminal", True))
            info = {"terminated": terminal, "truncated": not terminal}
            result.append(Trajectory(states, actions, None if rews is None else np.asarray(rews), None, info))
        except DataError as exc:
            raise DataError(f"trajectory {i}: {exc.message}", hint=exc.hint) from None
        if i and names != feature_names:
            raise DataError(f"trajectory {i}: observation entries {names} differ from trajectory 0's {feature_names}")
        feature_names = names
    meta = {"source_format": "imitation"}
    if feature_names:
        meta["feature_names"] = feature_names
    meta.update(metadata or {})
    return Demonstrations(result, metadata=meta)


def _imitation_classes() -> tuple[type, type]:
    try:
        from imitation.data.types import Trajectory as ImitationTrajectory, TrajectoryWithRew
    except ImportError:
        return PlainTrajectory, PlainTrajectoryWithRew
    return ImitationTrajectory, TrajectoryWithRew


def to_imitation(demos: Demonstrations, *, classes: tuple[type, type] | None = None) -> list[Any]:
    """One imitation trajectory per demonstration: ``TrajectoryWithRew`` when the demonstrations
    have rewards. ``classes``: ``(Trajectory, TrajectoryWithRew)`` to build (default: imitation's
    when installed, else :class:`PlainTrajectory`/:class:`PlainTrajectoryWithRew`).

    imitation needs array observations, at least one action, and the final state (``T`` states,
    ``T - 1`` actions); ``terminal`` is ``info["terminated"]``, true when the info does not say.
    """
    if demos.state_kind not in kinds.ARRAY_KINDS:
        raise DataError(f"imitation trajectories hold array observations; these demonstrations have "
                        f"{demos.state_kind} states")
    if not demos.has_actions or demos.action_kind not in kinds.ARRAY_KINDS:
        raise DataError("imitation trajectories hold array actions; these demonstrations have "
                        f"{'no' if not demos.has_actions else demos.action_kind} actions")
    plain, with_rewards = classes or _imitation_classes()
    result = []
    for i, t in enumerate(demos):
        if t.n_actions != len(t) - 1 or t.n_actions == 0:
            raise DataError(f"trajectory {i} has {len(t)} states and {t.n_actions} actions; imitation needs the "
                            "final state (one more state than actions) and at least one action")
        terminal = t.info.get("terminated", True) is not False
        fields = {"obs": t.states, "acts": t.actions, "infos": None, "terminal": terminal}
        result.append(with_rewards(**fields, rews=t.rewards) if demos.has_rewards else plain(**fields))
    return result
