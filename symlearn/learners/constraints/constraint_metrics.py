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

The full pair space counts pairs no rule-abiding agent ever meets (a Hanoi configuration that
breaks the rules, a traffic cell off the road). :func:`reachable_pairs` gives the smaller space of
every action in the states reachable from the start distribution when only the allowed pairs of
a constraint set are taken; scoring there asks "would an agent that starts where the experts
start and obeys these rules ever meet a misclassified pair?".

>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((3, 2, 3)); P[0, 0, 1] = P[0, 1, 2] = P[1, :, 1] = P[2, :, 2] = 1
>>> mdp = TabularMDP(P, np.zeros((3, 2)), [1, 0, 0], [False, True, True])
>>> reachable_pairs(mdp, np.array([[False, True], [False, False], [False, False]])).astype(int).tolist()
[[1, 1], [0, 0], [0, 0]]
"""

from __future__ import annotations

from typing import Any

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


def reachable_pairs(mdp: Any, forbidden: np.ndarray, initial: np.ndarray | None = None) -> np.ndarray:
    """Boolean ``(S, A)``: every action of every non-terminal state reachable from ``initial``
    (default: the MDP's start distribution) by allowed pairs (``~forbidden``) with positive
    transition probability. Terminal states are left out (nothing is decided there)."""
    P = np.asarray(mdp.transitions)
    forbidden = np.asarray(forbidden, dtype=bool)
    start = np.asarray(mdp.initial if initial is None else initial) > 0
    reached = start.copy()
    frontier = start.copy()
    # one boolean (S, S) step relation of the allowed pairs, then a breadth-first closure
    step = ((P > 0) & ~forbidden[:, :, None]).any(axis=1)
    while frontier.any():
        new = step[frontier].any(axis=0) & ~reached
        reached |= new
        frontier = new
    reached &= ~np.asarray(mdp.terminal, dtype=bool)
    return np.repeat(reached[:, None], P.shape[1], axis=1)


def reach_scores(learned: np.ndarray, truth: np.ndarray, mdp: Any, space: np.ndarray) -> dict[str, float | int]:
    """FPR and FNR of ``learned`` against ``truth`` on the pairs an agent that obeys ``truth`` can
    meet: every pair of ``space`` in a state it reaches from the model's start distribution
    (:func:`reachable_pairs`). The other pairs of ``space`` lie in states no rule-abiding
    demonstration can visit, so no demonstration can tell what a rule forbids there (a rule that
    forbids everything in such a state and one that forbids nothing explain the data alike);
    ``unreachable`` counts them. Keys: ``reach_fpr``, ``reach_fnr``, ``reach_pairs``, ``unreachable``."""
    space = np.asarray(space, dtype=bool)
    reach = reachable_pairs(mdp, np.asarray(truth, dtype=bool) | ~space) & space
    scores = constraint_metrics(learned, truth, reach)
    return {"reach_fpr": scores["fpr"], "reach_fnr": scores["fnr"], "reach_pairs": int(reach.sum()),
            "unreachable": int((space & ~reach).sum())}

