"""An ordered, validated collection of trajectories that all describe the same kind of data."""

from __future__ import annotations

import os
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import Any, overload

import numpy as np

from symlearn.data import kinds
from symlearn.data.trajectory import Label, Trajectory
from symlearn.errors import DataError


class Demonstrations(Sequence[Trajectory]):
    """Trajectories with one state kind, one action kind and the same optional fields.

    ``metadata`` is free JSON (environment id, grounding, recording seed, ...) saved with the data.

    >>> demos = Demonstrations([Trajectory([0, 1], [2]), Trajectory([0, 3, 4], [1, 1])])
    >>> len(demos), demos.summary()["n_steps"]
    (2, 5)
    """

    def __init__(self, trajectories: Iterable[Trajectory], *, metadata: Mapping[str, Any] | None = None):
        items = tuple(trajectories)
        if not items:
            raise DataError("demonstrations are empty: at least one trajectory is needed")
        for i, traj in enumerate(items):
            if not isinstance(traj, Trajectory):
                raise DataError(f"trajectory {i} is a {type(traj).__name__}, not a Trajectory")
        _check_consistent(items)
        self._items = items
        self.metadata: dict[str, Any] = Trajectory._info(metadata)

    # --- sequence protocol ----------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._items)

    @overload
    def __getitem__(self, index: int) -> Trajectory: ...
    @overload
    def __getitem__(self, index: slice | Sequence[int] | np.ndarray) -> Demonstrations: ...

    def __getitem__(self, index):
        if isinstance(index, (int, np.integer)):
            return self._items[index]
        if isinstance(index, slice):
            return Demonstrations(self._items[index], metadata=self.metadata)
        picked = np.asarray(index)
        if picked.dtype == bool:
            if picked.shape != (len(self),):
                raise DataError(f"boolean mask has length {picked.size}, expected {len(self)}")
            picked = np.flatnonzero(picked)
        return Demonstrations([self._items[int(i)] for i in picked], metadata=self.metadata)

    def __iter__(self) -> Iterator[Trajectory]:
        return iter(self._items)

    def __add__(self, other: Demonstrations) -> Demonstrations:
        if not isinstance(other, Demonstrations):
            return NotImplemented
        return Demonstrations.concatenate([self, other])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Demonstrations):
            return NotImplemented
        return self.metadata == other.metadata and self._items == other._items

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        first = self._items[0]
        return (
            f"Demonstrations({len(self)} trajectories, {self.n_steps} steps, "
            f"{first.state_kind} states, {first.action_kind or 'no'} actions)"
        )

    @staticmethod
    def concatenate(parts: Iterable[Demonstrations]) -> Demonstrations:
        """Join collections in order; metadata of earlier parts wins on conflicting keys."""
        parts = list(parts)
        metadata: dict[str, Any] = {}
        for part in reversed(parts):
            metadata.update(part.metadata)
        return Demonstrations([t for part in parts for t in part], metadata=metadata)

    # --- shared properties ------------------------------------------------------------------
    @property
    def state_kind(self) -> str:
        return self._items[0].state_kind

    @property
    def action_kind(self) -> str | None:
        return next((t.action_kind for t in self._items if t.n_actions), None)

    @property
    def has_actions(self) -> bool:
        return self._items[0].actions is not None

    @property
    def has_rewards(self) -> bool:
        return self._items[0].rewards is not None

    @property
    def has_labels(self) -> bool:
        return self._items[0].labels is not None

    @property
    def n_steps(self) -> int:
        return sum(len(t) for t in self._items)

    # --- conversions ------------------------------------------------------------------------
    def to_state_action_pairs(self) -> list[tuple[Any, Any]]:
        """All ``(state, action)`` pairs in order, as hashable Python values."""
        if not self.has_actions:
            raise DataError("these demonstrations have no actions (state-only)")
        return [pair for t in self._items for pair in t.state_action_pairs()]

    def to_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """States and actions of every step with an action, stacked for array kinds."""
        if not self.has_actions:
            raise DataError("these demonstrations have no actions (state-only)")
        if self.state_kind not in kinds.ARRAY_KINDS or self.action_kind not in kinds.ARRAY_KINDS | {None}:
            raise DataError(
                f"to_arrays needs array states and actions, got {self.state_kind} and {self.action_kind}",
                hint="use to_state_action_pairs() for feature dicts and symbols",
            )
        states = np.concatenate([t.states[: t.n_actions] for t in self._items])
        actions = np.concatenate([t.actions for t in self._items if t.n_actions])
        return states, actions

    def to_label_words(self) -> list[tuple[Label, ...]]:
        """Every trajectory's labels as a word over sets of propositions."""
        if not self.has_labels:
            raise DataError("these demonstrations have no labels", hint="record them with a labeler")
        return [t.label_word() for t in self._items]

    # --- statistics ---------------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """JSON-ready summary statistics of the collection."""
        lengths = np.array([len(t) for t in self._items])
        first = self._items[0]
        report: dict[str, Any] = {
            "n_trajectories": len(self),
            "n_steps": int(lengths.sum()),
            "length": _describe(lengths),
            "state_kind": first.state_kind,
            "state_shape": list(first.state_shape),
            "action_kind": self.action_kind,
            "has_rewards": self.has_rewards,
            "has_labels": self.has_labels,
        }
        if first.state_kind != "image":
            report["n_distinct_states"] = len({t.state(i) for t in self._items for i in range(len(t))})
        if self.has_actions:
            report["n_state_actions"] = sum(t.n_actions for t in self._items)
            report["n_distinct_actions"] = len({t.action(i) for t in self._items for i in range(t.n_actions)})
        if self.has_rewards:
            report["return"] = _describe(np.array([t.total_reward() for t in self._items]))
        if self.has_labels:
            counts = Counter(p for t in self._items for step in t.labels for p in step)
            report["label_counts"] = dict(sorted(counts.items()))
        if first.state_kind == "vector" and int(np.prod(first.state_shape or (1,))) <= 64:
            stacked = np.concatenate([t.states for t in self._items]).astype(np.float64)
            report["state_min"] = np.atleast_1d(stacked.min(axis=0)).tolist()
            report["state_max"] = np.atleast_1d(stacked.max(axis=0)).tolist()
        return report

    # --- persistence --------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str], *, format: str | None = None) -> None:
        """Write to ``.jsonl``, ``.npz`` or ``.hdf5`` (chosen by suffix; ``format="d4rl"`` for a
        D4RL table in ``.npz``), atomically."""
        from symlearn.data.files import save

        save(self, path, format=format)

    @staticmethod
    def load(path: str | os.PathLike[str]) -> Demonstrations:
        """Read a file written by :meth:`save` (or by hand, for JSONL), a D4RL table or a Minari
        dataset folder."""
        from symlearn.data.files import load

        return load(path)


def _describe(values: np.ndarray) -> dict[str, float]:
    return {
        "min": float(values.min()),
        "max": float(values.max()),
        "mean": float(values.mean()),
        "std": float(values.std()),
    }


def _check_consistent(items: tuple[Trajectory, ...]) -> None:
    first = items[0]
    for i, traj in enumerate(items[1:], start=1):
        if traj.state_kind != first.state_kind:
            raise DataError(f"trajectory {i} has {traj.state_kind} states, trajectory 0 has {first.state_kind}",
                            hint=kinds.same_kind_hint("state", traj.state_kind, first.state_kind))
        if traj.state_shape != first.state_shape:
            raise DataError(
                f"ragged states across trajectories: trajectory {i} has per-step shape "
                f"{traj.state_shape}, trajectory 0 has {first.state_shape}"
            )
        if first.state_kind in kinds.ARRAY_KINDS and first.state_kind != "discrete" and traj.states.dtype != first.states.dtype:
            raise DataError(f"trajectory {i} stores states as {traj.states.dtype}, trajectory 0 as {first.states.dtype}")
        for name in ("actions", "rewards", "labels"):
            if (getattr(traj, name) is None) != (getattr(first, name) is None):
                has = "has" if getattr(traj, name) is not None else "has no"
                raise DataError(
                    f"trajectory {i} {has} {name} but trajectory 0 does not agree",
                    hint=f"give {name} for every trajectory or for none",
                )
    with_actions = [(i, t) for i, t in enumerate(items) if t.n_actions]
    if with_actions:
        i0, ref = with_actions[0]
        for i, traj in with_actions[1:]:
            if traj.action_kind != ref.action_kind or traj.action_shape != ref.action_shape:
                raise DataError(
                    f"trajectory {i} has {traj.action_kind} actions of shape {traj.action_shape}, "
                    f"trajectory {i0} has {ref.action_kind} actions of shape {ref.action_shape}",
                    hint=kinds.same_kind_hint("action", traj.action_kind, ref.action_kind),
                )
