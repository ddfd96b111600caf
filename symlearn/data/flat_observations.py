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
from collections.abc import Iterable, Sequence

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
