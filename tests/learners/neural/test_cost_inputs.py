"""Which inputs a neural cost reads: the environment's declared constraint features by default,
the group-sparsity penalty on the network's inputs, and ME-/VME-ICRL's multiplier rule."""

import gymnasium as gym
import numpy as np
import pytest
import torch

from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.errors import SymlearnError
from symlearn.learners.neural import NeuralMCEICRL, NeuralMEICRL
from symlearn.rl.episodes import EpisodeBatch
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.learners.neural.fit_setup import cost_inputs, declared_inputs
from symlearn.learners.neural.input_selection import select_inputs
from symlearn.learners.neural.input_sparsity import input_norms, input_penalty, input_shares
from symlearn.learners.neural.mce_icrl import dual_step
from symlearn.learners.neural.me_icrl import PER_ROLLOUT_RULE, discounted_cost, forward_lagrangian
from symlearn.learners.neural.neural_cost import NeuralCost
from symlearn.rl.ppo import LagrangianConfig, Multipliers


class Named(gym.Env):
    """A 3-entry observation with names; ``features`` as given."""

    def __init__(self, features=None, names=("a", "b", "c")):
        self.observation_space = gym.spaces.Box(-1, 1, (3,), np.float32)
        self.action_space = gym.spaces.Box(-1, 1, (1,), np.float32)
        if names is not None:
            self.observation_names = names
        if features is not None:
            self.feature_names = features


def test_declared_features_are_the_default_inputs():
    assert declared_inputs(BlockedPoint()) == [0, 1]
    assert cost_inputs(BlockedPoint(), None, 4) == ([0, 1], "declared features")
    assert cost_inputs(BlockedPoint(), "all", 4) == ([0, 1, 2, 3], "all")
    assert cost_inputs(BlockedPoint(), [3], 4) == ([3], "given")
    assert cost_inputs(Named(("c", "a")), None, 3) == ([2, 0], "declared features")
    # no declaration, a feature that is no observation entry, or unnamed observations: every entry
    for env in (Named(), Named(("a", "z")), Named(("a",), names=None)):
        assert declared_inputs(env) is None and cost_inputs(env, None, 3) == ([0, 1, 2], "all")
    with pytest.raises(SymlearnError, match="obs_dims"):
        cost_inputs(BlockedPoint(), "some", 4)
    with pytest.raises(SymlearnError, match="outside"):
        cost_inputs(BlockedPoint(), [4], 4)


def test_learners_read_the_declared_features_and_report_them():
    demos = expert_demonstrations(3, seed=0)
    tiny = dict(n_iterations=1, nominal_steps=512, policy_steps=512, n_policy_episodes=2, hidden_sizes=(8,))
    learner = NeuralMCEICRL(**tiny, n_features=2, pretrain_epochs=1, select_inputs=0).fit(demos, BlockedPoint)
    assert learner.cost_.phi.obs_dims == (0, 1)
    inputs = learner.result_.metrics["cost_inputs"]
    assert inputs["entries"] == [0, 1] and inputs["names"] == ["x", "y"] and inputs["from"] == "declared features"
    assert inputs["selection"] is None
    assert len(inputs["shares"]) == 2 and sum(inputs["shares"]) == pytest.approx(1.0)
    every = NeuralMEICRL(**tiny, backward_epochs=1, obs_dims="all", select_inputs=0).fit(demos, BlockedPoint)
    assert every.cost_.phi.obs_dims == (0, 1, 2, 3) and every.result_.metrics["cost_inputs"]["from"] == "all"
    # with the selection (the default): a subset of the candidates, recorded
    selected = NeuralMCEICRL(**tiny, n_features=2, pretrain_epochs=1).fit(demos, BlockedPoint)
    record = selected.result_.metrics["cost_inputs"]["selection"]
    assert record["candidates"] == [0, 1] and set(record["selected"]) <= {0, 1} and record["selected"]
    assert list(selected.cost_.phi.obs_dims) == record["selected"]


def test_selection_keeps_the_fewest_entries_that_separate():
    """Expert and policy differ in entry 2 only (entry 0 a weaker copy of it, 1 and 3 noise): the
    selection keeps entry 2 alone; where two entries are needed (an XOR of 0 and 1) it keeps both."""
    rng = np.random.default_rng(0)
    n = 600
    expert, policy = rng.normal(0, 1, (n, 4)), rng.normal(0, 1, (n, 4))
    expert[:, 2] += 3.0
    expert[:, 0] += 0.5 * 3.0 + rng.normal(0, 1, n)
    chosen = select_inputs(expert, policy, [0, 1, 2, 3], tolerance=0.01, seed=0)
    assert chosen.selected == (2,) and chosen.steps[0] > 0.95 and chosen.all_candidates_auc > 0.95
    # XOR: neither entry alone separates, both together do
    a, b = rng.choice([-1.0, 1.0], (2, 2 * n))
    points = np.stack([a + rng.normal(0, 0.2, 2 * n), b + rng.normal(0, 0.2, 2 * n), rng.normal(0, 1, 2 * n)], 1)
    same = a == b
    both = select_inputs(points[same], points[~same], [0, 1, 2], tolerance=0.01, seed=0)
    assert both.selected == (0, 1) and both.steps[-1] > 0.95
    # off, a single candidate, too few rows: every candidate
    assert select_inputs(expert, policy, [0, 1, 2, 3], tolerance=0.0).selected == (0, 1, 2, 3)
    assert select_inputs(expert, policy, [3], tolerance=0.01).selected == (3,)
    assert select_inputs(expert[:10], policy[:10], [0, 2], tolerance=0.01).selected == (0, 2)
    with pytest.raises(SymlearnError, match="select_inputs"):
        NeuralMCEICRL(select_inputs=0.7).fit(expert_demonstrations(1, seed=0), BlockedPoint)


def test_selection_among_many_candidates_starts_from_the_entries_a_tree_splits_on(monkeypatch):
    """151 candidates (MiniGrid's flattened observation), entry 40 the one that separates: the
    elimination starts from the entries one tree splits on, a few dozen cross-validations instead
    of some 11,000 (minutes)."""
    import symlearn.learners.neural.input_selection as selection

    rng = np.random.default_rng(0)
    expert, policy = rng.normal(0, 1, (300, 151)), rng.normal(0, 1, (300, 151))
    expert[:, 40] += 3.0
    calls = []
    scored = selection.separation_auc
    monkeypatch.setattr(selection, "separation_auc", lambda *a, **k: calls.append(1) or scored(*a, **k))
    chosen = select_inputs(expert, policy, list(range(151)), tolerance=0.01, seed=0)
    assert chosen.selected == (40,) and len(calls) < 300


def test_group_sparsity_drops_the_inputs_the_gap_does_not_need():
    """Expert and policy differ in input 0 only; inputs 1 and 2 are noise of the same spread.
    With the penalty the noise columns end near 0 while input 0 keeps its weights; without it
    they stay near their initial size."""
    rng = np.random.default_rng(0)
    n = 400
    expert = rng.normal(0, 1, (n, 3)).astype(np.float32)
    policy = rng.normal(0, 1, (n, 3)).astype(np.float32)
    expert[:, 0] += 1.5
    policy[:, 0] -= 1.5
    weights = torch.full((n,), 1.0 / n)

    def train(sparsity):
        phi = FeatureNetwork([0, 1, 2], 0, 2, (16,), torch.Generator().manual_seed(1))
        phi.fit_standardisation(np.concatenate([expert, policy]), None)
        optimizer = torch.optim.Adam(phi.parameters(), lr=1e-2)
        lambdas = np.ones(2)
        for _ in range(10):
            lambdas, _, _ = dual_step(phi, optimizer, lambdas, ((torch.from_numpy(expert), None), weights),
                                      ((torch.from_numpy(policy), None), weights), lambda_lr=1e-3, alpha=0.0,
                                      zeta_lr=1e-2, zeta_steps=30, input_sparsity=sparsity)
        return phi

    sparse, dense = train(0.05), train(0.0)
    norms = input_norms(sparse)
    assert norms[0] > 0.5 and max(norms[1:]) < 0.1 * norms[0], norms
    assert input_shares(sparse)[0] > 0.9 and sum(input_shares(sparse)) == pytest.approx(1.0)
    assert min(input_norms(dense)[1:]) > 0.3 and max(norms[1:]) < 0.2 * min(input_norms(dense)[1:]), input_norms(dense)
    with torch.no_grad():
        assert float(input_penalty(sparse)) < float(input_penalty(dense))
    # the separation is kept: phi is higher on policy states
    with torch.no_grad():
        assert float(sparse(torch.from_numpy(policy)).mean() - sparse(torch.from_numpy(expert)).mean()) > 0.3


def test_input_sparsity_is_checked():
    with pytest.raises(SymlearnError, match="input_sparsity"):
        NeuralMCEICRL(input_sparsity=-1.0).fit(expert_demonstrations(1, seed=0), BlockedPoint)


def test_me_icrl_multiplier_rule():
    # held fixed in the forward step: every rule of Multipliers only raises it against a limit of 0
    for rule in ("gradient", "adam", "pid"):
        fixed = LagrangianConfig(**forward_lagrangian({"update": rule}, 2.5, per_rollout=False))
        assert fixed.advantage_scale == "raw" and fixed.cost_limit == 0.0
        m = Multipliers(fixed, 1)
        assert [float(m.update([7.0])[0]) for _ in range(3)] == [2.5, 2.5, 2.5]
    rollout = LagrangianConfig(**forward_lagrangian(None, 1.0, per_rollout=True))
    assert (rollout.update, rollout.lr, rollout.max_multiplier) == (PER_ROLLOUT_RULE["update"], PER_ROLLOUT_RULE["lr"],
                                                                   None)
    assert float(Multipliers(rollout, 1).update([7.0])[0]) > 1.0
    # J: the mean discounted episode sum of the learned cost
    env = BlockedPoint()
    phi = FeatureNetwork([0], 0, 1, (4,), torch.Generator().manual_seed(0))
    cost = NeuralCost.for_env(env, phi)
    cost.set_lambdas([1.0])
    E, T = 2, 3
    obs = np.zeros((E, T, 4), dtype=np.float32)
    mask = np.array([[True, True, True], [True, False, False]])
    batch = EpisodeBatch(obs, np.zeros((E, T, 2)), np.zeros((E, T)), np.zeros((E, T)), mask)
    c = float(cost(obs[0, :1])[0])  # the same state everywhere
    assert discounted_cost(cost, batch, 0.5) == pytest.approx(c * ((1 + 0.5 + 0.25) + 1) / 2)
    with pytest.raises(SymlearnError, match="lambda_lr"):
        NeuralMEICRL(lambda_lr=0.0).fit(expert_demonstrations(1, seed=0), BlockedPoint)


def test_me_icrl_multiplier_rises_by_the_cost_gap():
    demos = expert_demonstrations(3, seed=0)
    tiny = dict(n_iterations=2, nominal_steps=512, policy_steps=512, n_policy_episodes=2, hidden_sizes=(8,),
                backward_epochs=1)
    learner = NeuralMEICRL(**tiny, lambda_lr=0.5).fit(demos, BlockedPoint)
    history = [h.multiplier for h in learner.history_]
    # a step of 0.5 x (a positive discounted cost sum over up to 100 steps) per iteration, never back
    assert 0 < history[0] <= history[1] and learner.multiplier_ == history[-1]
