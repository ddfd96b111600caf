import numpy as np
import pytest

from symlearn.backends import CostWrapper, Shield
from symlearn.envs.gridworld import StochasticGridworld, make_gridworld
from symlearn.errors import SymlearnError
from symlearn.rl.q_learning import q_learning


def test_shielded_agent_never_violates_and_plain_agent_does():
    mask = StochasticGridworld(0.0).constraint_mask()
    plain = q_learning(make_gridworld(0.0), 200, learning_rate=0.5, discount=0.95, seed=1)
    shielded = q_learning(Shield(make_gridworld(0.0), mask), 200, learning_rate=0.5, discount=0.95, seed=1)
    assert plain.violations.sum() > 0 and shielded.violations.sum() == 0
    greedy = shielded.greedy_policy(~mask)
    assert not mask[np.arange(49), greedy][~StochasticGridworld(0.0).forbidden_states].any()


def test_ignoring_the_mask_is_possible():
    mask = StochasticGridworld(0.0).constraint_mask()
    env = Shield(make_gridworld(0.0), mask, mode="refuse", refusal_reward=-2)
    result = q_learning(env, 50, use_action_mask=False, seed=0, learning_rate=0.5, discount=0.95, max_steps=300)
    assert env.interventions > 0 and result.violations.sum() == 0


def test_costs_are_summed_and_can_shape_learning():
    mask = StochasticGridworld(0.0).constraint_mask()
    env = CostWrapper(make_gridworld(0.0), mask, violation_cost=10)
    result = q_learning(env, 300, learning_rate=0.5, discount=0.95, seed=2, cost_weight=1.0)
    assert result.costs[:20].sum() > 0
    assert result.costs[-20:].sum() < result.costs[:20].sum()


def test_seeded_runs_repeat():
    a = q_learning(make_gridworld(0.3), 30, seed=5)
    b = q_learning(make_gridworld(0.3), 30, seed=5)
    np.testing.assert_array_equal(a.q_values, b.q_values)
    np.testing.assert_array_equal(a.returns, b.returns)


def test_bad_settings():
    with pytest.raises(SymlearnError, match="n_episodes"):
        q_learning(make_gridworld(0.0), 0)
    with pytest.raises(SymlearnError, match="learning_rate"):
        q_learning(make_gridworld(0.0), 1, learning_rate=2)
    import gymnasium as gym
    with pytest.raises(SymlearnError, match="Discrete"):
        q_learning(gym.make("CartPole-v1"), 1)
