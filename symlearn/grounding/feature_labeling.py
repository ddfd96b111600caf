"""Labelings defined by inequalities over named features, and the callable form for Python users.

A continuous state (a car's position and speed, an image's encoded features) has no finite
table of propositions; :class:`FeatureLabeling` says when each proposition holds with
inequalities over the features of a :class:`~symlearn.grounding.features.FeatureMap`:

    near_goal:  dist < 0.5
    fast:       speed >= 2 & lane == 1          (< <= > >= == != compare with a number)
    zone_a:     x < 1 & y < 1  |  x > 4 & y > 4

A proposition holds when one of its conjunctions holds (``|`` between conjunctions, ``&``
between atoms ``feature op number``). Conditions are plain text in the JSON form (see
``docs/FORMATS.md``) and errors name the proposition and the column within its condition.

:class:`CallableLabeling` wraps a Python function ``state -> iterable of proposition names``
with its declared propositions; it labels anything but cannot be saved.

>>> from symlearn.grounding.features import FeatureMap
>>> lab = FeatureLabeling(FeatureMap(["x", "y"]), {"left": "x < 0", "corner": "x < 0 & y < 0 | x > 5 & y > 5"})
>>> sorted(lab.label([-1, -2])), sorted(lab.label([6, 6])), sorted(lab.label([1, 0]))
(['corner', 'left'], ['corner'], [])
>>> lab.condition("corner").to_string(one_line=True)
'x < 0 & y < 0 | x > 5 & y > 5'
>>> FeatureLabeling.from_json(lab.to_json()) == lab
True
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from symlearn.errors import DataError, ParseError, SymlearnError, with_excerpt
from symlearn.grounding.features import FeatureMap
from symlearn.json_document import JsonFile
from symlearn.grounding.labeling import LabelingBase
from symlearn.logic.dnf import DNF
from symlearn.logic.dnf import parse as parse_dnf

FORMAT_VERSION = 1

#: a proposition's condition is a DNF formula over the features (one value type for both uses)
Condition = DNF


def parse_condition(text: str, *, where: str = "condition", source: str | None = None) -> DNF:
    """Read ``"x < 1 & y > 0 | z >= 2"`` (the one-line DNF syntax of :mod:`symlearn.logic.dnf`);
    a mistake is a :class:`ParseError` naming ``where`` and the column within ``text`` (in the
    message, with the condition and a caret: the column is not one of ``source``'s, whose
    condition is a JSON string)."""
    if not isinstance(text, str) or not text.strip():
        raise ParseError(f"{where}: the condition is empty", file=source, hint="write e.g. 'x < 1 & y > 0'")
    if "\n" in text.strip():
        raise ParseError(f"{where}: a condition is one line; join conjunctions with |", file=source)
    try:
        condition = parse_dnf(text)
    except ParseError as exc:
        message = f"{where}: {exc.message}"
        if exc.column is not None:
            message = with_excerpt(f"{where}, column {exc.column} of its condition: {exc.message}", text, exc.column)
        raise ParseError(message, file=source, hint=exc.hint) from None
    if not condition.conjunctions:
        raise ParseError(f"{where}: the condition is never true", file=source)
    return condition


class FeatureLabeling(LabelingBase, JsonFile):
    """Propositions defined by inequality conditions over a feature map (see module docstring)."""

    def __init__(self, features: FeatureMap | Iterable[str], conditions: Mapping[str, str | Condition], *,
                 meanings: Mapping[str, str] | None = None) -> None:
        self.feature_map = features if isinstance(features, FeatureMap) else FeatureMap(list(features))
        if not conditions:
            raise DataError("a feature labeling needs at least one proposition")
        parsed: dict[str, Condition] = {}
        for name, condition in conditions.items():
            if not isinstance(name, str) or not name:
                raise DataError(f"{name!r} is not a proposition name")
            cond = condition if isinstance(condition, DNF) else parse_condition(condition, where=f"proposition {name!r}")
            unknown = sorted(set(cond.features) - set(self.feature_map.names))
            if unknown:
                raise DataError(f"proposition {name!r} uses unknown feature {unknown[0]!r}",
                                hint="features: " + ", ".join(self.feature_map.names))
            parsed[name] = cond
        self._conditions = parsed
        self._meanings = {p: (meanings or {}).get(p, "") for p in parsed}

    @property
    def propositions(self) -> tuple[str, ...]:
        return tuple(self._conditions)

    def condition(self, proposition: str) -> Condition:
        return self._conditions[proposition]

    def label(self, state: Any) -> frozenset[str]:
        row = self.feature_map.features(state)[None, :]
        return frozenset(p for p, c in self._conditions.items() if c.evaluate(row, self.feature_map.names)[0])

    def label_matrix(self, features: np.ndarray) -> np.ndarray:
        """``(N, P)`` booleans for a feature matrix ``(N, k)``, vectorised over the rows."""
        features = np.asarray(features, dtype=np.float64)
        out = np.zeros((features.shape[0], len(self._conditions)), dtype=bool)
        for j, cond in enumerate(self._conditions.values()):
            out[:, j] = cond.evaluate(features, self.feature_map.names)
        return out

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FeatureLabeling):
            return NotImplemented
        return (self.feature_map, self._conditions, self._meanings) == \
            (other.feature_map, other._conditions, other._meanings)

    def __repr__(self) -> str:
        return f"FeatureLabeling({len(self._conditions)} propositions over {self.feature_map.n_features} features)"

    # --- persistence ----------------------------------------------------------------------
    def to_document(self) -> dict[str, Any]:
        if self.feature_map.function is not None:
            raise SymlearnError("this labeling's feature map is a Python function, which cannot be saved")
        return {"symlearn": "labeling", "format_version": FORMAT_VERSION, "kind": "features",
                "features": json.loads(self.feature_map.to_json()),
                "propositions": [{"name": p, "meaning": self._meanings[p], "when": c.to_string(one_line=True)}
                                 for p, c in self._conditions.items()]}

    def to_json(self) -> str:
        return json.dumps(self.to_document(), indent=1)

    @classmethod
    def from_document(cls, doc: Mapping[str, Any], *, source: str = "<string>") -> FeatureLabeling:
        try:
            features = FeatureMap.from_json(json.dumps(doc["features"]), source=source)
            props = doc["propositions"]
            conditions = {p["name"]: parse_condition(p["when"], where=f"proposition {p['name']!r}", source=source)
                          for p in props}
            meanings = {p["name"]: p.get("meaning", "") for p in props}
        except (KeyError, TypeError) as exc:
            raise DataError(f"malformed feature labeling ({type(exc).__name__}: {exc})", file=source,
                            hint="expected 'features': {feature map}, 'propositions': [{name, meaning, when}]") from None
        try:
            return cls(features, conditions, meanings=meanings)
        except DataError as exc:
            raise DataError(exc.message, file=source, hint=exc.hint) from None

    @classmethod
    def from_json(cls, text: str, *, source: str = "<string>") -> FeatureLabeling:
        from symlearn.grounding.labeling import load_labeling_text

        labeling = load_labeling_text(text, source=source)
        if not isinstance(labeling, cls):
            raise DataError("this labeling is not defined by features", file=source)
        return labeling



class CallableLabeling(LabelingBase):
    """``CallableLabeling(function, propositions, meanings=None)``: ``function(state)`` returns the
    names of the true propositions; any name outside ``propositions`` is a :class:`DataError`.

    >>> lab = CallableLabeling(lambda s: {"even"} if s % 2 == 0 else set(), ["even"])
    >>> sorted(lab.label(4)), sorted(lab.label(3))
    (['even'], [])
    """

    def __init__(self, function: Callable[[Any], Iterable[str]], propositions: Iterable[str], *,
                 meanings: Mapping[str, str] | None = None) -> None:
        self.function = function
        self._props = tuple(dict.fromkeys(propositions))
        if not self._props:
            raise DataError("a callable labeling must declare its propositions")
        self._meanings = {p: (meanings or {}).get(p, "") for p in self._props}

    @property
    def propositions(self) -> tuple[str, ...]:
        return self._props

    def label(self, state: Any) -> frozenset[str]:
        found = frozenset(self.function(state))
        unknown = sorted(found - set(self._props))
        if unknown:
            raise DataError(f"the labeling function returned undeclared proposition {unknown[0]!r}",
                            hint="declared: " + ", ".join(self._props))
        return found

    def to_json(self) -> str:
        raise SymlearnError("a labeling defined by a Python function cannot be saved",
                            hint="tabulate it (Labeling) or define it by features (FeatureLabeling)")

    def __repr__(self) -> str:
        return f"CallableLabeling({', '.join(self._props)})"


__all__ = ["CallableLabeling", "Condition", "FeatureLabeling", "parse_condition"]
