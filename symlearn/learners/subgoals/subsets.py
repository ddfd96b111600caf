"""Candidate feature subsets C(F): which features a sub-goal may be defined over.

The user names them (thesis, section 6.4.1: e.g. the xyz of each object). Forms accepted by
:func:`feature_subsets`:

* text ``"red=0,1,2;blue=3,4,5"`` (column indices, or feature names: ``"red=rx,ry,rz"``);
* a mapping ``{"red": [0, 1, 2], "blue": ["bx", "by", "bz"]}``;
* None: one subset ``all`` of every feature (C(F) = {F}, as in the thesis' drone experiment).

>>> [(s.name, s.features) for s in feature_subsets("red=0,1;blue=y", ("x", "y"))]
[('red', (0, 1)), ('blue', (1,))]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from symlearn.errors import DataError


@dataclass(frozen=True)
class FeatureSubset:
    name: str
    features: tuple[int, ...]


def feature_subsets(subsets: Any, feature_names: Sequence[str]) -> list[FeatureSubset]:
    """The subsets as column indices, every name and index checked against ``feature_names``."""
    k = len(feature_names)
    if subsets is None:
        return [FeatureSubset("all", tuple(range(k)))]
    if isinstance(subsets, str):
        subsets = _parse(subsets)
    if not isinstance(subsets, Mapping) or not subsets:
        raise DataError("feature subsets must be a non-empty mapping name -> features",
                        hint="for example 'red=0,1,2;blue=3,4,5'")
    result = []
    for name, columns in subsets.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise DataError(f"feature subset name {name!r} must be an identifier (letters, digits, _)")
        if isinstance(columns, (str, int)):
            columns = [columns]
        indices = []
        for column in columns:
            indices.append(_column(name, column, feature_names))
        if not indices:
            raise DataError(f"feature subset {name!r} names no feature")
        if len(set(indices)) != len(indices):
            raise DataError(f"feature subset {name!r} names a feature twice")
        result.append(FeatureSubset(name, tuple(indices)))
    return result


def _column(subset: str, column: Any, feature_names: Sequence[str]) -> int:
    k = len(feature_names)
    if isinstance(column, str) and not column.strip().lstrip("-").isdigit():
        if column.strip() not in feature_names:
            raise DataError(f"feature subset {subset!r}: no feature named {column.strip()!r}",
                            hint="features: " + ", ".join(feature_names))
        return list(feature_names).index(column.strip())
    try:
        index = int(column)
    except (TypeError, ValueError):
        raise DataError(f"feature subset {subset!r}: {column!r} is neither a column index nor a name") from None
    if isinstance(column, bool) or not 0 <= index < k:
        raise DataError(f"feature subset {subset!r}: column {index} is out of range; the states have {k} "
                        f"features (columns 0..{k - 1})")
    return index


def _parse(text: str) -> dict[str, list[str]]:
    """``name=c,c,...;name=...`` -> mapping (columns as text, resolved by the caller)."""
    result: dict[str, list[str]] = {}
    column = 1
    for part in text.split(";"):
        if not part.strip():
            column += len(part) + 1
            continue
        name, eq, columns = part.partition("=")
        if not eq or not name.strip():
            raise DataError(f"feature subset {part.strip()!r} at column {column} of the subsets text: "
                            "expected name=c,c,...", hint="for example 'red=0,1,2;blue=3,4,5'")
        if name.strip() in result:
            raise DataError(f"feature subset {name.strip()!r} is given twice")
        result[name.strip()] = [c for c in (c.strip() for c in columns.split(",")) if c]
        column += len(part) + 1
    return result
