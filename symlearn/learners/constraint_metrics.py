"""How well a learned constraint set matches the ground truth, over a finite pair space.

A *positive* is a forbidden pair. Over the pairs in ``space``:

* false-positive rate = allowed pairs wrongly forbidden / allowed pairs (over-restriction: the
  agent loses options it had);
* false-negative rate = forbidden pairs wrongly allowed / forbidden pairs (missed rules: the
  agent may break them);
* accuracy = pairs classified like the truth / all pairs.

>>> import numpy as np
>>> truth = np.array([[True, False], [False, False]])
>>> learned = np.array([[True, True], [False, False]])
>>> constraint_metrics(learned, truth)
{'fpr': 0.3333333333333333, 'fnr': 0.0, 'accuracy': 0.75, 'forbidden': 2}
"""

from __future__ import annotations

import numpy as np

from symlearn.errors import SymlearnError


def constraint_metrics(learned: np.ndarray, truth: np.ndarray, space: np.ndarray | None = None) -> dict[str, float]:
    """FPR, FNR, accuracy of ``learned`` against ``truth`` (boolean forbidden masks) on ``space``."""
    learned, truth = np.asarray(learned, dtype=bool), np.asarray(truth, dtype=bool)
    if learned.shape != truth.shape:
        raise SymlearnError(f"learned mask has shape {learned.shape}, the truth {truth.shape}")
    space = np.ones_like(truth) if space is None else np.asarray(space, dtype=bool)
    learned, truth = learned[space], truth[space]
    allowed, forbidden = ~truth, truth
    return {
        "fpr": float((learned & allowed).sum() / max(allowed.sum(), 1)),
        "fnr": float((~learned & forbidden).sum() / max(forbidden.sum(), 1)),
        "accuracy": float((learned == truth).mean()) if truth.size else 1.0,
        "forbidden": int(learned.sum()),
    }
