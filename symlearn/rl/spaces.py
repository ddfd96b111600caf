"""One encoding of gymnasium ``Box`` and ``Discrete`` spaces for the networks that read them.

A space is described as JSON (:func:`space_spec`: ``{"kind": "discrete", "n", "start"}`` or
``{"kind": "box", "shape"}``, with ``bounds`` also ``low``/``high``, an unbounded side as null), so
a saved model names the spaces it was made for; a value becomes a float32 row of
:func:`spec_width` entries: a ``Box`` value flattened, a ``Discrete`` id one-hot (:func:`one_hot`).
PPO's networks (:class:`~symlearn.rl.ppo.ActorCritic`) and the learned neural cost
(:class:`~symlearn.learners.neural.neural_cost.NeuralCost`) both use it. :func:`encode` is the
checked path for data a user brings (demonstrations, a rollout handed to a learned cost): shapes,
whole ids in range and finite numbers, each a :class:`~symlearn.errors.DataError`.
``ActorCritic.features`` encodes every environment step and skips those checks (the environment
itself produced the value).

Numpy only: importing this module does not import torch.

>>> from gymnasium import spaces
>>> space_spec(spaces.Discrete(3, start=1)), spec_width({"kind": "box", "shape": [2, 3]})
({'kind': 'discrete', 'n': 3, 'start': 1}, 6)
>>> encode([1, 3], space_spec(spaces.Discrete(3, start=1)), "ids").tolist()
[[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
"""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.errors import DataError

SPACE_KINDS = ("Box", "Discrete")  # gymnasium's class names of the spaces :func:`space_spec` describes


def space_spec(space: Any, bounds: bool = False) -> dict[str, Any]:
    """A JSON description of a gymnasium Box or Discrete space (with ``bounds``, a Box's
    ``low``/``high`` too, flattened, an unbounded side as null: JSON has no infinity). Callers
    that name who cannot use another kind of space check :data:`SPACE_KINDS` first."""
    kind = type(space).__name__
    if kind == "Discrete":
        return {"kind": "discrete", "n": int(space.n), "start": int(getattr(space, "start", 0))}
    if kind == "Box":
        spec: dict[str, Any] = {"kind": "box", "shape": [int(n) for n in space.shape]}
        if bounds:
            spec["low"] = [float(x) if np.isfinite(x) else None for x in np.asarray(space.low, np.float64).ravel()]
            spec["high"] = [float(x) if np.isfinite(x) else None for x in np.asarray(space.high, np.float64).ravel()]
        return spec
    raise DataError(f"only Box and Discrete spaces can be encoded, got {kind}",
                    hint="flatten dict/tuple spaces with a gymnasium wrapper (e.g. FlattenObservation)")


def spec_width(spec: dict[str, Any]) -> int:
    """Width of the flattened (Box) or one-hot (Discrete) encoding of a space."""
    return int(spec["n"]) if spec["kind"] == "discrete" else int(np.prod(spec["shape"], dtype=np.int64))


def one_hot(ids: np.ndarray, width: int) -> np.ndarray:
    """float32 ``(B, width)`` rows, 1 at each of the ``B`` ids (already shifted to ``0..width-1``)."""
    out = np.zeros((ids.size, width), dtype=np.float32)
    out[np.arange(ids.size), ids] = 1.0
    return out


def rollout_values(rows: np.ndarray, spec: dict[str, Any]) -> np.ndarray:
    """Rows as a PPO rollout holds them -> the values the environment used, as :func:`encode`
    takes them: a Discrete observation's one-hot row (``width`` entries, ``ActorCritic.features``)
    or a Discrete action's index ``0..n-1`` becomes the space's id (``start`` added); a Box row
    (flattened, as the networks read it) gets the space's shape back, so a ``(2, 3)`` observation
    is ``(B, 2, 3)`` again. ``rows`` is ``(B, width)`` for observations, ``(B,)`` for Discrete
    actions.

    >>> spec = {"kind": "discrete", "n": 3, "start": 2}
    >>> rollout_values(np.array([[0, 1, 0], [0, 0, 1]], np.float32), spec).tolist(), rollout_values(np.array([0, 2]), spec).tolist()
    ([3, 4], [2, 4])
    >>> rollout_values(np.zeros((4, 6)), {"kind": "box", "shape": [2, 3]}).shape
    (4, 2, 3)
    """
    if spec["kind"] != "discrete":
        shape = spec.get("shape")
        rows = np.asarray(rows)
        if shape is None or rows.ndim == 0 or rows.size != len(rows) * spec_width(spec):
            return rows     # no shape known, or not one row per value: encode() names the mismatch
        return rows.reshape(len(rows), *shape)
    rows = np.asarray(rows)
    ids = rows.reshape(len(rows), -1).argmax(axis=1) if rows.ndim == 2 else rows.astype(np.int64)
    return ids.astype(np.int64) + int(spec.get("start", 0))


def encode(values: Any, spec: dict[str, Any], what: str) -> np.ndarray:
    """A batch of raw observations or actions -> float32 ``(B, width)`` (one-hot for Discrete).
    Wrong shapes, ids out of range and non-finite numbers are :class:`DataError`."""
    width = spec_width(spec)
    raw = np.asarray(values)
    if raw.size and raw.dtype.kind not in "biuf":
        example = raw.reshape(-1)[0]
        raise DataError(f"{what} must be numbers, got {'text' if raw.dtype.kind == 'U' else raw.dtype} "
                        f"(e.g. {str(example)[:40]!r})",
                        hint="give ids or vectors as numbers, in the order of the environment's space")
    if spec["kind"] == "discrete":
        ids = raw.reshape(-1)
        if ids.size and not np.issubdtype(ids.dtype, np.integer):
            if not np.all(np.isfinite(ids.astype(np.float64))) or np.any(ids != np.round(ids)):
                raise DataError(f"{what} must be whole ids of a Discrete({width}) space")
        ids = ids.astype(np.int64) - spec.get("start", 0)
        if ids.size and (ids.min() < 0 or ids.max() >= width):
            outside = sorted({int(i) for i in ids[(ids < 0) | (ids >= width)]})[:5]
            raise DataError(f"{what} ids outside Discrete({width}): {outside}")
        return one_hot(ids, width)
    with np.errstate(over="ignore"):  # beyond float32's range: said below, not as a numpy warning
        array = np.asarray(values, dtype=np.float32)
    shape = tuple(spec["shape"])
    if array.shape[array.ndim - len(shape):] != shape:
        raise DataError(f"{what} have shape {array.shape[1:] if array.ndim > len(shape) else array.shape}, "
                        f"the space's is {shape}")
    array = array.reshape(-1, width)
    if not np.isfinite(array).all():
        rows = np.flatnonzero(~np.isfinite(array).all(1))
        finite_before = raw.dtype.kind == "f" and bool(np.isfinite(raw.reshape(len(array), -1)[rows[0]]).all())
        reason = "beyond float32's range (about 3.4e38)" if finite_before else "not finite (NaN or inf)"
        raise DataError(f"{what} are {reason} in {rows.size} row(s), the first at row {rows[0]}")
    return array


__all__ = ["SPACE_KINDS", "encode", "one_hot", "rollout_values", "space_spec", "spec_width"]
