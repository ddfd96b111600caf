import gymnasium as gym
import numpy as np
import pytest

from symlearn.data import record
from symlearn.errors import SymlearnError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import value_iteration


def test_corridor_values_are_discounted_distances():
    n = 5
    P = np.zeros((n, 2, n))
    for s in range(n):
        P[s, 0, s] = 1
        P[s, 1, min(s + 1, n - 1)] = 1
    mdp = TabularMDP(P, np.zeros((n, 2)), np.eye(n)[0], np.zeros(n, bool)).with_goal(n - 1, goal_reward=1.0)
    result = value_iteration(mdp, discount=0.9)
    assert result.converged
    assert result.values == pytest.approx([0.9**3, 0.9**2, 0.9, 1.0, 0.0])
    assert result.policy[:4].tolist() == [1, 1, 1, 1]


def test_expert_beats_random_on_frozen_lake():
    env = gym.make("FrozenLake-v1", is_slippery=True)
    mdp = TabularMDP.from_gymnasium(env)
    policy = value_iteration(mdp, discount=0.99).policy
    expert = record(env, lambda s: int(policy[s]), 200, seed=0)
    random = record(env, "random", 200, seed=0)
    success = lambda d: np.mean([t.total_reward() > 0 for t in d])  # noqa: E731
    assert success(expert) > 0.6 > 0.1 > success(random)


def test_bad_discount():
    env = gym.make("FrozenLake-v1")
    with pytest.raises(SymlearnError, match="discount"):
        value_iteration(TabularMDP.from_gymnasium(env), discount=1.5)
