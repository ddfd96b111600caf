"""Dict and Tuple observations flattened into one vector per step, with a name per column.

symlearn's learners read a state as one numeric vector (or a dict of named scalars, which is
slow for long numeric data), so an observation given as a tree of arrays (gymnasium's ``Dict``
and ``Tuple`` spaces, as Minari stores them and as imitation's ``DictObs`` holds them) becomes
one ``vector`` state: the leaves in key order (sorted, as gymnasium's ``Dict`` sorts them; Tuple
entries ``_index_0, _index_1, ...`` in index order), each leaf's columns in row-major order.
Column names join the keys with ``.`` and add ``[i]`` for the entries of a vector leaf
(``achieved_goal[0]``, ``agent.pos[1]``); the names go into the demonstrations' metadata as
``feature_names``. For ``Box`` leaves this is the order of ``gymnasium.spaces.flatten``;
``Discrete`` leaves stay one integer column (``flatten`` would one-hot them).

Leaves with more than one dimension per step (an image beside a vector) are refused: flattening
would scatter the pixels into thousands of anonymous columns.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from symlearn.errors import DataError

_TUPLE_KEY = re.compile(r"_index_(\d+)\Z")


def ordered_keys(keys: Iterable[str]) -> list[str]:
    """Dict keys sorted; Tuple keys (``_index_<i>``) by their index."""
    keys = list(keys)
    if keys and all(_TUPLE_KEY.match(k) for k in keys):
        return sorted(keys, key=lambda k: int(_TUPLE_KEY.match(k).group(1)))
    return sorted(keys)


def leaf_name(path: Sequence[str]) -> str:
    """``("agent", "_index_1")`` -> ``"agent.1"``."""
    parts = []
    for key in path:
        match = _TUPLE_KEY.match(key)
        parts.append(match.group(1) if match else key)
    return ".".join(parts)


def flatten_leaves(leaves: Sequence[tuple[str, np.ndarray]], what: str) -> tuple[np.ndarray, list[str]]:
    """Stack ``(name, array of shape (T,) or (T, k))`` leaves into ``(T, d)`` and their names."""
    if not leaves:
        raise DataError(f"{what}: the observation has no entries")
    rows = len(leaves[0][1])
    columns, names = [], []
    for name, values in leaves:
        if values.ndim == 0 or len(values) != rows:
            raise DataError(f"{what}: entry {name!r} has {len(values) if values.ndim else 0} rows, "
                            f"entry {leaves[0][0]!r} has {rows}", hint="every entry needs one row per step")
        if values.ndim > 2:
            raise DataError(f"{what}: entry {name!r} has shape {values.shape[1:]} per step; only scalars and "
                            "vectors are flattened into a state vector",
                            hint="record image observations on their own (a Box observation space), not "
                                 "inside a Dict or Tuple")
        if values.dtype.kind not in "biuf":
            raise DataError(f"{what}: entry {name!r} is not numeric (dtype {values.dtype})")
        if values.ndim == 1:
            columns.append(values.reshape(rows, 1))
            names.append(name)
        else:
            columns.append(values)
            names.extend(f"{name}[{i}]" for i in range(values.shape[1]))
    dtype = np.result_type(*(c.dtype for c in columns))
    if dtype.kind == "b":  # booleans alone: keep them numbers, as a vector state must be
        dtype = np.dtype(np.int64)
    return np.concatenate([c.astype(dtype, copy=False) for c in columns], axis=1), names


# --- one live observation (recording, and the names `train --cost` reads) -------------------------
#
# The same names as the stored readers above, so a constraint learned from a Minari dataset, from
# imitation trajectories or from `record()` reads the same columns when an agent is trained: a leaf
# of shape () (``Discrete``, a 0-d ``Box``) is one column named by its path; a leaf of shape (k,)
# gives ``name[0]`` ... ``name[k-1]`` (also for k = 1, as a stored (T, 1) column is named).


def has_parts(value: object) -> bool:
    """Whether a live observation is a tree (a mapping, or a tuple/list holding arrays or
    containers) rather than one value or a plain sequence of numbers."""
    return isinstance(value, Mapping) or (
        isinstance(value, (tuple, list)) and any(isinstance(v, (Mapping, tuple, list, np.ndarray)) for v in value))


def _observation_leaves(value: object, path: tuple[str, ...], leaves: list[tuple[str, np.ndarray]],
                        skip_images: bool, what: str) -> None:
    if isinstance(value, Mapping):
        odd = [key for key in value if not isinstance(key, str)]
        if odd:
            raise DataError(f"{what}: observation keys must be strings, got {odd[0]!r}")
        for key in ordered_keys(value.keys()):
            _observation_leaves(value[key], path + (key,), leaves, skip_images, what)
        return
    if has_parts(value):
        for i, item in enumerate(value):
            _observation_leaves(item, path + (f"_index_{i}",), leaves, skip_images, what)
        return
    array = np.asarray(value)
    name = leaf_name(path) if path else "observation"
    if array.ndim > 1 or array.dtype.kind not in "biuf":
        if skip_images:
            return
        detail = f"has shape {array.shape}" if array.ndim > 1 else f"is not numeric ({array.dtype})"
        raise DataError(f"{what}: entry {name!r} {detail}; only numbers and vectors become named columns",
                        hint="choose what to keep with record(..., observation=lambda o: o[KEY])")
    leaves.append((name, array))


def is_symbolic_mapping(value: object) -> bool:
    """A flat mapping of plain numbers (a grid cell and a key flag): stored as it is, a symbolic state."""
    return (isinstance(value, Mapping) and bool(value)
            and all(isinstance(key, str) for key in value)
            and all(not isinstance(v, (Mapping, tuple, list)) and np.ndim(v) == 0 for v in value.values()))


def observation_columns(value: object, what: str = "observation", *,
                        skip_images: bool = False) -> tuple[np.ndarray, list[str]]:
    """One ``Dict``/``Tuple`` observation as a float vector and a name per entry (the module doc's
    names). Leaves of more than one dimension (an image) are refused, or left out with
    ``skip_images``; so are non-numeric leaves (text)."""
    leaves: list[tuple[str, np.ndarray]] = []
    _observation_leaves(value, (), leaves, skip_images, what)
    columns, names = [], []
    for name, array in leaves:
        if array.ndim == 0:
            columns.append(array.reshape(1))
            names.append(name)
        else:
            columns.append(array)
            names.extend(f"{name}[{i}]" for i in range(len(array)))
    if not columns:
        return np.zeros(0, dtype=np.float64), []
    return np.concatenate([c.astype(np.float64, copy=False) for c in columns]), names


def observation_features(value: object) -> dict[str, float]:
    """The named numbers of one ``Dict``/``Tuple`` observation, as ``info["features"]`` reports them:
    a symbolic mapping by its keys, anything else by :func:`observation_columns` (images left out)."""
    if is_symbolic_mapping(value):
        return {str(key): float(np.asarray(v)) for key, v in value.items()  # type: ignore[union-attr]
                if np.asarray(v).dtype.kind in "biuf"}
    if isinstance(value, (tuple, list)) and not has_parts(value):
        # a Tuple of numbers is stored as a plain vector, whose columns learn dnf calls x0, x1, ...
        return {f"x{i}": float(v) for i, v in enumerate(value) if np.asarray(v).dtype.kind in "biuf"}
    vector, names = observation_columns(value, skip_images=True)
    return dict(zip(names, vector.tolist()))
