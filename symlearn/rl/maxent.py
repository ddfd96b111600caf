"""Maximum-entropy planning on a :class:`~symlearn.mdp.TabularMDP`, exact and in log space.

Three pieces, each vectorised over all states and actions:

* :func:`soft_value_iteration` -- the discounted soft Bellman fixed point
  ``Q = R - C + gamma * E[V(s')]``, ``V = beta * logsumexp(Q / beta)``; its policy
  ``exp((Q - V) / beta)`` maximises reward plus ``beta`` times the *causal* entropy. With
  ``entropy="trajectory"`` the expectation over next states is replaced by
  ``beta * log E[exp(V(s') / beta)]``: the trajectory-level (non-causal) MaxEnt model, in
  which a trajectory's probability is proportional to its dynamics probability times
  ``exp(return / beta)``, as if the agent could pick its successor. It over-weights lucky
  transitions when the dynamics are stochastic and equals the causal version when they are not.
* :func:`maxent_backward_pass` -- the goal-conditioned partition functions ``Z_sa`` and ``Z_s``
  over trajectories of at most ``horizon`` steps (Ziebart et al. 2008, the form used by maximum
  likelihood constraint inference) and the policy ``Z_sa / Z_s``.
* :func:`forward_pass` -- expected (discounted) state and state-action visitation of a policy.

Every quantity that could under- or overflow (partition functions over long horizons, ``exp(V /
beta)`` for small ``beta``) is kept as a logarithm and combined with ``logsumexp``.

>>> P = np.zeros((2, 2, 2)); P[0, 0, 0] = P[0, 1, 1] = P[1, :, 1] = 1
>>> mdp = TabularMDP(P, [[0.0, 0.0], [0.0, 0.0]], [1, 0], [False, True])
>>> result = maxent_backward_pass(mdp, goals=[1], horizon=3)
>>> np.round(result.policy[0], 3).tolist()   # paths: stay 0, 1 or 2 times before moving
[0.667, 0.333]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.special import logsumexp

from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import check_mask

Entropy = Literal["causal", "trajectory"]


def _allowed(mdp: TabularMDP, allowed: np.ndarray | None) -> np.ndarray:
    if allowed is None:
        return np.ones((mdp.n_states, mdp.n_actions), dtype=bool)
    return check_mask(mdp, allowed, "allowed mask")


def _masked_softmax_policy(logits: np.ndarray, allowed: np.ndarray) -> np.ndarray:
    """Row-wise softmax over allowed actions; a row with no finite logit becomes uniform over
    its allowed actions (or over all actions when none is allowed), so every row sums to one."""
    logits = np.where(allowed, logits, -np.inf)
    top = logits.max(axis=1, keepdims=True)
    finite = np.isfinite(top[:, 0])
    weights = np.zeros_like(logits)
    weights[finite] = np.exp(logits[finite] - top[finite])
    stuck = ~finite
    fallback = allowed[stuck].astype(np.float64)
    fallback[fallback.sum(axis=1) == 0] = 1.0
    weights[stuck] = fallback
    return weights / weights.sum(axis=1, keepdims=True)


# --- soft value iteration -----------------------------------------------------------------------
@dataclass(frozen=True)
class SoftValueResult:
    values: np.ndarray  # V[s]
    q_values: np.ndarray  # Q[s, a]; -inf where not allowed
    policy: np.ndarray  # pi[s, a], rows sum to one
    iterations: int
    converged: bool


def soft_value_iteration(
    mdp: TabularMDP,
    *,
    beta: float = 1.0,
    discount: float = 0.99,
    cost: np.ndarray | None = None,
    allowed: np.ndarray | None = None,
    entropy: Entropy = "causal",
    tol: float = 1e-8,
    max_iterations: int = 100_000,
    initial_values: np.ndarray | None = None,
) -> SoftValueResult:
    """Soft (maximum-entropy) value iteration; see the module docstring for both entropies.

    ``cost[s, a]`` is subtracted from the reward (MCE-ICRL's ``lambda . phi``); ``allowed``
    masks actions out. Terminal states are worth zero. ``initial_values`` warm-starts the
    iteration (useful when the cost changes a little between calls). Converges for ``discount < 1`` (or for
    ``discount == 1`` when every policy reaches a terminal state).

    >>> P = np.zeros((2, 2, 2)); P[0, 0, 0] = P[0, 1, 1] = P[1, :, 1] = 1
    >>> mdp = TabularMDP(P, [[0.0, 1.0], [0.0, 0.0]], [1, 0], [False, True])
    >>> r = soft_value_iteration(mdp, beta=1.0, discount=0.5)
    >>> round(float(r.policy[0].sum()), 6), bool(r.policy[0, 1] > r.policy[0, 0])
    (1.0, True)
    """
    if beta <= 0:
        raise SymlearnError(f"beta (the entropy weight) must be positive, got {beta}")
    if not 0.0 <= discount <= 1.0:
        raise SymlearnError(f"discount must lie in [0, 1], got {discount}")
    if entropy not in ("causal", "trajectory"):
        raise SymlearnError(f"entropy must be 'causal' or 'trajectory', got {entropy!r}")
    mask = _allowed(mdp, allowed)
    reward = mdp.rewards - (0.0 if cost is None else _check_cost(mdp, cost))
    live = ~mdp.terminal
    P = mdp.transitions
    with np.errstate(divide="ignore"):
        log_P = np.log(P)
    values = np.zeros(mdp.n_states) if initial_values is None else np.array(initial_values, dtype=np.float64)
    if values.shape != (mdp.n_states,):
        raise ModelError(f"initial_values must have length {mdp.n_states}, got shape {values.shape}")
    q = np.full(reward.shape, -np.inf)
    converged = False
    iteration = 0
    for iteration in range(1, max_iterations + 1):
        if entropy == "causal":
            future = P @ np.where(np.isfinite(values), values, 0.0)
            # A successor without any allowed action is worth -inf, whatever its probability.
            dead = np.isneginf(values)
            if dead.any():
                future = np.where((P[:, :, dead] > 0).any(axis=2), -np.inf, future)
        else:
            future = beta * logsumexp(log_P + values[None, None, :] / beta, axis=2)
        q = np.where(mask, reward + discount * future, -np.inf)
        q[mdp.terminal] = np.where(mask[mdp.terminal], 0.0, -np.inf)
        new_values = np.zeros(mdp.n_states)
        with np.errstate(divide="ignore"):
            new_values[live] = beta * logsumexp(q[live] / beta, axis=1)
        finite = np.isfinite(new_values) & np.isfinite(values)
        delta = float(np.max(np.abs(new_values[finite] - values[finite]), initial=0.0))
        same_support = np.array_equal(np.isfinite(new_values), np.isfinite(values))
        values = new_values
        if delta < tol and same_support:
            converged = True
            break
    with np.errstate(invalid="ignore"):  # -inf - -inf in states with no allowed action
        logits = np.nan_to_num((q - values[:, None]) / beta, nan=-np.inf)
    policy = _masked_softmax_policy(logits, mask)
    return SoftValueResult(values, q, policy, iteration, converged)


def _check_cost(mdp: TabularMDP, cost: np.ndarray) -> np.ndarray:
    array = np.asarray(cost, dtype=np.float64)
    if array.shape != (mdp.n_states, mdp.n_actions) or not np.isfinite(array).all():
        raise ModelError(f"cost must be a finite array of shape {(mdp.n_states, mdp.n_actions)}, got {array.shape}")
    return array


# --- goal-conditioned backward pass ----------------------------------------------------------
@dataclass(frozen=True)
class BackwardPassResult:
    log_z_sa: np.ndarray  # log Z[s, a]; -inf where no allowed trajectory reaches a goal
    log_z_s: np.ndarray  # log Z[s]
    policy: np.ndarray  # Z_sa / Z_s, uniform over allowed actions where Z_s = 0


class _Successors:
    """``logsumexp(log_weight[s, a, :] + v)`` over next states, for many ``v``.

    A gymnasium toy-text world has one or a few successors per pair (Taxi: 500 states, 1 of 500),
    so summing only over the pairs' successors -- the entries with ``P > 0``, every other term
    being ``exp(-inf) = 0`` -- is the same sum in a few hundredth of the time: the dense
    ``(S, A, S)`` logsumexp took 4.6 s per backward pass on Taxi. Dense worlds keep the dense sum.
    """

    def __init__(self, log_weight: np.ndarray) -> None:
        self.log_weight = log_weight
        self.shape = log_weight.shape[:2]
        finite = np.isfinite(log_weight)
        counts = finite.sum(axis=2).reshape(-1)
        # reduceat needs a non-empty group per pair; a pair that reaches nothing stays dense
        self.sparse = finite.sum() * 4 <= finite.size and bool((counts > 0).all())
        if self.sparse:
            pairs, self.next_states = np.nonzero(finite.reshape(-1, finite.shape[2]))
            self.weights = log_weight.reshape(-1, finite.shape[2])[pairs, self.next_states]
            self.starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
            self.pair_of = pairs

    def logsumexp(self, v: np.ndarray) -> np.ndarray:
        if not self.sparse:
            return logsumexp(self.log_weight + v[None, None, :], axis=2)
        terms = self.weights + v[self.next_states]
        top = np.maximum.reduceat(terms, self.starts)
        finite = np.isfinite(top)
        shifted = np.exp(terms - np.where(finite, top, 0.0)[self.pair_of])
        with np.errstate(divide="ignore"):
            total = np.log(np.add.reduceat(shifted, self.starts)) + top
        return np.where(finite, total, top).reshape(self.shape)


def maxent_backward_pass(
    mdp: TabularMDP,
    goals: Sequence[int] | np.ndarray,
    horizon: int,
    *,
    reward: np.ndarray | None = None,
    allowed: np.ndarray | None = None,
) -> BackwardPassResult:
    """Partition functions over the trajectories that reach one of ``goals`` in at most
    ``horizon`` steps, each weighted by its dynamics probability times ``exp(sum of rewards)``:

    ``Z_sa = sum_s' P(s'|s,a) exp(R(s,a,s')) Z_s'`` and ``Z_s = sum_{a allowed} Z_sa``, with
    ``Z_g = 1`` at a goal (absorbing: a trajectory ends when it first reaches a goal).
    ``reward`` is ``(S, A)`` or ``(S, A, S)`` (default: the MDP's rewards).
    """
    if horizon < 1:
        raise SymlearnError(f"the planning horizon must be at least 1, got {horizon}")
    mask = _allowed(mdp, allowed)
    goal_mask = np.zeros(mdp.n_states, dtype=bool)
    goal_ids = np.asarray(list(goals), dtype=np.int64)
    if goal_ids.size == 0:
        raise SymlearnError("the backward pass needs at least one goal state")
    if ((goal_ids < 0) | (goal_ids >= mdp.n_states)).any():
        raise ModelError(f"goal states must lie in 0..{mdp.n_states - 1}, got {goal_ids.tolist()}")
    goal_mask[goal_ids] = True
    R = mdp.rewards if reward is None else np.asarray(reward, dtype=np.float64)
    if R.shape == (mdp.n_states, mdp.n_actions):
        R = np.broadcast_to(R[:, :, None], mdp.transitions.shape)
    if R.shape != mdp.transitions.shape:
        raise ModelError(f"reward must have shape (S, A) or (S, A, S), got {R.shape}")
    with np.errstate(divide="ignore"):
        log_weight = np.log(mdp.transitions) + R  # log(P exp R), -inf where P = 0
    # Non-goal terminal states end a trajectory without reaching a goal: they contribute nothing.
    dead_end = mdp.terminal & ~goal_mask
    successors = _Successors(log_weight)
    log_z_s = np.where(goal_mask, 0.0, -np.inf)
    log_z_sa = np.full(mask.shape, -np.inf)
    for _ in range(horizon):
        log_z_sa = successors.logsumexp(log_z_s)
        log_z_sa = np.where(mask & ~(goal_mask | dead_end)[:, None], log_z_sa, -np.inf)
        log_z_s = np.where(goal_mask, 0.0, logsumexp(log_z_sa, axis=1))
    policy = _masked_softmax_policy(log_z_sa, mask)
    return BackwardPassResult(log_z_sa, log_z_s, policy)


# --- forward pass -------------------------------------------------------------------------------
@dataclass(frozen=True)
class Visitation:
    states: np.ndarray  # expected (discounted) number of visits of each state, terminal included
    state_actions: np.ndarray  # expected (discounted) number of times each action is taken
    remaining: float  # probability mass still moving after the horizon


def forward_pass(
    mdp: TabularMDP,
    policy: np.ndarray,
    horizon: int,
    *,
    initial: np.ndarray | None = None,
    discount: float = 1.0,
    tol: float = 0.0,
) -> Visitation:
    """Expected visitation frequencies of ``policy`` over ``horizon`` steps.

    ``D_0 = initial``; ``D_{t+1}(s') = sum_{s,a} D_t(s) pi(a|s) P(s'|s,a)`` over non-terminal
    ``s`` (an episode stops in a terminal state, which is counted as visited but takes no
    action). Step ``t`` is weighted by ``discount ** t``. Stops early once less than ``tol`` of
    the mass is still moving.
    """
    policy = np.asarray(policy, dtype=np.float64)
    if policy.shape != (mdp.n_states, mdp.n_actions):
        raise ModelError(f"policy must have shape {(mdp.n_states, mdp.n_actions)}, got {policy.shape}")
    start = mdp.initial if initial is None else np.asarray(initial, dtype=np.float64)
    if start.shape != (mdp.n_states,):
        raise ModelError(f"initial distribution must have length {mdp.n_states}")
    live = (~mdp.terminal).astype(np.float64)
    occupancy = start.copy()
    states = np.zeros(mdp.n_states)
    state_actions = np.zeros(policy.shape)
    weight = 1.0
    for _ in range(horizon):
        states += weight * occupancy
        moving = occupancy * live
        taken = moving[:, None] * policy
        state_actions += weight * taken
        occupancy = np.einsum("sa,sat->t", taken, mdp.transitions)
        weight *= discount
        if occupancy[~mdp.terminal].sum() <= tol:
            states += weight * occupancy
            return Visitation(states, state_actions, float(occupancy[~mdp.terminal].sum()))
    states += weight * occupancy
    return Visitation(states, state_actions, float((occupancy * live).sum()))
