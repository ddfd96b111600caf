"""Sub-goals as dense regions of the demonstration frames: DBSCAN, cluster means and prototypes.

The thesis (section 7.4.3) clusters the features of all frames with DBSCAN and takes, per cluster,
the frame closest to the cluster mean as its *prototype* (eq. 7.4). Its Table 7.1 tuned eps and
min samples by hand per task; here both default to values derived from the data, the same rule
for every task:

* **Which frames.** Consecutive frames of one demonstration are either *still* (they differ by
  rendering noise only) or *moving*; Otsu's threshold on the logarithm of the consecutive feature
  distances separates the two. Only still frames are clustered: sub-goals are where demonstrators
  linger, and frames in motion would otherwise attach to (and bridge) the clusters next to them.
  Moving frames get label -1, like DBSCAN's noise.
* **min_samples** is half the median still run (at least 3): a sub-goal visited once is still a
  cluster, a short pause is not.
* **eps** is half the median distance between consecutive still runs of a demonstration (the
  mean feature of one run to that of the next). Consecutive runs always show different
  sub-goals, so this median is the size of one sub-goal change in this data, whatever the
  rendering, the feature extractor or the demonstrator's speed. Frames of one sub-goal differ by
  noise and by small placement differences between visits, frames of two sub-goals by about one
  change; half of it is the midpoint. (A quarter split revisits of a pyramid whose three blocks
  were each placed a little differently; see ``benchmarks/rm_inference.py`` for the +-30 % sweep.)

Both are overridable (``eps=``, ``min_samples=``); :class:`Defaults` records how they were found.

>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> still = [rng.normal(c, 0.05, (20, 2)) for c in ((0, 0), (3, 0), (3, 3))]
>>> moving = [np.linspace((0, 0), (3, 0), 7)[1:-1], np.linspace((3, 0), (3, 3), 7)[1:-1]]
>>> x = np.concatenate([still[0], moving[0], still[1], moving[1], still[2]])
>>> found = find_clusters(x, [len(x)])
>>> found.n_clusters, found.labels[:3].tolist(), bool(found.labels[-1] != found.labels[0])
(3, [0, 0, 0], True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from symlearn.errors import DataError


def otsu_threshold(values: np.ndarray) -> float:
    """The split of 1-D ``values`` maximising the between-group variance (Otsu), between two values."""
    v = np.sort(np.asarray(values, dtype=np.float64))
    if len(v) < 2 or v[0] == v[-1]:
        return float(v[-1]) if len(v) else 0.0
    n = len(v)
    left_sum = np.cumsum(v)[:-1]
    counts = np.arange(1, n)
    mean_left = left_sum / counts
    mean_right = (v.sum() - left_sum) / (n - counts)
    between = counts * (n - counts) * (mean_left - mean_right) ** 2
    between[v[:-1] == v[1:]] = -1  # a split must fall between two different values
    k = int(np.argmax(between))
    return float((v[k] + v[k + 1]) / 2)


def _log(values: np.ndarray) -> np.ndarray:
    positive = values[values > 0]
    floor = positive.min() / 10 if len(positive) else 1e-12
    return np.log(np.maximum(values, floor))


@dataclass(frozen=True)
class Defaults:
    """How eps and min_samples were chosen (``given`` when the user set them)."""

    eps: float
    min_samples: int
    eps_source: str
    min_samples_source: str
    still_threshold: float  # consecutive-frame distance below which a frame is "still"
    median_still_run: float
    median_jump: float  # median distance between consecutive still runs (nan: fewer than two runs)

    def as_dict(self) -> dict:
        return dict(vars(self))


def still_frames(features: np.ndarray, lengths: Sequence[int]) -> tuple[np.ndarray, float]:
    """Boolean mask of still frames (every step to a neighbouring frame below the threshold) and the threshold."""
    steps, start = [], 0
    for n in lengths:
        steps.append(np.linalg.norm(np.diff(features[start:start + n], axis=0), axis=1))
        start += n
    all_steps = np.concatenate(steps)
    if len(all_steps) < 2:
        return np.ones(len(features), dtype=bool), float("inf")
    threshold = float(np.exp(otsu_threshold(_log(all_steps))))
    mask = []
    for d in steps:
        small = d < threshold
        before = np.concatenate([[True], small])  # step from the previous frame (none for the first)
        after = np.concatenate([small, [True]])
        mask.append(before & after)
    return np.concatenate(mask), threshold


def still_runs(mask: np.ndarray, lengths: Sequence[int]) -> list[tuple[int, int]]:
    """``(start, stop)`` frame ranges of maximal still runs (never across demonstrations)."""
    runs, start = [], 0
    for n in lengths:
        t = start
        while t < start + n:
            if mask[t]:
                u = t
                while u < start + n and mask[u]:
                    u += 1
                runs.append((t, u))
                t = u
            else:
                t += 1
        start += n
    return runs


def derive_defaults(features: np.ndarray, lengths: Sequence[int], eps: float | None = None,
                    min_samples: int | None = None) -> tuple[Defaults, np.ndarray]:
    """eps and min_samples for ``features`` of demonstrations of ``lengths`` frames (see the module
    docstring), and the mask of still frames."""
    mask, threshold = still_frames(features, lengths)
    runs = [(a, b) for a, b in still_runs(mask, lengths) if b - a >= 2]
    median_run = float(np.median([b - a for a, b in runs])) if runs else 1.0
    given_samples = min_samples is not None
    if min_samples is None:
        min_samples = max(3, int(median_run // 2))
    if isinstance(min_samples, bool) or not isinstance(min_samples, (int, np.integer)) or min_samples < 1:
        raise DataError(f"min_samples must be a positive integer, got {min_samples!r}")
    jumps, start = [], 0
    for n in lengths:  # consecutive runs inside one demonstration
        inside = [features[a:b].mean(axis=0) for a, b in runs if start <= a < start + n]
        jumps += [float(np.linalg.norm(q - p)) for p, q in zip(inside, inside[1:])]
        start += n
    median_jump = float(np.median(jumps)) if jumps else float("nan")
    given_eps = eps is not None
    if eps is None:
        if not jumps:
            raise DataError("the demonstrations never move from one still scene to another, so there are no "
                            "sub-goals to find", hint="give demonstrations of the task being done (or eps=)")
        eps = median_jump / 2
    if isinstance(eps, bool) or not (isinstance(eps, (int, float, np.floating)) and np.isfinite(eps) and eps > 0):
        raise DataError(f"eps must be a positive number, got {eps!r}")
    return Defaults(float(eps), int(min_samples), "given" if given_eps else "half the median jump between still runs",
                    "given" if given_samples else "half the median still run", threshold, median_run,
                    median_jump), mask


@dataclass(frozen=True)
class Clusters:
    """DBSCAN's result: ``labels`` per frame (-1 = noise), per cluster ``means``, ``prototypes``
    (frame index closest to the mean, eq. 7.4), ``sizes``; ``defaults`` as used."""

    labels: np.ndarray
    means: np.ndarray
    prototypes: np.ndarray
    sizes: np.ndarray
    defaults: Defaults

    @property
    def n_clusters(self) -> int:
        return len(self.sizes)


def find_clusters(features: np.ndarray, lengths: Sequence[int], *, eps: float | None = None,
                  min_samples: int | None = None) -> Clusters:
    """DBSCAN over the still frames with data-derived defaults; clusters numbered by first appearance."""
    from sklearn.cluster import DBSCAN

    features = np.asarray(features, dtype=np.float64)
    if features.ndim != 2 or len(features) < 2:
        raise DataError(f"sub-goal clustering needs at least 2 frames, got {len(features)}")
    if sum(lengths) != len(features):
        raise DataError(f"lengths sum to {sum(lengths)} but there are {len(features)} frames")
    defaults, still = derive_defaults(features, lengths, eps, min_samples)
    raw = np.full(len(features), -1)
    if still.sum() >= 1:
        raw[still] = DBSCAN(eps=defaults.eps, min_samples=min(defaults.min_samples, int(still.sum()))
                            ).fit_predict(features[still])
    order: dict[int, int] = {}
    for value in raw:  # renumber by first appearance, so cluster 0 is where the first demonstration starts
        if value >= 0 and value not in order:
            order[int(value)] = len(order)
    labels = np.array([order.get(int(v), -1) for v in raw])
    means, prototypes, sizes = [], [], []
    for c in range(len(order)):
        members = np.flatnonzero(labels == c)
        mean = features[members].mean(axis=0)
        means.append(mean)
        prototypes.append(members[np.argmin(np.linalg.norm(features[members] - mean, axis=1))])
        sizes.append(len(members))
    dim = features.shape[1]
    return Clusters(labels, np.asarray(means).reshape(-1, dim), np.asarray(prototypes, dtype=int),
                    np.asarray(sizes, dtype=int), defaults)


def purity(labels: np.ndarray, truth: Sequence) -> tuple[float, list[float]]:
    """Weighted and per-cluster purity: the share of a cluster's frames with its most common truth
    value (frames between sub-goals are a truth value of their own)."""
    truth = np.asarray([str(t) for t in truth])
    per_cluster, total, majority = [], 0, 0
    for c in sorted(set(labels.tolist()) - {-1}):
        values, counts = np.unique(truth[labels == c], return_counts=True)
        per_cluster.append(float(counts.max() / counts.sum()))
        total += counts.sum()
        majority += counts.max()
    return (float(majority / total) if total else 0.0), per_cluster


__all__ = ["Clusters", "Defaults", "derive_defaults", "find_clusters", "otsu_threshold", "purity", "still_frames",
           "still_runs"]
