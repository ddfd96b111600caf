"""VME-ICRL (variational baseline): the Beta parameterisation, the backward step on known data,
the contract on a tiny budget, bad parameters, and (slow) BlockedPoint."""

import inspect
import json

import numpy as np
import pytest
import torch
from sklearn.base import clone
from torch.distributions import Beta

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner, NotFittedError, record_dict
from symlearn.learners.neural import NeuralCost, NeuralVMEICRL, VMEIteration
from symlearn.rl.episodes import EpisodeBatch
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.icrl_metrics import recovery
from symlearn.learners.neural.vme_icrl import beta_parameters, expected_log_feasibility, variational_backward_step

TINY = dict(n_iterations=2, nominal_steps=1024, policy_steps=1024, n_policy_episodes=4, backward_epochs=3,
            obs_dims=[0, 1], hidden_sizes=(16,))


def test_beta_parameters_mean_and_concentration():
    outputs = torch.tensor([[0.25, 0.0], [0.5, 1.0], [0.9, 0.5]])
    a, b = beta_parameters(outputs, (2.0, 10.0))
    assert torch.allclose(a / (a + b), 1 - outputs[:, 0])  # the cost phi_1 is 1 - E[zeta]
    assert torch.allclose(a + b, torch.tensor([2.0, 10.0, 6.0]))
    # the closed-form E[log zeta] agrees with sampling
    samples = Beta(a, b).sample((200_000,)).log().mean(0)
    assert torch.allclose(expected_log_feasibility(a, b), samples, atol=0.02)


def test_variational_step_separates_expert_from_policy_states():
    env = BlockedPoint()
    phi = FeatureNetwork([0], 0, 2, (16,), torch.Generator().manual_seed(0))
    cost = NeuralCost.for_env(env, phi)
    cost.set_lambdas([1.0, 0.0])
    E, T = 8, 20
    policy_obs = np.zeros((E, T, 4), dtype=np.float32)
    policy_obs[..., 0] = np.linspace(-5, -1, T)[None, :] + np.linspace(0, 2, E)[:, None]
    batch = EpisodeBatch(policy_obs, np.zeros((E, T, 2)), np.zeros((E, T)), np.zeros((E, T)), np.ones((E, T), bool))
    expert_x = torch.zeros((100, 4))
    expert_x[:, 0] = torch.linspace(0, 5, 100)
    phi.fit_standardisation(np.concatenate([expert_x.numpy(), policy_obs.reshape(-1, 4)]), None)
    optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
    expert_f, policy_f, epochs, _, _, prior_kl, kappa = variational_backward_step(
        phi, optimizer, (expert_x, None), batch, cost, epochs=100, kl_weight=0.01, prior=(1.0, 0.1),
        concentration=(1.0, 100.0), target_kl=1e9)
    assert epochs == 100 and expert_f > 0.6 and policy_f < 0.4 and expert_f > policy_f + 0.3
    assert prior_kl >= 0 and 1.0 <= kappa <= 100.0
    # the learned cost (phi_1 = 1 - E[zeta]) is high where the policy went and the expert did not
    assert cost(np.array([[-4.0, 0, 0, 0]]))[0] > cost(np.array([[3.0, 0, 0, 0]]))[0] + 0.3
    # a heavy KL weight pulls every pair toward the prior's mean (0.91) instead
    phi2 = FeatureNetwork([0], 0, 2, (16,), torch.Generator().manual_seed(0))
    phi2.load_state_dict(phi.state_dict())
    cost2 = NeuralCost.for_env(env, phi2)
    variational_backward_step(phi2, torch.optim.Adam(phi2.parameters(), lr=1e-2), (expert_x, None), batch, cost2,
                              epochs=60, kl_weight=100.0, prior=(1.0, 0.1), concentration=(1.0, 100.0),
                              target_kl=1e9)
    with torch.no_grad():
        assert float(1 - phi2(*cost2.tensors(policy_obs.reshape(-1, 4)))[:, 0].mean()) > policy_f + 0.2
    # the KL test stops the epochs at once when no drift is allowed
    stopped = variational_backward_step(phi, optimizer, (expert_x, None), batch, cost, epochs=50, kl_weight=0.01,
                                        prior=(1.0, 0.1), concentration=(1.0, 100.0), target_kl=1e-12)[2]
    assert stopped <= 1


def test_vme_icrl_contract(tmp_path):
    learner = NeuralVMEICRL(**TINY)
    assert isinstance(learner, Learner)
    names = [p for p in inspect.signature(type(learner).__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(names) == set(vars(learner))
    assert "regularizer" not in names and "kl_weight" in names
    assert clone(learner).get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early.safetensors")
    assert learner.fit(expert_demonstrations(3, seed=0), BlockedPoint) is learner
    assert len(learner.history_) == 2 and all(isinstance(h, VMEIteration) for h in learner.history_)
    record = record_dict(learner.history_[0])
    assert {"prior_kl", "concentration", "multiplier", "epochs"} <= set(record)
    assert learner.result_.timings["total"] > 0 and learner.multiplier_ >= 0
    path = learner.save(tmp_path / "vme.safetensors")
    loaded = NeuralCost.load(path, BlockedPoint())
    assert loaded.lambdas.tolist() == [1.0, 0.0]
    probe = np.random.default_rng(0).normal(size=(5, 4))
    assert np.allclose(loaded(probe), learner.cost_(probe), atol=1e-6)
    json.dumps(learner.result_.as_dict())


@pytest.mark.parametrize("bad, match", [(dict(kl_weight=-1.0), "kl_weight"), (dict(prior=(1.0, 0.0)), "prior"),
                                        (dict(prior=(1.0,)), "prior"), (dict(concentration=(5.0, 2.0)), "min < max"),
                                        (dict(beta=float("nan")), "beta")])
def test_vme_icrl_bad_parameters(bad, match):
    with pytest.raises(SymlearnError, match=match):
        NeuralVMEICRL(**{**TINY, **bad}).fit(expert_demonstrations(1, seed=0), BlockedPoint)


@pytest.mark.slow
def test_vme_icrl_on_blocked_point():
    demos = expert_demonstrations(20, seed=0)
    learner = NeuralVMEICRL(obs_dims=[0, 1]).fit(demos, BlockedPoint)
    first = learner.history_[0]
    assert first.expert_feasibility > first.policy_feasibility + 0.2
    states = np.concatenate([np.asarray(t.states) for t in demos])
    assert recovery(learner.cost_, BlockedPoint().is_unsafe, states).auc >= 0.9
