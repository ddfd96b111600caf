"""ME-ICRL (the baseline): the backward step on known data, the contract on a tiny budget, and
(slow) BlockedPoint."""

import inspect
import json

import numpy as np
import pytest
import torch
from sklearn.base import clone

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner, NotFittedError, record_dict
from symlearn.learners.neural import NeuralCost, NeuralMEICRL
from symlearn.rl.episodes import EpisodeBatch
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.icrl_metrics import recovery
from symlearn.learners.neural.me_icrl import backward_step

TINY = dict(n_iterations=2, nominal_steps=1024, policy_steps=1024, n_policy_episodes=4, backward_epochs=3,
            obs_dims=[0, 1], hidden_sizes=(16,))


def test_backward_step_makes_policy_only_states_infeasible():
    env = BlockedPoint()
    phi = FeatureNetwork([0], 0, 1, (16,), torch.Generator().manual_seed(0))
    cost = NeuralCost.for_env(env, phi)
    cost.set_lambdas([1.0])
    E, T = 8, 20
    policy_obs = np.zeros((E, T, 4), dtype=np.float32)
    # the policy goes where the expert never does, each episode a little differently
    policy_obs[..., 0] = np.linspace(-5, -1, T)[None, :] + np.linspace(0, 2, E)[:, None]
    batch = EpisodeBatch(policy_obs, np.zeros((E, T, 2)), np.zeros((E, T)), np.zeros((E, T)), np.ones((E, T), bool))
    expert_x = torch.zeros((100, 4))
    expert_x[:, 0] = torch.linspace(0, 5, 100)
    phi.fit_standardisation(np.concatenate([expert_x.numpy(), policy_obs.reshape(-1, 4)]), None)
    optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
    expert_feas, policy_feas, epochs, kl_on, kl_no = backward_step(
        phi, optimizer, (expert_x, None), batch, cost, epochs=30, regularizer=0.1, target_kl=1e9)
    assert epochs == 30 and expert_feas > 0.6 and policy_feas < 0.4 and expert_feas > policy_feas + 0.3
    # the KL test stops the epochs once the reweighted samples drift from the sampled ones
    _, _, stopped, _, _ = backward_step(phi, optimizer, (expert_x, None), batch, cost, epochs=50, regularizer=0.1,
                                        target_kl=1e-12)
    assert stopped <= 1


def test_me_icrl_contract(tmp_path):
    learner = NeuralMEICRL(**TINY)
    assert isinstance(learner, Learner)
    names = [p for p in inspect.signature(type(learner).__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(names) == set(vars(learner))
    assert clone(learner).get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early.safetensors")
    assert learner.fit(expert_demonstrations(3, seed=0), BlockedPoint) is learner
    assert len(learner.history_) == 2 and all(isinstance(record_dict(h), dict) for h in learner.history_)
    assert learner.result_.timings["total"] > 0 and learner.multiplier_ >= 0
    path = learner.save(tmp_path / "me.safetensors")
    loaded = NeuralCost.load(path, BlockedPoint())
    assert loaded.lambdas.tolist() == [1.0]
    json.dumps(learner.result_.as_dict())
    with pytest.raises(SymlearnError, match="beta"):
        NeuralMEICRL(beta=-1.0).fit(expert_demonstrations(1, seed=0), BlockedPoint)


@pytest.mark.slow
def test_me_icrl_on_blocked_point():
    """The feasibility network recovers the wall (AUC ~0.99 on seeds 0-2); the policy's turn is
    less reliable (seed 2 of benchmarks/icrl_blocked_point.py kept violating), so it is not asserted."""
    demos = expert_demonstrations(20, seed=0)
    learner = NeuralMEICRL(obs_dims=[0, 1]).fit(demos, BlockedPoint)
    first = learner.history_[0]
    assert first.expert_feasibility > first.policy_feasibility + 0.2
    states = np.concatenate([np.asarray(t.states) for t in demos])
    assert recovery(learner.cost_, BlockedPoint().is_unsafe, states).auc >= 0.9
