"""Readable box sides for a fitted one-class tree: few digits, no slivers (issue #25).

A grown tree's box sides are data values (a child's box is the bounding box of its points), so
its formula prints them with 16--17 digits, and two neighbouring children of a split leave a gap
between the last point of one and the first point of the next -- often far narrower than the
data's resolution, a "sliver" rule ``x > 0.8463 & x < 0.8471`` across the expert's own path.
:func:`readable_tree` rewrites the tree:

* **Thresholds.** Every side becomes the number with the fewest significant digits in the range
  where no demonstration point changes side: a lower side ``v`` moves down, strictly above the
  midpoint to the next smaller value of that feature in the data; an upper side moves up,
  strictly below the midpoint to the next larger value; and neither by more than ``tolerance``
  (a share of the feature's bandwidth, so a bound next to no data does not jump far). Every
  point thus keeps its side of every atom and its leaf; siblings stay disjoint (their sides
  stay on either side of the midpoint between them). The rounded value is the one stored in the
  boxes, so the formula, the boxes and ``predict`` agree, and the text reads back exactly.
* **Slivers.** A gap between neighbouring children is closed when it is narrower than the
  feature's resolution (its bandwidth), or when a demonstrated step crosses it: two consecutive
  states of one demonstration, both inside the parent's box, on either side of the gap. The
  straight segment between them lies in the parent's box (a box is convex) and passes through
  the gap, so the expert moved through it -- a gap its sampling rate skipped, not a region it
  avoided. (A bandwidth can be far finer than the data's spacing where most points crowd in one
  mode: a thermostat holding its set point gives a bandwidth of 0.06 degrees and gaps of 0.1-0.4
  degrees on the way there.) Both children then meet at one cut ``c`` (the shortest number
  between the two), the left child's side becomes the largest float below ``c`` and the formula
  writes it ``x < c`` -- exact for floats, and no gap rule is written. This changes the learned
  set by the closed gaps only (made safe), which :func:`readable_tree` counts for the file
  header, by cause.
"""

from __future__ import annotations

import math
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

import numpy as np

__all__ = ["fewest_digits", "readable_tree"]


def fewest_digits(value: float, low: float, high: float, *, low_open: bool, high_open: bool) -> float:
    """The number with the fewest significant digits in the interval from ``low`` to ``high``
    (``value`` lies in it; among the shortest, the one nearest ``value``).

    >>> fewest_digits(0.84631234, 0.8455, 0.84631234, low_open=True, high_open=False)
    0.846
    >>> fewest_digits(0.2, 0.15, 0.25, low_open=False, high_open=True)
    0.2
    """

    def inside(x: float) -> bool:
        above = x > low if low_open else x >= low
        below = x < high if high_open else x <= high
        return above and below

    if inside(0.0) and (low < 0 < high or value == 0):
        return 0.0
    exact = Decimal(repr(float(value)))
    scale = max(abs(value), abs(low) if math.isfinite(low) else 0.0, abs(high) if math.isfinite(high) else 0.0)
    exponent = math.floor(math.log10(scale)) if scale > 0 else 0
    for digits in range(1, 18):
        step = Decimal(1).scaleb(exponent - digits + 1)
        found = [float((exact / step).to_integral_value(rounding) * step) for rounding in (ROUND_FLOOR, ROUND_CEILING)]
        found = [x for x in found if inside(x)]
        if found:
            return min(found, key=lambda x: (abs(x - value), x))
    return float(value)


class _Sides:
    """The rounding of one tree's sides: per feature, the sorted distinct data values."""

    def __init__(self, X: np.ndarray, tolerance: np.ndarray) -> None:
        self.values = [np.unique(X[:, d]) for d in range(X.shape[1])]
        self.tolerance = tolerance
        self.cache: dict[tuple[int, str, float], float] = {}

    def _neighbours(self, d: int, v: float) -> tuple[float, float]:
        values = self.values[d]
        i = int(np.searchsorted(values, v, side="left"))
        below = float(values[i - 1]) if i > 0 else -math.inf
        j = int(np.searchsorted(values, v, side="right"))
        above = float(values[j]) if j < len(values) else math.inf
        return below, above

    def round(self, d: int, v: float, role: str) -> float:
        key = (d, role, v)
        if key not in self.cache:
            below, above = self._neighbours(d, v)
            tol = float(self.tolerance[d])
            if role == "lower":
                floor = max((below + v) / 2 if math.isfinite(below) else -math.inf, v - tol)
                self.cache[key] = fewest_digits(v, floor, v, low_open=True, high_open=False) if floor < v else v
            else:
                ceiling = min((v + above) / 2 if math.isfinite(above) else math.inf, v + tol)
                self.cache[key] = fewest_digits(v, v, ceiling, low_open=False, high_open=True) if ceiling > v else v
        return self.cache[key]


def crossed(X: np.ndarray, steps: np.ndarray | None, members: np.ndarray, j: int, upper: float,
            lower: float) -> bool:
    """Whether a demonstrated step (a row ``(a, b)`` of ``steps``: consecutive states of one
    demonstration, indices into ``X``) with both states among ``members`` (a boolean mask: the
    points of the parent node) goes from ``x_j <= upper`` to ``x_j >= lower`` or back."""
    if steps is None or not len(steps):
        return False
    inside = members[steps[:, 0]] & members[steps[:, 1]]
    a, b = X[steps[:, 0], j], X[steps[:, 1], j]
    return bool(np.any(inside & (np.minimum(a, b) <= upper) & (np.maximum(a, b) >= lower)))


def readable_tree(tree, X: np.ndarray, resolution: np.ndarray, *, tolerance_share: float = 0.1,
                  steps: np.ndarray | None = None):
    """``(tree, closed)``: ``tree`` with rounded sides and closed slivers (module docstring), and
    the number of gaps closed by cause: ``{"narrow": n, "crossed": m}`` (a gap both narrow and
    crossed counts as narrow). ``resolution``: per feature, the width below which a gap between
    siblings is a sliver (the bandwidth); a side moves by at most ``tolerance_share`` of it.
    ``steps``: ``[M, 2]`` row indices of ``X``, the demonstrated steps (None: the rows are not
    trajectories, only narrow gaps are closed)."""
    from symlearn.learners.trees.one_class_tree import Box, OneClassTree, TreeNode

    sides = _Sides(X, tolerance_share * np.asarray(resolution, dtype=np.float64))
    closed = {"narrow": 0, "crossed": 0}

    def side(d: int, v: float, role: str, override: dict) -> float:
        return override[(d, role, v)] if (d, role, v) in override else sides.round(d, v, role)

    def rebuild(node, override: dict, members: np.ndarray):
        k = len(node.box.lower)
        box = Box(tuple(side(d, node.box.lower[d], "lower", override) for d in range(k)),
                  tuple(side(d, node.box.upper[d], "upper", override) for d in range(k)))
        if node.is_leaf:
            return TreeNode(box, node.n_samples, node.depth)
        j = node.feature
        scoped = [dict(override) for _ in node.children]
        for n in range(len(node.children) - 1):
            upper, lower = node.children[n].box.upper[j], node.children[n + 1].box.lower[j]
            cause = "narrow" if lower - upper < resolution[j] else \
                "crossed" if crossed(X, steps, members, j, upper, lower) else None
            if cause:  # a sliver: the two children meet at one cut
                cut = fewest_digits((upper + lower) / 2, upper, lower, low_open=True, high_open=False)
                scoped[n][(j, "upper", upper)] = float(np.nextafter(cut, -math.inf))
                scoped[n + 1][(j, "lower", lower)] = cut
                closed[cause] += 1
        # the children split the node's points by their interval on j (the unrounded sides)
        parts = [members & (X[:, j] >= c.box.lower[j]) & (X[:, j] <= c.box.upper[j]) for c in node.children]
        children = tuple(rebuild(c, o, m) for c, o, m in zip(node.children, scoped, parts))
        return TreeNode(box, node.n_samples, node.depth, j, children, node.gain)

    return OneClassTree(rebuild(tree.root, {}, np.ones(len(X), dtype=bool)), tree.feature_names), closed
