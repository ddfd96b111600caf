"""Sub-goals: balls in subspaces of a state's features, and the labeling they define.

A sub-goal (thesis, section 6.3.1) is a centre ``c`` over a subset of the state's features and a
radius ``r``; a state reaches it when the Euclidean distance between its projection on those
features and ``c`` is at most ``r``. A :class:`SubGoalSet` is therefore a labeling: the
propositions true in a state are the sub-goals it reaches.

States are float vectors. A NaN feature means "not observed in this frame" (an object the camera
did not detect): a sub-goal whose features are not all observed is *not reached* in that frame --
unknown is never taken for reached, and it is not an error.

>>> g = SubGoal("red_0", "red", (0, 1), (1.0, 2.0), 0.5)
>>> g.reached([[1.0, 2.2, 9.0], [3.0, 2.0, 0.0], [float("nan"), 2.0, 0.0]]).tolist()
[True, False, False]
>>> goals = SubGoalSet([g, SubGoal("blue_0", "blue", (2,), (0.0,), 0.1)])
>>> sorted(goals.label([1.0, 2.0, 0.05]))
['blue_0', 'red_0']
>>> SubGoalSet.from_json(goals.to_json()) == goals
True
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError
from symlearn.grounding.labeling import LabelingBase
from symlearn.json_document import JsonFile, read_document

FORMAT_VERSION = 1
MAGIC = "subgoals"


@dataclass(frozen=True)
class SubGoal:
    """``name``: the symbol of the sub-goal; ``subset``: the name of its feature subset;
    ``features``: the state columns it reads; ``centre`` (one value per feature) and ``radius``."""

    name: str
    subset: str
    features: tuple[int, ...]
    centre: tuple[float, ...]
    radius: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise DataError(f"sub-goal name {self.name!r} must be an identifier (letters, digits, _)")
        object.__setattr__(self, "features", tuple(int(i) for i in self.features))
        object.__setattr__(self, "centre", tuple(float(v) for v in self.centre))
        object.__setattr__(self, "radius", float(self.radius))
        if not self.features or len(set(self.features)) != len(self.features) or min(self.features) < 0:
            raise DataError(f"sub-goal {self.name}: features must be distinct column indices, got {self.features}")
        if len(self.centre) != len(self.features):
            raise DataError(f"sub-goal {self.name}: {len(self.centre)} centre values for "
                            f"{len(self.features)} features")
        if not all(math.isfinite(v) for v in self.centre) or not (math.isfinite(self.radius) and self.radius >= 0):
            raise DataError(f"sub-goal {self.name}: centre and radius must be finite, radius >= 0")

    def distances(self, frames: Any) -> np.ndarray:
        """Distance of each frame's projection to the centre (NaN where a feature is unobserved)."""
        frames = _frames(frames)
        if frames.shape[1] <= max(self.features):
            raise DataError(f"sub-goal {self.name} reads feature column {max(self.features)}, "
                            f"but the states have {frames.shape[1]} features")
        diff = frames[:, self.features] - np.asarray(self.centre)
        return np.sqrt(np.einsum("ij,ij->i", diff, diff))

    def reached(self, frames: Any) -> np.ndarray:
        """Whether each frame reaches the sub-goal (False where it is unobserved)."""
        with np.errstate(invalid="ignore"):
            return self.distances(frames) <= self.radius

    def observed(self, frames: Any) -> np.ndarray:
        """Whether every feature of the sub-goal is observed in each frame."""
        frames = _frames(frames)
        return ~np.isnan(frames[:, self.features]).any(axis=1)

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "subset": self.subset, "features": list(self.features),
                "centre": list(self.centre), "radius": self.radius}


def _frames(frames: Any) -> np.ndarray:
    array = np.asarray(frames, dtype=np.float64)
    if array.ndim == 1:
        array = array[None, :]
    if array.ndim != 2:
        raise DataError(f"states must be a (T, k) array of features, got shape {array.shape}")
    return array


class SubGoalSet(LabelingBase, JsonFile):
    """An ordered set of sub-goals; as a labeling, a state's label is the sub-goals it reaches."""

    def __init__(self, subgoals: Iterable[SubGoal], *, feature_names: Sequence[str] | None = None) -> None:
        self.subgoals = tuple(subgoals)
        names = [g.name for g in self.subgoals]
        if len(set(names)) != len(names):
            raise DataError(f"sub-goal names repeat: {', '.join(names)}")
        self.feature_names = tuple(feature_names) if feature_names is not None else None
        self._by_name = {g.name: g for g in self.subgoals}
        self._meanings = {g.name: _meaning(g, self.feature_names) for g in self.subgoals}

    @property
    def propositions(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.subgoals)

    def __len__(self) -> int:
        return len(self.subgoals)

    def __iter__(self):
        return iter(self.subgoals)

    def __getitem__(self, name: str) -> SubGoal:
        try:
            return self._by_name[name]
        except KeyError:
            raise DataError(f"unknown sub-goal {name!r}", hint="known: " + ", ".join(self._by_name)) from None

    def __contains__(self, name: object) -> bool:
        return name in self._by_name

    def reached_matrix(self, frames: Any) -> np.ndarray:
        """``(T, G)`` booleans: frame ``t`` reaches sub-goal ``g`` (in :attr:`propositions` order)."""
        frames = _frames(frames)
        if not self.subgoals:
            return np.zeros((len(frames), 0), dtype=bool)
        return np.column_stack([g.reached(frames) for g in self.subgoals])

    def label(self, state: Any) -> frozenset[str]:
        row = self.reached_matrix(state)[0]
        return frozenset(g.name for g, hit in zip(self.subgoals, row) if hit)

    def match(self, truth: SubGoalSet, tolerance: float) -> dict[str, str]:
        """``{own name: truth name}``: each sub-goal paired with the truth's sub-goal over the same
        features whose centre is nearest, if within ``tolerance`` (each truth sub-goal used once,
        closest pairs first). Scoring a learned set against a known one uses it."""
        pairs = []
        for g in self.subgoals:
            for h in truth.subgoals:
                if g.features == h.features:
                    pairs.append((float(np.linalg.norm(np.subtract(g.centre, h.centre))), g.name, h.name))
        mapping: dict[str, str] = {}
        used: set[str] = set()
        for distance, mine, theirs in sorted(pairs):
            if distance <= tolerance and mine not in mapping and theirs not in used:
                mapping[mine] = theirs
                used.add(theirs)
        return mapping

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SubGoalSet):
            return NotImplemented
        return self.subgoals == other.subgoals and self.feature_names == other.feature_names

    def __repr__(self) -> str:
        return f"SubGoalSet({', '.join(self.propositions)})"

    # --- persistence ----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        return {"symlearn": MAGIC, "format_version": FORMAT_VERSION,
                "feature_names": list(self.feature_names) if self.feature_names is not None else None,
                "subgoals": [g.as_dict() for g in self.subgoals]}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), allow_nan=False)

    @classmethod
    def from_json(cls, text, *, source: str = "<string>") -> SubGoalSet:
        doc = read_document(text, MAGIC, FORMAT_VERSION, source=source)
        try:
            goals = [SubGoal(item["name"], item["subset"], tuple(item["features"]), tuple(item["centre"]),
                             item["radius"]) for item in doc["subgoals"]]
            return cls(goals, feature_names=doc.get("feature_names"))
        except (KeyError, TypeError, ValueError) as exc:
            raise DataError(f"malformed sub-goal set ({type(exc).__name__}: {exc})", file=source) from None
        except DataError as exc:
            raise DataError(exc.message, file=source, hint=exc.hint) from None


def _meaning(goal: SubGoal, feature_names: Sequence[str] | None) -> str:
    names = [feature_names[i] if feature_names and i < len(feature_names) else f"x{i}" for i in goal.features]
    centre = ", ".join(f"{n}={v:.4g}" for n, v in zip(names, goal.centre))
    return f"{goal.subset} within {goal.radius:.3g} of ({centre})"


__all__ = ["SubGoal", "SubGoalSet"]
