"""GACL (the GAIL-style baseline): the discriminator step on known data and the contract on a tiny budget."""

import inspect

import numpy as np
import pytest
import torch
from sklearn.base import clone

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.learners.base import Learner, NotFittedError, record_dict
from symlearn.learners.neural import NeuralCost, NeuralGACL
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.gacl import discriminator_step


def test_discriminator_separates_expert_from_policy_pairs():
    phi = FeatureNetwork([0], 0, 1, (16,), torch.Generator().manual_seed(0))
    expert = torch.zeros((100, 4))
    expert[:, 0] = torch.linspace(0, 5, 100)
    policy = torch.zeros((100, 4))
    policy[:, 0] = torch.linspace(-5, -0.5, 100)
    phi.fit_standardisation(torch.cat([expert, policy]).numpy(), None)
    optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
    expert_d, policy_d = discriminator_step(phi, optimizer, (expert, None), (policy, None), steps=60)
    assert expert_d > 0.8 and policy_d < 0.2
    # the same pairs on both sides: nothing to tell apart, D stays near 1/2
    same_d, other_d = discriminator_step(phi, optimizer, (expert, None), (expert, None), steps=200)
    assert abs(same_d - 0.5) < 0.1 and same_d == pytest.approx(other_d)


def test_gacl_contract(tmp_path):
    learner = NeuralGACL(n_iterations=2, nominal_steps=1024, policy_steps=1024, n_policy_episodes=4, disc_steps=3,
                         obs_dims=[0, 1], hidden_sizes=(16,))
    assert isinstance(learner, Learner)
    names = [p for p in inspect.signature(type(learner).__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(names) == set(vars(learner))
    assert clone(learner).get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early.safetensors")
    assert learner.fit(expert_demonstrations(3, seed=0), BlockedPoint) is learner
    assert len(learner.history_) == 2 and all(isinstance(record_dict(h), dict) for h in learner.history_)
    first = learner.history_[0]
    assert first.expert_d > first.policy_d  # the nominal policy runs into the wall, the expert never does
    cost = NeuralCost.load(learner.save(tmp_path / "gacl.safetensors"), BlockedPoint())
    states = np.zeros((3, 4), dtype=np.float32)
    assert ((cost(states) > 0) & (cost(states) < 1)).all()  # C = 1 - D


def test_icrl_bar_shows_return_and_violation(monkeypatch):
    # the learner's own bar (beside the inner PPO's) carries the sampled policy's return and true violation rate
    import symlearn.learners.neural.alternation as alternation
    from progress_recording import recording_bar

    shown = recording_bar(monkeypatch, alternation)
    learner = NeuralGACL(n_iterations=2, nominal_steps=512, policy_steps=512, n_policy_episodes=2, disc_steps=1,
                         obs_dims=[0, 1], hidden_sizes=(8,))
    learner.fit(expert_demonstrations(2, seed=0), BlockedPoint)
    assert [set(numbers) for numbers in shown] == [{"return", "violation"}] * 2
    assert [numbers["return"] for numbers in shown] == [h.reward for h in learner.history_]
