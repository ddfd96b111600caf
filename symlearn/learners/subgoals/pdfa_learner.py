"""Learning a sub-goal PDFA from demonstrations (thesis, chapter 6): the learner.

``SubgoalPDFALearner().fit(demonstrations, features)`` runs the three steps:

1. sub-goals by clustering each candidate feature subset (:mod:`.clustering`);
2. every demonstration as a word of sub-goals (Algorithm 6.1, :mod:`.words`);
3. the PDFA of their orderings (Algorithm 6.2 and eqs. 6.2/6.3, :mod:`.ordering_automaton`),

and the greedy plan of the result (:mod:`symlearn.backends.subgoal_plan` executes plans).

The saved artefact (``save(path.json)``, also ``result_.text``) is the PDFA's
``symlearn-automaton`` JSON with three more keys -- ``subgoals`` (name -> centre, radius,
subset, features), ``plan`` and ``words`` (each distinct word and how often it was seen) -- so
``symlearn automaton show`` reads it as a PDFA and the sub-goals travel with it.

>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> def demo(order):  # an object at 0 visits 1 and 2 on a line, dwelling 10 frames at each
...     path = [0.0] * 5 + sum(([float(g)] * 10 for g in order), [])
...     return np.array(path)[:, None] + rng.normal(0, 0.01, (len(path), 1))
>>> learner = SubgoalPDFALearner(eps=0.1).fit([demo([1, 2])] * 3 + [demo([2, 1])], ["x"])
>>> [round(g.centre[0], 1) for g in learner.subgoals_], learner.plan_
([1.0, 2.0], ['all_0', 'all_1'])
"""

from __future__ import annotations

import json
import time
import warnings
from collections import Counter
from typing import Any

import numpy as np

from symlearn.backends.subgoal_plan import greedy_plan
from symlearn.errors import DataError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import FIT_CALLER, renamed_arguments
from symlearn.learners.subgoals.clustering import METHODS, find_subgoals
from symlearn.learners.subgoals.frames import demonstration_frames
from symlearn.learners.subgoals.ordering_automaton import PROBABILITIES, count_orderings, ordering_pdfa
from symlearn.learners.subgoals.subsets import feature_subsets
from symlearn.learners.subgoals.words import demonstration_words


class SubgoalPDFALearner(Learner):
    """Sub-goals by clustering, a PDFA of their orderings, and its greedy plan.

    Parameters: ``subsets`` (candidate feature subsets: ``"red=0,1,2;blue=3,4,5"``, a mapping, or
    None for all features as one subset), ``eps`` and ``min_samples`` (DBSCAN; None: derived from
    the data per subset, see :mod:`.clustering`), ``method`` (``dbscan`` or ``hdbscan``),
    ``cell_fraction`` (collapse resolution as a fraction of ``eps``), ``probabilities``
    (``consistent`` or ``thesis``).

    Results: ``subgoals_`` (:class:`~symlearn.grounding.subgoals.SubGoalSet`), ``words_`` (one
    tuple of sub-goal names per demonstration), ``counts_`` (Algorithm 6.2's counts), ``pdfa_``,
    ``plan_`` (greedy plan, sub-goal names), ``history_`` (one ``ClusterRecord`` per subset).
    """

    artefact_suffix = ".json"

    def __init__(self, subsets: Any = None, eps: float | None = None, min_samples: float | None = None,
                 method: str = "dbscan", cell_fraction: float = 0.25, probabilities: str = "consistent") -> None:
        self.subsets = subsets
        self.eps = eps
        self.min_samples = min_samples
        self.method = method
        self.cell_fraction = cell_fraction
        self.probabilities = probabilities

    @renamed_arguments(features="world")
    def fit(self, demonstrations: Any, world: Any = None) -> SubgoalPDFALearner:
        """``demonstrations``: see :func:`.frames.demonstration_frames` (NaN = unobserved);
        ``world`` names the features: a FeatureMap, feature names, or None."""
        if self.probabilities not in PROBABILITIES:
            raise DataError(f"unknown probabilities {self.probabilities!r}", hint="use " + " or ".join(PROBABILITIES))
        if self.method not in METHODS:
            raise DataError(f"unknown clustering method {self.method!r}", hint="use " + " or ".join(METHODS))
        started = time.perf_counter()
        frames, names = demonstration_frames(demonstrations, world)
        subsets = feature_subsets(self.subsets, names)
        self.warnings_ = setting_warnings(frames, names, subsets)
        for message in self.warnings_:
            warnings.warn(message, UserWarning, stacklevel=FIT_CALLER)
        t_read = time.perf_counter()
        subgoals, records = find_subgoals(frames, subsets, eps=self.eps, min_samples=self.min_samples,
                                          method=self.method, cell_fraction=self.cell_fraction, feature_names=names)
        t_cluster = time.perf_counter()
        for message in wide_subgoal_warnings(subgoals, frames):
            self.warnings_.append(message)
            warnings.warn(message, UserWarning, stacklevel=FIT_CALLER)
        words = demonstration_words(subgoals, frames)
        for message in empty_word_warnings(words, frames):
            self.warnings_.append(message)
            warnings.warn(message, UserWarning, stacklevel=FIT_CALLER)
        t_words = time.perf_counter()
        counts = count_orderings(words, subgoals.propositions)
        pdfa = ordering_pdfa(counts, self.probabilities)
        t_automaton = time.perf_counter()
        plan = greedy_plan(pdfa)
        t_plan = time.perf_counter()

        self.feature_names_ = names
        self.subgoals_ = subgoals
        self.words_ = words
        self.counts_ = counts
        self.pdfa_ = pdfa
        self.plan_ = list(plan.subgoals)
        self.history_ = records
        metrics = {"demonstrations": len(frames), "frames": int(sum(len(f) for f in frames)),
                   "subgoals": len(subgoals), "states": pdfa.n_states, "edges": pdfa.n_edges,
                   "accepting": len(pdfa.accepting), "distinct_words": len(set(words)),
                   "empty_words": sum(1 for w in words if not w), "plan_probability": plan.probability}
        timings = {"read": t_read - started, "clustering": t_cluster - t_read, "words": t_words - t_cluster,
                   "automaton": t_automaton - t_words, "plan": t_plan - t_automaton,
                   "total": max(time.perf_counter() - started, 1e-9)}
        self._set_result(pdfa, plan_document_text(pdfa, subgoals, words, self.plan_), metrics=metrics,
                         timings=timings, history=records)
        return self


def setting_warnings(frames, names, subsets) -> list[str]:
    """One warning per subset that clusters on a feature constant within every demonstration but
    different between them (:mod:`symlearn.learners.episode_settings`): its sub-goals then also
    tell the demonstrations' settings apart."""
    from symlearn.learners.episode_settings import episode_settings

    settings = set(episode_settings(frames))
    out = []
    for subset in subsets:
        hit = [names[c] for c in subset.features if c in settings]
        if hit:
            kept = [str(c) for c in subset.features if c not in settings]
            hint = f"; leave {'it' if len(hit) == 1 else 'them'} out (--subsets '{subset.name}={','.join(kept)}')" \
                if kept else ""
            out.append(f"feature(s) {', '.join(hit)} of subset {subset.name} are constant within every demonstration "
                       f"and differ between them (a setting of the episode, not a choice of the expert): its sub-goals "
                       f"also sort the demonstrations by that setting{hint}")
    return out


#: a sub-goal whose radius exceeds this share of its frames' extent (bounding-box diagonal) is no place
WIDE_SUBGOAL = 0.25


def wide_subgoal_warnings(subgoals, frames) -> list[str]:
    """One warning per sub-goal wider than :data:`WIDE_SUBGOAL` of the extent of its subset's frames:
    a place where demonstrations dwell is small; a cluster that wide is several places joined by
    the frames between them (a demonstration passing through puts several frames within ``eps``
    of each other when ``eps`` is more than about half its step)."""
    out = []
    for goal in subgoals:
        columns = list(goal.features)
        stacked = np.concatenate([f[:, columns] for f in frames])
        stacked = stacked[~np.isnan(stacked).any(axis=1)]
        if not len(stacked):
            continue
        extent = float(np.linalg.norm(stacked.max(axis=0) - stacked.min(axis=0)))
        if extent > 0 and goal.radius > WIDE_SUBGOAL * extent:
            out.append(f"sub-goal {goal.name} has radius {goal.radius:.3g}, {goal.radius / extent:.0%} of the extent "
                       f"of its frames ({extent:.3g}): no single place, but several joined by the frames in between "
                       "(lower --eps below half a demonstration's step, or raise --min-samples)")
    return out


def empty_word_warnings(words, frames) -> list[str]:
    """One warning when some demonstrations, but not all, visit no sub-goal: each is the word
    "stop at once" and carries the same weight in the plan's probabilities as a whole tour, so one
    broken recording (a single frame, a run cut at the start) beside one good tour makes a plan of
    "stop at once" at p = 0.5. Nothing here can tell a real "do nothing" from a broken file, so the
    learner keeps them and says which they are."""
    empty = [i for i, w in enumerate(words) if not w]
    if not empty or len(empty) == len(words):
        return []
    shown = ", ".join(f"{i} ({len(frames[i])} frame{'s' if len(frames[i]) != 1 else ''})" for i in empty[:5])
    more = f" and {len(empty) - 5} more" if len(empty) > 5 else ""
    return [f"{len(empty)} of {len(words)} demonstrations visit no sub-goal (demonstration {shown}{more}): each "
            "counts as a tour that stops at once in the plan's probabilities (remove them if they are broken "
            "recordings)"]


def plan_document(pdfa, subgoals, words, plan) -> dict[str, Any]:
    """The PDFA's automaton JSON plus ``subgoals``, ``plan`` and ``words`` (see the module doc)."""
    document = pdfa.to_dict()
    document["subgoals"] = {g.name: {"subset": g.subset, "features": list(g.features), "centre": list(g.centre),
                                     "radius": g.radius} for g in subgoals}
    document["plan"] = list(plan)
    document["words"] = [{"word": list(w), "count": n} for w, n in Counter(words).most_common()]
    return document


def plan_document_text(pdfa, subgoals, words, plan) -> str:
    return json.dumps(plan_document(pdfa, subgoals, words, plan), indent=1, allow_nan=False) + "\n"
