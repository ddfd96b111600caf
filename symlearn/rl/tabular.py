"""Exact dynamic programming on a :class:`~symlearn.mdp.TabularMDP` (vectorised with numpy)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symlearn.errors import SymlearnError
from symlearn.mdp import TabularMDP


@dataclass(frozen=True)
class ValueIterationResult:
    values: np.ndarray  # V[s]
    q_values: np.ndarray  # Q[s, a]
    policy: np.ndarray  # greedy action per state
    iterations: int
    converged: bool


def value_iteration(
    mdp: TabularMDP, discount: float = 0.99, tol: float = 1e-8, max_iterations: int = 100_000
) -> ValueIterationResult:
    """Optimal values by Bellman backups until the largest change drops below ``tol``.

    Terminal states are worth zero: no reward is collected after an episode ends.
    """
    if not 0.0 <= discount <= 1.0:
        raise SymlearnError(f"discount must lie in [0, 1], got {discount}")
    live = (~mdp.terminal).astype(np.float64)
    values = np.zeros(mdp.n_states)
    q = mdp.rewards.copy()
    for iteration in range(1, max_iterations + 1):
        q = mdp.rewards + discount * mdp.transitions @ values
        q[mdp.terminal] = 0.0
        new_values = q.max(axis=1) * live
        delta = float(np.max(np.abs(new_values - values)))
        values = new_values
        if delta < tol:
            return ValueIterationResult(values, q, q.argmax(axis=1), iteration, True)
    return ValueIterationResult(values, q, q.argmax(axis=1), max_iterations, False)
