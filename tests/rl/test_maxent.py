import itertools

import numpy as np
import pytest

from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP
from symlearn.rl.maxent import forward_pass, maxent_backward_pass, soft_value_iteration
from symlearn.rl.tabular import sample_rollouts


def tiny_stochastic_mdp(seed=0, S=4, A=3):
    """Random dynamics; the last state is a terminal goal."""
    rng = np.random.default_rng(seed)
    P = rng.random((S, A, S)) * (rng.random((S, A, S)) < 0.6)
    P[:, :, S - 1] += 0.05
    P /= P.sum(axis=2, keepdims=True)
    P[S - 1] = 0
    P[S - 1, :, S - 1] = 1
    R = rng.normal(size=(S, A))
    R[S - 1] = 0
    terminal = np.zeros(S, bool)
    terminal[S - 1] = True
    return TabularMDP(P, R, np.eye(S)[0], terminal)


def brute_force_partition(mdp, goal, horizon, reward, allowed):
    """Sum over every action/successor sequence of at most `horizon` steps that first reaches
    `goal`, of prob * exp(sum of rewards); returned per (start state, first action)."""
    S, A = mdp.n_states, mdp.n_actions
    Z = np.zeros((S, A))
    for s0, a0 in itertools.product(range(S), range(A)):
        if s0 == goal or not allowed[s0, a0]:
            continue
        stack = [(s0, a0, 1.0, 0.0, 1)]
        while stack:
            s, a, prob, ret, depth = stack.pop()
            for nxt in range(S):
                p = mdp.transitions[s, a, nxt]
                if p == 0:
                    continue
                w, r = prob * p, ret + reward[s, a, nxt]
                if nxt == goal:
                    Z[s0, a0] += w * np.exp(r)
                elif depth < horizon and not mdp.terminal[nxt]:
                    stack.extend((nxt, b, w, r, depth + 1) for b in range(A) if allowed[nxt, b])
    return Z


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_backward_pass_matches_brute_force(seed):
    mdp = tiny_stochastic_mdp(seed)
    rng = np.random.default_rng(seed + 10)
    reward = rng.normal(size=mdp.transitions.shape)
    allowed = rng.random((mdp.n_states, mdp.n_actions)) < 0.8
    allowed[:, 0] = True
    horizon = 4
    result = maxent_backward_pass(mdp, [3], horizon, reward=reward, allowed=allowed)
    expected = brute_force_partition(mdp, 3, horizon, reward, allowed)
    live = np.arange(mdp.n_states) != 3
    with np.errstate(divide="ignore"):
        np.testing.assert_allclose(np.exp(result.log_z_sa[live]), expected[live], rtol=1e-9, atol=1e-300)
    np.testing.assert_allclose(result.policy.sum(axis=1), 1.0)
    assert (result.policy[~allowed] == 0).all()
    z_s = expected[live].sum(axis=1)
    np.testing.assert_allclose(result.policy[live], expected[live] / z_s[:, None], rtol=1e-9)


def test_backward_pass_stays_finite_over_long_horizons():
    mdp = tiny_stochastic_mdp(3)
    big = np.full(mdp.transitions.shape, 50.0)  # exp(50 * 2000) overflows any float
    result = maxent_backward_pass(mdp, [3], 2000, reward=big)
    assert np.isfinite(result.log_z_s).all() and np.isfinite(result.policy).all()
    np.testing.assert_allclose(result.policy.sum(axis=1), 1.0)
    tiny = np.full(mdp.transitions.shape, -50.0)  # and exp(-50 * 2000) underflows to 0
    result = maxent_backward_pass(mdp, [3], 2000, reward=tiny)
    assert np.isfinite(result.log_z_s).all()
    np.testing.assert_allclose(result.policy.sum(axis=1), 1.0)


def soft_q_brute_force(mdp, beta, discount, horizon, entropy):
    """Finite-horizon soft Bellman recursion written out state by state (no vectorisation)."""
    S, A = mdp.n_states, mdp.n_actions
    V = np.zeros(S)
    for _ in range(horizon):
        Q = np.zeros((S, A))
        for s in range(S):
            for a in range(A):
                if entropy == "causal":
                    future = sum(mdp.transitions[s, a, t] * V[t] for t in range(S))
                else:
                    future = beta * np.log(sum(mdp.transitions[s, a, t] * np.exp(V[t] / beta) for t in range(S)))
                Q[s, a] = 0.0 if mdp.terminal[s] else mdp.rewards[s, a] + discount * future
        V = np.array([0.0 if mdp.terminal[s] else beta * np.log(np.exp(Q[s] / beta).sum()) for s in range(S)])
    return Q, V


@pytest.mark.parametrize("entropy", ["causal", "trajectory"])
def test_soft_value_iteration_matches_the_written_out_recursion(entropy):
    mdp = tiny_stochastic_mdp(4)
    result = soft_value_iteration(mdp, beta=0.7, discount=0.9, entropy=entropy, tol=1e-12)
    Q, V = soft_q_brute_force(mdp, 0.7, 0.9, 400, entropy)
    assert result.converged
    np.testing.assert_allclose(result.values, V, atol=1e-8)
    np.testing.assert_allclose(result.policy.sum(axis=1), 1.0)
    live = ~mdp.terminal
    np.testing.assert_allclose(result.policy[live], np.exp((Q[live] - V[live, None]) / 0.7), atol=1e-8)


def test_causal_and_trajectory_entropy_agree_on_deterministic_dynamics():
    S, A = 5, 2
    P = np.zeros((S, A, S))
    for s in range(S):
        P[s, 0, s] = 1
        P[s, 1, min(s + 1, S - 1)] = 1
    mdp = TabularMDP(P, -np.ones((S, A)), np.eye(S)[0], np.eye(S)[S - 1].astype(bool))
    a = soft_value_iteration(mdp, beta=0.5, discount=0.95, entropy="causal")
    b = soft_value_iteration(mdp, beta=0.5, discount=0.95, entropy="trajectory")
    np.testing.assert_allclose(a.policy, b.policy, atol=1e-9)


def test_trajectory_entropy_is_optimistic_about_a_risky_action():
    # Action 1 reaches the goal with probability 0.5 and otherwise a trap worth -10 per step.
    P = np.zeros((3, 2, 3))
    P[0, 0, 2] = 1  # safe but costs 3
    P[0, 1, [1, 2]] = 0.5
    P[1, :, 1] = 1
    P[2, :, 2] = 1
    R = np.array([[-3.0, 0.0], [-10.0, -10.0], [0.0, 0.0]])
    mdp = TabularMDP(P, R, [1, 0, 0], [False, False, True])
    causal = soft_value_iteration(mdp, beta=0.1, discount=0.9, entropy="causal")
    trajectory = soft_value_iteration(mdp, beta=0.1, discount=0.9, entropy="trajectory")
    assert causal.policy[0, 0] > 0.99  # the expected value of gambling is terrible
    assert trajectory.policy[0, 1] > 0.99  # the lucky outcome dominates log E exp(V)


def test_small_beta_stays_finite():
    mdp = tiny_stochastic_mdp(5)
    result = soft_value_iteration(mdp, beta=1e-4, discount=0.9, entropy="trajectory")
    assert np.isfinite(result.values).all() and np.isfinite(result.policy).all()


def test_forward_pass_matches_monte_carlo():
    mdp = tiny_stochastic_mdp(6)
    policy = np.random.default_rng(0).dirichlet(np.ones(mdp.n_actions), size=mdp.n_states)
    horizon = 12
    exact = forward_pass(mdp, policy, horizon)
    rollouts = sample_rollouts(mdp, policy, 40_000, horizon, np.random.default_rng(1))
    counts = np.zeros((mdp.n_states, mdp.n_actions))
    taken = rollouts.actions >= 0
    np.add.at(counts, (rollouts.states[:, :-1][taken], rollouts.actions[taken]), 1)
    counts /= 40_000
    np.testing.assert_allclose(counts, exact.state_actions, atol=0.03)
    # every episode starts once, and the goal is counted once per arrival
    assert exact.states[0] >= 1.0
    reached = (rollouts.states == 3).any(axis=1).mean()
    assert exact.states[3] == pytest.approx(reached, abs=0.01)


def test_forward_pass_discounting():
    mdp = tiny_stochastic_mdp(7)
    policy = np.full((mdp.n_states, mdp.n_actions), 1 / mdp.n_actions)
    plain = forward_pass(mdp, policy, 30).state_actions.sum()
    discounted = forward_pass(mdp, policy, 30, discount=0.5).state_actions.sum()
    assert 1.0 <= discounted < plain


def test_bad_arguments():
    mdp = tiny_stochastic_mdp(0)
    with pytest.raises(SymlearnError, match="beta"):
        soft_value_iteration(mdp, beta=0)
    with pytest.raises(SymlearnError, match="entropy"):
        soft_value_iteration(mdp, entropy="shannon")
    with pytest.raises(ModelError, match="allowed mask must have shape"):
        soft_value_iteration(mdp, allowed=np.ones((2, 2), bool))
    with pytest.raises(ModelError, match="goal states"):
        maxent_backward_pass(mdp, [17], 5)
    with pytest.raises(SymlearnError, match="horizon"):
        maxent_backward_pass(mdp, [3], 0)
    with pytest.raises(ModelError, match="policy must have shape"):
        forward_pass(mdp, np.ones((1, 1)), 5)


def test_the_backward_pass_of_a_sparse_world_is_the_dense_sum():
    """Worlds with a few successors per pair (gymnasium's toy text: Taxi has 1 of 500) sum over
    those only; before, the dense (S, A, S) logsumexp took 4.6 s per pass on Taxi, and `learn
    constraints --env Taxi-v4 --method ml` ran for minutes. The result is the dense one, unreachable
    pairs (-inf) included."""
    from scipy.special import logsumexp

    rng = np.random.default_rng(3)
    S, A = 30, 4
    P = np.zeros((S, A, S))
    for s, a in itertools.product(range(S), range(A)):
        successors = rng.choice(S, size=rng.integers(1, 3), replace=False)
        P[s, a, successors] = rng.random(len(successors)) + 0.1
    P[S - 1] = 0
    P[S - 1, :, S - 1] = 1
    P[S - 2] = 0
    P[S - 2, :, S - 2] = 1     # a trap: nothing reaches the goal from it
    P /= P.sum(axis=2, keepdims=True)
    R = rng.normal(size=(S, A))
    terminal = np.zeros(S, bool)
    terminal[S - 1] = True
    mdp = TabularMDP(P, R, np.eye(S)[0], terminal)
    allowed = rng.random((S, A)) < 0.8
    allowed[:, 0] = True
    result = maxent_backward_pass(mdp, [S - 1], 12, allowed=allowed)

    with np.errstate(divide="ignore"):
        log_weight = np.log(P) + R[:, :, None]
    goal = np.zeros(S, bool)
    goal[S - 1] = True
    log_z_s = np.where(goal, 0.0, -np.inf)
    for _ in range(12):
        log_z_sa = logsumexp(log_weight + log_z_s[None, None, :], axis=2)
        log_z_sa = np.where(allowed & ~goal[:, None], log_z_sa, -np.inf)
        log_z_s = np.where(goal, 0.0, logsumexp(log_z_sa, axis=1))
    assert np.array_equal(np.isfinite(result.log_z_sa), np.isfinite(log_z_sa))
    assert np.isinf(result.log_z_s[S - 2])
    finite = np.isfinite(log_z_sa)
    np.testing.assert_allclose(result.log_z_sa[finite], log_z_sa[finite], rtol=1e-12, atol=1e-12)
