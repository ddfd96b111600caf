"""Exact dynamic programming on a :class:`~symlearn.mdp.TabularMDP` (vectorised with numpy)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP


@dataclass(frozen=True)
class ValueIterationResult:
    values: np.ndarray  # V[s]
    q_values: np.ndarray  # Q[s, a]
    policy: np.ndarray  # greedy action per state
    iterations: int
    converged: bool


def value_iteration(
    mdp: TabularMDP,
    discount: float = 0.99,
    tol: float = 1e-8,
    max_iterations: int = 100_000,
    *,
    allowed: np.ndarray | None = None,
) -> ValueIterationResult:
    """Optimal values by Bellman backups until the largest change drops below ``tol``.

    Terminal states are worth zero: no reward is collected after an episode ends. ``allowed``
    (boolean ``(S, A)``, e.g. ``restrict(...).allowed``) limits the actions a policy may take;
    a state with none allowed keeps all its actions (it is a dead end of the constraint set,
    which :func:`restrict` already keeps every allowed action away from).
    """
    if not 0.0 <= discount <= 1.0:
        raise SymlearnError(f"discount must lie in [0, 1], got {discount}")
    live = (~mdp.terminal).astype(np.float64)
    usable = np.ones((mdp.n_states, mdp.n_actions), bool) if allowed is None else check_mask(mdp, allowed, "allowed mask")
    usable = usable | ~usable.any(axis=1, keepdims=True)
    values = np.zeros(mdp.n_states)
    q = mdp.rewards.copy()
    for iteration in range(1, max_iterations + 1):
        q = mdp.rewards + discount * mdp.transitions @ values
        q[mdp.terminal] = 0.0
        q = np.where(usable, q, -np.inf)
        new_values = q.max(axis=1) * live
        delta = float(np.max(np.abs(new_values - values)))
        values = new_values
        if delta < tol:
            return ValueIterationResult(values, q, q.argmax(axis=1), iteration, True)
    return ValueIterationResult(values, q, q.argmax(axis=1), max_iterations, False)


# --- constraint sets: boolean masks over (S, A) -------------------------------------------------
def check_mask(mdp: TabularMDP, mask: np.ndarray, what: str = "constraint mask") -> np.ndarray:
    """``mask`` as a boolean ``(S, A)`` array, or a :class:`ModelError` naming the wrong shape."""
    array = np.asarray(mask)
    if array.shape != (mdp.n_states, mdp.n_actions):
        raise ModelError(
            f"{what} must have shape (S, A) = {(mdp.n_states, mdp.n_actions)}, got {array.shape}",
            hint="a constraint set is a boolean array with True for every forbidden state-action pair",
        )
    if array.dtype != bool and not np.isin(array, (0, 1)).all():
        raise ModelError(f"{what} must be boolean (True = forbidden)")
    return array.astype(bool)


@dataclass(frozen=True)
class Restriction:
    """An MDP restricted by a constraint set.

    ``forbidden[s, a]`` is the closed constraint set: the given pairs, every action of a state
    left with no valid action (an *empty* state), and every pair that can enter an empty state.
    ``allowed`` is its complement; planners take it as their action mask. Empty states stay in
    the model (the tensors keep their shape) but no allowed action reaches them.
    """

    mdp: TabularMDP
    forbidden: np.ndarray
    empty_states: np.ndarray  # bool (S,)
    kept: np.ndarray  # bool (S, A): pairs the closure would have forbidden but ``protected`` kept

    @property
    def allowed(self) -> np.ndarray:
        return ~self.forbidden

    @property
    def n_forbidden(self) -> int:
        return int(self.forbidden.sum())


def restrict(mdp: TabularMDP, forbidden: np.ndarray, *, protected: np.ndarray | None = None) -> Restriction:
    """Remove the ``forbidden`` state-action pairs from ``mdp`` and close the set.

    A non-terminal state whose actions are all forbidden is *empty*: no valid behaviour can pass
    through it, so every pair with a positive probability of entering it is forbidden too, until
    nothing changes. ``protected`` pairs (for instance demonstrated ones, which cannot be
    constraints) are never added by this closure; the ones it would have added are in ``kept``.

    >>> P = np.zeros((3, 2, 3)); P[:, 0, 0] = 1; P[:, 1, 2] = 1; P[0, 1] = [0, 1, 0]
    >>> mask = np.zeros((3, 2), bool); mask[1] = True          # state 1 loses both actions
    >>> r = restrict(TabularMDP(P, np.zeros((3, 2)), [1, 0, 0], [False] * 3), mask)
    >>> r.empty_states.tolist(), r.forbidden[0].tolist()
    ([False, True, False], [False, True])
    """
    result = check_mask(mdp, forbidden).copy()
    guard = np.zeros_like(result) if protected is None else check_mask(mdp, protected, "protected mask")
    kept = np.zeros_like(result)
    live = ~mdp.terminal
    reaches = mdp.transitions > 0  # (S, A, S)
    while True:
        empty = live & result.all(axis=1)
        into_empty = reaches[:, :, empty].any(axis=2) & live[:, None]
        new = into_empty & ~result
        kept |= new & guard
        new &= ~guard
        if not new.any():
            break
        result |= new
    return Restriction(mdp, result, live & result.all(axis=1), kept)


# --- sampling episodes from a tabular policy ----------------------------------------------------
@dataclass(frozen=True)
class Rollouts:
    """``n`` sampled episodes as padded arrays; ``length[i]`` steps were taken in episode ``i``."""

    states: np.ndarray  # (n, T + 1), -1 after the episode ended
    actions: np.ndarray  # (n, T), -1 after the episode ended
    rewards: np.ndarray  # (n, T), 0 after the episode ended
    length: np.ndarray  # (n,)

    def returns(self) -> np.ndarray:
        return self.rewards.sum(axis=1)

    def fraction_in(self, states: np.ndarray) -> np.ndarray:
        """Per episode, the fraction of its steps that ended in one of ``states`` (a bool mask)."""
        nxt = self.states[:, 1:]
        hit = (nxt >= 0) & np.asarray(states, bool)[np.maximum(nxt, 0)]
        return hit.sum(axis=1) / np.maximum(self.length, 1)


def sample_rollouts(
    mdp: TabularMDP, policy: np.ndarray, n: int, horizon: int, rng: np.random.Generator
) -> Rollouts:
    """Run ``n`` episodes of a stochastic policy ``policy[s, a]`` in parallel (vectorised).

    Episodes start from ``mdp.initial`` and stop on a terminal state or after ``horizon`` steps.
    """
    policy = np.asarray(policy, dtype=np.float64)
    if policy.shape != (mdp.n_states, mdp.n_actions):
        raise ModelError(f"policy must have shape {(mdp.n_states, mdp.n_actions)}, got {policy.shape}")
    policy_cdf = np.cumsum(policy, axis=1)
    policy_cdf /= policy_cdf[:, -1:]
    step_cdf = np.cumsum(mdp.transitions, axis=2)
    states = np.full((n, horizon + 1), -1, dtype=np.int64)
    actions = np.full((n, horizon), -1, dtype=np.int64)
    rewards = np.zeros((n, horizon))
    current = rng.choice(mdp.n_states, size=n, p=mdp.initial)
    states[:, 0] = current
    running = ~mdp.terminal[current]
    length = np.zeros(n, dtype=np.int64)
    for t in range(horizon):
        idx = np.flatnonzero(running)
        if idx.size == 0:
            break
        s = current[idx]
        a = np.minimum((rng.random(idx.size)[:, None] > policy_cdf[s]).sum(axis=1), mdp.n_actions - 1)
        nxt = np.minimum((rng.random(idx.size)[:, None] > step_cdf[s, a]).sum(axis=1), mdp.n_states - 1)
        actions[idx, t] = a
        rewards[idx, t] = mdp.rewards[s, a]
        states[idx, t + 1] = nxt
        current[idx] = nxt
        length[idx] += 1
        running[idx] = ~mdp.terminal[nxt]
    return Rollouts(states, actions, rewards, length)
