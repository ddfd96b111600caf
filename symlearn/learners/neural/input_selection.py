"""Which observation entries a neural cost reads: the fewest candidates that tell the expert's
states from the nominal policy's.

A cost network reading every candidate entry is free to lean on all that differ between expert
and policy, and the constraint explains only some of those differences. Measured on BlockedPoint
(docs/BENCHMARKS.md, "Neural ICRL: the cost's inputs"): reading ``(x, y)``, MCE-ICRL's cost rose
along the nominal policy's drift toward ``+y`` as much as toward the wall (recovery AUC 0.90 on one
seed); reading ``x`` alone, AUC 1.00 on every seed. ``y`` adds nothing to telling expert from
nominal states once ``x`` is known (a held-out AUC of 0.9927 against 0.9926), so a rule that
keeps an entry only when it adds something drops it.

:func:`select_inputs` is that rule, a greedy backward elimination (a wrapper method in the sense
of Kohavi and John, 1997) with an Occam stopping test: score a set of entries by the held-out ROC
AUC of a small classifier separating expert states from nominal ones (a depth-4 decision tree,
3-fold stratified cross-validation, so that an entry is scored by how well it generalises, not by
how well a tree memorises it); starting from every candidate, drop the entry whose removal costs
the least, as long as the remaining set still scores within ``tolerance`` of all candidates
together. With more than :data:`MAX_BACKWARD` candidates (MiniGrid's 151 entries, a MuJoCo
robot's 105) one removal at a time costs O(d^2) cross-validations, minutes; elimination then
starts from the entries one tree on all candidates splits on (at most 15), when they alone
score within ``tolerance`` (else from every candidate, as before, up to :data:`MAX_FULL_BACKWARD`
of them; more, a camera's pixels, are all kept: elimination would take hours). Backward rather than forward: entries that separate only together (an XOR) each look
useless alone, and a forward search would never take the first of them. The learners run it
once, on the demonstrations and the nominal policy's sampled episodes, before the feature
network is built.

What it cannot do: tell apart two entries that separate equally well. Reading every entry of
BlockedPoint's observation it keeps ``vx`` (the expert never moves toward the wall; AUC 0.9996
alone) rather than ``x``: the demonstrations do not say which one the constraint is about. The
environment's declaration of what its constraints read (``feature_names``,
:func:`~symlearn.learners.neural.fit_setup.cost_inputs`) does, and is the default candidate set.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: the classifier and cross-validation of :func:`select_inputs` (module docstring)
TREE_DEPTH = 4
MIN_LEAF = 20
FOLDS = 3
#: above this many candidates, elimination starts from the entries one tree on all of them splits on
MAX_BACKWARD = 16
#: the most candidates elimination runs on one at a time when the split entries alone fall short:
#: O(d^2) cross-validations, about a minute at 64; a (16, 16, 3) camera's 768 would take hours
MAX_FULL_BACKWARD = 64


@dataclass(frozen=True)
class InputSelection:
    """What :func:`select_inputs` did: the candidates, the entries kept (in observation order),
    the held-out AUC after each removal, the AUC of all candidates together, the tolerance."""

    candidates: tuple[int, ...]
    selected: tuple[int, ...]
    steps: tuple[float, ...] = field(default=())
    all_candidates_auc: float | None = None
    tolerance: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        return {"candidates": list(self.candidates), "selected": list(self.selected), "auc_steps": list(self.steps),
                "all_candidates_auc": self.all_candidates_auc, "tolerance": self.tolerance}


def separation_auc(expert: np.ndarray, policy: np.ndarray, columns: Sequence[int], seed: int | None) -> float:
    """Held-out ROC AUC of a depth-:data:`TREE_DEPTH` tree telling ``policy`` rows from ``expert``
    rows on ``columns`` (mean over :data:`FOLDS` stratified folds)."""
    from sklearn.model_selection import StratifiedKFold, cross_val_score
    from sklearn.tree import DecisionTreeClassifier

    x = np.concatenate([expert[:, list(columns)], policy[:, list(columns)]]).astype(np.float64)
    y = np.concatenate([np.zeros(len(expert)), np.ones(len(policy))])
    tree = DecisionTreeClassifier(max_depth=TREE_DEPTH, min_samples_leaf=MIN_LEAF, random_state=0)
    folds = StratifiedKFold(FOLDS, shuffle=True, random_state=0 if seed is None else int(seed))
    return float(cross_val_score(tree, x, y, cv=folds, scoring="roc_auc").mean())


def _split_columns(expert: np.ndarray, policy: np.ndarray, candidates: Sequence[int]) -> list[int]:
    """The candidates a depth-:data:`TREE_DEPTH` tree on all of them splits on (at most 15), in
    candidate order: where there are many candidates, backward elimination starts from these."""
    from sklearn.tree import DecisionTreeClassifier

    x = np.concatenate([expert[:, list(candidates)], policy[:, list(candidates)]]).astype(np.float64)
    y = np.concatenate([np.zeros(len(expert)), np.ones(len(policy))])
    tree = DecisionTreeClassifier(max_depth=TREE_DEPTH, min_samples_leaf=MIN_LEAF, random_state=0).fit(x, y)
    used = {int(f) for f in tree.tree_.feature if f >= 0}
    return [c for i, c in enumerate(candidates) if i in used] or list(candidates)


def select_inputs(expert: np.ndarray, policy: np.ndarray, candidates: Sequence[int], *, tolerance: float,
                  seed: int | None = 0) -> InputSelection:
    """The fewest of ``candidates`` (column indices of the flattened observations ``expert``
    ``(n, d)`` and ``policy`` ``(m, d)``) that separate the two (module docstring). With
    ``tolerance <= 0``, a single candidate, or too few rows to cross-validate, every candidate."""
    candidates = tuple(int(i) for i in candidates)
    if tolerance <= 0 or len(candidates) < 2 or min(len(expert), len(policy)) < FOLDS * MIN_LEAF:
        return InputSelection(candidates, candidates, tolerance=float(tolerance))
    everything = separation_auc(expert, policy, candidates, seed)
    kept, steps = list(candidates), []
    if len(kept) > MAX_BACKWARD:   # one removal at a time would cost O(d^2) cross-validations
        used = _split_columns(expert, policy, candidates)
        if len(used) < len(kept):
            score = separation_auc(expert, policy, used, seed)
            if score >= everything - tolerance:
                kept = used
                steps.append(score)
        if len(kept) > MAX_FULL_BACKWARD:   # too many to eliminate one at a time: the cost reads them all
            return InputSelection(candidates, candidates, tuple(steps), float(everything), float(tolerance))
    while len(kept) > 1:
        scores = [separation_auc(expert, policy, [i for i in kept if i != j], seed) for j in kept]
        k = int(np.argmax(scores))
        if scores[k] < everything - tolerance:
            break
        kept.pop(k)
        steps.append(scores[k])
    return InputSelection(candidates, tuple(kept), tuple(steps), float(everything), float(tolerance))


def inputs_report(cost: Any, inputs_from: str, selection: InputSelection | None = None) -> dict[str, Any]:
    """What a learner's result says of its cost's inputs: the observation ``entries`` its
    network reads, their ``names`` (None where the environment names none), where the candidates
    came from (``from``: ``"given"``, ``"declared features"`` or ``"all"``, see
    :func:`~symlearn.learners.neural.fit_setup.cost_inputs`), the ``selection`` (None when off)
    and every input's ``shares`` of the first layer's weight
    (:func:`~symlearn.learners.neural.input_sparsity.input_shares`; the action's entries last for
    state-action features)."""
    from symlearn.learners.neural.input_sparsity import input_shares

    entries = [int(i) for i in cost.phi.obs_dims]
    names = cost.observation_names
    return {"entries": entries, "names": None if names is None else [names[i] for i in entries],
            "from": inputs_from, "selection": None if selection is None else selection.as_dict(),
            "shares": input_shares(cost.phi)}





def choose_inputs(setup: Any, nominal: Any, tolerance: float, seed: int | None) -> InputSelection | None:
    """:func:`select_inputs` among a fit's candidate entries (``setup``: a
    :class:`~symlearn.learners.neural.fit_setup.FitSetup`) on its demonstrations and the nominal
    policy's episodes ``nominal`` (an :class:`~symlearn.rl.episodes.EpisodeBatch`);
    None when ``tolerance`` is 0 (selection off)."""
    from symlearn.learners.neural.neural_cost import encode

    if not tolerance:
        return None
    nominal_x = encode(nominal.pairs()[0], setup.obs_spec, "sampled observations")
    return select_inputs(setup.expert_x, nominal_x, setup.obs_dims, tolerance=float(tolerance), seed=seed)


__all__ = ["FOLDS", "InputSelection", "MAX_BACKWARD", "MAX_FULL_BACKWARD", "MIN_LEAF", "TREE_DEPTH", "choose_inputs", "inputs_report", "select_inputs",
           "separation_auc"]
