"""Reward machines from image demonstrations (thesis chapter 7, section 7.4).

:class:`RewardMachineInference` runs the whole of section 7.4 on a set of video demonstrations:
frames -> visual features (:mod:`.features`, PCA by default) -> DBSCAN clusters of the still frames
with data-derived eps and min_samples, their prototypes (:mod:`.prototypes`, eq. 7.4) -> the
labeling by distance to the prototypes (:mod:`.labeling`, eq. 7.5, kappa so at most one
proposition holds) -> Algorithm 7.1 over the label sequences (:mod:`.machine_building`) -> the
sparse reward machine (1 on reaching the final state) and its potential-shaped version
(:func:`symlearn.backends.goal_shaping.shape`, eqs. 7.6-7.7).

Machine states are numbered from the initial one (the cluster the demonstrations start in) in the
order Algorithm 7.1 first enters them; proposition ``p<i>`` is "the scene looks like the
prototype of state ``u<i>``". Clusters no demonstration enters through a label are dropped (with
a warning and their count in ``result_.metrics``).

>>> from symlearn.envs.rendered_blocks.demonstrator import demonstrations
>>> learner = RewardMachineInference().fit(demonstrations("place-2", seed=0).front)
>>> learner.machine_.n_states, sorted(learner.machine_.accepting), learner.labeling_.propositions
(4, [2], ('p0', 'p1', 'p2', 'p3'))
"""

from __future__ import annotations

import time
import warnings
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from symlearn.backends.goal_shaping import shape
from symlearn.errors import DataError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import FIT_CALLER, renamed_arguments
from symlearn.learners.reward_machines.features import as_frames, check_pixel_values, extract, make_extractor
from symlearn.learners.reward_machines.labeling import PrototypeLabeling, check_exclusive
from symlearn.learners.reward_machines.machine_building import infer_transitions, machine_from_edges
from symlearn.learners.reward_machines.prototypes import find_clusters


class DroppedClustersWarning(UserWarning):
    """Some clusters were never entered by a demonstration and are not machine states."""


@dataclass(frozen=True)
class StateRecord:
    """One machine state: its proposition, cluster, size and prototype frame."""

    state: int
    proposition: str
    cluster: int
    frames: int
    prototype_demonstration: int
    prototype_frame: int

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def frames_of(demonstrations: Any) -> tuple[np.ndarray, list[int]]:
    """All frames ``(N, H, W, C)`` and the frames per demonstration, validated."""
    if hasattr(demonstrations, "state_kind"):  # Demonstrations
        if demonstrations.state_kind != "image":
            raise DataError(f"the demonstrations hold {demonstrations.state_kind} states, not images",
                            hint="give video demonstrations (NPZ states of shape (T, H, W[, C]))")
        runs = [np.asarray(t.states) for t in demonstrations]
    else:
        runs = [np.asarray(r) for r in demonstrations]
        if not runs:
            raise DataError("no demonstrations given")
        shapes: dict[tuple, int] = {}
        for r in runs:
            if r.ndim < 3:
                raise DataError(f"a demonstration of shape {r.shape} is not a sequence of images (T, H, W[, C])")
            shapes[r.shape[1:]] = shapes.get(r.shape[1:], 0) + 1
        if len(shapes) > 1:
            counts = ", ".join(f"{n} x {s}" for s, n in sorted(shapes.items(), key=lambda kv: -kv[1]))
            raise DataError(f"frames of mixed sizes: {counts}", hint="render or crop every frame to one size")
    lengths = [len(r) for r in runs]
    frames = np.concatenate(runs)
    if len(frames) < 2:
        raise DataError(f"{len(frames)} frame: at least two frames are needed to find sub-goals")
    if np.issubdtype(frames.dtype, np.number):  # the value range of all of them (as_frames sees one)
        check_pixel_values(frames, "demonstration frames")
    as_frames(frames[:1], "demonstration frames")  # dtype and shape checks before any work
    return frames, lengths


class RewardMachineInference(Learner):
    """Infer a reward machine and its labeling from video demonstrations (see the module docstring).

    Parameters: ``features`` ("pca", "autoencoder", "random-cnn", or an extractor object),
    ``feature_extractor`` (a callable frames -> vectors; overrides ``features``),
    ``n_components`` (PCA components / autoencoder latent size; default chosen from the data),
    ``eps``, ``min_samples`` (DBSCAN; default derived from the data), ``kappa`` (labeling radius;
    default half the smallest prototype distance), ``gamma`` (shaping, None: no shaped machine),
    ``cache`` (reuse features of the same frames), ``random_state``.
    """

    artefact_suffix = ".json"

    def __init__(self, features: Any = "pca", feature_extractor: Any = None, n_components: int | None = None,
                 eps: float | None = None, min_samples: int | None = None, kappa: float | None = None,
                 gamma: float | None = 0.9, cache: bool = True, random_state: int = 0) -> None:
        self.features = features
        self.feature_extractor = feature_extractor
        self.n_components = n_components
        self.eps = eps
        self.min_samples = min_samples
        self.kappa = kappa
        self.gamma = gamma
        self.cache = cache
        self.random_state = random_state

    @renamed_arguments(domain="world")
    def fit(self, demonstrations: Any, world: Any = None) -> RewardMachineInference:
        clock = time.perf_counter()
        timings: dict[str, float] = {}
        frames, lengths = frames_of(demonstrations)
        starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(int)

        extractor = make_extractor(self.feature_extractor if self.feature_extractor is not None else self.features,
                                   n_components=self.n_components, random_state=self.random_state)
        tick = time.perf_counter()
        extractor, features, cached = extract(extractor, frames, cache=self.cache)
        timings["features"] = time.perf_counter() - tick

        tick = time.perf_counter()
        clusters = find_clusters(features, lengths, eps=self.eps, min_samples=self.min_samples)
        timings["clustering"] = time.perf_counter() - tick
        if clusters.n_clusters == 0:
            raise DataError("no sub-goal cluster found: no group of still frames is dense enough",
                            hint=f"eps {clusters.defaults.eps:.3g} / min_samples {clusters.defaults.min_samples} "
                                 "may be too small for these frames")

        # the initial state: the cluster most demonstrations are in when they first settle
        first = []
        for start, n in zip(starts, lengths):
            inside = clusters.labels[start:start + n]
            settled = inside[inside >= 0]
            first.append(int(settled[0]) if len(settled) else -1)
        known = [c for c in first if c >= 0]
        if not known:
            raise DataError("no demonstration ever settles in a sub-goal cluster")
        initial = max(set(known), key=known.count)

        tick = time.perf_counter()
        prototype_features = features[clusters.prototypes]
        all_names = [f"c{c}" for c in range(clusters.n_clusters)]
        labeling = PrototypeLabeling(extractor, prototype_features, self.kappa, all_names) \
            if clusters.n_clusters > 1 else None
        if labeling is None:
            raise DataError(f"the demonstrations never leave the initial cluster ({int(clusters.sizes[0])} frames "
                            "in one cluster, no other sub-goal)", hint="check the demonstrations, or lower eps")
        matrix = labeling.label_matrix(features=features)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            several = check_exclusive(matrix)
        for w in caught:
            warnings.warn(w.message, w.category, stacklevel=FIT_CALLER)
        words = [[frozenset(all_names[c] for c in np.flatnonzero(row)) for row in matrix[s:s + n]]
                 for s, n in zip(starts, lengths)]
        timings["labeling"] = time.perf_counter() - tick

        tick = time.perf_counter()
        delta = infer_transitions(words, {name: c for c, name in enumerate(all_names)}, initial)
        if not delta:
            raise DataError("the demonstrations never leave the initial cluster: no transition to infer",
                            hint="give demonstrations of the task being done, or a smaller kappa/eps")
        order = [initial]  # states in the order Algorithm 7.1 first enters them
        for word in words:
            u = initial
            for label in word:
                for p in sorted(label):
                    if (u, p) in delta:
                        u = delta[(u, p)]
                        if u not in order:
                            order.append(u)
        dropped = [c for c in range(clusters.n_clusters) if c not in order]
        if dropped:
            warnings.warn(f"{len(dropped)} of {clusters.n_clusters} clusters are never entered by a demonstration "
                          "and are left out of the machine", DroppedClustersWarning, stacklevel=FIT_CALLER)
        state_of_cluster = {c: k for k, c in enumerate(order)}
        names = [f"p{k}" for k in range(len(order))]
        edges = {(state_of_cluster[u], names[state_of_cluster[int(p[1:])]]): state_of_cluster[v]
                 for (u, p), v in delta.items()}
        finals = set()
        for word in words:
            u = initial
            for label in word:
                for p in sorted(label):
                    u = delta.get((u, p), u)
            finals.add(state_of_cluster[u])
        machine = machine_from_edges(names, edges, 0, finals)
        timings["machine"] = time.perf_counter() - tick

        self.features_ = extractor
        self.frame_features_ = features
        self.clusters_ = clusters
        self.cluster_labels_ = clusters.labels
        self.lengths_ = list(lengths)
        self.state_clusters_ = list(order)
        self.labeling_ = PrototypeLabeling(extractor, prototype_features[order], labeling.kappa, names)
        self.label_words_ = [tuple(frozenset(names[state_of_cluster[int(p[1:])]] for p in label
                                            if int(p[1:]) in state_of_cluster) for label in word)
                             for word in words]
        self.prototype_indices_ = [int(clusters.prototypes[c]) for c in order]
        self.prototype_frames_ = frames[self.prototype_indices_]
        self.machine_ = machine
        self.shaped_machine_ = shape(machine, self.gamma) if self.gamma is not None else None
        self.eps_, self.min_samples_, self.kappa_ = clusters.defaults.eps, clusters.defaults.min_samples, labeling.kappa
        timings["total"] = time.perf_counter() - clock
        history = []
        for k, c in enumerate(order):
            index = int(clusters.prototypes[c])
            demo = int(np.searchsorted(starts, index, side="right") - 1)
            history.append(StateRecord(k, names[k], c, int(clusters.sizes[c]), demo, index - int(starts[demo])))
        artefact = self.shaped_machine_ or machine
        metrics = {"states": machine.n_states, "edges": len(edges), "clusters": clusters.n_clusters,
                   "dropped_clusters": len(dropped), "frames": int(len(frames)),
                   "clustered_frames": int(np.sum(clusters.labels >= 0)), "multiple_label_frames": several,
                   "eps": self.eps_, "min_samples": self.min_samples_, "kappa": self.kappa_,
                   "features": extractor.config(), "features_cached": cached, **{
                       f"defaults.{k}": v for k, v in clusters.defaults.as_dict().items()}}
        self._set_result(artefact, artefact.to_json(), metrics=metrics, timings=timings, history=history)
        return self

    def label_words(self, demonstrations: Any) -> list[tuple[frozenset[str], ...]]:
        """The abstract demonstrations of other videos under the learned labeling."""
        self.check_fitted()
        frames, lengths = frames_of(demonstrations)
        matrix = self.labeling_.label_matrix(frames)
        words, start = [], 0
        for n in lengths:
            words.append(tuple(frozenset(p for p, h in zip(self.labeling_.propositions, row) if h)
                               for row in matrix[start:start + n]))
            start += n
        return words


__all__ = ["DroppedClustersWarning", "RewardMachineInference", "StateRecord", "frames_of"]
