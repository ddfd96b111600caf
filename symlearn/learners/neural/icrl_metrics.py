"""What an ICRL run is judged by: reward, violations, feasible reward and recovery of the constraint.

* **reward**, **violation rate**, **feasible reward** of a policy's episodes:
  :func:`~symlearn.rl.episode_metrics.episode_metrics` (they judge any policy, so they live in
  ``rl``; named here too, beside the recovery they are reported with).
* **recovery** (:func:`recovery`): how well the learned cost separates the true unsafe set from
  the safe one on states sampled uniformly from the box around the expert's states, widened by
  ``margin`` times its width on every side (so the sample reaches past where the expert went --
  into the unsafe set the expert avoided -- without drifting to states no one would visit).
  ``auc`` is the ROC AUC of the cost as a score for "unsafe" (``sklearn.metrics.roc_auc_score``:
  1 = every unsafe state costs more than every safe one; threshold-free); ``iou`` the
  intersection over union of the predicted unsafe set (normalised cost ``C / sum(lambda)`` at
  least ``threshold``, 0.5 by default: the ``lambda``-weighted feature average is above one half)
  with the true one. A state-action cost is scored per state by its mean over ``n_actions``
  uniformly sampled actions.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError
from symlearn.rl.episode_metrics import EpisodeMetrics, episode_metrics


@dataclass(frozen=True)
class Recovery:
    auc: float  # NaN when the sample holds only safe or only unsafe states
    iou: float
    unsafe_share: float  # share of the sampled states that are truly unsafe
    samples: int
    threshold: float
    margin: float = 0.25  # the box's widening the states were sampled with

    def as_dict(self) -> dict[str, Any]:
        return {"auc": _plain(self.auc), "iou": _plain(self.iou), "unsafe_share": self.unsafe_share,
                "samples": self.samples, "threshold": self.threshold, "margin": self.margin}


#: the widenings ``recovery(margin="auto")`` tries, in order
AUTO_MARGINS = (0.25, 0.5, 1.0, 2.0, 4.0)


def sample_around(states: np.ndarray, n: int, margin: float, rng: np.random.Generator) -> np.ndarray:
    """``n`` states uniform in the bounding box of ``states`` ``(m, d)`` widened by ``margin``
    times its width on each side (an entry the states never vary in is widened by ``margin``)."""
    states = np.asarray(states, dtype=np.float64).reshape(len(states), -1)
    if not len(states) or not np.isfinite(states).all():
        raise DataError("recovery needs finite reference states")
    low, high = states.min(axis=0), states.max(axis=0)
    width = np.where(high > low, high - low, 1.0)
    return rng.uniform(low - margin * width, high + margin * width, size=(n, states.shape[1]))


def recovery(cost: Any, unsafe: Callable[[np.ndarray], np.ndarray], reference_states: np.ndarray, *,
             n: int = 20_000, margin: float | str = 0.25, threshold: float = 0.5, n_actions: int = 8,
             action_sampler: Callable[[int, np.random.Generator], np.ndarray] | None = None,
             seed: int | None = 0) -> Recovery:
    """Recovery of the true unsafe set by a learned :class:`~symlearn.learners.neural.NeuralCost`
    (module docstring). ``unsafe(states) -> bool array`` is the ground truth; ``reference_states``
    the expert's (flattened) observations; ``action_sampler(k, rng) -> (k, ...)`` actions for a
    state-action cost. ``margin="auto"``: the first of :data:`AUTO_MARGINS` whose box holds at
    least 1 % safe and 1 % unsafe states (an expert that keeps far from the boundary relative to
    the spread of its own states leaves the unsafe set outside the 0.25 box, and the AUC undefined);
    the margin used is in the result."""
    from sklearn.metrics import roc_auc_score

    if not 0 < threshold < 1:
        raise DataError(f"threshold must be in (0, 1), got {threshold}")
    margins = AUTO_MARGINS if margin == "auto" else (margin,)
    for used in margins:
        rng = np.random.default_rng(seed)
        states = sample_around(reference_states, n, float(used), rng).astype(np.float32)
        truth = np.asarray(unsafe(states), dtype=bool).reshape(-1)
        if truth.shape != (n,):
            raise DataError(f"the ground truth gave {truth.size} verdicts for {n} states")
        if 0.01 <= truth.mean() <= 0.99:
            break
    if getattr(cost, "uses_actions", False):
        if action_sampler is None:
            raise DataError("a state-action cost needs an action_sampler for recovery")
        scores = np.mean([cost(states, action_sampler(n, rng)) for _ in range(n_actions)], axis=0)
    else:
        scores = np.asarray(cost(states), dtype=np.float64)
    total = float(np.sum(np.asarray(cost.lambdas))) if hasattr(cost, "lambdas") else 1.0
    predicted = scores >= threshold * total if total > 0 else np.zeros(n, dtype=bool)
    both = truth.any() and (~truth).any()
    auc = float(roc_auc_score(truth, scores)) if both else math.nan
    union = np.sum(predicted | truth)
    iou = float(np.sum(predicted & truth) / union) if union else math.nan
    return Recovery(auc, iou, float(truth.mean()), n, threshold, float(used))


def _plain(x: float) -> float | None:
    return None if isinstance(x, float) and math.isnan(x) else x


__all__ = ["AUTO_MARGINS", "EpisodeMetrics", "Recovery", "episode_metrics", "recovery", "sample_around"]
