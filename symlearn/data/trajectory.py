"""One demonstration: a sequence of states, optionally with actions, rewards, labels and info.

Length conventions (``T`` = number of states):

* ``actions`` has ``T`` entries (an action taken in every state) or ``T - 1`` (the last state is
  where the episode ended); state-only and video demonstrations leave it ``None``;
* ``rewards`` has one entry per action, or ``T`` entries when there are no actions;
* ``labels`` has ``T`` entries: the set of propositions true in each state.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Mapping
from typing import Any

import numpy as np

from symlearn.data import kinds
from symlearn.data.kinds import Kind
from symlearn.errors import DataError

Label = frozenset[str]


class Trajectory:
    """An immutable, validated demonstration.

    >>> t = Trajectory(states=[0, 1, 2], actions=[1, 1], labels=[[], ["key"], ["door"]])
    >>> len(t), t.state_kind, t.action_kind
    (3, 'discrete', 'discrete')
    >>> t.label_word()[1]
    frozenset({'key'})
    """

    __slots__ = ("states", "actions", "rewards", "labels", "info", "state_kind", "action_kind")

    def __init__(
        self,
        states: Any,
        actions: Any | None = None,
        rewards: Any | None = None,
        labels: Iterable[Iterable[str]] | None = None,
        info: Mapping[str, Any] | None = None,
    ) -> None:
        state_kind, state_values = kinds.normalize_column(states, "states")
        n = len(state_values)
        if n == 0:
            raise DataError("a trajectory needs at least one state, got none")
        set_ = object.__setattr__
        set_(self, "states", state_values)
        set_(self, "state_kind", state_kind)

        action_kind: Kind | None = None
        action_values = None
        if actions is not None:
            action_kind, action_values = kinds.normalize_column(actions, "actions")
            if action_kind == "image":  # any array of 2 or more dimensions per step, not only pictures
                shape = tuple(np.shape(action_values)[1:])
                raise DataError(f"actions must be one id, 1-D vector, feature dict or symbol per step, got arrays "
                                f"of shape {shape}", hint="store each action flattened (numpy.ravel)")
            if len(action_values) not in (n, n - 1):
                raise DataError(
                    f"mismatched lengths: {len(action_values)} actions for {n} states",
                    hint="give one action per state, or one fewer when the last state is final",
                )
            if len(action_values) == 0:  # a one-state episode: no action, so no kind either
                action_kind, action_values = None, ()
        set_(self, "actions", action_values)
        set_(self, "action_kind", action_kind)

        set_(self, "rewards", None if rewards is None else self._rewards(rewards, action_values, n))
        set_(self, "labels", None if labels is None else self._labels(labels, n))
        set_(self, "info", self._info(info))

    # --- validation -------------------------------------------------------------------------
    @staticmethod
    def _rewards(rewards: Any, actions: Any, n: int) -> np.ndarray:
        try:
            values = np.asarray(rewards, dtype=np.float64)
        except (TypeError, ValueError):
            raise DataError("rewards must be numbers") from None
        if values.ndim != 1:
            raise DataError(f"rewards must be one number per step, got shape {values.shape}")
        expected = n if actions is None else len(actions)
        if len(values) != expected:
            per = "action" if actions is not None else "state"
            raise DataError(f"mismatched lengths: {len(values)} rewards, expected one per {per} ({expected})")
        kinds.check_finite(values, "rewards")
        return values

    @staticmethod
    def _labels(labels: Iterable[Iterable[str]], n: int) -> tuple[Label, ...]:
        if isinstance(labels, (str, bytes)):
            raise DataError("labels must be one collection of propositions per state, got a string")
        result = []
        for t, step in enumerate(labels):
            if isinstance(step, (str, bytes)):
                raise DataError(
                    f"labels at step {t} must be a collection of propositions, got the string {step!r}",
                    hint=f"write [{step!r}] for a single proposition",
                )
            if isinstance(step, Mapping):
                true = sorted(str(k) for k, v in step.items() if v)
                raise DataError(f"labels at step {t} must be a list of the true propositions, got an object",
                                hint=f"write {json.dumps(true)} (an object's keys would all count as true, "
                                     "whatever their values)")
            props = frozenset(step)
            for prop in props:
                if not isinstance(prop, str) or not prop or prop != prop.strip() or "\x00" in prop:
                    raise DataError(f"labels at step {t}: {prop!r} is not a proposition name")
            result.append(props)
        if len(result) != n:
            raise DataError(f"mismatched lengths: {len(result)} labels for {n} states")
        return tuple(result)

    @staticmethod
    def _info(info: Mapping[str, Any] | None) -> dict[str, Any]:
        if info is None:
            return {}
        if not isinstance(info, Mapping):
            raise DataError(f"info must be a mapping, got {type(info).__name__}")
        try:
            # Info is persisted as JSON, so it must be JSON now, not fail at save time.
            return json.loads(json.dumps(dict(info), allow_nan=False))
        except (TypeError, ValueError) as exc:
            raise DataError(f"info must hold JSON values only: {exc}") from None

    # --- immutability and comparison ---------------------------------------------------------
    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("Trajectory is immutable; build a new one")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Trajectory):
            return NotImplemented
        if (self.state_kind, self.action_kind) != (other.state_kind, other.action_kind):
            return False
        if not kinds.columns_equal(self.state_kind, self.states, other.states):
            return False
        if (self.actions is None) != (other.actions is None):
            return False
        if self.n_actions and not kinds.columns_equal(self.action_kind, self.actions, other.actions):
            return False
        if (self.rewards is None) != (other.rewards is None):
            return False
        if self.rewards is not None and not np.array_equal(self.rewards, other.rewards):
            return False
        return self.labels == other.labels and self.info == other.info

    __hash__ = None  # type: ignore[assignment]  # equal-but-mutable arrays inside

    def __len__(self) -> int:
        return len(self.states)

    def __repr__(self) -> str:
        parts = [f"{len(self)} {self.state_kind} states"]
        if self.actions is not None:
            parts.append(f"{len(self.actions)} {self.action_kind} actions")
        if self.rewards is not None:
            parts.append(f"return {self.rewards.sum():g}")
        if self.labels is not None:
            parts.append("labelled")
        return f"Trajectory({', '.join(parts)})"

    # --- views ----------------------------------------------------------------------------------
    @property
    def n_actions(self) -> int:
        return 0 if self.actions is None else len(self.actions)

    @property
    def state_shape(self) -> tuple:
        """Per-step shape of array states, or the sorted feature names of dict states."""
        return kinds.step_shape(self.state_kind, self.states)

    @property
    def action_shape(self) -> tuple:
        return () if self.actions is None else kinds.step_shape(self.action_kind, self.actions)

    def state(self, t: int) -> Any:
        """State ``t`` as a hashable Python value (tuples for arrays, sorted items for dicts)."""
        return kinds.as_python(self.state_kind, self.states, t)

    def action(self, t: int) -> Any:
        if self.actions is None:
            raise DataError("this trajectory has no actions (state-only demonstration)")
        return kinds.as_python(self.action_kind, self.actions, t)

    def state_action_pairs(self) -> Iterator[tuple[Any, Any]]:
        """``(state, action)`` for every step that has an action, as hashable Python values."""
        for t in range(self.n_actions):
            yield self.state(t), self.action(t)

    def label_word(self) -> tuple[Label, ...]:
        """The labels as a finite word over sets of propositions (for LTLf and automata)."""
        if self.labels is None:
            raise DataError("this trajectory has no labels", hint="record it with a labeler")
        return self.labels

    def total_reward(self) -> float:
        if self.rewards is None:
            raise DataError("this trajectory has no rewards")
        return float(self.rewards.sum())
