"""numba kernels of compiled DNF evaluation (see :mod:`symlearn.logic.dnf_eval`).

Imported on the first evaluation only, so ``import symlearn.logic`` does not load numba.
Compiled with ``cache=True``: the machine code is kept in ``__pycache__`` (or numba's user
cache) and later processes load it instead of compiling again.

Every kernel works on one chunk of rows ``[start, stop)`` of the points ``X`` (``[N, k]`` float64,
any strides); ``cols[s]`` is the column of step ``s`` (the plan's ``s``-th used feature).
"""

from __future__ import annotations

import numpy as np
from numba import njit

_OPTIONS = {"cache": True, "nogil": True, "boundscheck": False}
_U = np.uintp
_L1_BYTES = 16384
_FEW = 8           # up to this many points go the bitmask way whatever the plan's form
_SCAN = 8          # thresholds scanned one by one in a bucket before a binary search takes over
# what a kernel writes per point: whether any conjunction holds ([N, 1] bool), which ones hold
# ([N, m] bool), or the index of the first that holds, m when none does ([N, 1] int64)
ANY, EACH, FIRST = 0, 1, 2


@njit(**_OPTIONS)
def first_nan(X, start, stop, cols):
    """Flat index ``row * S + step`` of the first NaN in a used column of the chunk, else -1."""
    S = cols.shape[0]
    for i in range(start, stop):
        for s in range(S):
            v = X[i, cols[s]]
            if v != v:
                return i * S + s
    return -1


@njit(**_OPTIONS)
def _in_bucket(x, t, lo, hi, j):
    """Cell code of ``x`` given that ``t[lo + j]`` is the first threshold that may not lie below
    it (``t[lo:hi]`` sorted): ``#{t < x} + #{t <= x}``, counted from ``j``."""
    n = hi - lo
    stop = min(n, j + _SCAN)
    while j < stop and t[lo + j] < x:
        j += 1
    if j == stop and j < n and t[lo + j] < x:          # a crowded bucket: binary search the rest
        a, b = j, n
        while a < b:
            mid = (a + b) >> 1
            if t[lo + mid] < x:
                a = mid + 1
            else:
                b = mid
        j = a
    code = 2 * j
    if j < n and t[lo + j] == x:
        code += 1
    return code


@njit(**_OPTIONS)
def codes(X, start, stop, cols, grid, offsets, first, thresholds, out):
    """``out[s, i - start]``: the cell code of ``X[i, cols[s]]``; returns whether a used value of
    the chunk is NaN (its code is then meaningless).

    A monotone bucket ``g = trunc(clip(x * scale + shift, 0, top))``; ``j = first[g]`` counts the
    thresholds of the lower buckets, all below ``x``, and the bucket's threshold ``t[j]`` (NaN
    past the last) is compared without a branch: ``code = 2 j + (t < x) + (t <= x)``. A bucket
    with several thresholds (rare: the grid has ``16 T`` buckets) has ``first[g] = -(1 + j)`` and
    a search from ``j``. Indices are unsigned: no wraparound arithmetic."""
    S = cols.shape[0]
    r = stop - start
    nan = False
    for s in range(S):
        col = _U(cols[s])
        scale = grid[s, 0]
        shift = grid[s, 1]
        top = grid[s, 2]
        f_s = first[offsets[s, 0]:offsets[s + 1, 0]]
        t_s = thresholds[offsets[s, 1]:offsets[s + 1, 1]]
        row = out[s]
        for i in range(r):
            x = X[_U(start + i), col]
            nan |= x != x
            u = x * scale + shift
            u = u if u < top else top
            u = u if u > 0.0 else 0.0
            j = np.intp(f_s[_U(u)])
            if j >= 0:
                t = t_s[_U(j)]
                row[_U(i)] = 2 * j + (t < x) + (t <= x)
            else:
                row[_U(i)] = _in_bucket(x, t_s, 0, t_s.shape[0] - 1, -j - 1)
    return nan


@njit(**_OPTIONS)
def combine_masks(codes_, r, offsets, masks, done, init, out, start, mode, m):
    """Bitmask form: AND the rows of conjunction bits that each feature's cell allows. One or
    two words stay in registers and every point takes every step (no branch to mispredict);
    wider masks stop a point as soon as no bit is left or, for the disjunction, a conjunction
    whose features are all done kept its bit. ``FIRST``: the lowest bit left."""
    S = codes_.shape[0]
    W = masks.shape[1]
    per_conjunction = mode != ANY
    if W <= 2 and mode == ANY:
        i0 = init[0]
        i1 = init[1] if W == 2 else np.uint64(0)
        for i in range(r):
            a0 = i0
            a1 = i1
            for s in range(S):
                row = _U(offsets[s, 2] + np.intp(codes_[s, i]))
                a0 &= masks[row, 0]
                if W == 2:
                    a1 &= masks[row, 1]
            out[start + i, 0] = (a0 | a1) != 0
        return
    acc = np.empty(W, np.uint64)
    for i in range(r):
        hit = False
        for w in range(W):
            acc[w] = init[w]
            if acc[w] & done[0, w]:
                hit = True
        if not hit or per_conjunction:
            for s in range(S):
                row = _U(offsets[s, 2] + np.intp(codes_[s, i]))
                left = np.uint64(0)
                fired = np.uint64(0)
                for w in range(W):
                    v = acc[w] & masks[row, w]
                    acc[w] = v
                    left |= v
                    fired |= v & done[s + 1, w]
                if left == 0:
                    break
                if fired != 0 and not per_conjunction:
                    hit = True
                    break
        if mode == EACH:
            for c in range(m):
                out[start + i, c] = ((acc[c >> 6] >> np.uint64(c & 63)) & np.uint64(1)) != 0
        elif mode == FIRST:
            first = m
            for w in range(W):
                v = acc[w]
                if v != 0:
                    b = 0
                    while (v & np.uint64(1)) == 0:
                        v >>= np.uint64(1)
                        b += 1
                    first = min(m, w * 64 + b)
                    break
            out[start + i, 0] = first
        else:
            out[start + i, 0] = hit


@njit(**_OPTIONS)
def combine_boxes(codes_, r, test_start, test_step, lo, hi, always, out, start, mode, res, tmp, firsts):
    """Box form: conjunction ``c`` holds where every code lies in its interval; vectorised over
    the points of the chunk (codes are small unsigned integers, many to a SIMD register).
    ``res`` and ``tmp`` are uint8 scratch rows, ``firsts`` an int64 one (``FIRST``)."""
    m = test_start.shape[0] - 1
    per_conjunction = mode != ANY
    for i in range(r):
        res[i] = 0
        firsts[i] = m
    open_ = r                    # FIRST: points no conjunction has held on yet
    for c in range(m):
        if mode == FIRST and open_ == 0:
            break
        a = test_start[c]
        b = test_start[c + 1]
        if b == a:
            value = np.uint8(always[c])
            if mode == EACH:
                for i in range(r):
                    out[start + i, c] = value != 0
            elif mode == FIRST:
                if value != 0:
                    for i in range(r):
                        if firsts[i] == m:
                            firsts[i] = c
                            open_ -= 1
            else:
                for i in range(r):
                    res[i] |= value
            continue
        if b - a == 1:
            f = codes_[test_step[a]]
            l0, h0 = lo[a], hi[a]
            for i in range(r):
                tmp[i] = (f[i] >= l0) & (f[i] <= h0)
        else:
            f = codes_[test_step[a]]
            g = codes_[test_step[a + 1]]
            l0, h0, l1, h1 = lo[a], hi[a], lo[a + 1], hi[a + 1]
            if b - a == 2 and not per_conjunction:      # the common case straight into res
                for i in range(r):
                    res[i] |= (f[i] >= l0) & (f[i] <= h0) & (g[i] >= l1) & (g[i] <= h1)
                continue
            for i in range(r):
                tmp[i] = (f[i] >= l0) & (f[i] <= h0) & (g[i] >= l1) & (g[i] <= h1)
            j = a + 2
            while j < b:
                f = codes_[test_step[j]]
                l0, h0 = lo[j], hi[j]
                if j + 1 < b:
                    g = codes_[test_step[j + 1]]
                    l1, h1 = lo[j + 1], hi[j + 1]
                    for i in range(r):
                        tmp[i] &= (f[i] >= l0) & (f[i] <= h0) & (g[i] >= l1) & (g[i] <= h1)
                else:
                    for i in range(r):
                        tmp[i] &= (f[i] >= l0) & (f[i] <= h0)
                j += 2
        if mode == EACH:
            for i in range(r):
                out[start + i, c] = tmp[i] != 0
        elif mode == FIRST:
            for i in range(r):
                if tmp[i] != 0 and firsts[i] == m:
                    firsts[i] = c
                    open_ -= 1
        else:
            for i in range(r):
                res[i] |= tmp[i]
    if mode == FIRST:
        for i in range(r):
            out[start + i, 0] = firsts[i]
    elif mode == ANY:
        for i in range(r):
            out[start + i, 0] = res[i] != 0


# the header of a packed plan (see dnf_eval.Plan.pack): int64 words at the start of its bytes
H_S, H_M, H_MASKS, H_CHUNK, H_W, H_ROWS, H_NT = 0, 1, 2, 3, 4, 5, 6
H_I, H_F, H_FIRST, H_MASK_BYTES, H_ALWAYS, H_END = 7, 8, 9, 10, 11, 12


@njit(**_OPTIONS)
def evaluate(X, cols, mode, out, P, bounds):
    """The whole evaluation, chunk by chunk, into ``out`` (``[N, m]`` bool for ``EACH``, ``[N, 1]``
    bool for ``ANY``, ``[N, 1]`` int64 for ``FIRST``); returns the flat index of the first NaN or -1. The plan comes packed in one
    byte array ``P`` and the code intervals ``bounds`` (their dtype is the codes'): every
    argument costs at a call, and one point should cost about a microsecond."""
    h = P[:8 * 16].view(np.int64)
    n = X.shape[0]
    S = h[H_S]
    m = h[H_M]
    use_masks = h[H_MASKS] != 0 or n <= _FEW   # a few points: per point, no per-conjunction loops
    chunk = min(n, h[H_CHUNK])
    W = h[H_W]
    R = h[H_ROWS]
    I = P[h[H_I]:h[H_F]].view(np.int64)
    F = P[h[H_F]:h[H_FIRST]].view(np.float64)
    first = P[h[H_FIRST]:h[H_MASK_BYTES]].view(np.int32)
    masks = P[h[H_MASK_BYTES]:h[H_ALWAYS]].view(np.uint64).reshape((R + S + 2, W))
    always = P[h[H_ALWAYS]:h[H_ALWAYS] + m]
    grid = F[:3 * S].reshape((S, 3))
    thresholds = F[3 * S:]
    offsets = I[:3 * (S + 1)].reshape((S + 1, 3))
    test_start = I[3 * (S + 1):3 * (S + 1) + m + 1]
    test_step = I[3 * (S + 1) + m + 1:]
    done = masks[R:R + S + 1]
    init = masks[R + S + 1]
    lo = bounds[0]
    hi = bounds[1]
    scratch = np.empty((S, chunk), bounds.dtype)
    res = np.empty(chunk, np.uint8)
    tmp = np.empty(chunk, np.uint8)
    firsts = np.empty(chunk, np.int64)
    # codes go feature by feature over rows that fit in L1 (a strided column read misses it
    # once per value when the rows are long)
    rows = max(16, min(chunk, _L1_BYTES // max(1, X.shape[1] * X.itemsize)))
    for start in range(0, n, chunk):
        stop = min(n, start + chunk)
        for a in range(start, stop, rows):
            b = min(stop, a + rows)
            if codes(X, a, b, cols, grid, offsets, first, thresholds, scratch[:, a - start:b - start]):
                return first_nan(X, a, b, cols)
        if use_masks:
            combine_masks(scratch, stop - start, offsets, masks, done, init, out, start, mode, m)
        else:
            combine_boxes(scratch, stop - start, test_start, test_step, lo, hi, always, out, start,
                          mode, res, tmp, firsts)
    return -1
