"""Sub-goals by clustering (thesis, section 6.4.1), on weighted collapsed frames.

For each candidate feature subset, every observed frame of every demonstration is projected on
the subset and the projections are clustered with DBSCAN; clusters holding the first frame of a
demonstration (an initial state) are dropped where at least half of the demonstrations that reach
them start in them (a place a few demonstrations start near is still a sub-goal for the others);
clusters of pass-through frames are dropped too: where a cluster's frames that have a frame of
the same demonstration before or after them in the cluster (the demonstration stayed) weigh less
than ``min_samples``, demonstrations only pass there (a deterministic walker puts one frame of every
tour on the same point of a shared path, a dense cluster nobody stays in);
each remaining cluster is a sub-goal: its centre is
the mean of its frames, its radius the largest distance from the centre to one of its core points
(plus the collapse resolution).

**Collapsed frames.** A demonstrator dwells: an object that was put down sits still for the rest
of the demonstration, and thousands of demonstrations repeat the same places. Clustering every
raw frame makes time and memory grow with the number of frames (DBSCAN's neighbourhoods are
quadratic in a dense place). So the projections are first snapped to a grid of cell
``cell_fraction * eps / sqrt(d)`` (a cell's diagonal is ``cell_fraction * eps``), and each
occupied cell becomes *one* point at the mean of its frames, weighted by their number
(DBSCAN's ``sample_weight``: a point is core when the *weight* within ``eps`` reaches
``min_samples``). The number of points is then bounded by the occupied volume, not by the number
of frames; a neighbourhood is distorted by at most one cell diagonal. Centres are computed from
the raw frames (the cells keep coordinate sums), so collapsing does not move them.

**Defaults from the data** (per subset, overridable):

* ``eps``: ``max(0.02 * diagonal of the projections' bounding box, 4 * lower-quartile step)``,
  the step being the distance between consecutive observed frames of a demonstration, and at
  most **half the travel step**. Where a demonstrator dwells for at least a quarter of the
  frames, the lower quartile of the steps is detection noise; the median is not, when more than
  half the frames are in motion (a drone flying between places), and then an ``eps`` from it
  chains the places together. But a demonstrator fast against its noise (a cook walking 0.3 per
  step, dwelling with noise 0.05) gets an ``eps`` from the noise alone (0.45) that spans more
  than one walking step: a pass then puts about ``2 * eps / step`` frames in a neighbourhood, not
  one (``min_samples`` below assumes one), and the busy paths join the places and the start into
  one cluster. So the steps are split in two modes, dwelling and travelling (Otsu's threshold
  on their logarithms, :func:`otsu_split`; the reward-machine learner tells still from moving
  frames the same way), and ``eps`` is capped at half the *travel step*, the lower quartile of
  the upper mode (:func:`travel_step`): the slower passes (accelerating near a place, a slower
  demonstrator) leave about one frame in a neighbourhood too; half the median travel step left
  two and more from the slow third of a tracker whose demonstrators moved 8 to 40 pixels per step,
  and an extra sub-goal. A demonstrator that travels in long steps against its noise (the guide's
  robot, 20 of the 21 block-world data sets of the benchmarks) keeps the ``eps`` from the noise;
  the drone's and Reacher's are capped (0.288 -> 0.222, 0.0103 -> 0.0076) with the same sub-goals
  and plans. ``ClusterRecord.eps_source`` says which bound was used.
  ``benchmarks/subgoal_defaults.py`` compares this rule with others on every data set the
  benchmarks, the demo, the tests and the guide use, and on fresh demonstrators;
* ``min_samples`` (a weight, in frames): ``max(3, ceil(1.5 * number of demonstrations))``. A
  sub-goal is a place where demonstrations dwell: on average more than one frame per
  demonstration (every demonstration dwelling two frames, or half of them four). A place a
  demonstration merely passes through gets at most about one frame from each demonstration that
  passes there (the first and last frames of a carry lie close to where it starts and ends), so
  its weight grows with the number of demonstrations too: a fixed ``min_samples`` would turn
  busy transit paths into sub-goals once there are enough demonstrations, a share of them does
  not.

``method="hdbscan"`` runs scikit-learn's HDBSCAN instead (``min_cluster_size`` = ``min_samples``;
``eps`` then only sets the collapse resolution); it has no sample weights, so each collapsed
point is repeated in proportion to its weight (at most about ``HDBSCAN_POINTS`` points in all):
an approximation, offered for comparison.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet
from symlearn.learners.subgoals.subsets import FeatureSubset
from symlearn.progress import progress

HDBSCAN_POINTS = 20_000
METHODS = ("dbscan", "hdbscan")


@dataclass(frozen=True)
class ClusterRecord:
    """What clustering one feature subset did."""

    subset: str
    frames: int  # observed frames projected on the subset
    points: int  # weighted points after collapsing
    eps: float
    min_samples: float
    clusters: int  # found by DBSCAN
    dropped_initial: int  # of those, holding an initial state
    noise_weight: float  # frames in no cluster
    seconds: float
    eps_source: str = "given"  # or the default's bound: "dwelling noise", "half the travel step" ("no frames")
    dropped_passing: int = 0  # of the clusters found, made of pass-through frames (:func:`_passing_place`)

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class CollapsedFrames:
    """Grid-collapsed projections of one subset: point = mean of its cell's frames."""

    points: np.ndarray  # (P, d)
    weights: np.ndarray  # (P,) frames per point
    sums: np.ndarray  # (P, d) coordinate sums of those frames
    initial: np.ndarray  # (P,) bool: the cell holds a demonstration's first frame
    index: np.ndarray | None = None  # (N,) the point each projected frame was collapsed into


def collapse(projected: np.ndarray, initial: np.ndarray, cell: float) -> CollapsedFrames:
    """Snap ``projected`` (``(N, d)``, no NaN) to cells of side ``cell``; one weighted point per cell."""
    if len(projected) == 0:
        d = projected.shape[1]
        return CollapsedFrames(np.zeros((0, d)), np.zeros(0), np.zeros((0, d)), np.zeros(0, dtype=bool))
    keys = np.floor(projected / cell).astype(np.int64)
    _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    sums = np.zeros((len(counts), projected.shape[1]))
    np.add.at(sums, inverse, projected)
    has_initial = np.zeros(len(counts), dtype=bool)
    has_initial[inverse[initial]] = True
    weights = counts.astype(np.float64)
    return CollapsedFrames(sums / weights[:, None], weights, sums, has_initial, inverse)


def _start_place(members: np.ndarray, collapsed: CollapsedFrames, initial: np.ndarray,
                 demonstration: np.ndarray) -> bool:
    """Whether a cluster holding some demonstration's first frame is where demonstrations start:
    at least half of the demonstrations that reach it start in it. A place every demonstration
    goes to stays a sub-goal when a few of them happen to start in or next to it (an object
    whose random start lies near its goal: that demonstration's approach chains its first frame
    into the goal's cluster), which dropping on any first frame would throw away for all."""
    frames = members[collapsed.index]
    visiting = np.unique(demonstration[frames])
    starting = np.unique(demonstration[frames & initial])
    return 2 * len(starting) >= len(visiting)


def _passing_place(members: np.ndarray, collapsed: CollapsedFrames, demonstration: np.ndarray,
                   min_samples: float) -> bool:
    """Whether a cluster is a place demonstrations pass through, not one where they stay: without
    its pass-through frames (a frame whose demonstration's previous and next observed frames both
    lie outside the cluster) its weight falls below ``min_samples``. Where every demonstration
    puts its frames on the same points (a deterministic walker), the one frame that each of them
    leaves at the same spot on a shared path (the last step before a place, passed on the way in
    and out) piles up into a dense cluster although nobody stays there; a place where
    demonstrations dwell keeps its runs of consecutive frames."""
    frames = members[collapsed.index]
    if not frames.any():
        return False
    # consecutive frames of one demonstration are adjacent in the concatenated observed frames:
    # a pair of them both in the cluster makes both staying frames
    pair = frames[:-1] & frames[1:] & (demonstration[:-1] == demonstration[1:])
    staying = np.zeros(len(frames), dtype=bool)
    staying[:-1] |= pair
    staying[1:] |= pair
    return float(staying.sum()) < min_samples


#: bins of the log-step histogram that :func:`otsu_split` splits (a fraction of a percent of the
#: log range per bin; an exact split of a million sorted steps costs more than the clustering)
OTSU_BINS = 512


def otsu_split(values: np.ndarray) -> float | None:
    """The threshold between the two modes of non-negative ``values``: Otsu's split (the largest
    between-group variance) of the histogram of their logarithms (:data:`OTSU_BINS` bins), zeros
    counted in the lowest bin; None when there are fewer than two distinct values. (The
    reward-machine learner separates still from moving frames by Otsu's split of the log steps too,
    :mod:`symlearn.learners.reward_machines.prototypes`.)"""
    v = np.asarray(values, dtype=np.float64)
    positive = v[v > 0]
    if len(v) < 2 or not len(positive) or v.min() == v.max():
        return None
    logs = np.log(np.maximum(v, positive.min() / 10))
    counts, edges = np.histogram(logs, bins=OTSU_BINS)
    centres = (edges[:-1] + edges[1:]) / 2
    n_left = np.cumsum(counts)[:-1].astype(np.float64)
    sum_left = np.cumsum(counts * centres)[:-1]
    n, total = float(counts.sum()), float((counts * centres).sum())
    with np.errstate(divide="ignore", invalid="ignore"):
        between = n_left * (n - n_left) * (sum_left / n_left - (total - sum_left) / (n - n_left)) ** 2
    between[(n_left == 0) | (n_left == n)] = -1  # both groups non-empty
    k = int(np.argmax(between))
    return float(np.exp(edges[k + 1]))


def travel_step(steps: np.ndarray) -> float | None:
    """The step of a demonstration in motion: the lower quartile of the upper mode of
    consecutive-frame ``steps`` (:func:`otsu_split`). The lower quartile, not the median: passes
    slower than the typical one (a demonstrator accelerating near a place, a slower demonstrator)
    leave more frames in a neighbourhood, and they too should leave about one. None when the steps
    do not split."""
    threshold = otsu_split(steps)
    if threshold is None:
        return None
    moving = steps[steps > threshold]
    return float(np.quantile(moving, 0.25)) if len(moving) else None


@dataclass(frozen=True)
class EpsChoice:
    """How the default ``eps`` of a subset was found (:func:`derive_eps`)."""

    eps: float
    source: str  # "dwelling noise" or "half the travel step"
    noise_eps: float  # max(0.02 * diagonal, 4 * lower-quartile step)
    travel_step: float | None  # lower-quartile step in motion (None: the steps do not split in two modes)


def derive_eps(runs: Sequence[np.ndarray]) -> EpsChoice:
    """The default ``eps`` of projected ``runs`` (see the module docstring): ``max(0.02 *
    bounding-box diagonal, 4 * lower-quartile consecutive step)``, at most half the travel step."""
    observed = [r[~np.isnan(r).any(axis=1)] for r in runs]
    stacked = np.concatenate([r for r in observed if len(r)]) if any(len(r) for r in observed) else None
    if stacked is None:
        return EpsChoice(1.0, "no frames", 1.0, None)
    diagonal = float(np.linalg.norm(stacked.max(axis=0) - stacked.min(axis=0)))
    steps = [np.linalg.norm(np.diff(r, axis=0), axis=1) for r in observed if len(r) > 1]
    all_steps = np.concatenate(steps) if steps else np.zeros(0)
    step = float(np.quantile(all_steps, 0.25)) if len(all_steps) else 0.0
    noise_eps = max(0.02 * diagonal, 4 * step)
    noise_eps = noise_eps if noise_eps > 0 else 1e-6
    travel = travel_step(all_steps)
    if travel is not None and travel / 2 < noise_eps:
        return EpsChoice(travel / 2, "half the travel step", noise_eps, travel)
    return EpsChoice(noise_eps, "dwelling noise", noise_eps, travel)


def default_eps(runs: Sequence[np.ndarray]) -> float:
    """The default ``eps`` of projected runs (:func:`derive_eps`)."""
    return derive_eps(runs).eps


#: beyond this, squared Euclidean distances between frames overflow float64 (about 1.8e308)
MAX_MAGNITUDE = 1e150


def _check_magnitude(runs: Sequence[np.ndarray], subset: str) -> None:
    """Refuse feature values whose distances would overflow to infinity (DBSCAN, eps, grid cells)."""
    largest = max((float(np.nanmax(np.abs(r))) for r in runs if r.size and not np.isnan(r).all()), default=0.0)
    if largest > MAX_MAGNITUDE:
        raise DataError(f"the frames hold values up to {largest:.3g} in feature subset {subset!r}: distances "
                        f"between frames overflow beyond {MAX_MAGNITUDE:.0e}", hint="rescale the features (e.g. to metres, or "
                        "divided by their range), or leave such columns out of --subsets")


def default_min_samples(n_demonstrations: int) -> float:
    return float(max(3, math.ceil(1.5 * n_demonstrations)))


def find_subgoals(frames: Sequence[np.ndarray], subsets: Sequence[FeatureSubset], *, eps: float | None = None,
                  min_samples: float | None = None, method: str = "dbscan", cell_fraction: float = 0.25,
                  feature_names: Sequence[str] | None = None) -> tuple[SubGoalSet, list[ClusterRecord]]:
    """Sub-goals of ``frames`` (one ``(T_i, k)`` array per demonstration, NaN = unobserved)."""
    if method not in METHODS:
        raise DataError(f"unknown clustering method {method!r}", hint="use " + " or ".join(METHODS))
    if eps is not None and not (isinstance(eps, (int, float)) and math.isfinite(eps) and eps > 0):
        raise DataError(f"eps must be a positive number, got {eps!r}")
    if min_samples is not None and not (isinstance(min_samples, (int, float)) and min_samples >= 1):
        raise DataError(f"min_samples must be at least 1, got {min_samples!r}")
    if not 0 < cell_fraction <= 1:
        raise DataError(f"cell_fraction must be in (0, 1], got {cell_fraction!r}")
    goals: list[SubGoal] = []
    records: list[ClusterRecord] = []
    never_observed = []
    for subset in progress(subsets, total=len(subsets), desc="clustering"):
        started = time.perf_counter()
        runs = [f[:, subset.features] for f in frames]
        _check_magnitude(runs, subset.name)
        if eps is not None:
            subset_eps, eps_source = float(eps), "given"
        else:
            choice = derive_eps(runs)
            subset_eps, eps_source = choice.eps, choice.source
        subset_min = float(min_samples) if min_samples is not None else default_min_samples(len(frames))
        observed = [~np.isnan(r).any(axis=1) for r in runs]
        projected = np.concatenate([r[m] for r, m in zip(runs, observed)])
        # a demonstration's first frame, where it is observed: the initial states
        initial = np.concatenate([np.arange(m.sum()) < int(m[0]) for m in observed])
        demonstration = np.concatenate([np.full(int(m.sum()), i) for i, m in enumerate(observed)])
        if len(projected) == 0:
            never_observed.append(subset.name)
            records.append(ClusterRecord(subset.name, 0, 0, subset_eps, subset_min, 0, 0, 0.0,
                                         time.perf_counter() - started, eps_source))
            continue
        cell = cell_fraction * subset_eps / math.sqrt(len(subset.features))
        collapsed = collapse(projected, initial, cell)
        labels, core = _cluster(collapsed, subset_eps, subset_min, method)
        found, dropped, passing = [], 0, 0
        for label in range(labels.max() + 1 if len(labels) else 0):
            members = labels == label
            if collapsed.initial[members].any() and _start_place(members, collapsed, initial, demonstration):
                dropped += 1
                continue
            if _passing_place(members, collapsed, demonstration, subset_min):
                passing += 1
                continue
            weight = collapsed.weights[members].sum()
            centre = collapsed.sums[members].sum(axis=0) / weight
            inner = members & core if (members & core).any() else members
            distances = np.linalg.norm(collapsed.points[inner] - centre, axis=1)
            found.append((tuple(centre.tolist()), float(distances.max()) + cell_fraction * subset_eps))
        # names in the order of the centres, so a re-run on the same data names them alike
        for k, (centre, radius) in enumerate(sorted(found)):
            goals.append(SubGoal(f"{subset.name}_{k}", subset.name, subset.features, centre, radius))
        records.append(ClusterRecord(subset.name, int(len(projected)), int(len(collapsed.weights)), subset_eps,
                                     subset_min, int(labels.max() + 1) if len(labels) else 0, dropped,
                                     float(collapsed.weights[labels < 0].sum()), time.perf_counter() - started,
                                     eps_source, passing))
    if not goals:
        if len(never_observed) == len(subsets):
            raise DataError("every frame is unobserved (NaN) on every feature subset: nothing to cluster",
                            hint="check the demonstrations and the subsets' columns")
        described = "; ".join(f"{r.subset}: {r.clusters} clusters, {r.dropped_initial} holding an initial state, "
                              + (f"{r.dropped_passing} of pass-through frames, " if r.dropped_passing else "")
                              + f"eps={r.eps:.3g}, min_samples={r.min_samples:.3g}" for r in records)
        hint = ("lower min_samples (--min-samples) so sparser places count, or raise eps (--eps) so a dwelling "
                "place forms one cluster")
        if any(r.clusters and r.dropped_initial == r.clusters for r in records):
            # the start was joined to the places: transit frames, not too little density
            hint = ("every cluster held a demonstration's first frame: the frames between the start and the places "
                    "joined them into one, as a demonstration passing through puts several frames within eps of "
                    "each other when eps is more than about half its step; lower eps (--eps) or raise min_samples "
                    "(--min-samples)")
        raise DataError(f"no sub-goal found ({described})", hint=hint)
    return SubGoalSet(goals, feature_names=feature_names), records


def _cluster(collapsed: CollapsedFrames, eps: float, min_samples: float, method: str) -> tuple[np.ndarray, np.ndarray]:
    """Cluster label per collapsed point (-1 = noise) and whether it is a core point."""
    if method == "dbscan":
        from sklearn.cluster import DBSCAN

        model = DBSCAN(eps=eps, min_samples=max(1, math.ceil(min_samples))).fit(collapsed.points, sample_weight=collapsed.weights)
        core = np.zeros(len(collapsed.weights), dtype=bool)
        core[model.core_sample_indices_] = True
        return model.labels_, core
    from sklearn.cluster import HDBSCAN

    total = collapsed.weights.sum()
    scale = min(1.0, HDBSCAN_POINTS / total)
    repeats = np.maximum(1, np.round(collapsed.weights * scale)).astype(np.int64)
    expanded = np.repeat(collapsed.points, repeats, axis=0)
    size = max(2, int(round(min_samples * scale)))
    labels = HDBSCAN(min_cluster_size=size, copy=True).fit(expanded).labels_
    point_labels = np.full(len(repeats), -1)
    # a collapsed point takes the label most of its copies got (copies are consecutive)
    for p, values in enumerate(np.split(labels, np.cumsum(repeats)[:-1])):
        values = values[values >= 0]
        if len(values):
            point_labels[p] = np.bincount(values).argmax()
    return point_labels, point_labels >= 0
