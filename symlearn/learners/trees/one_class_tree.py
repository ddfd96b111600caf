"""One-class decision trees (Itani et al.) and the DNF constraint they define (thesis, chapter 4).

The expert's states, as ``k`` named features, are the *target class*. The tree covers them with
hyper-rectangles ("safe boxes"); everything outside every box is where the expert never goes,
written as a formula in disjunctive normal form (DNF) over ``feature op number`` atoms.

**Growing the tree.** The root is the bounding box of the data. Each feature has a kernel
bandwidth ``h``: ``bandwidth="silverman"`` (``0.9 min(std, IQR / 1.34) n^(-1/5)``), ``"scott"``
(``1.06 std n^(-1/5)``) -- the rule applied to all the data, and at a node never finer than the
rule applied to the node's own points (sparse nodes get a coarser resolution) -- or a number
(that fraction of the feature's range, everywhere). At a node, for every feature that is not
constant there:

1. *Density.* A 1-D kernel density estimate of the node's values on a grid of ``grid_size``
   bins over their range: the histogram smoothed by a Gaussian of width ``h``, by FFT for all
   features at once, with the values reflected at both ends of the range (no artificial drop
   at the edges of the box) -- :func:`binned_kde`, O(points + bins) where a
   ``scipy.stats.gaussian_kde`` is O(points x grid points).
2. *Intervals.* The density, divided by its maximum, is *low* where it is below
   ``density_threshold``. The range is cut (a) wherever the density crosses that level -- a
   dense mode is cut off from a sparse plateau beside it -- and (b) inside every run of empty
   bins at least ``h`` wide (a gap in the data). A low stretch *between* two dense ones (a
   local minimum below the level: a low-density gap between two modes) is offered both ways:
   as its own interval (a sparse bridge) and cut once at its lowest point (two overlapping
   modes); the gain picks. Intervals without data vanish; one with fewer than
   ``min_samples_leaf`` points joins the neighbour it is closer to.
3. *Gain.* The purity of a split is the share of the node's box that the children's boxes
   leave out, ``gain = 1 - sum_children vol(child box) / vol(node box)``. For this score a box
   is *robust* -- on every feature it spans the mean plus and minus ``box_sigmas`` standard
   deviations of its points (the range of a sample grows with its size: with min/max boxes,
   cutting any sample in parts would pay in many dimensions; the standard deviation does not
   grow) --, every side is lengthened by ``h`` (splitting below the resolution does not pay;
   flat boxes of duplicated points still have a volume), and a side counts as tightened only
   when it lies inside the node's by more than ``h`` and more than :data:`MIN_TIGHTENING`
   (10 %) of the node's extent. Before scoring, neighbouring intervals are merged back,
   smallest loss first, while the merged box is no larger than its two parts: a cut that
   leaves no space out (slicing one dense region, or cutting off a tail whose box is as wide)
   is no cut.

The feature with the largest gain splits the node; gains within ``min_gain`` of the best are
not told apart, and among those the split with the fewest children, then the feature listed
first, wins (so the tree does not flip with the noise of the sample). The chosen split's inner
cuts then move by at most one bandwidth, to where the two neighbouring children's exact boxes
are smallest: the density places a cut only up to its bandwidth, and a few points on the wrong
side of it could stretch a box far (in the toy below, a cut at a corner). A node is a leaf at
depth ``max_depth``, with fewer than ``2 * min_samples_leaf`` points, when every feature is
constant on it, or when no split gains more than ``min_gain``.

A child's box is the bounding box of its points (exact, not robust), except that a side less
than ``h`` inside its parent's keeps the parent's side (tightening below the resolution would
only add clauses to the formula), and the outer children keep the parent's outer sides on the
split feature. The leaves are the safe boxes: every demonstrated point lies in one of them,
and they are pairwise disjoint (closed, data-exact on the inner sides of every split).

**The constraint formula** (the thesis' eq. 4.2, read as the union of the children, as in its
worked example, plus the per-feature minimum/maximum rules). With ``P`` the intervals on the
path from the root to a node (the tightest bound per feature), the formula is the disjunction of

* ``x_d < min_d`` and ``x_d > max_d`` for every feature (outside the data's bounds);
* for a split of node ``t`` on feature ``j`` into intervals ``[L_1, R_1] < ... < [L_N, R_N]``:
  the gaps ``P_t & x_j > R_n & x_j < L_{n+1}``, and for child ``n`` every other feature ``d``
  on which its box is tighter than ``t``'s: ``P_t & x_j >= L_n & x_j <= R_n & x_d < lo``
  (``> hi``), then the same for the child's own split.

Where ``x_d < lo`` (``> hi``) meets a bound of ``P_t`` on the same feature and side, a
conjunction keeps the tighter of the two (the same points, one atom fewer).

**Readable sides** (``readable=True``, the default): after growing, every box side is rounded to
the fewest significant digits that keep every demonstration point on its side, and a gap between
neighbouring children narrower than the feature's bandwidth, or crossed by a demonstrated step
(a "sliver" of unsafe space across the expert's own path), is closed (:mod:`~symlearn.learners.trees.readable_bounds`); the file's
``#`` header says how many. The rounded values are the stored ones, so everything below holds
for them.

It holds exactly on the points outside every leaf box (:meth:`OneClassTreeConstraint.predict`
and ``dnf_.evaluate`` agree everywhere; the tests check this on dense grids).

The thesis' toy (Fig. 4.1): an expert going along ``[0.1, 0.7] x [0.1, 0.3]`` and up
``[0.7, 0.9] x [0.1, 0.9]`` gives two leaves, close to those two rectangles:

>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> bottom = np.column_stack([rng.uniform(0.1, 0.7, 600), rng.uniform(0.1, 0.3, 600)])
>>> right = np.column_stack([rng.uniform(0.7, 0.9, 800), rng.uniform(0.1, 0.9, 800)])
>>> tree = OneClassTreeConstraint().fit(np.vstack([bottom, right]))
>>> [tuple(round(v, 1) for v in b.lower + b.upper) for b in tree.safe_boxes_]
[(0.1, 0.1, 0.7, 0.3), (0.7, 0.1, 0.9, 0.9)]
>>> tree.predict([[0.3, 0.2], [0.3, 0.6], [1.0, 0.5]]).tolist()  # True = unsafe
[False, True, True]

**Features.** ``fit(demonstrations, features)`` (the second argument is ``world``): the states of a
:class:`~symlearn.data.Demonstrations` (vectors, feature dicts, or anything a
:class:`~symlearn.grounding.FeatureMap` with a function or table maps), or a plain ``[N, k]``
array (a 1-D array is ``N`` values of one feature). Only *states* are read: to learn over
state-action features, build the ``[N, k]`` feature vectors of the pairs yourself (e.g. the
state and action columns side by side) and pass that array with their names.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, SymlearnError
from symlearn.grounding.features import FeatureMap
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import FIT_CALLER, renamed_arguments
from symlearn.logic.dnf import DNF, Atom, Conjunction

__all__ = ["Box", "TreeNode", "OneClassTree", "SplitRecord", "OneClassTreeConstraint", "binned_kde"]

_BANDWIDTH_RULES = ("silverman", "scott")

#: when the gain is measured, a box side counts as tightened only if it lies inside the
#: reference box by more than one bandwidth and more than this share of the box's extent
MIN_TIGHTENING = 0.1


# -- values ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Box:
    """An axis-aligned box ``lower <= x <= upper`` (closed on every side), in feature order."""

    lower: tuple[float, ...]
    upper: tuple[float, ...]

    def contains(self, X: Any) -> np.ndarray:
        """Whether each row of ``X`` (``[N, k]``) lies in the box."""
        X = np.asarray(X, dtype=np.float64)
        if X.ndim == 1:  # one point, or N values of a one-feature box
            X = X.reshape(-1, 1) if len(self.lower) == 1 else X[None, :]
        return np.all((X >= np.asarray(self.lower)) & (X <= np.asarray(self.upper)), axis=1)

    @property
    def widths(self) -> tuple[float, ...]:
        return tuple(u - lo for lo, u in zip(self.lower, self.upper))

    def as_dict(self, names: Sequence[str] | None = None) -> dict[str, list[float]]:
        """``{feature: [lower, upper]}``."""
        names = names or [f"x{i}" for i in range(len(self.lower))]
        return {n: [lo, u] for n, lo, u in zip(names, self.lower, self.upper)}


@dataclass(frozen=True)
class TreeNode:
    """A node of a one-class tree.

    ``box`` is the bounding box of the node's points (the root's: the data's bounds), with
    the parent's side kept where it would be tightened by less than the bandwidth (module
    docstring). An internal node splits on ``feature`` into ``children``, ordered along that feature; a
    child's interval ``[L, R]`` on it (:attr:`intervals`) is its box's side there, tightened
    to its data. A leaf (no children) is a safe box.
    """

    box: Box
    n_samples: int
    depth: int
    feature: int | None = None
    children: tuple[TreeNode, ...] = ()
    gain: float = 0.0

    @property
    def is_leaf(self) -> bool:
        return not self.children

    @property
    def intervals(self) -> tuple[tuple[float, float], ...]:
        """``[L, R]`` of each child on the split feature (empty at a leaf)."""
        if self.feature is None:
            return ()
        j = self.feature
        return tuple((c.box.lower[j], c.box.upper[j]) for c in self.children)

    def walk(self) -> Iterator[TreeNode]:
        """This node and its descendants, depth first, children in order."""
        yield self
        for child in self.children:
            yield from child.walk()

    def leaves(self) -> list[TreeNode]:
        return [n for n in self.walk() if n.is_leaf]


@dataclass(frozen=True)
class OneClassTree:
    """A fitted one-class tree: the root node and the feature names its indices refer to."""

    root: TreeNode
    feature_names: tuple[str, ...]

    @property
    def n_features(self) -> int:
        return len(self.feature_names)

    def leaves(self) -> list[TreeNode]:
        """The leaves, depth first (the order of :attr:`OneClassTreeConstraint.safe_boxes_`)."""
        return self.root.leaves()

    @property
    def n_leaves(self) -> int:
        return len(self.leaves())

    @property
    def n_nodes(self) -> int:
        return sum(1 for _ in self.root.walk())

    @property
    def depth(self) -> int:
        return max(n.depth for n in self.root.walk())

    def apply(self, X: Any) -> np.ndarray:
        """Index (into :meth:`leaves`) of the leaf box holding each row of ``X``, -1 for none."""
        X = _as_points(X, self.n_features)
        out = np.full(len(X), -1, dtype=np.int64)
        leaf_ids = {id(n): i for i, n in enumerate(self.leaves())}
        inside = self.root.box.contains(X) if len(X) else np.zeros(0, dtype=bool)
        stack = [(self.root, np.flatnonzero(inside))]
        while stack:
            node, rows = stack.pop()
            if not len(rows):
                continue
            if node.is_leaf:
                out[rows] = leaf_ids[id(node)]
                continue
            values = X[rows, node.feature]
            lows = np.array([lo for lo, _ in node.intervals])
            highs = np.array([hi for _, hi in node.intervals])
            which = np.searchsorted(lows, values, side="right") - 1
            ok = which >= 0
            ok[ok] &= values[ok] <= highs[which[ok]]
            for c, child in enumerate(node.children):
                mine = rows[ok & (which == c)]
                if len(mine):
                    stack.append((child, mine[child.box.contains(X[mine])]))
        return out

    def contains(self, X: Any) -> np.ndarray:
        """Whether each row of ``X`` lies in some leaf box (is *safe*)."""
        return self.apply(X) >= 0

    def as_dict(self) -> dict[str, Any]:
        def node(n: TreeNode) -> dict[str, Any]:
            doc: dict[str, Any] = {"n_samples": n.n_samples, "box": n.box.as_dict(self.feature_names)}
            if not n.is_leaf:
                doc.update(feature=self.feature_names[n.feature], gain=n.gain,
                           children=[node(c) for c in n.children])
            return doc
        return {"feature_names": list(self.feature_names), "root": node(self.root)}


@dataclass(frozen=True)
class SplitRecord:
    """One split of the fit (the history of :attr:`LearnerResult.history`)."""

    depth: int
    feature: str
    n_samples: int
    n_children: int
    gain: float
    intervals: list[list[float]] = field(default_factory=list)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


# -- the kernel density estimate -----------------------------------------------------------------

def binned_kde(counts: np.ndarray, sigma_bins: Any) -> np.ndarray:
    """Gaussian-smoothed histograms, one per row of ``counts`` (``[F, G]``), reflected at both ends.

    ``sigma_bins`` (scalar or ``[F]``) is the kernel's standard deviation in bins. The rows are
    extended evenly (``c, reversed(c)``: period ``2G``), so the circular convolution by FFT is
    the reflection-corrected KDE on ``[0, G]`` for any bandwidth. Returns unnormalised
    densities (the smoothed counts), ``>= 0``.

    >>> smooth = binned_kde(np.array([[0, 0, 4, 0, 0]], dtype=float), 1.0)
    >>> bool(np.isclose(smooth.sum(), 4.0)), int(smooth.argmax())
    (True, 2)
    """
    counts = np.atleast_2d(np.asarray(counts, dtype=np.float64))
    n_bins = counts.shape[1]
    sigma = np.broadcast_to(np.asarray(sigma_bins, dtype=np.float64), (counts.shape[0],))
    extended = np.concatenate([counts, counts[:, ::-1]], axis=1)
    spectrum = np.fft.rfft(extended, axis=1)
    freq = np.fft.rfftfreq(2 * n_bins)
    spectrum *= np.exp(-2.0 * np.pi ** 2 * sigma[:, None] ** 2 * freq[None, :] ** 2)
    smooth = np.fft.irfft(spectrum, n=2 * n_bins, axis=1)[:, :n_bins]
    return np.maximum(smooth, 0.0)


# -- the learner ------------------------------------------------------------------------------------

class OneClassTreeConstraint(Learner):
    """A one-class decision tree over named features and its DNF of the unsafe region.

    ``OneClassTreeConstraint(max_depth=5).fit(demonstrations, features)``; see the module
    docstring for the algorithm and the formula.

    Hyper-parameters: ``max_depth`` (>= 1; the root is depth 0), ``bandwidth`` (``"silverman"``,
    ``"scott"`` or a fraction of each feature's range), ``min_samples_leaf`` (>= 1),
    ``density_threshold`` (in (0, 1): below this share of the maximum the density is low),
    ``min_gain`` (in [0, 1): the least gain a split needs, and the margin within which gains
    tie), ``box_sigmas`` (> 0: for the gain, a box spans its points' mean plus and minus this
    many standard deviations on each feature), ``grid_size`` (bins of the density grid,
    16 to 4096), ``readable`` (default True: every box side is rounded to the fewest significant
    digits that keep every demonstration point on the same side of it, and gaps between
    neighbouring children narrower than the feature's bandwidth or crossed by a demonstrated
    step are closed -- see
    :mod:`~symlearn.learners.trees.readable_bounds`; False keeps the data's values and every gap),
    ``close_crossed`` (default True: with ``readable``, a gap a demonstrated step crossed is
    closed, as a continuous path passes through it; False where neighbouring values are not
    neighbours in the world -- the ids of a ``Discrete`` observation, where 3 -> 5 jumps over 4),
    ``whole_numbers`` (default False; True where every feature takes whole-number values only, as
    the ids of a ``Discrete`` observation: an unsafe conjunction that holds at no whole-number
    point, such as the slab ``x0 > 1 & x0 < 2`` between two ids, forbids nothing and is dropped,
    said in ``notes_``),
    ``warn_unsafe_share`` (default 0.5: a ``UserWarning``, also in ``warnings_``, when the formula
    marks more than this share of the data's bounding box unsafe; None: never), ``inputs`` (names
    of the features the rules may test, e.g. the positions of an observation that also holds
    velocities; default None: every feature -- the tree splits on whatever the expert's states
    vary in, so a velocity the expert never had makes a state unsafe), ``random_state``
    (the fit is deterministic and does not use it; it is kept so that pipelines can pass one to
    every learner).

    The unsafe share is computed exactly, not sampled: the leaves are disjoint boxes inside the
    bounding box, so it is one minus the sum of their volume shares (over the features that vary).

    >>> learner = OneClassTreeConstraint(max_depth=2).fit([[0.0, 0.0], [0.1, 0.2], [0.2, 0.1]], ["x", "y"])
    >>> print(learner.dnf_)
    x < 0
    x > 0.2
    y < 0
    y > 0.2
    >>> learner.predict([[0.1, 0.1], [0.1, 0.3]]).tolist()
    [False, True]

    Results: ``tree_`` (:class:`OneClassTree`), ``dnf_`` (the unsafe set, a
    :class:`~symlearn.logic.dnf.DNF`), ``safe_boxes_`` (the leaf boxes, :class:`Box`),
    ``feature_names_`` (the features the rules test: ``inputs`` when given), ``input_columns_``
    (their positions among all the features, or None),
    ``bounds_`` (the data's per-feature minimum and maximum, a :class:`Box`), ``n_samples_``,
    ``history_`` (one :class:`SplitRecord` per split), ``unsafe_share_``, ``slivers_closed_``
    (of them ``slivers_crossed_``: closed because a demonstrated step crossed them),
    ``notes_`` and ``warnings_`` (the ``#`` header lines of the text after the first, which says
    how the set was made and from what: the demonstrations' ``metadata["source"]`` where they
    carry one, and the number of points), ``result_`` (text: the header and ``str(dnf_)``).
    ``save(path)`` writes the DNF text (``symlearn.logic.dnf.parse`` reads it back).
    """

    artefact_suffix = ".dnf"

    def __init__(self, *, max_depth: int = 5, bandwidth: str | float = "silverman", min_samples_leaf: int = 5,
                 density_threshold: float = 0.5, min_gain: float = 0.05, box_sigmas: float = 2.5,
                 grid_size: int = 256, readable: bool = True, warn_unsafe_share: float | None = 0.5,
                 inputs: Sequence[str] | None = None, close_crossed: bool = True, whole_numbers: bool = False,
                 random_state: Any = None) -> None:
        self.max_depth = max_depth
        self.bandwidth = bandwidth
        self.min_samples_leaf = min_samples_leaf
        self.density_threshold = density_threshold
        self.min_gain = min_gain
        self.box_sigmas = box_sigmas
        self.grid_size = grid_size
        self.readable = readable
        self.warn_unsafe_share = warn_unsafe_share
        self.inputs = inputs
        self.close_crossed = close_crossed
        self.whole_numbers = whole_numbers
        self.random_state = random_state

    # --- fitting -------------------------------------------------------------------------------
    def _check_params(self) -> None:
        def integer(value: Any) -> bool:
            return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))

        if not integer(self.max_depth) or self.max_depth < 1:
            raise SymlearnError(f"max_depth must be an integer >= 1, got {self.max_depth!r}",
                                hint="max_depth=1 splits the root once")
        if not integer(self.min_samples_leaf) or self.min_samples_leaf < 1:
            raise SymlearnError(f"min_samples_leaf must be an integer >= 1, got {self.min_samples_leaf!r}")
        if not isinstance(self.close_crossed, (bool, np.bool_)):
            raise SymlearnError(f"close_crossed must be True or False, got {self.close_crossed!r}")
        if not isinstance(self.whole_numbers, (bool, np.bool_)):
            raise SymlearnError(f"whole_numbers must be True or False, got {self.whole_numbers!r}")
        if not integer(self.grid_size) or not 16 <= self.grid_size <= 4096:
            raise SymlearnError(f"grid_size must be an integer in [16, 4096], got {self.grid_size!r}")
        if isinstance(self.bandwidth, str):
            if self.bandwidth not in _BANDWIDTH_RULES:
                raise SymlearnError(f"unknown bandwidth rule {self.bandwidth!r}",
                                    hint="use 'silverman', 'scott' or a positive fraction of the feature range")
        elif isinstance(self.bandwidth, (bool, np.bool_)) or not isinstance(self.bandwidth, (int, float, np.number)) \
                or not math.isfinite(float(self.bandwidth)) or float(self.bandwidth) <= 0:
            raise SymlearnError(f"bandwidth must be 'silverman', 'scott' or a positive number, got {self.bandwidth!r}")
        if not isinstance(self.density_threshold, (int, float, np.number)) or not 0 < float(self.density_threshold) < 1:
            raise SymlearnError(f"density_threshold must be in (0, 1), got {self.density_threshold!r}")
        if not isinstance(self.min_gain, (int, float, np.number)) or not 0 <= float(self.min_gain) < 1:
            raise SymlearnError(f"min_gain must be in [0, 1), got {self.min_gain!r}")
        if isinstance(self.box_sigmas, (bool, np.bool_)) or not isinstance(self.box_sigmas, (int, float, np.number)) \
                or not 0 < float(self.box_sigmas) < math.inf:
            raise SymlearnError(f"box_sigmas must be a positive number, got {self.box_sigmas!r}")

    @renamed_arguments(features="world")
    def fit(self, demonstrations: Any, world: Any = None) -> OneClassTreeConstraint:
        """Learn the tree and the DNF from ``demonstrations`` (see the module docstring).

        ``world`` names the features: a :class:`~symlearn.grounding.FeatureMap`, a list of
        names, or None (the keys of feature-dict states, else ``x0 .. x{k-1}``).
        """
        self._check_params()
        started = time.perf_counter()
        X, names = feature_matrix(demonstrations, world)
        self.input_columns_ = _input_columns(self.inputs, names)
        if self.input_columns_ is not None:  # the rules may test only these (velocities left out, ...)
            X, names = X[:, self.input_columns_], tuple(names[i] for i in self.input_columns_)
        t_features = time.perf_counter()
        grower = _Grower(X, self)
        tree = OneClassTree(grower.grow(), names)
        closed = {"narrow": 0, "crossed": 0}
        lengths = demonstration_lengths(demonstrations, len(X))
        steps = demonstrated_steps(lengths) if self.close_crossed else None
        if self.readable:
            from symlearn.learners.trees.readable_bounds import readable_tree

            tree, closed = readable_tree(tree, X, grower.h, steps=steps)
        slivers = closed["narrow"] + closed["crossed"]
        root = tree.root
        t_tree = time.perf_counter()
        dnf = tree_dnf(tree)
        empty = 0
        if self.whole_numbers:
            kept = tuple(c for c in dnf.conjunctions if _holds_at_a_whole_number(c))
            empty, dnf = len(dnf.conjunctions) - len(kept), DNF(kept)
        t_dnf = time.perf_counter()

        self.feature_names_ = names
        self.n_samples_ = len(X)
        self.bounds_ = root.box
        self.tree_ = tree
        self.safe_boxes_ = tuple(leaf.box for leaf in tree.leaves())
        self.dnf_ = dnf
        # the splits in growing order (pre-order), with the intervals as stored (rounded)
        internal = [n for n in root.walk() if not n.is_leaf]
        self.history_ = [SplitRecord(r[0], names[r[1]], r[2], r[3], r[4], [list(iv) for iv in n.intervals])
                         for r, n in zip(grower.splits, internal)]
        safe_share = _volume_fraction(self.safe_boxes_, root.box)
        self.unsafe_share_ = max(0.0, 1.0 - safe_share)
        lattice = _lattice_unsafe_share(X, dnf, names)
        if lattice is not None:
            # whole-number features (cells, counters, ids): the states are the lattice's points,
            # and boxes around single points have no volume, so the volume share would call a
            # formula that forbids no possible state "100% unsafe"
            self.unsafe_share_ = lattice
        self.slivers_closed_ = slivers
        self.slivers_crossed_ = closed["crossed"]
        self.notes_ = _notes(self, closed, steps is not None)
        if empty:
            self.notes_.append(f"{empty} conjunction(s) that hold at no whole-number point (slabs between ids) "
                               "dropped: they forbid nothing")
        if len(self.safe_boxes_) == 1 and X.shape[1] > 1:
            # a single box is right for a box-shaped safe set, but the rules then say nothing about
            # the inside of the data's range: a region the demonstrations avoid there (the corner
            # x > 0.7 & y > 0.7 of an L-shaped safe set) is unsafe in truth and absent here, and the
            # file gives no sign of it unless said
            self.notes_.append("no split: the rules only bound each feature's range, so a region the demonstrations "
                               "avoid inside that range (a corner of it) is not forbidden; check such a region "
                               "with dnf eval, or add its rule by hand")
        self.warnings_ = []
        if self.warn_unsafe_share is not None and self.unsafe_share_ > float(self.warn_unsafe_share):
            self.warnings_.append(
                f"the formula marks {self.unsafe_share_:.0%} of the demonstrations' bounding box unsafe: every "
                "state the expert never visited counts as unsafe; if the allowed space is larger, give "
                "demonstrations that cover it")
        distinct = len(np.unique(X, axis=0))
        if distinct < 2 * self.min_samples_leaf:
            # too few points to split: the safe set is their bounding box (one point: that point
            # alone), with no warning before, since a box of no volume has no share to report
            self.warnings_.append(
                f"only {distinct} distinct demonstration point(s), fewer than two leaves' worth "
                f"(min_samples_leaf {self.min_samples_leaf}, --min-samples-leaf): the safe set is their bounding box, everything "
                "outside it is unsafe; give more demonstrations")
        self.warnings_.extend(episode_setting_warnings(X, names, lengths, dnf))
        for message in self.warnings_:
            warnings.warn(message, UserWarning, stacklevel=FIT_CALLER)
        metrics = {"n_samples": len(X), "n_features": len(names), "n_nodes": tree.n_nodes,
                   "n_leaves": tree.n_leaves, "depth": tree.depth, "n_conjunctions": len(dnf),
                   "n_atoms": sum(len(c) for c in dnf),
                   "safe_volume_fraction": safe_share, "unsafe_share": self.unsafe_share_,
                   "slivers_closed": slivers, "slivers_crossed": closed["crossed"]}
        timings = {"features": t_features - started, "tree": t_tree - t_features, "dnf": t_dnf - t_tree,
                   "total": max(time.perf_counter() - started, 1e-9)}
        made = (f"unsafe set learned by a one-class tree (max depth {self.max_depth}) from "
                f"{_data_description(demonstrations, len(X))}; one rule per line, edit freely")
        header = "".join(f"# {line}\n" for line in [made, *self.notes_, *(f"warning: {w}" for w in self.warnings_)])
        self._set_result(dnf, header + str(dnf), metrics=metrics, timings=timings, history=self.history_)
        return self

    def save(self, path: Any) -> Path:
        """Write the unsafe set: the DNF text with its ``#`` header (how it was made, notes,
        warnings), or the DNF's JSON when ``path`` ends in ``.json`` (as :meth:`DNF.save`)."""
        self.check_fitted()
        if str(path).endswith(".json"):
            return self.dnf_.save(path)
        return super().save(path)

    # --- using the result ---------------------------------------------------------------------
    def predict(self, X: Any) -> np.ndarray:
        """``True`` for each row of ``X`` (``[N, k]``, or one point ``[k]``) outside every safe box.
        With ``inputs``, rows may hold every feature (the chosen columns are read) or just those."""
        self.check_fitted()
        columns = self.__dict__.get("input_columns_")
        if columns is not None:
            X = np.asarray(X, dtype=np.float64)
            if X.shape[-1] != len(self.feature_names_):
                X = X[..., columns]
        return ~self.tree_.contains(X)

    def export_text(self, digits: int = 4) -> str:
        """The tree as indented text: per child its interval, its points, the other features it
        tightens (relative to its parent's box) and whether it is a leaf (a safe box)."""
        self.check_fitted()
        return tree_text(self.tree_, digits=digits)

    def to_dot(self, *, digits: int = 4, title: str | None = None) -> str:
        """The tree as Graphviz DOT text (render it with :func:`symlearn.rendering.render_dot`)."""
        self.check_fitted()
        from symlearn.learners.trees.tree_dot import tree_to_dot

        return tree_to_dot(self.tree_, digits=digits, title=title)

    def _repr_svg_(self) -> str | None:
        if "result_" not in self.__dict__:
            return None
        from symlearn.rendering import dot_to_svg_text

        return dot_to_svg_text(self.to_dot())


# -- input ------------------------------------------------------------------------------------------


class UnknownInputs(SymlearnError):
    """``inputs`` names a feature the data lacks; ``unknown`` lists them, ``names`` has the
    features there are (a command says its own flag instead of the parameter's name)."""

    def __init__(self, unknown: Sequence[str], names: Sequence[str]) -> None:
        super().__init__(f"inputs: no feature named {', '.join(map(repr, unknown))}",
                         hint=f"the features are {', '.join(names)}")
        self.unknown, self.names = list(unknown), list(names)


def _input_columns(inputs: Sequence[str] | None, names: Sequence[str]) -> list[int] | None:
    """The positions of ``inputs`` among the feature ``names`` (None: every feature)."""
    if inputs is None:
        return None
    if isinstance(inputs, str):
        inputs = [part.strip() for part in inputs.split(",")]
    chosen = list(inputs)
    if not chosen:
        raise SymlearnError("inputs names no feature", hint=f"the features are {', '.join(names)}")
    unknown = [name for name in chosen if name not in names]
    if unknown:
        raise UnknownInputs(unknown, names)
    if len(set(chosen)) != len(chosen):
        raise SymlearnError(f"inputs names a feature twice: {', '.join(chosen)}")
    return [list(names).index(name) for name in chosen]

def _as_demonstrations(demonstrations: Any) -> Any:
    """A :class:`~symlearn.data.Trajectory` or a list of them as ``Demonstrations``; anything else
    (``Demonstrations`` themselves, an array of points) as it is."""
    from symlearn.data import Demonstrations, Trajectory

    if isinstance(demonstrations, Trajectory):
        return Demonstrations([demonstrations])
    if isinstance(demonstrations, (list, tuple)) and demonstrations and \
            all(isinstance(t, Trajectory) for t in demonstrations):
        return Demonstrations(demonstrations)
    return demonstrations


def feature_matrix(demonstrations: Any, features: Any = None) -> tuple[np.ndarray, tuple[str, ...]]:
    """``([N, k] float array, names)`` of the demonstrated states (see the module docstring)."""
    from symlearn.data import Demonstrations

    feature_map = features if isinstance(features, FeatureMap) else None
    demonstrations = _as_demonstrations(demonstrations)
    if isinstance(demonstrations, Demonstrations):
        named = None if feature_map is not None or features is None or isinstance(features, str) else tuple(features)
        X, default_names = _states_matrix(demonstrations, feature_map, named)
    else:
        X = _numeric_array(demonstrations)
        default_names = None
        if feature_map is not None and feature_map != FeatureMap(feature_map.names):
            X = feature_map.matrix(list(X))  # a function or table: the rows are states
    if X.shape[0] == 0:
        raise DataError("the demonstrations are empty: no state to learn from")
    if X.shape[1] == 0:
        raise DataError("the states have no features")
    names = _names(features, X.shape[1], default_names)
    bad = ~np.isfinite(X)
    if bad.any():
        row, col = (int(v) for v in np.argwhere(bad)[0])
        raise DataError(f"feature {names[col]} of point {row} is not finite ({X[row, col]})",
                        hint="remove or impute NaN/inf values before fitting")
    return X, names


def _numeric_array(data: Any) -> np.ndarray:
    try:
        X = np.asarray(data, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"cannot read {type(data).__name__} as an [N, k] array of numbers",
                        hint="pass a Demonstrations, or an [N, k] numeric array") from None
    if X.ndim == 1:
        X = X[:, None]
    if X.ndim != 2:
        raise DataError(f"points must form an [N, k] array, got shape {X.shape}")
    return X


def _states_matrix(demos: Any, feature_map: FeatureMap | None,
                   named: tuple[str, ...] | None = None) -> tuple[np.ndarray, tuple[str, ...] | None]:
    """The states as rows (array states flattened); feature-dict states read by key: those of ``feature_map``, else the
    ``named`` features (which must be keys of the states: a dict's own names are never replaced
    by position), else the states' own keys."""
    kind = demos.state_kind
    if kind == "features" and named is not None and demos[0].states:
        own = tuple(demos[0].states[0])
        if set(named) != set(own):
            raise DataError(f"the states name their features ({', '.join(own)}); the names given are "
                            f"{', '.join(map(str, named))}",
                            hint="feature-dict states are read by their own keys: leave out --features, or give "
                                 "those keys; with --env, demonstrations of that environment name its features")
        feature_map = FeatureMap(named)
    if feature_map is not None and feature_map != FeatureMap(feature_map.names):
        states = [s for t in demos for s in (t.states if kind != "vector" else list(t.states))]
        return feature_map.matrix(states), None
    if kind in ("vector", "image"):
        # a multi-dimensional state (a (2, 3) Box observation) is its entries in row-major order,
        # the columns x0, x1, ... that `train --cost` reads from the flattened observation too
        X = np.concatenate([np.asarray(t.states, dtype=np.float64).reshape(len(t.states), -1) for t in demos])
        return X, None
    if kind == "features":
        keys = feature_map.names if feature_map is not None else tuple(demos[0].states[0])
        rows = []
        for i, t in enumerate(demos):
            for step, state in enumerate(t.states):
                row = []
                for key in keys:
                    if key not in state:
                        raise DataError(f"demonstration {i}, step {step}: the state has no feature {key!r}")
                    value = state[key]
                    if isinstance(value, str):
                        raise DataError(f"demonstration {i}, step {step}: feature {key!r} is the text {value!r}",
                                        hint="a one-class tree needs numeric features")
                    row.append(float(value))
                rows.append(row)
        return np.asarray(rows, dtype=np.float64).reshape(len(rows), len(keys)), tuple(keys)
    raise DataError(f"cannot read features from {kind} states",
                    hint="pass a FeatureMap with a function or a table, or an [N, k] array of features")


def _names(features: Any, k: int, default: tuple[str, ...] | None) -> tuple[str, ...]:
    if isinstance(features, FeatureMap):
        names = features.names
    elif features is None:
        names = default if default is not None else tuple(f"x{i}" for i in range(k))
    else:
        names = (features,) if isinstance(features, str) else tuple(features)
        for n in names:
            if not isinstance(n, str) or not n or "\n" in n:
                raise DataError(f"feature name {n!r} must be a non-empty one-line string")
        if len(set(names)) != len(names):
            raise DataError(f"feature names repeat: {', '.join(names)}")
    if len(names) != k:
        raise DataError(f"{len(names)} feature names ({', '.join(names)}) for points with {k} features")
    return tuple(names)


def _as_points(X: Any, k: int) -> np.ndarray:
    try:
        X = np.asarray(X, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError("points must be numbers") from None
    if X.ndim == 1 and (X.shape[0] == k and k > 1 or k == 1):
        X = X.reshape(-1, k) if k == 1 else X[None, :]
    if X.ndim != 2 or X.shape[1] != k:
        raise DataError(f"points must have shape (N, {k}), got {X.shape}")
    if np.isnan(X).any():
        row = int(np.argwhere(np.isnan(X))[0][0])
        raise DataError(f"point {row} has a NaN feature")
    return X


# -- growing ----------------------------------------------------------------------------------------

class _Grower:
    """The recursive splitting of one fit (module docstring, "Growing the tree")."""

    def __init__(self, X: np.ndarray, params: OneClassTreeConstraint) -> None:
        self.X = X
        self.max_depth = int(params.max_depth)
        self.min_leaf = int(params.min_samples_leaf)
        self.level = float(params.density_threshold)
        self.min_gain = float(params.min_gain)
        self.n_bins = int(params.grid_size)
        self.sigmas = float(params.box_sigmas)
        self.h = bandwidths(X, params.bandwidth)
        self.rule = params.bandwidth if isinstance(params.bandwidth, str) else None
        self.splits: list[tuple[int, int, int, int, float, list[list[float]]]] = []

    def grow(self) -> TreeNode:
        lo, hi = self.X.min(axis=0), self.X.max(axis=0)
        return self._node(np.arange(len(self.X)), 0, Box(tuple(lo.tolist()), tuple(hi.tolist())))

    def _node(self, rows: np.ndarray, depth: int, box: Box) -> TreeNode:
        if depth >= self.max_depth or len(rows) < 2 * self.min_leaf:
            return TreeNode(box, len(rows), depth)
        Xn = self.X[rows]
        best = self._best_split(Xn, Xn.min(axis=0), Xn.max(axis=0))
        if best is None:
            return TreeNode(box, len(rows), depth)
        gain, j, order, starts, h = best
        ends = list(starts[1:]) + [len(rows)]
        parts = [rows[order[a:b]] for a, b in zip(starts, ends)]
        boxes = [self._child_box(box, self.X[part], j, h, first=n == 0, last=n == len(parts) - 1)
                 for n, part in enumerate(parts)]
        self.splits.append((depth, j, len(rows), len(parts), gain, [[b.lower[j], b.upper[j]] for b in boxes]))
        children = tuple(self._node(part, depth + 1, child_box) for part, child_box in zip(parts, boxes))
        return TreeNode(box, len(rows), depth, j, children, gain)

    def _child_box(self, parent: Box, Xc: np.ndarray, j: int, h: np.ndarray, *, first: bool, last: bool) -> Box:
        """The bounding box of a child's points; on the other features, a side less than one
        bandwidth inside the parent's stays the parent's; on ``j`` the outer children keep the
        parent's outer sides (so the children's intervals span the parent's)."""
        p_lo, p_hi = np.asarray(parent.lower), np.asarray(parent.upper)
        lo, hi = Xc.min(axis=0), Xc.max(axis=0)
        lo = np.where(lo - p_lo < h, p_lo, lo)
        hi = np.where(p_hi - hi < h, p_hi, hi)
        data_lo, data_hi = Xc[:, j].min(), Xc[:, j].max()
        lo[j] = p_lo[j] if first else data_lo
        hi[j] = p_hi[j] if last else data_hi
        return Box(tuple(lo.tolist()), tuple(hi.tolist()))

    def _best_split(self, Xn: np.ndarray, lo: np.ndarray, hi: np.ndarray):
        m, k = Xn.shape
        width = hi - lo
        active = np.flatnonzero(width > 0)
        if not len(active):
            return None
        G, ka = self.n_bins, len(active)
        with np.errstate(over="ignore", invalid="ignore"):
            scaled = (Xn[:, active] - lo[active]) / width[active] * G
        bins = np.clip(np.nan_to_num(scaled, nan=0.0, posinf=G - 1, neginf=0.0), 0, G - 1).astype(np.int64)
        flat_bins = bins + np.arange(ka) * G  # [m, ka]: bin of each value on the stacked grid
        counts = np.bincount(flat_bins.ravel(), minlength=ka * G).reshape(ka, G).astype(np.float64)
        h = self.h[active]
        if self.rule is not None:  # never finer than the rule applied to the node's own points
            h = np.maximum(h, _rule_bandwidth(Xn[:, active], self.rule, counts, width[active]))
        sigma_bins = h / width[active] * G
        density = binned_kde(counts, sigma_bins)
        peak = density.max(axis=1, keepdims=True)
        low = density < self.level * np.where(peak > 0, peak, 1.0)
        volume = _Volume(lo[active], width[active], h, G, self.sigmas)
        node_lo, node_hi = volume.extent(counts[None])

        candidates = []
        for a, j in enumerate(active):
            for labels in self._partitions(counts[a], low[a], density[a], sigma_bins[a]):
                n_raw = int(labels[-1]) + 1
                point_labels = labels[bins[:, a]]
                hists = np.bincount((point_labels[:, None] * (ka * G) + flat_bins).ravel(),
                                    minlength=n_raw * ka * G).reshape(n_raw, ka, G).astype(np.float64)
                groups, hists = volume.merge(hists, node_lo, node_hi)
                if len(groups) < 2:
                    continue
                gain = 1.0 - float(np.exp(volume.log(*volume.extent(hists), node_lo, node_hi)).sum())
                if gain > self.min_gain:
                    candidates.append((gain, len(groups), int(j), a, labels, groups))
        if not candidates:
            return None
        # gains closer than min_gain to the best are not told apart: fewest children, then the
        # feature listed first
        top = max(c[0] for c in candidates)
        gain, n_children, j, a, labels, groups = min((c for c in candidates if c[0] >= top - self.min_gain),
                                                     key=lambda c: (c[1], c[2]))
        merged = np.zeros(int(labels[-1]) + 1, dtype=np.int64)
        for new, members in enumerate(groups):
            merged[members] = new
        bin_group = merged[labels]
        h_node = self.h.copy()
        h_node[active] = h
        cuts = [0] + [int(np.argmax(bin_group == n)) for n in range(1, n_children)] + [G]
        cuts = self._refine(Xn, bins[:, a], cuts, int(math.ceil(sigma_bins[a])), lo, hi, h_node, active)
        point_labels = np.searchsorted(np.asarray(cuts[1:-1]), bins[:, a], side="right")
        order = np.argsort(point_labels, kind="stable")
        starts = np.searchsorted(point_labels[order], np.arange(n_children))
        return gain, j, order, starts, h_node

    def _refine(self, Xn: np.ndarray, bins: np.ndarray, cuts: list[int], reach: int, lo: np.ndarray,
                hi: np.ndarray, h: np.ndarray, active: np.ndarray) -> list[int]:
        """Move each inner cut of the chosen split (a bin boundary) by at most one bandwidth
        to where the two children's exact boxes are smallest: the density places a cut only up
        to its bandwidth, and a few points on the wrong side can stretch a box far."""
        cuts = list(cuts)
        log_node = np.log(hi[active] - lo[active] + h[active])

        def log_volume(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
            lower = np.where(lower - lo < h, lo, lower)[..., active]
            upper = np.where(hi - upper < h, hi, upper)[..., active]
            return (np.log(upper - lower + h[active]) - log_node).sum(axis=-1)

        for n in range(1, len(cuts) - 1):
            first, stop = cuts[n - 1], cuts[n + 1]
            inside = np.flatnonzero((bins >= first) & (bins < stop))
            order = inside[np.argsort(bins[inside], kind="stable")]
            used, starts = np.unique(bins[order], return_index=True)
            points = Xn[order]
            bin_lo = np.minimum.reduceat(points, starts, axis=0)
            bin_hi = np.maximum.reduceat(points, starts, axis=0)
            before = np.cumsum(np.diff(np.append(starts, len(order))))  # points in the first i + 1 bins
            # candidate splits: after the i-th used bin, for cut positions within reach
            window = np.arange(max(first + 1, cuts[n] - reach), min(stop - 1, cuts[n] + reach) + 1)
            split = np.unique(np.searchsorted(used, window))  # number of used bins left of the cut
            split = split[(split > 0) & (split < len(used))]
            left_n = before[split - 1]
            split = split[(left_n >= self.min_leaf) & (len(order) - left_n >= self.min_leaf)]
            if not len(split):
                continue
            left = log_volume(np.minimum.accumulate(bin_lo)[split - 1], np.maximum.accumulate(bin_hi)[split - 1])
            right = log_volume(np.minimum.accumulate(bin_lo[::-1])[::-1][split],
                               np.maximum.accumulate(bin_hi[::-1])[::-1][split])
            top = np.maximum(left, right).max()
            total = np.exp(left - top) + np.exp(right - top)
            current = int(np.searchsorted(used, cuts[n]))
            best = split[int(np.argmin(total))]
            if current in split and total[int(np.flatnonzero(split == current)[0])] <= total.min() * (1 + 1e-9):
                continue  # keep the cut where it is when moving it gains nothing
            cuts[n] = int(used[best - 1]) + 1 if best - 1 >= 0 else cuts[n]
        return cuts

    def _partitions(self, counts: np.ndarray, low: np.ndarray, density: np.ndarray,
                    sigma_bins: float) -> list[np.ndarray]:
        """Candidate partitions of one feature's grid, as interval labels per bin.

        Cuts where the density crosses the level and in empty runs at least one bandwidth wide
        (module docstring). A low-density stretch *between* two dense ones is then either its
        own interval (cut at both crossings: a sparse bridge) or split at its lowest point (two
        overlapping modes); both are offered when there is such a stretch, and the gain picks.
        """
        G = len(counts)
        cut = np.zeros(G, dtype=bool)  # cut[b]: a boundary between bin b - 1 and bin b
        cut[1:] = low[1:] != low[:-1]  # the density crosses the level
        empty = counts == 0
        if empty.any():  # runs of empty bins at least one bandwidth wide
            need = max(1, int(math.ceil(sigma_bins)))
            edges = np.diff(np.concatenate([[0], empty.astype(np.int8), [0]]))
            for start, stop in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)):
                if stop - start >= need and start > 0 and stop < G:
                    cut[start] = True
        variants = [cut]
        edges = np.diff(np.concatenate([[0], low.astype(np.int8), [0]]))
        valleys = [(a, b) for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)) if a > 0 and b < G]
        if valleys:
            at_minimum = cut.copy()
            for a, b in valleys:
                at_minimum[a] = at_minimum[b] = False
                at_minimum[a + int(np.argmin(density[a:b]))] = True
            variants.append(at_minimum)
        return [labels for labels in (self._labels(c, counts) for c in variants) if labels is not None]

    def _labels(self, cut: np.ndarray, counts: np.ndarray) -> np.ndarray | None:
        """Interval index of every bin (non-decreasing, 0-based, every interval holds data),
        or None when the cuts leave one interval only."""
        if not cut.any():
            return None
        empty = counts == 0
        raw = np.cumsum(cut)
        sizes = np.bincount(raw, weights=counts)
        kept = np.flatnonzero(sizes > 0)
        if len(kept) < 2:
            return None
        # intervals as (first bin, last bin, count); bins of dropped (empty) intervals go nowhere
        firsts = [int(np.flatnonzero((raw == r) & ~empty)[0]) for r in kept]
        lasts = [int(np.flatnonzero((raw == r) & ~empty)[-1]) for r in kept]
        sizes_kept = [float(sizes[r]) for r in kept]
        groups = [[r] for r in kept]
        while len(groups) > 1:
            small = [i for i, s in enumerate(sizes_kept) if s < self.min_leaf]
            if not small:
                break
            i = small[0]
            left_gap = firsts[i] - lasts[i - 1] if i > 0 else math.inf
            right_gap = firsts[i + 1] - lasts[i] if i + 1 < len(groups) else math.inf
            other = i - 1 if left_gap <= right_gap else i + 1
            a, b = min(i, other), max(i, other)
            groups[a] += groups[b]
            sizes_kept[a] += sizes_kept[b]
            firsts[a], lasts[a] = firsts[a], lasts[b]
            del groups[b], sizes_kept[b], firsts[b], lasts[b]
        if len(groups) < 2:
            return None
        relabel = np.zeros(int(raw[-1]) + 1, dtype=np.int64)
        for new, members in enumerate(groups):
            relabel[members] = new
        # dropped empty intervals: give them the label of the interval before (no point lands there)
        for r in range(len(relabel)):
            if sizes[r] == 0:
                relabel[r] = relabel[r - 1] if r > 0 else 0
        return relabel[raw]


def _std(X: np.ndarray) -> np.ndarray:
    """Each column's standard deviation, computed on the column scaled to at most 1 so that
    values near the float64 limit (1e300) do not overflow in the squares (it is never larger
    than the largest value)."""
    with np.errstate(over="ignore", invalid="ignore"):
        std = X.std(axis=0)
    if np.isfinite(std).all():
        return std  # the plain computation wherever it does not overflow (results stay bit-identical)
    scale = np.abs(X).max(axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    return np.where(np.isfinite(std), std, (X / scale).std(axis=0) * scale)


def bandwidths(X: np.ndarray, rule: str | float) -> np.ndarray:
    """Kernel bandwidth of every feature over all the data (0 for a constant feature)."""
    n = len(X)
    spread = X.max(axis=0) - X.min(axis=0)
    if not isinstance(rule, str):
        return float(rule) * spread
    std = _std(X)
    if rule == "scott":
        return 1.06 * std * n ** -0.2
    q1, q3 = np.percentile(X, [25, 75], axis=0)
    iqr = q3 - q1
    return 0.9 * np.where(iqr > 0, np.minimum(std, iqr / 1.34), std) * n ** -0.2


def _rule_bandwidth(Xa: np.ndarray, rule: str, counts: np.ndarray, width: np.ndarray) -> np.ndarray:
    """The bandwidth rule on a node's points (the IQR read off the node's histograms)."""
    m = len(Xa)
    std = _std(Xa)
    if rule == "scott":
        return 1.06 * std * m ** -0.2
    cum = np.cumsum(counts, axis=1)
    q1 = np.argmax(cum >= 0.25 * m, axis=1)
    q3 = np.argmax(cum >= 0.75 * m, axis=1)
    iqr = (q3 - q1) * width / counts.shape[1]
    return 0.9 * np.where(iqr > 0, np.minimum(std, iqr / 1.34), std) * m ** -0.2


class _Volume:
    """Volumes of groups of a node's points, as shares of the node's, on the node's density grid.

    A group's box is *robust*: on each feature it spans the mean plus and minus ``sigmas``
    standard deviations of the group's values (the range of a sample grows with its size;
    measured by min/max, cutting any sample in parts would pay in many dimensions; the
    standard deviation does not grow). Boxes are clipped to the reference box
    (the node's, or the merged box when merging), a side counts as tightened only when it lies
    inside the reference's by more than the bandwidth and :data:`MIN_TIGHTENING` of its extent,
    and every side is lengthened by the bandwidth.
    """

    def __init__(self, lo: np.ndarray, width: np.ndarray, h: np.ndarray, n_bins: int, sigmas: float) -> None:
        self.lo, self.step, self.h, self.sigmas = lo, width / n_bins, h, sigmas
        self.centers = (np.arange(n_bins) + 0.5)

    def extent(self, hists: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Robust ``(lower, upper)`` ``[C, ka]`` of groups given as histograms ``[C, ka, G]``."""
        size = np.maximum(hists.sum(axis=-1), 1.0)
        mean = hists @ self.centers / size
        var = np.maximum(hists @ self.centers ** 2 / size - mean ** 2, 0.0)
        half = self.sigmas * np.sqrt(var)
        return self.lo + (mean - half) * self.step, self.lo + (mean + half) * self.step

    def snap(self, ref_lo: np.ndarray, ref_hi: np.ndarray) -> np.ndarray:
        """How far inside the reference box a side must lie to count as tightened."""
        return np.maximum(self.h, MIN_TIGHTENING * (ref_hi - ref_lo))

    def log(self, lower: np.ndarray, upper: np.ndarray, ref_lo: np.ndarray, ref_hi: np.ndarray) -> np.ndarray:
        """Log share of the reference box's volume of each box (rows of ``lower``/``upper``)."""
        snap = self.snap(ref_lo, ref_hi)
        lower = np.where(lower - ref_lo < snap, ref_lo, np.minimum(lower, ref_hi))
        upper = np.where(ref_hi - upper < snap, ref_hi, np.maximum(upper, lower))
        return (np.log(upper - lower + self.h) - np.log(ref_hi - ref_lo + self.h)).sum(axis=-1)

    def merge(self, hists: np.ndarray, node_lo: np.ndarray, node_hi: np.ndarray):
        """Merge neighbouring intervals, smallest loss first, while a merged box is no larger
        than its two parts. Returns the groups of interval indices and their histograms."""
        groups = [[i] for i in range(len(hists))]
        lower, upper = self.extent(hists)
        while len(groups) > 1:
            pair = hists[:-1] + hists[1:]
            merged_lo, merged_hi = self.extent(pair)
            logs = [self.log(merged_lo, merged_hi, node_lo, node_hi)]
            for part in (slice(None, -1), slice(1, None)):
                snap = self.snap(merged_lo, merged_hi)
                part_lo = np.where(lower[part] - merged_lo < snap, merged_lo, lower[part])
                part_hi = np.where(merged_hi - upper[part] < snap, merged_hi, upper[part])
                logs.append(self.log(part_lo, part_hi, node_lo, node_hi))
            # relative to the largest of the three volumes (volumes in many dimensions underflow)
            top = np.maximum.reduce(logs)
            change = np.exp(logs[0] - top) - np.exp(logs[1] - top) - np.exp(logs[2] - top)
            i = int(np.argmin(change))
            if change[i] > 1e-9:
                break
            groups[i:i + 2] = [groups[i] + groups[i + 1]]
            hists = np.concatenate([hists[:i], pair[i:i + 1], hists[i + 2:]])
            lower = np.concatenate([lower[:i], merged_lo[i:i + 1], lower[i + 2:]])
            upper = np.concatenate([upper[:i], merged_hi[i:i + 1], upper[i + 2:]])
        return groups, hists


def _data_description(demonstrations: Any, n_points: int) -> str:
    """What the header says the formula was learned from: the demonstrations' own
    ``metadata["source"]`` (``"20 expert episodes of toy-navigation"``, a file's path: set where
    they were loaded or recorded, e.g. by ``recipes.experts.demonstrations``) with the number of
    points, else the number of points alone (an array, or demonstrations that do not say)."""
    metadata = getattr(demonstrations, "metadata", None)
    source = metadata.get("source") if isinstance(metadata, dict) else None
    # one line whatever a file's metadata holds: a line break would end the # comment mid-header
    source = " ".join(source.split()) if isinstance(source, str) else ""
    points = f"{n_points} points"
    return f"{source} ({points})" if source else points


def _notes(learner: OneClassTreeConstraint, closed: dict[str, int], trajectories: bool) -> list[str]:
    """The file-header lines that say how the formula was made readable (``closed``: the gaps
    closed by cause; ``trajectories``: whether the points came as demonstrations, whose steps
    can cross a gap)."""
    if not learner.readable:
        return ["thresholds are the data's values (readable=False)"]
    notes = ["thresholds: the fewest significant digits that keep every demonstration point on the same side "
             "of every rule"]
    narrow, crossed = closed["narrow"], closed["crossed"]
    narrow_text = "narrower than the data's resolution (the kernel bandwidth)"
    crossed_text = "crossed by a demonstrated step"
    if narrow and crossed:
        notes.append(f"{narrow + crossed} gap(s) between neighbouring safe boxes were closed (made safe): "
                     f"{narrow} {narrow_text}, {crossed} {crossed_text}")
    elif narrow or crossed:
        notes.append(f"{narrow + crossed} gap(s) between neighbouring safe boxes "
                     f"{narrow_text if narrow else crossed_text} were closed (made safe)")
    else:
        notes.append("no gap between neighbouring safe boxes was narrower than the data's resolution"
                     + (" or crossed by a demonstrated step" if trajectories else ""))
    return notes


def episode_setting_warnings(X: np.ndarray, names: Sequence[str], lengths: np.ndarray | None, dnf: DNF) -> list[str]:
    """One warning per feature that is constant within every demonstration but differs between
    them -- a setting of the episode (the weather, a goal's place), not something the expert
    chose -- when rules other than the data's bounds test it: they say which settings the
    demonstrations happened to have, and rarely a constraint. ``lengths``: the rows of ``X`` per
    demonstration (:func:`demonstration_lengths`; None: the points are no demonstrations)."""
    from symlearn.learners.episode_settings import episode_settings

    if lengths is None:
        return []
    settings = episode_settings(np.split(X, np.cumsum(lengths)[:-1]))
    out = []
    for d in settings:
        n_rules = sum(1 for c in dnf if len(c.atoms) > 1 and any(a.feature == names[d] for a in c.atoms))
        if n_rules:
            others = [n for i, n in enumerate(names) if i != d and i not in settings]
            hint = f"; leave it out with --inputs {','.join(others)} (inputs= in Python)" if others else ""
            out.append(f"feature {names[d]} is constant within every demonstration and differs between them "
                       f"(a setting of the episode, not a choice of the expert): the {n_rules} rule(s) testing "
                       f"it say which settings the demonstrations had{hint}")
    return out


def demonstration_lengths(demonstrations: Any, n_rows: int) -> np.ndarray | None:
    """The number of rows of the feature matrix (which holds the demonstrations' states in order)
    each demonstration gave, or None when the points did not come as demonstrations."""
    from symlearn.data import Demonstrations

    demonstrations = _as_demonstrations(demonstrations)
    if not isinstance(demonstrations, Demonstrations):
        return None
    lengths = np.array([len(t.states) for t in demonstrations], dtype=np.int64)
    return lengths if int(lengths.sum()) == n_rows else None


def demonstrated_steps(lengths: np.ndarray | None) -> np.ndarray | None:
    """``[M, 2]`` indices of consecutive rows that are consecutive states of one demonstration,
    from :func:`demonstration_lengths` (None stays None)."""
    if lengths is None:
        return None
    first = np.arange(int(lengths.sum()) - 1, dtype=np.int64)
    first = first[~np.isin(first, np.cumsum(lengths) - 1)]  # a demonstration's last row starts no step
    return np.column_stack([first, first + 1])


#: whole-number points of the bounding box counted one by one at most (past it: the volume share)
LATTICE_POINTS = 100_000


def _lattice_unsafe_share(X: np.ndarray, dnf, names: Sequence[str]) -> float | None:
    """Share of the whole-number points of the data's bounding box that ``dnf`` marks unsafe,
    where every value of the data is a whole number and there are at most ``LATTICE_POINTS``
    of them; else None."""
    X = np.asarray(X, dtype=np.float64)
    if X.size == 0 or not np.array_equal(X, np.round(X)):
        return None
    lo, hi = X.min(axis=0), X.max(axis=0)
    extents = (hi - lo + 1).astype(np.float64)
    # summed in logs: the product of many columns' extents (a picture's pixels) overflows a float
    if float(np.sum(np.log(extents))) > np.log(LATTICE_POINTS):
        return None
    axes = [np.arange(a, b + 1) for a, b in zip(lo, hi)]
    points = np.stack([g.reshape(-1) for g in np.meshgrid(*axes, indexing="ij")], axis=1)
    return float(np.mean(dnf.evaluate(points, list(names))))


def _volume_fraction(boxes: Sequence[Box], bounds: Box) -> float:
    """Share of the bounds' volume the boxes cover, over the features that vary (boxes are disjoint)."""
    lo, hi = np.asarray(bounds.lower), np.asarray(bounds.upper)
    varying = hi > lo
    if not varying.any():
        return 1.0
    total = 0.0
    for b in boxes:
        ratio = (np.asarray(b.upper) - np.asarray(b.lower))[varying] / (hi - lo)[varying]
        total += float(np.prod(ratio))
    return total


# -- the formula --------------------------------------------------------------------------------------

def tree_dnf(tree: OneClassTree) -> DNF:
    """The DNF of the points outside every leaf box (module docstring, "The constraint formula")."""
    names = tree.feature_names
    root = tree.root
    conjunctions: list[Conjunction] = []
    for d, name in enumerate(names):
        conjunctions.append(Conjunction((Atom(name, "<", root.box.lower[d]),)))
        conjunctions.append(Conjunction((Atom(name, ">", root.box.upper[d]),)))

    def path_atoms(path: dict[int, tuple[float, float]]) -> list[Atom]:
        atoms = []
        for d, (lower, upper) in path.items():
            atoms += [Atom(names[d], ">=", lower), _upper_atom(names[d], "<=", upper)]
        return atoms

    def visit(node: TreeNode, path: dict[int, tuple[float, float]]) -> None:
        if node.is_leaf:
            return
        j = node.feature
        for n, child in enumerate(node.children):
            low, high = child.box.lower[j], child.box.upper[j]
            previous = node.children[n - 1].box.upper[j] if n > 0 else None
            if previous is not None and np.nextafter(previous, math.inf) < low:  # a gap (not a closed sliver)
                conjunctions.append(Conjunction(tuple(path_atoms(path)) + (
                    _upper_atom(names[j], ">", previous), Atom(names[j], "<", low))))
            inner = dict(path)
            inner[j] = (low, high)
            inside = path_atoms(inner)
            for d in range(len(names)):
                if d == j:
                    continue
                if child.box.lower[d] > node.box.lower[d]:
                    conjunctions.append(Conjunction(tuple(inside) + (Atom(names[d], "<", child.box.lower[d]),)))
                if child.box.upper[d] < node.box.upper[d]:
                    conjunctions.append(Conjunction(tuple(inside) + (_upper_atom(names[d], ">", child.box.upper[d]),)))
            visit(child, inner)

    visit(root, {})
    # a side tightened below an ancestor's split adds a second bound on that feature in the same
    # direction (x1 < -0.39 & x1 < -0.64): keep the tightest, the same set of points
    return DNF(tuple(c.simplify() for c in conjunctions))


def _upper_atom(name: str, op: str, upper: float) -> Atom:
    """``name <= upper`` / ``name > upper``, written ``name < c`` / ``name >= c`` with ``c`` the next
    float when that prints shorter: the same set of floats, and how a closed sliver's left side
    (the largest float below the cut, see :mod:`readable_bounds`) reads as the cut itself."""
    from symlearn.logic.dnf import format_number

    nxt = float(np.nextafter(upper, math.inf))
    if math.isfinite(nxt) and len(format_number(nxt)) < len(format_number(float(upper))):
        return Atom(name, "<" if op == "<=" else ">=", nxt)
    return Atom(name, op, upper)


# -- text -------------------------------------------------------------------------------------------

def _num(value: float, digits: int) -> str:
    return f"{value:.{digits}g}"


def _range(name: str, lower: float, upper: float, digits: int) -> str:
    return f"{name} in [{_num(lower, digits)}, {_num(upper, digits)}]"


def tightened(parent: Box, child: Box, names: Sequence[str], skip: int | None, digits: int) -> list[str]:
    """``name in [lo, hi]`` for the features on which ``child`` is tighter than ``parent``."""
    return [_range(n, child.lower[d], child.upper[d], digits) for d, n in enumerate(names)
            if d != skip and (child.lower[d] > parent.lower[d] or child.upper[d] < parent.upper[d])]


def tree_text(tree: OneClassTree, digits: int = 4) -> str:
    names = tree.feature_names
    root = tree.root
    bounds = ", ".join(_range(n, root.box.lower[d], root.box.upper[d], digits) for d, n in enumerate(names))
    lines = [f"root: {root.n_samples} samples; {bounds}" + ("; leaf" if root.is_leaf else "")]

    def visit(node: TreeNode, indent: str) -> None:
        j = node.feature
        for child in node.children:
            parts = [_range(names[j], child.box.lower[j], child.box.upper[j], digits) + f": {child.n_samples} samples"]
            parts += tightened(node.box, child.box, names, j, digits)
            if child.is_leaf:
                parts.append("leaf")
            lines.append(f"{indent}|--- " + "; ".join(parts))
            visit(child, indent + "|   ")

    visit(root, "")
    return "\n".join(lines) + "\n"


def _holds_at_a_whole_number(conjunction: Conjunction) -> bool:
    """Whether some whole-number point satisfies every atom: each feature's interval (the
    conjunction's box) must hold an integer (``x > 1 & x < 2`` holds none, ``x >= 1 & x < 2`` holds 1)."""
    return all(interval.holds_whole_number for interval in conjunction.box().values())
