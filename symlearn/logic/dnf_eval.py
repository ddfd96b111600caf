"""Compiled evaluation of DNF formulas: what :meth:`symlearn.logic.dnf.DNF.evaluate` runs.

A formula is compiled once (the plan is cached on the value) into per-feature *cell codes*
and one of two combination forms; :mod:`symlearn.logic._dnf_kernels` runs them with numba.

* **Cell codes.** The ``T`` sorted thresholds of a feature cut the line into ``2T + 1`` cells:
  below, on and between the thresholds, code ``#{t < x} + #{t <= x}``. Every atom on the feature
  is a set of consecutive cells, so the atoms of one conjunction on one feature are one code
  interval ``[lo, hi]``. A value finds its code through a uniform grid over the thresholds'
  span: ``g = trunc(clip(x * scale + shift, 0, G + 1))`` is monotone in ``x`` (rounding is), so
  a bucket without a threshold has one code, read from a table, and only values in the few
  buckets that hold a threshold compare against it (the thresholds were bucketed by the same
  float operations, so this is exact). Thresholds spread so unevenly that buckets are crowded
  get a binary search inside the bucket.
* **Bitmasks** (few features, or a formula whose features are few per point): per feature and
  cell, the bits of the conjunctions that allow it; a point ANDs one row per feature. Features
  go in a greedy set-cover order and a point stops as soon as no bit is left or (for the
  disjunction) a conjunction whose features are all done kept its bit.
* **Boxes** (many features): per conjunction, its code intervals are tested on a chunk of
  points at once; codes are 1-, 2- or 4-byte unsigned integers, so a SIMD register tests 16-64
  points.

The form is picked by an estimate of the work per point. NaN in a used column is an error (it
would compare false with every bound); a chunk is swept for NaN before its codes are computed.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from symlearn.errors import DataError

__all__ = ["Plan", "Evaluator", "compile_plan"]

CHUNK = 2048                 # rows per chunk: codes and results of a chunk stay in L1/L2
PARALLEL_MIN_POINTS = 1 << 16  # from this many points, row blocks are evaluated in threads
_THREADS: int | None = None
_POOL = None
_MAX_BUCKETS = 1 << 14       # per feature, 4 bytes a bucket: the tables stay in L1/L2
_BUCKETS_PER_THRESHOLD = 16  # few buckets hold two thresholds of spread-out ones
_kernels = None


def kernels():
    """The numba kernels (imported, and compiled or loaded from numba's cache, on first use)."""
    global _kernels
    if _kernels is None:
        from symlearn.logic import _dnf_kernels

        _kernels = _dnf_kernels
    return _kernels


@dataclass(eq=False)
class Plan:
    """A compiled formula; arrays are read-only and shared by every evaluation."""

    features: tuple[str, ...]          # the used features, in evaluation (step) order
    m: int                             # conjunctions
    use_masks: bool                    # the bitmask form (else boxes)
    grid: np.ndarray                   # [S, 3] scale, shift, top
    offsets: np.ndarray                # [S + 1, 3] bucket table, threshold and mask-row offsets
    first: np.ndarray                  # int32 per bucket: the thresholds in lower buckets
    thresholds: np.ndarray             # float64, per feature sorted and padded with NaN
    masks: np.ndarray                  # [rows, W] uint64: conjunctions a cell allows
    done: np.ndarray                   # [S + 1, W] conjunctions whose features are all done after s steps
    init: np.ndarray                   # [W] satisfiable conjunctions
    test_start: np.ndarray             # [m + 1] int64: the code intervals of conjunction c
    test_step: np.ndarray              # which step (feature) each interval is on
    lo: np.ndarray                     # interval bounds, the code dtype
    hi: np.ndarray
    always: np.ndarray                 # [m] bool: conjunctions without atoms
    never: np.ndarray                  # [m] bool: unsatisfiable conjunctions
    code_dtype: np.dtype = field(default=np.dtype(np.uint16))

    @property
    def mode(self) -> str:
        return "masks" if self.use_masks else "boxes"

    def pack(self, chunk: int = CHUNK) -> tuple[np.ndarray, np.ndarray]:
        """What the kernel takes: one byte array (header, integers, floats, bucket tables, masks,
        constant conjunctions; 8-byte aligned parts) and the code intervals ``[2, tests]``.
        Few arguments, since every argument costs at a call."""
        S = len(self.features)
        W = self.masks.shape[1]
        parts = [np.concatenate([self.offsets.ravel(), self.test_start, self.test_step]).astype(np.int64),
                 np.concatenate([self.grid.ravel(), self.thresholds]).astype(np.float64),
                 self.first.astype(np.int32),
                 np.concatenate([self.masks, self.done, self.init[None, :]]).astype(np.uint64),
                 self.always.astype(np.uint8)]
        blobs = [np.ascontiguousarray(p).view(np.uint8).ravel() for p in parts]
        header = np.zeros(16, dtype=np.int64)
        at = header.nbytes
        starts = []
        for blob in blobs:
            starts.append(at)
            at += -(-len(blob) // 8) * 8
        header[:7] = S, self.m, int(self.use_masks), max(1, chunk), W, len(self.masks), len(self.test_step)
        header[7:13] = starts + [at]
        P = np.zeros(at, dtype=np.uint8)
        P[:header.nbytes] = header.view(np.uint8)
        for start, blob in zip(starts, blobs):
            P[start:start + len(blob)] = blob
        bounds = np.stack([self.lo, self.hi]) if len(self.lo) else np.zeros((2, 0), self.code_dtype)
        return _frozen(P), _frozen(bounds)

    @cached_property
    def packed(self) -> tuple[np.ndarray, ...]:
        return self.pack()

    def run(self, X: np.ndarray, cols: np.ndarray, per_conjunction: bool, *, chunk: int = CHUNK,
            first: bool = False) -> np.ndarray:
        """Truth of every row of ``X`` (``[N, k]`` float64 without NaN in ``cols``), ``cols[s]``
        the column of step ``s``; ``first=True``: per row the index of the first conjunction
        that holds (``m`` when none does), int64 ``[N]``, without the ``[N, m]`` matrix."""
        n = X.shape[0]
        if not self.features or n == 0:
            if first:
                holding = np.flatnonzero(self.always)
                return np.full(n, holding[0] if len(holding) else self.m, dtype=np.int64)
            if per_conjunction:
                return np.broadcast_to(self.always, (n, self.m)).copy()
            return np.full(n, bool(self.always.any()))
        packed = self.packed if chunk == CHUNK else self.pack(chunk)
        k = _kernels or kernels()
        if first:
            out2 = np.empty((n, 1), dtype=np.int64)
            bad = _evaluate(k, X, cols, k.FIRST, out2, packed, chunk)
            out = out2.reshape(n)
        elif per_conjunction:
            out = np.empty((n, self.m), dtype=bool)
            bad = _evaluate(k, X, cols, k.EACH, out, packed, chunk)
        else:
            out2 = np.empty((n, 1), dtype=bool)
            bad = _evaluate(k, X, cols, k.ANY, out2, packed, chunk)
            out = out2.reshape(n)
        if bad >= 0:
            row, step = divmod(int(bad), len(self.features))
            raise DataError(f"feature {self.features[step]} is NaN in point {row}",
                            hint="NaN compares false with every bound; clean or drop those points")
        return out


def _threads() -> int:
    """Threads for one large evaluation: the CPUs this process may run on (at most 8)."""
    global _THREADS
    if _THREADS is None:
        try:
            _THREADS = max(1, min(8, len(os.sched_getaffinity(0))))
        except (AttributeError, OSError):
            _THREADS = max(1, min(8, os.cpu_count() or 1))
    return _THREADS


def _evaluate(k: Any, X: np.ndarray, cols: np.ndarray, mode: int, out: np.ndarray, packed: tuple, chunk: int) -> int:
    """The kernel over all rows; from :data:`PARALLEL_MIN_POINTS` rows on, over row blocks in
    threads (the kernel releases the GIL, and rows are independent). Returns the flat index
    ``row * S + step`` of the first NaN, or -1."""
    n = X.shape[0]
    threads = _threads() if n >= PARALLEL_MIN_POINTS else 1
    if threads == 1:
        return k.evaluate(X, cols, mode, out, *packed)
    global _POOL
    if _POOL is None:
        from concurrent.futures import ThreadPoolExecutor

        _POOL = ThreadPoolExecutor(max_workers=_threads(), thread_name_prefix="symlearn-dnf")
    # blocks of whole chunks, so every thread's chunks are the serial run's chunks
    per = -(-(-(-n // chunk)) // threads) * chunk
    starts = list(range(0, n, per))
    jobs = [_POOL.submit(k.evaluate, X[a:a + per], cols, mode, out[a:a + per], *packed) for a in starts]
    S = int(packed[0][:8].view(np.int64)[0])       # the header's first word: steps per point
    for a, job in zip(starts, jobs):                # the first NaN in row order, as the serial run finds it
        bad = job.result()
        if bad >= 0:
            for later in jobs:
                later.result()
            return bad + a * S
    return -1


class Evaluator:
    """A formula bound to one order of feature columns: ``evaluator(X)`` for ``[N, k]`` or
    ``[k]`` points in that order, without resolving names again (``DNF.evaluator(features)``)."""

    def __init__(self, plan: Plan, names: Sequence[str]) -> None:
        self.plan = plan
        self.names = tuple(names)
        index = {n: i for i, n in enumerate(self.names)}
        missing = [f for f in plan.features if f not in index]
        if missing:
            raise _unknown(missing, self.names)
        self.cols = np.array([index[f] for f in plan.features], dtype=np.intp)
        self._one = (len(self.names),)

    def __call__(self, X: Any, per_conjunction: bool = False) -> np.ndarray:
        if type(X) is np.ndarray and X.dtype == np.float64 and X.shape == self._one:   # one point: no checks to redo
            X = X.reshape(1, -1)
        else:
            X = _as_points(X, len(self.names))
        return self.plan.run(X, self.cols, per_conjunction)

    def first(self, X: Any) -> np.ndarray:
        """Per point, the index of the first conjunction (in the formula's order) that holds, or
        ``m`` when none does: int64 ``[N]`` (what rule counting in ascending complexity needs,
        without an ``[N, m]`` matrix)."""
        if type(X) is np.ndarray and X.dtype == np.float64 and X.shape == self._one:
            X = X.reshape(1, -1)
        else:
            X = _as_points(X, len(self.names))
        return self.plan.run(X, self.cols, False, first=True)


# -- inputs ----------------------------------------------------------------------------------

def feature_names(features: Any) -> tuple[str, ...]:
    names = getattr(features, "names", features)
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",")]
    names = tuple(str(n) for n in names)
    if len(set(names)) != len(names):
        raise DataError(f"feature names repeat: {', '.join(names)}")
    return names


def _unknown(missing: Sequence[str], known: Sequence[str]) -> DataError:
    return DataError(f"unknown feature{'s' if len(missing) > 1 else ''} {', '.join(missing)}",
                     hint="the points have: " + (", ".join(known) or "no features"))


def _as_points(X: Any, k: int, names: Sequence[str] | None = None) -> np.ndarray:
    """``X`` as a float64 ``[N, k]`` array (a view when it already is one)."""
    X = np.asarray(X)
    if X.ndim == 1 and X.shape[0] == k:
        X = X[None, :]
    if X.ndim != 2 or X.shape[1] != k:
        what = f" for features {', '.join(names)}" if names is not None else ""
        raise DataError(f"points must have shape (N, {k}){what}; got {X.shape}")
    if X.dtype != np.float64:
        if X.dtype.kind not in "biuf":
            raise DataError(f"features must hold numbers, not {X.dtype}")
        X = X.astype(np.float64)
    return X


def points(plan: Plan, X: Any, features: Any) -> tuple[np.ndarray, np.ndarray]:
    """The points as one float64 ``[N, k]`` array and the column of every step of ``plan``."""
    used = plan.features
    if isinstance(X, Mapping):
        missing = [f for f in used if f not in X]
        if missing:
            raise _unknown(missing, tuple(X))
        columns = [np.asarray(X[f]) for f in used]
        if any(c.ndim != 1 for c in columns) or len({c.shape for c in columns}) > 1:
            raise DataError("named feature columns must be 1-D arrays of one length; got shapes "
                            + ", ".join(f"{f}: {np.asarray(X[f]).shape}" for f in used))
        for f, c in zip(used, columns):
            if c.dtype.kind not in "biuf":
                raise DataError(f"feature {f} must hold numbers, not {c.dtype}")
        n = columns[0].shape[0] if columns else (len(np.asarray(next(iter(X.values())))) if X else 0)
        block = np.empty((n, len(used)))
        for j, c in enumerate(columns):
            block[:, j] = c
        return block, np.arange(len(used), dtype=np.intp)
    if features is None:
        raise DataError("name the columns of the points (features=[...])")
    names = feature_names(features)
    X = np.asarray(X)
    X = _as_points(X, len(names), names)
    index = {n: i for i, n in enumerate(names)}
    missing = [f for f in used if f not in index]
    if missing:
        raise _unknown(missing, names)
    return X, np.array([index[f] for f in used], dtype=np.intp)


# -- compilation -----------------------------------------------------------------------------

def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a


def _bucket(t: np.ndarray, scale: float, shift: float, top: float) -> np.ndarray:
    """The kernels' bucket of each value (the same float64 operations, in the same order)."""
    u = np.add(np.multiply(t, scale), shift)
    u = np.where(u < top, u, top)
    u = np.where(u > 0.0, u, 0.0)
    return u.astype(np.intp)


def _grid(t: np.ndarray) -> tuple[float, float, float, np.ndarray]:
    """``scale, shift, top`` and the bucket table ``first`` of sorted thresholds ``t``: per bucket
    the thresholds in lower buckets, negated (``-(1 + j)``) when it holds more than one."""
    T = len(t)
    span = float(t[-1]) - float(t[0])                       # Python floats: inf on overflow, no warning
    G = int(min(_MAX_BUCKETS, max(16, _BUCKETS_PER_THRESHOLD * T)))
    # t[0] falls in the middle of bucket 1 and t[-1] in bucket G: values beyond the thresholds
    # fill buckets 0 and G + 1, which hold none
    scale = (G - 1) / span if span > 0 else 1.0
    shift = 1.5 - float(t[0]) * scale
    if not (math.isfinite(scale) and math.isfinite(shift) and scale > 0):
        G, scale, shift = -1, 0.0, 0.0                       # one bucket: a binary search over all
    top = float(G + 1)
    counts = np.bincount(_bucket(t, scale, shift, top), minlength=G + 2)
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    crowded = counts > 1
    first[crowded] = -(1 + first[crowded])
    return scale, shift, top, first.astype(np.int32)


def _cell_intervals(formula: Any, features: Sequence[str], thresholds: dict[str, list[float]]):
    """Per conjunction: ``{step: (lo, hi)}`` code intervals (``None`` when unsatisfiable)."""
    position = {f: {v: i for i, v in enumerate(thresholds[f])} for f in features}
    step_of = {f: s for s, f in enumerate(features)}
    boxes = []
    for c in formula.conjunctions:
        box: dict[int, list[int]] = {}
        for a in c.atoms:
            T = len(thresholds[a.feature])
            s = step_of[a.feature]
            lo, hi = box.get(s, (0, 2 * T))
            i = position[a.feature][a.value]
            if a.op == "<":
                hi = min(hi, 2 * i)
            elif a.op == "<=":
                hi = min(hi, 2 * i + 1)
            elif a.op == ">":
                lo = max(lo, 2 * i + 2)
            else:
                lo = max(lo, 2 * i + 1)
            box[s] = (lo, hi)
        boxes.append(None if any(lo > hi for lo, hi in box.values()) else box)
    return boxes


def _order(formula: Any) -> list[str]:
    """Features in greedy set-cover order: each next one appears in the most conjunctions not
    yet touched (ties: in the most conjunctions, then by name), so points leave early."""
    uses: dict[str, set[int]] = {}
    for j, c in enumerate(formula.conjunctions):
        for a in c.atoms:
            uses.setdefault(a.feature, set()).add(j)
    left = sorted(uses)
    untouched = set(range(len(formula.conjunctions)))
    order = []
    while left:
        best = max(left, key=lambda f: (len(uses[f] & untouched), len(uses[f]), [-ord(ch) for ch in f]))
        order.append(best)
        left.remove(best)
        untouched -= uses[best]
    return order


def _bits(flags: np.ndarray, W: int) -> np.ndarray:
    """Boolean ``[..., m]`` -> ``[..., W]`` uint64 words, bit ``c`` = conjunction ``c``."""
    flags = np.asarray(flags, dtype=bool)
    padded = np.zeros(flags.shape[:-1] + (64 * W,), dtype=bool)
    padded[..., : flags.shape[-1]] = flags
    return np.ascontiguousarray(np.packbits(padded, axis=-1, bitorder="little").view("<u8"))


#: the largest mask tables compile_plan builds (bytes); beyond, a formula is evaluated by box tests
MASK_BYTES = 64 << 20


def compile_plan(formula: Any, *, mode: str | None = None) -> Plan:
    """Compile ``formula`` (a :class:`~symlearn.logic.dnf.DNF`); ``mode`` forces ``"masks"`` or
    ``"boxes"`` (tests use it), else the cheaper one by an estimate of the work per point."""
    conjunctions = formula.conjunctions
    m = len(conjunctions)
    W = max(1, -(-m // 64))
    features = _order(formula)
    S = len(features)
    thresholds = {f: sorted({a.value for c in conjunctions for a in c.atoms if a.feature == f}) for f in features}
    boxes = _cell_intervals(formula, features, thresholds)
    never = np.array([b is None for b in boxes], dtype=bool)
    always = np.array([b is not None and not b for b in boxes], dtype=bool)

    # the mask tables hold a bit per (threshold cell, conjunction) and feature: quadratic in the
    # formula (100,000 conjunctions over one feature's 100,000 thresholds: 2.5 GB packed, 20 GB
    # while built). Past MASK_BYTES only the box tests are compiled, which are linear
    mask_bytes = sum(2 * len(thresholds[f]) + 1 for f in features) * W * 8
    build_masks = mask_bytes <= MASK_BYTES or mode == "masks"
    grid = np.zeros((S, 3))
    offsets = np.zeros((S + 1, 3), dtype=np.intp)
    tables, padded, mask_rows = [], [], []
    for s, f in enumerate(features):
        t = np.array(thresholds[f], dtype=np.float64)
        scale, shift, top, first = _grid(t)
        grid[s] = scale, shift, top
        tables.append(first)
        padded.append(np.concatenate([t, [np.nan]]))     # compares false with everything, +inf too
        cells = np.arange(2 * len(t) + 1)
        if build_masks:
            allowed = np.ones((len(cells), m), dtype=bool)
            for j, box in enumerate(boxes):
                if box is None:
                    allowed[:, j] = False
                elif s in box:
                    lo, hi = box[s]
                    allowed[:, j] = (cells >= lo) & (cells <= hi)
            mask_rows.append(_bits(allowed, W))
        offsets[s + 1] = offsets[s] + (len(first), len(t) + 1, len(cells))
    largest_code = max((2 * len(v) for v in thresholds.values()), default=0)
    code_dtype = np.dtype(np.uint8 if largest_code < 1 << 8 else np.uint16 if largest_code < 1 << 16 else np.uint32)

    seen: set[int] = set()
    done = np.zeros((S + 1, m), dtype=bool)
    for s in range(S + 1):
        done[s] = [b is not None and set(b) <= seen for b in boxes]
        if s < S:
            seen.add(s)
    test_start, test_step, lo, hi = [0], [], [], []
    for box in boxes:
        for s, (a, b) in sorted((box or {}).items()):
            test_step.append(s)
            lo.append(a)
            hi.append(b)
        test_start.append(len(test_step))

    if mode is None:
        # measured per point on this kernel (ns, 2-core VM): a mask step ~0.9 with one or two
        # words (kept in registers), else ~1.2 + 0.12 per word (early exits included); a box
        # test ~0.012 on 1-byte codes, ~0.017 on wider ones (SIMD over the points)
        mask_cost = S * (0.9 if W <= 2 else 1.2 + 0.12 * W)
        box_cost = len(test_step) * (0.012 if code_dtype.itemsize == 1 else 0.017)
        use_masks = build_masks and mask_cost <= box_cost
    else:
        if mode not in ("masks", "boxes"):
            raise ValueError(f"mode must be 'masks' or 'boxes', not {mode!r}")
        use_masks = mode == "masks"

    empty_rows = np.zeros((0, W), dtype=np.uint64)
    return Plan(
        features=tuple(features), m=m, use_masks=use_masks, grid=_frozen(grid), offsets=_frozen(offsets),
        first=_frozen(np.concatenate(tables) if tables else np.zeros(0, np.int32)),
        thresholds=_frozen(np.concatenate(padded) if padded else np.zeros(0)),
        masks=_frozen(np.concatenate(mask_rows) if mask_rows else empty_rows),
        done=_frozen(_bits(done, W)), init=_frozen(_bits(~never, W)),
        test_start=_frozen(np.array(test_start, dtype=np.intp)), test_step=_frozen(np.array(test_step, dtype=np.intp)),
        lo=_frozen(np.array(lo, dtype=code_dtype)), hi=_frozen(np.array(hi, dtype=code_dtype)),
        always=_frozen(always), never=_frozen(never), code_dtype=code_dtype,
    )
