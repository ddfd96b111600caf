"""How deep inside a DNF formula's unsafe set a point lies: the shaping term of a DNF cost.

A DNF cost of 1 per unsafe step tells an agent that it is in the unsafe set, not which way is
out. Where the safe set is a narrow corridor (what a one-class tree learns from an expert who
kept to one route) an agent that cut across pays the same on every step of the short cut and
learns that the fastest way through is the cheapest: measured on a robot that must go round a
disk, PPO-Lagrangian stayed on the diagonal for 150k steps while its multiplier rose to 24
(docs/BENCHMARKS.md, "DNF costs shaped by depth"). Charging ``1 + weight * depth`` instead keeps
every safe step free and the unsafe steps' ranking by how far they are from safety, so the cost's
gradient points out of the unsafe set.

**Depth.** Every conjunction is an axis-aligned box (its atoms' intervals, open or closed ends).
``depth(x)`` is 0 where no conjunction holds; else the smallest distance, along a single feature
axis, to a point that no conjunction holds on -- the exit may cross several touching boxes
(walking right from ``x``: jump to the far end of every box that holds at the current point,
until none does) -- measured in units of that feature's *span* (the distance between its smallest
and its largest finite threshold in the formula; 1 where it has fewer than two). A point with no
such exit along any axis (inside a rule that bounds nothing) gets :data:`NO_EXIT_DEPTH` spans.
Axis exits bound the Euclidean distance to the safe set from above; they are exact for one box
and cheap: ``O(N x m x k)`` per pass, a pass per crossed box, in chunks that bound the memory.

>>> from symlearn.logic.dnf import parse
>>> depth = ViolationDepth(parse("x > 0.5 & x < 1 & y < 2\\nx >= 1 & x < 1.5"), ["x", "y"])
>>> depth(np.array([[0.2, 0.0], [0.6, 0.0], [1.2, 0.0], [0.9, 1.9]])).round(3).tolist()
[0.0, 0.1, 0.3, 0.1]
"""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.errors import DataError

NO_EXIT_DEPTH = 1.0  # spans: the depth of a point no single-axis move takes out of the unsafe set
CHUNK_CELLS = 4_000_000  # points x boxes x features evaluated at once (bounds the memory per call)


def _within(x: np.ndarray, lo: np.ndarray, lo_closed: np.ndarray, hi: np.ndarray, hi_closed: np.ndarray) -> np.ndarray:
    return ((x > lo) | ((x == lo) & lo_closed)) & ((x < hi) | ((x == hi) & hi_closed))


class ViolationDepth:
    """``ViolationDepth(dnf, names)(X) -> [N]`` depths of the points ``X [N, k]`` (module doc)."""

    def __init__(self, dnf: Any, names: Any) -> None:
        self.names = tuple(names)
        index = {name: i for i, name in enumerate(self.names)}
        unknown = sorted(set(dnf.features) - set(index))
        if unknown:
            raise DataError(f"the formula uses feature {unknown[0]!r}, which the points do not have",
                            hint="features: " + ", ".join(self.names))
        m, k = len(dnf.conjunctions), len(self.names)
        self.lo, self.hi = np.full((m, k), -np.inf), np.full((m, k), np.inf)
        self.lo_closed, self.hi_closed = np.zeros((m, k), dtype=bool), np.zeros((m, k), dtype=bool)
        for i, conjunction in enumerate(dnf.conjunctions):
            for feature, interval in conjunction.box().items():
                j = index[feature]
                self.lo[i, j], self.hi[i, j] = interval.lo, interval.hi
                self.lo_closed[i, j], self.hi_closed[i, j] = interval.lo_closed, interval.hi_closed
        self.spans = np.ones(k)
        for j in range(k):
            ends = np.concatenate([self.lo[:, j], self.hi[:, j]])
            ends = ends[np.isfinite(ends)]
            if len(ends) >= 2 and ends.max() > ends.min():
                self.spans[j] = ends.max() - ends.min()
        # the far end of each box along each axis, as a point outside it: a closed end's next float
        self._right = np.where(self.hi_closed, np.nextafter(self.hi, np.inf), self.hi)
        self._left = np.where(self.lo_closed, np.nextafter(self.lo, -np.inf), self.lo)

    def __call__(self, X: Any) -> np.ndarray:
        X = np.atleast_2d(np.asarray(X, dtype=np.float64))
        if X.shape[1] != len(self.names):
            raise DataError(f"expected {len(self.names)} features ({', '.join(self.names)}), got {X.shape[1]}")
        m, k = self.lo.shape
        if m == 0 or len(X) == 0:
            return np.zeros(len(X))
        step = max(1, CHUNK_CELLS // (m * k))
        return np.concatenate([self._depth(X[start:start + step]) for start in range(0, len(X), step)])

    def _depth(self, X: np.ndarray) -> np.ndarray:
        inside = _within(X[:, None, :], self.lo[None], self.lo_closed[None], self.hi[None], self.hi_closed[None])
        misses = (~inside).sum(axis=2)   # [N, m]: atoms of each box the point is outside of
        unsafe = (misses == 0).any(axis=1)
        best = np.full(len(X), np.inf)
        rows = np.flatnonzero(unsafe)
        if not len(rows):
            return np.zeros(len(X))
        X, inside, misses = X[rows], inside[rows], misses[rows]
        for j in range(X.shape[1]):
            # the boxes that hold somewhere on the line through x along axis j
            on_line = (misses - ~inside[:, :, j]) == 0
            if not on_line.any():
                continue
            lo, hi = self.lo[None, :, j], self.hi[None, :, j]
            lo_closed, hi_closed = self.lo_closed[None, :, j], self.hi_closed[None, :, j]
            for ends, extreme in ((self._right[None, :, j], np.max), (self._left[None, :, j], np.min)):
                t = X[:, j].copy()
                fill = -np.inf if extreme is np.max else np.inf
                for _ in range(self.lo.shape[0] + 1):   # each pass leaves at least one more box behind
                    holds = on_line & _within(t[:, None], lo, lo_closed, hi, hi_closed)
                    if not holds.any():
                        break
                    reach = extreme(np.where(holds, ends, fill), axis=1)
                    t = np.where(holds.any(axis=1), reach, t)
                distance = np.abs(t - X[:, j]) / self.spans[j]
                best[rows] = np.minimum(best[rows], np.where(np.isfinite(distance), distance, np.inf))
        out = np.zeros(len(best))
        out[rows] = np.where(np.isfinite(best[rows]), best[rows], NO_EXIT_DEPTH)
        return out


__all__ = ["CHUNK_CELLS", "NO_EXIT_DEPTH", "ViolationDepth"]
