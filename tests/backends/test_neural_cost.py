"""A learned neural cost as an agent uses it: the rollout cost and reward, the per-step cost."""

import numpy as np
import pytest

from symlearn.backends.neural_cost import NeuralRolloutCost, NeuralRolloutReward, NeuralStepCost
from symlearn.rl.ppo import Rollout


class LinearCost:
    """Not a NeuralCost: what the adapters need of one, in numpy (backends never import learners)."""

    uses_actions = True
    action_spec = {"kind": "box", "shape": [1], "low": [-1.0], "high": [1.0]}

    def __call__(self, obs, actions=None):
        return obs.sum(axis=1) + (0.0 if actions is None else 10.0 * actions[:, 0])


def rollout(T=3, N=2):
    rng = np.random.default_rng(0)
    obs = rng.normal(size=(T, N, 2))
    actions = np.array([[[0.5], [3.0]]] * T)   # the second copy's action lies outside the bounds
    return Rollout(obs, actions, obs + 1, rng.normal(size=(T, N)), np.zeros((T, N)), {})


def test_rollout_cost_clips_actions_to_the_bounds_the_environment_applied():
    r = rollout()
    costs = NeuralRolloutCost(LinearCost())(r)
    assert costs.shape == (3, 2)
    np.testing.assert_allclose(costs[:, 0], r.obs[:, 0].sum(axis=1) + 5.0)
    np.testing.assert_allclose(costs[:, 1], r.obs[:, 1].sum(axis=1) + 10.0)   # 3.0 clipped to 1.0
    np.testing.assert_allclose(NeuralRolloutReward(LinearCost())(r), r.rewards - costs)
    assert NeuralRolloutCost(LinearCost()).info_keys == ()


def test_a_state_cost_is_shown_no_actions():
    cost = LinearCost()
    cost.uses_actions = False
    r = rollout()
    np.testing.assert_allclose(NeuralRolloutCost(cost)(r), r.obs.sum(axis=2))
    assert NeuralStepCost(cost)(r.obs[0, 0], r.actions[0, 0], r.next_obs[0, 0], {}).tolist() == \
        pytest.approx([r.obs[0, 0].sum()])


def test_step_cost_is_one_number_per_step():
    step = NeuralStepCost(LinearCost())(np.array([0.25, 0.5]), np.array([0.5]), None, {})
    assert step.dtype == np.float64 and step.tolist() == [5.75]


def test_a_neural_cost_delegates_to_the_adapters():
    torch = pytest.importorskip("torch")
    import gymnasium as gym

    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    class Env:
        observation_space = gym.spaces.Box(-5, 5, (2,))
        action_space = gym.spaces.Box(-1, 1, (1,))

    cost = NeuralCost.for_env(Env(), FeatureNetwork([0, 1], 1, 1, (4,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([2.0])
    r = rollout()
    expected = NeuralRolloutCost(cost)(r)
    np.testing.assert_array_equal(cost.cost_of_rollout(r), expected)
    np.testing.assert_array_equal(cost.cost_fn()(r), expected)
    np.testing.assert_array_equal(cost.reward_fn()(r), r.rewards - expected)
    # one row through the network instead of six: equal up to float32 rounding
    np.testing.assert_allclose(cost.step_cost()(r.obs[0, 0], np.clip(r.actions[0, 0], -1, 1), None, {}),
                               expected[0, 0:1], rtol=1e-6)
