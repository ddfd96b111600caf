"""Feature maps: a raw state as named numeric features.

One-class trees, sub-goal clustering and feature-defined labelings all speak of *named*
features (``speed``, ``x``, ``dist_to_obstacle``), while environments hand out arrays, dicts or
objects. A :class:`FeatureMap` is that translation, as a value:

* ``FeatureMap(["x", "y"])`` reads a vector state by position (``state[0]`` is ``x``) and a
  mapping state by key;
* ``FeatureMap(["x", "y"], function=f)`` calls ``f(state)`` (a vector in ``names`` order or a
  mapping) -- the Python form, for derived features; it cannot be saved;
* ``FeatureMap(["x", "y"], table=...)`` holds the features of finitely many hashable states
  (an ``(S, k)`` array indexed by integer state ids, or a mapping state -> vector).

A name is any one-line text; in a condition, one that is not an identifier is double-quoted
(``"pos[0]" > 0.5``, as DNF files write the names ``record`` gives a ``Dict`` observation's
parts). ``features(state)`` returns a float vector in ``names`` order; NaN and infinite values are a
:class:`~symlearn.errors.DataError` (a learner fed NaN would silently learn nonsense).

>>> fm = FeatureMap(["x", "y"])
>>> fm.features([0.5, 2]).tolist(), fm.features({"y": 1, "x": 3}).tolist()
([0.5, 2.0], [3.0, 1.0])
>>> FeatureMap.from_json(fm.to_json()) == fm
True
"""

from __future__ import annotations

import json
from collections.abc import Callable, Hashable, Mapping, Sequence
from typing import Any

import numpy as np

from symlearn.errors import DataError, SymlearnError
from symlearn.json_document import JsonFile, read_document
from symlearn.json_position import JsonPathError, located

FORMAT_VERSION = 1
MAGIC = "feature-map"


class FeatureMap(JsonFile):
    """Named numeric features of a state (see the module docstring for the three forms)."""

    def __init__(self, names: Sequence[str], *, function: Callable[[Any], Any] | None = None,
                 table: np.ndarray | Mapping[Hashable, Sequence[float]] | None = None) -> None:
        names = tuple(names)
        if not names:
            raise DataError("a feature map needs at least one feature name")
        for n in names:
            # any one-line name: conditions over it quote it as DNF files do ("achieved_goal[0]" > 0.5)
            if not isinstance(n, str) or not n.strip() or "\n" in n or "\r" in n:
                raise DataError(f"feature name {n!r} must be a non-empty name on one line",
                                hint='a name that is not an identifier is quoted in conditions: "pos[0]" > 0.5')
        if len(set(names)) != len(names):
            raise DataError(f"feature names repeat: {', '.join(names)}")
        if function is not None and table is not None:
            raise SymlearnError("give a function or a table, not both")
        self.names = names
        self.function = function
        self._table: np.ndarray | dict[Hashable, np.ndarray] | None = None
        if isinstance(table, Mapping):
            self._table = {k: self._check(np.asarray(v, dtype=np.float64), f"state {k!r}") for k, v in table.items()}
        elif table is not None:
            array = np.asarray(table, dtype=np.float64)
            if array.ndim != 2 or array.shape[1] != len(names):
                raise DataError(f"a feature table must have shape (S, {len(names)}), got {array.shape}")
            self._table = self._check(array, "the feature table")

    @property
    def n_features(self) -> int:
        return len(self.names)

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise DataError(f"unknown feature {name!r}", hint="known: " + ", ".join(self.names)) from None

    def _check(self, vector: np.ndarray, where: str) -> np.ndarray:
        if vector.shape[-1:] != (len(self.names),):
            raise DataError(f"{where}: expected {len(self.names)} features ({', '.join(self.names)}), "
                            f"got shape {vector.shape}")
        if not np.isfinite(vector).all():
            raise DataError(f"{where}: features must be finite (found NaN or inf)")
        return vector

    def features(self, state: Any) -> np.ndarray:
        """The feature vector of one state, in :attr:`names` order."""
        if self._table is not None:
            return self._lookup(state)
        value = self.function(state) if self.function is not None else state
        if isinstance(value, Mapping):
            missing = [n for n in self.names if n not in value]
            if missing:
                raise DataError(f"state has no feature {missing[0]!r}", hint="it has: " + ", ".join(map(str, value)))
            value = [value[n] for n in self.names]
        try:
            vector = np.asarray(value, dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise DataError(f"state {state!r} has no numeric features") from None
        return self._check(vector, "state")

    __call__ = features

    def _lookup(self, state: Any) -> np.ndarray:
        table = self._table
        if isinstance(table, dict):
            key = state.item() if hasattr(state, "item") and getattr(state, "ndim", 1) == 0 else state
            if key not in table:
                raise DataError(f"state {state!r} is not in the feature table")
            return table[key]
        if isinstance(state, (bool, np.bool_)) or not isinstance(state, (int, np.integer)) \
                or not 0 <= int(state) < len(table):
            raise DataError(f"state {state!r} is not a state id of the feature table (0..{len(table) - 1})")
        return table[int(state)]

    def matrix(self, states: Sequence[Any]) -> np.ndarray:
        """``(len(states), k)`` features of many states."""
        return np.stack([self.features(s) for s in states]) if len(states) else np.zeros((0, self.n_features))

    def as_dict(self, state: Any) -> dict[str, float]:
        return dict(zip(self.names, self.features(state).tolist()))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FeatureMap):
            return NotImplemented
        if self.names != other.names or self.function is not other.function:
            return False
        a, b = self._table, other._table
        if isinstance(a, np.ndarray) and isinstance(b, np.ndarray):
            return a.shape == b.shape and bool(np.array_equal(a, b))
        if isinstance(a, dict) and isinstance(b, dict):
            return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)
        return a is None and b is None

    def __repr__(self) -> str:
        kind = "function" if self.function is not None else "table" if self._table is not None else "by name/position"
        return f"FeatureMap({', '.join(self.names)}; {kind})"

    # --- persistence ----------------------------------------------------------------------
    def to_json(self) -> str:
        if self.function is not None:
            raise SymlearnError("a feature map defined by a Python function cannot be saved",
                                hint="save the features as a table instead (FeatureMap(names, table=...))")
        doc: dict[str, Any] = {"symlearn": MAGIC, "format_version": FORMAT_VERSION, "names": list(self.names)}
        if isinstance(self._table, np.ndarray):
            doc["table"] = self._table.tolist()
        elif isinstance(self._table, dict):
            doc["table_by_state"] = [[k, v.tolist()] for k, v in self._table.items()]
        return json.dumps(doc)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<string>") -> FeatureMap:
        doc = read_document(text, MAGIC, FORMAT_VERSION, source=source)
        try:
            _check_rows(doc)
        except JsonPathError as exc:
            exc.file = source
            raise located(exc, text) from None
        try:
            names = doc["names"]
            if "table" in doc:
                return cls(names, table=np.asarray(doc["table"], dtype=np.float64))
            if "table_by_state" in doc:
                return cls(names, table={_key(k): v for k, v in doc["table_by_state"]})
            return cls(names)
        except (KeyError, TypeError, ValueError) as exc:
            raise DataError(f"malformed feature map ({type(exc).__name__}: {exc})", file=source) from None
        except DataError as exc:
            raise DataError(exc.message, file=source, hint=exc.hint) from None



def _key(value: Any) -> Hashable:
    return tuple(_key(v) for v in value) if isinstance(value, list) else value


__all__ = ["FeatureMap"]


def _check_rows(doc: Any) -> None:
    """Each row of ``table`` (and each ``[state, row]`` of ``table_by_state``) a list of numbers
    with one entry per name, named by its JSON path: numpy's own words for a ragged table
    ("inhomogeneous shape after 1 dimensions") say neither which row nor what was expected."""
    names = doc.get("names")
    width = len(names) if isinstance(names, list) else None
    rows: list[tuple[tuple, Any]] = []
    if isinstance(doc.get("table"), list):
        rows = [(("table", i), row) for i, row in enumerate(doc["table"])]
    if isinstance(doc.get("table_by_state"), list):
        for i, entry in enumerate(doc["table_by_state"]):
            if not isinstance(entry, list) or len(entry) != 2:
                raise JsonPathError("expected [state, [feature values]]", path=("table_by_state", i))
            rows.append((("table_by_state", i, 1), entry[1]))
    for path, row in rows:
        if not isinstance(row, list) or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in row):
            raise JsonPathError("expected a list of numbers, one per feature name", path=path)
        if width is not None and len(row) != width:
            raise JsonPathError(f"{len(row)} values for {width} feature names ({', '.join(map(str, names))})",
                                path=path)
