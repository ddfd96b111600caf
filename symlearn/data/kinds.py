"""Recognise and normalise the per-step values of a trajectory (states or actions).

A column of values has one *kind*:

``discrete``  integer ids, stored as an ``int64`` array of shape ``(T,)``
``vector``    numbers, stored as a numeric array of shape ``(T,)`` (scalars) or ``(T, d)``
``image``     numeric arrays of two or more dimensions per step, shape ``(T, H, W[, C])``
``features``  dicts of named scalar features (numbers, booleans, strings), a tuple of dicts
``symbol``    strings such as ``"go(north)"``, a tuple of ``str``

Normalising on construction means equality after a save/load round trip is plain equality.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np

from symlearn.errors import DataError

Kind = Literal["discrete", "vector", "image", "features", "symbol"]
KINDS: tuple[Kind, ...] = ("discrete", "vector", "image", "features", "symbol")
ARRAY_KINDS = frozenset({"discrete", "vector", "image"})

_FEATURE_SCALARS = (bool, int, float, str)
_INT64_MAX = int(np.iinfo(np.int64).max)


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def normalize_column(values: Any, what: str) -> tuple[Kind, Any]:
    """Return ``(kind, normalised values)`` or raise :class:`DataError` naming ``what``."""
    if isinstance(values, np.ndarray):
        return _normalize_array(values, what)
    if isinstance(values, (str, bytes, Mapping)) or not isinstance(values, Sequence):
        raise DataError(f"{what} must be a sequence of per-step values, got {type(values).__name__}")
    items = list(values)
    if not items:
        return "discrete", np.zeros(0, dtype=np.int64)
    if all(_is_int(v) for v in items):
        odd = next((t for t, v in enumerate(items) if not -_INT64_MAX - 1 <= int(v) <= _INT64_MAX), None)
        if odd is not None:
            raise DataError(f"{what} hold {int(items[odd])} at step {odd}, beyond int64 "
                            f"(the largest integer symlearn keeps is {_INT64_MAX})")
        return "discrete", np.asarray(items, dtype=np.int64)
    if all(isinstance(v, str) for v in items):
        for t, v in enumerate(items):
            check_text(v, f"{what} at step {t}")
        return "symbol", tuple(items)
    if all(isinstance(v, Mapping) for v in items):
        return "features", _normalize_features(items, what)
    if any(isinstance(v, (str, Mapping)) for v in items):
        first = type(items[0]).__name__
        odd = next(t for t, v in enumerate(items) if type(v) is not type(items[0]))
        ids_and_names = {type(items[0]).__name__, type(items[odd]).__name__} == {"int", "str"}
        raise DataError(
            f"{what} mixes value types: step 0 is {first}, step {odd} is {type(items[odd]).__name__}",
            hint=same_kind_hint(what.split()[0].rstrip("s"), "discrete", "symbol") if ids_and_names else None,
        )
    return _normalize_array(_stack(items, what), what)


def _stack(items: list[Any], what: str) -> np.ndarray:
    shapes = [np.shape(v) for v in items]
    for t, shape in enumerate(shapes):
        if shape != shapes[0]:
            raise DataError(
                f"{what} are ragged: step {t} has shape {shape}, step 0 has shape {shapes[0]}",
                hint="every step must have the same shape",
            )
    try:
        return np.asarray(items)
    except (ValueError, TypeError) as exc:  # nested ragged lists
        raise DataError(f"{what} are ragged or not numeric: {exc}") from None


def _normalize_array(array: np.ndarray, what: str) -> tuple[Kind, np.ndarray]:
    if array.ndim == 0:
        raise DataError(f"{what} must have one entry per step, got a scalar")
    if array.dtype.kind == "U" and array.ndim == 1:
        return "symbol", tuple(str(v) for v in array)
    if array.dtype.kind not in "biuf":
        raise DataError(f"{what} must be numeric, got dtype {array.dtype}")
    if array.ndim >= 2 and 0 in array.shape[1:]:
        raise DataError(f"{what} hold no value per step (per-step shape {array.shape[1:]})",
                        hint="every step needs at least one number")
    if array.dtype.kind == "u" and array.ndim == 1 and array.size and int(array.max()) > _INT64_MAX:
        # int64 is how ids and integer vectors are kept: a larger uint64 would wrap to a negative number
        step = int(np.argwhere(array > _INT64_MAX)[0][0])
        raise DataError(f"{what} hold {int(array[array > _INT64_MAX][0])} at step {step}, beyond int64 "
                        f"(the largest integer symlearn keeps is {_INT64_MAX})")
    if array.dtype.kind in "iu" and array.ndim == 1:
        return "discrete", array.astype(np.int64)
    if array.dtype.kind == "b":
        array = array.astype(np.int64)
        if array.ndim == 1:
            return "discrete", array
    check_finite(array, what)
    kind: Kind = "vector" if array.ndim <= 2 else "image"
    return kind, np.ascontiguousarray(array)


class NonFiniteValues(DataError):
    """A step holds NaN or infinity (:func:`check_finite`); ``record()`` adds the episode and what to do."""

    def __init__(self, message: str, *, value: float | None = None, step: int | None = None, **location: Any) -> None:
        super().__init__(message, **location)   # re-raised as type(exc)(message, file=...) by some readers
        self.value, self.step = value, step


def check_finite(array: np.ndarray, what: str) -> None:
    """Raise :class:`NonFiniteValues` naming the first step that holds NaN or infinity."""
    if array.dtype.kind != "f":
        return
    bad = ~np.isfinite(array)
    if bad.any():
        step = int(np.argwhere(bad)[0][0])
        value = array.reshape(len(array), -1)[step][bad.reshape(len(array), -1)[step]][0]
        raise NonFiniteValues(f"{what} hold a non-finite value ({value}) at step {step}", value=float(value), step=step)


def check_text(value: str, where: str) -> None:
    # NUL cannot survive numpy's fixed-width strings in NPZ and never means anything in a symbol.
    if "\x00" in value:
        raise DataError(f"{where} contains a NUL character")


def _normalize_features(items: list[Mapping], what: str) -> tuple[dict[str, Any], ...]:
    keys = set(items[0])
    rows = []
    for t, row in enumerate(items):
        if set(row) != keys:
            missing = sorted(keys - set(row))
            extra = sorted(set(row) - keys)
            raise DataError(
                f"{what} have different feature names at step {t}: missing {missing}, extra {extra}"
            )
        clean: dict[str, Any] = {}
        for name, value in row.items():
            if not isinstance(name, str) or not name or "\x00" in name:
                raise DataError(f"{what}: feature names must be non-empty strings, got {name!r} at step {t}")
            clean[name] = _feature_scalar(value, f"{what}, feature {name!r} at step {t}")
        rows.append(clean)
    return tuple(rows)


def _feature_scalar(value: Any, where: str) -> Any:
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if _is_int(value):
        return int(value)
    if isinstance(value, numbers.Real):
        value = float(value)
        if not math.isfinite(value):
            raise DataError(f"{where} is not finite ({value})")
        return value
    if isinstance(value, str):
        check_text(value, where)
        return value
    raise DataError(f"{where} must be a number, boolean or string, got {type(value).__name__}")


def step_shape(kind: Kind, values: Any) -> tuple:
    """Shape of one step's value (array kinds) or the sorted feature names (features)."""
    if kind in ARRAY_KINDS:
        return tuple(values.shape[1:])
    if kind == "features":
        return tuple(sorted(values[0])) if values else ()
    return ()


def column_length(values: Any) -> int:
    return len(values)


def as_python(kind: Kind, values: Any, t: int) -> Any:
    """The value of step ``t`` as a hashable Python object (tuples for arrays)."""
    if kind == "discrete":
        return int(values[t])
    if kind in ("vector", "image"):
        row = values[t]
        return row.item() if row.ndim == 0 else tuple(row.ravel().tolist())
    if kind == "features":
        return tuple(sorted(values[t].items()))
    return values[t]


def columns_equal(kind: Kind, a: Any, b: Any) -> bool:
    if kind in ARRAY_KINDS:
        return a.dtype == b.dtype and a.shape == b.shape and bool(np.array_equal(a, b))
    return tuple(a) == tuple(b)


def same_kind_hint(what: str, kind: str, other: str) -> str | None:
    """Integer ids in one place and names in another (a domain reads either) are one mistake: say the fix."""
    if {kind, other} == {"discrete", "symbol"}:
        return (f"write every {what} of the file the same way, all as integer ids or all as names (strings): "
                "a domain folder reads either, but one file holds one kind")
    return None
