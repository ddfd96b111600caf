"""Neural MCE-ICRL: the feature network, the dual step, the learned cost's files and checks, the
learner contract on a tiny budget, and (slow) the BlockedPoint targets of issue 12."""

import inspect
import json

import numpy as np
import pytest
import torch
from sklearn.base import clone

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.envs.point_circle import PointCircle
from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.learners.base import Learner, LearnerResult, NotFittedError, record_dict
from symlearn.learners.neural import NeuralCost, NeuralMCEICRL
from symlearn.rl.episodes import demonstration_batch, sample_episodes
from symlearn.learners.neural.feature_network import FeatureNetwork, pretrain_autoencoder
from symlearn.learners.neural.icrl_metrics import recovery
from symlearn.rl.episode_metrics import episode_metrics
from symlearn.learners.neural.mce_icrl import dual_step

TINY = dict(n_iterations=2, nominal_steps=1024, policy_steps=1024, n_policy_episodes=4, pretrain_epochs=2,
            obs_dims=[0, 1], n_features=2, hidden_sizes=(16,))


@pytest.fixture(scope="module")
def tiny_fit():
    return NeuralMCEICRL(**TINY).fit(expert_demonstrations(4, seed=0), BlockedPoint)


# --- the feature network ---------------------------------------------------------------------------

def test_features_are_sigmoid_outputs_of_the_chosen_inputs():
    gen = torch.Generator().manual_seed(0)
    phi = FeatureNetwork([0], 0, 3, (8,), gen)
    obs = torch.randn(50, 4)
    out = phi(obs)
    assert out.shape == (50, 3) and ((out > 0) & (out < 1)).all()
    changed = obs.clone()
    changed[:, 1:] += 5.0  # entries phi does not read
    assert torch.equal(phi(changed), out)
    with pytest.raises(DataError, match="no actions"):
        FeatureNetwork([0], 2, 3, (8,), gen)(obs)


def test_autoencoder_pretraining_lowers_the_reconstruction_error():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(400, 4)).astype(np.float32)
    x[:, 2] = x[:, 0] * 2  # structure an encoder can find
    phi = FeatureNetwork(range(4), 0, 3, (32,), torch.Generator().manual_seed(0))
    phi.fit_standardisation(x, None)
    record = pretrain_autoencoder(phi, x, None, epochs=60, batch_size=64, generator=torch.Generator().manual_seed(1))
    assert record.mse_after < 0.5 * record.mse_before and record.samples == 400


def test_dual_step_raises_lambda_and_the_features_where_only_the_policy_goes():
    gen = torch.Generator().manual_seed(0)
    phi = FeatureNetwork([0], 0, 2, (16,), gen)
    expert_x = torch.linspace(0, 5, 100)[:, None]  # expert: x >= 0; policy: x < 0
    policy_x = torch.linspace(-5, -0.5, 100)[:, None]
    phi.fit_standardisation(torch.cat([expert_x, policy_x]).numpy(), None)
    w = torch.full((100,), 1.0)
    optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
    lambdas = np.zeros(2)
    gaps = []
    for _ in range(5):
        lambdas, fd, fp = dual_step(phi, optimizer, lambdas, ((expert_x, None), w), ((policy_x, None), w),
                                    lambda_lr=0.01, alpha=0.0, zeta_lr=1e-2, zeta_steps=20)
        gaps.append(fp - fd)
        assert (lambdas >= 0).all()
    assert (lambdas > 0).any() and gaps[-1].max() > gaps[0].max()  # the features learned to separate
    with torch.no_grad():
        cost = phi(policy_x).double().numpy() @ lambdas, phi(expert_x).double().numpy() @ lambdas
    assert cost[0].min() > cost[1].max()
    # roles swapped: where the expert's features exceed the policy's, the projection keeps lambda at 0
    trained = lambdas > 0
    swapped, _, _ = dual_step(phi, optimizer, np.zeros(2), ((policy_x, None), w), ((expert_x, None), w),
                              lambda_lr=0.01, alpha=0.0, zeta_lr=1e-2, zeta_steps=1)
    assert (swapped[trained] == 0).all()


def test_dual_step_leaves_zero_multipliers_when_the_expert_walks_longer():
    """The expert's episodes twice as long as the policy's (a detour round what the policy walks
    through, lava_grid): the expert's sums of the positive features exceed the policy's, so the
    first lambda step is projected to 0. The zeta steps still move phi (every feature weighed
    alike while all multipliers are 0) until the policy's sums exceed the expert's and lambda
    rises; before, phi and lambda stayed put and the learned cost was 0 everywhere."""
    gen = torch.Generator().manual_seed(0)
    phi = FeatureNetwork([0], 0, 2, (16,), gen)
    expert_x = torch.linspace(0, 5, 200)[:, None]  # expert: x >= 0, 200 steps
    policy_x = torch.linspace(-5, -0.5, 100)[:, None]  # policy: x < 0, 100 steps
    phi.fit_standardisation(torch.cat([expert_x, policy_x]).numpy(), None)
    expert_w, policy_w = torch.full((200,), 1.0), torch.full((100,), 1.0)
    optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
    lambdas = np.zeros(2)
    first = None
    for _ in range(8):
        lambdas, fd, fp = dual_step(phi, optimizer, lambdas, ((expert_x, None), expert_w),
                                    ((policy_x, None), policy_w), lambda_lr=0.01, alpha=0.0,
                                    zeta_lr=1e-2, zeta_steps=20)
        first = (lambdas.copy(), fd - fp) if first is None else first
    assert (first[0] == 0).all() and (first[1] > 0).all()  # the stuck start: expert's sums larger
    assert (lambdas > 0).any()
    with torch.no_grad():
        cost = phi(policy_x).double().numpy() @ lambdas, phi(expert_x).double().numpy() @ lambdas
    assert cost[0].min() > cost[1].max()


def test_remembered_policies_keep_the_cost_where_the_current_one_no_longer_goes():
    """cost_memory="all": the zeta steps separate the expert from every policy seen. An early
    policy went left (x < 0), the current one goes right beyond the expert (x > 5): with the
    current sample alone the cost turns to the right; with both remembered it stays on the left."""
    expert_x = torch.linspace(0, 5, 100)[:, None]
    left, right = torch.linspace(-5, -0.5, 100)[:, None], torch.linspace(5.5, 8, 100)[:, None]
    w = torch.full((100,), 1.0)
    costs = {}
    for mode in ("current", "all"):
        gen = torch.Generator().manual_seed(0)
        phi = FeatureNetwork([0], 0, 2, (16,), gen)
        phi.fit_standardisation(torch.cat([expert_x, left, right]).numpy(), None)
        optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
        lambdas = np.zeros(2)
        for _ in range(3):  # the early policy: left
            lambdas, _, _ = dual_step(phi, optimizer, lambdas, ((expert_x, None), w), ((left, None), w),
                                      lambda_lr=0.05, alpha=0.0, zeta_lr=1e-2, zeta_steps=20)
        memory = [((left, None), w), ((right, None), w)]
        for _ in range(15):  # the current policy: right
            lambdas, _, _ = dual_step(phi, optimizer, lambdas, ((expert_x, None), w), ((right, None), w),
                                      lambda_lr=0.05, alpha=0.0, zeta_lr=1e-2, zeta_steps=20,
                                      remembered=memory if mode == "all" else None)
        with torch.no_grad():
            costs[mode] = {k: float((phi(x).double().numpy() @ lambdas).mean())
                           for k, x in (("left", left), ("expert", expert_x))}
    assert costs["all"]["left"] > costs["all"]["expert"]  # remembered: the left stays costlier
    assert costs["all"]["left"] - costs["all"]["expert"] > costs["current"]["left"] - costs["current"]["expert"]


def _shared_start_costs(**settings):
    """A grid in miniature: the expert and the policy both start at (0, 0); the expert detours
    through y = 1, the policy walks straight along y = 0. Ten dual steps at the learner's
    settings (its defaults, overridden by ``settings``); the learned cost of the start, of the
    policy's own cells (1, 0), (2, 0), and of an expert cell (1, 1)."""
    learner = NeuralMCEICRL(**settings)
    gen = torch.Generator().manual_seed(0)
    phi = FeatureNetwork([0, 1], 0, learner.n_features, learner.hidden_sizes, gen)
    expert = torch.tensor([[0, 0], [0, 1], [1, 1], [2, 1], [3, 1], [3, 0]], dtype=torch.float32)
    policy = torch.tensor([[0, 0], [1, 0], [2, 0]], dtype=torch.float32)
    phi.fit_standardisation(torch.cat([expert, policy]).numpy(), None)
    expert_w, policy_w = 0.99 ** torch.arange(6.0), 0.99 ** torch.arange(3.0)
    optimizer = torch.optim.Adam(phi.parameters(), lr=learner.zeta_lr)
    lambdas = np.zeros(learner.n_features)
    for i in range(10):
        lambdas, _, _ = dual_step(phi, optimizer, lambdas, ((expert, None), expert_w), ((policy, None), policy_w),
                                  lambda_lr=learner.lambda_lr, alpha=0.0,
                                  zeta_lr=learner.zeta_lr * learner.zeta_decay ** i,
                                  zeta_steps=learner.zeta_steps, expert_weight=learner.expert_weight)
    with torch.no_grad():
        cells = torch.tensor([[0, 0], [1, 0], [2, 0], [1, 1]], dtype=torch.float32)
        return phi(cells).double().numpy() @ lambdas


def test_the_experts_shared_start_costs_nothing_at_the_defaults():
    """The states the expert shares with the policies (the start) must cost ~0 and only what the
    policies do beyond the expert be charged: lava_grid's learned cost charged the expert's
    start as much as the straight row through the lava, so the expert's own level (the limit
    ``train --cost`` holds an agent to) paid for a shorter route through the lava. With eq. 2.13
    as written (``expert_weight=1``) the shared start has no gradient of its own and costs what
    the straight row costs; at the defaults it costs ~0 and the straight row stays charged."""
    start, straight_1, straight_2, expert_cell = _shared_start_costs()
    assert min(straight_1, straight_2) > 0.5
    assert start < 0.05 * min(straight_1, straight_2) and expert_cell < 0.05 * min(straight_1, straight_2)
    start, straight_1, _, _ = _shared_start_costs(expert_weight=1.0)  # eq. 2.13 as written
    assert start > 0.5 * straight_1


def test_expert_weight_is_checked():
    with pytest.raises(SymlearnError, match="expert_weight"):
        NeuralMCEICRL(expert_weight=0.5).fit(expert_demonstrations(2, seed=0), BlockedPoint)


def test_cost_memory_is_checked():
    with pytest.raises(SymlearnError, match="cost_memory"):
        NeuralMCEICRL(cost_memory="some").fit(expert_demonstrations(2, seed=0), BlockedPoint)


# --- the learned cost --------------------------------------------------------------------------------

def _cost(env=None, dims=(0, 1), action_dim=0):
    env = env or BlockedPoint()
    phi = FeatureNetwork(dims, action_dim, 2, (8,), torch.Generator().manual_seed(0))
    cost = NeuralCost.for_env(env, phi)
    cost.set_lambdas([0.5, 2.0])
    return cost


def test_cost_round_trips_through_safetensors_and_json(tmp_path):
    cost = _cost()
    obs = np.random.default_rng(0).normal(size=(30, 4)).astype(np.float32)
    path = cost.save(tmp_path / "cost.safetensors")
    assert (tmp_path / "cost.json").is_file() and b"pickle" not in path.read_bytes()
    again = NeuralCost.load(path, BlockedPoint(wall=-4.0))
    np.testing.assert_allclose(again(obs), cost(obs), rtol=1e-6)
    assert (cost(obs) >= 0).all() and again.observation_names == ["x", "y", "vx", "vy"]
    # the same observation layout elsewhere (the transfer target) is accepted
    NeuralCost.load(path, PointCircle())


def test_a_cost_for_another_observation_space_is_refused(tmp_path):
    from symlearn.envs.toy_navigation import ToyNavigationEnv

    path = _cost().save(tmp_path / "cost.safetensors")
    with pytest.raises(ModelError, match=r"learned for observations Box\(4,\).*Box\(2,\)") as info:
        NeuralCost.load(path, ToyNavigationEnv())
    assert info.value.file == str(path)
    other = _cost()
    other.observation_names = ["a", "b", "c", "d"]
    with pytest.raises(ModelError, match="reads observation entries"):
        other.check_environment(BlockedPoint())


def test_a_tampered_cost_file_is_refused(tmp_path):
    path = _cost().save(tmp_path / "cost.safetensors")
    config = json.loads((tmp_path / "cost.json").read_text())
    config["config"]["phi"]["obs_dims"] = [0, 9]
    (tmp_path / "cost.json").write_text(json.dumps(config))
    with pytest.raises(ModelError):
        NeuralCost.load(path)


def test_cost_inputs_are_checked():
    cost = _cost()
    with pytest.raises(DataError, match="shape"):
        cost(np.zeros((5, 3)))
    bad = np.zeros((5, 4))
    bad[2, 1] = np.nan
    with pytest.raises(DataError, match="not finite"):
        cost(bad)


def test_rollout_reward_is_reward_minus_cost_in_one_pass():
    from symlearn.rl.ppo import Rollout

    cost = _cost()
    rng = np.random.default_rng(0)
    obs = rng.normal(size=(6, 3, 4)).astype(np.float32)
    rollout = Rollout(obs, rng.normal(size=(6, 3, 2)), obs, np.ones((6, 3)), np.zeros((6, 3)), {})
    learned = cost.reward_fn()(rollout)
    np.testing.assert_allclose(learned, 1.0 - cost(obs.reshape(-1, 4)).reshape(6, 3), rtol=1e-6)


# --- the learner -------------------------------------------------------------------------------------

def test_learner_contract(tiny_fit, tmp_path):
    learner = NeuralMCEICRL(**TINY)
    assert isinstance(learner, Learner)
    names = [p for p in inspect.signature(type(learner).__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(names) == set(vars(learner))
    assert clone(learner).get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early.safetensors")
    fitted = tiny_fit
    assert isinstance(fitted.result_, LearnerResult) and fitted.result_.timings["total"] > 0
    assert len(fitted.history_) == 2 and all(isinstance(record_dict(h), dict) for h in fitted.history_)
    h = fitted.history_[-1]
    assert len(h.lambdas) == len(h.expert_features) == len(h.policy_features) == 2
    assert h.policy_seconds > 0 and h.cost_seconds > 0 and 0 <= h.violation_rate <= 1
    assert (fitted.lambda_ >= 0).all() and fitted.pretrain_.mse_after < fitted.pretrain_.mse_before
    path = fitted.save(tmp_path / "out.safetensors")
    assert json.loads(path.with_suffix(".json").read_text())["kind"] == "neural-icrl-cost"
    json.dumps(fitted.result_.as_dict())


def test_bad_input_is_refused_before_training():
    demos = expert_demonstrations(2, seed=0)
    with pytest.raises(SymlearnError, match="beta must be a number > 0"):
        NeuralMCEICRL(beta=0.0).fit(demos, BlockedPoint)
    with pytest.raises(DataError, match=r"shape \(4,\), the space's is \(2,\)"):
        from symlearn.envs.toy_navigation import ToyNavigationEnv

        NeuralMCEICRL(**TINY).fit(demos, ToyNavigationEnv)
    with pytest.raises(SymlearnError, match="obs_dims"):
        NeuralMCEICRL(**{**TINY, "obs_dims": [7]}).fit(demos, BlockedPoint)


def test_episodes_and_metrics_of_the_fitted_policy(tiny_fit):
    batch = sample_episodes(tiny_fit.policy_, BlockedPoint, 3, seed=0, deterministic=True)
    assert batch.obs.shape == (3, 100, 4) and batch.mask.all()
    again = sample_episodes(tiny_fit.policy_, BlockedPoint, 3, seed=0, deterministic=True)
    np.testing.assert_array_equal(batch.obs, again.obs)
    metrics = episode_metrics(batch)
    assert metrics.feasible_reward <= metrics.reward + 1e-9
    expert = demonstration_batch(expert_demonstrations(3, seed=0))
    assert expert.obs.shape == (3, 100, 4) and episode_metrics(expert).violation_rate == 0


@pytest.mark.slow
def test_blocked_point_targets():
    """Issue 12's BlockedPoint targets at CI size (about 30 s unloaded)."""
    demos = expert_demonstrations(20, seed=0)
    learner = NeuralMCEICRL(obs_dims=[0, 1]).fit(demos, BlockedPoint)
    evaluate = lambda policy: episode_metrics(sample_episodes(policy, BlockedPoint, 20, seed=7,  # noqa: E731
                                                              deterministic=True))
    learned, nominal = evaluate(learner.policy_), evaluate(learner.nominal_policy_)
    expert = episode_metrics(demonstration_batch(demos))
    assert nominal.violation_rate >= 0.5
    assert learned.violation_rate <= 0.05 and learned.reward >= 0.7 * expert.reward
    states = np.concatenate([np.asarray(t.states) for t in demos])
    assert recovery(learner.cost_, BlockedPoint().is_unsafe, states).auc >= 0.9


def test_discrete_actions_and_state_action_features():
    """CartPole: Discrete(2) actions reach phi one-hot; the cost reads them."""
    import gymnasium

    from symlearn.data import record

    demos = record(gymnasium.make("CartPole-v1"), lambda o: int(o[2] > 0), 2, seed=0)
    learner = NeuralMCEICRL(**{**TINY, "features": "state_action", "obs_dims": None}).fit(demos, "CartPole-v1")
    cost = learner.cost_
    assert cost.uses_actions and cost.phi.action_dim == 2
    obs = np.zeros((2, 4), dtype=np.float32)
    assert cost(obs, [0, 1]).shape == (2,)
    with pytest.raises(DataError, match="outside Discrete"):
        cost(obs, [0, 2])
