"""PPO's observation and value normalisation and the scale-free PPO-Lagrangian (``advantage_scale``).

Budgets: every run here is 2k-12k steps on a five-cell corridor (about a second each on 2 cores).
The thesis' toy, solved with these settings, is the slow test at the end (100k steps).
"""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

torch = pytest.importorskip("torch")

from symlearn.errors import SymlearnError  # noqa: E402
from symlearn.rl.ppo import (  # noqa: E402
    OBS_CLIP,
    ActorCritic,
    LagrangianConfig,
    PPOConfig,
    _rescale_critics,
    evaluate,
    train_ppo,
)


class Line(gym.Env):
    """A point at 0..length on a line (a Box observation far from zero: 100 + position), reward
    ``-reward_unit`` a step, the episode ends at ``length``. Action 0 moves one cell, action 1
    jumps two and costs ``cost_unit``."""

    def __init__(self, length: int = 6, reward_unit: float = 1.0, cost_unit: float = 1.0):
        self.length, self.reward_unit, self.cost_unit = length, reward_unit, cost_unit
        self.observation_space = spaces.Box(0.0, 200.0, (1,), dtype=np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = 0
        return np.array([100.0], dtype=np.float32), {}

    def step(self, action):
        self.pos = min(self.length, self.pos + 1 + int(action))
        info = {"cost": self.cost_unit * float(action == 1)}
        return np.array([100.0 + self.pos], dtype=np.float32), -self.reward_unit, self.pos == self.length, False, info


SMALL = dict(n_envs=2, n_steps=64, batch_size=64, n_epochs=4, learning_rate=1e-3)


def _agent(normalize: bool) -> ActorCritic:
    return ActorCritic.for_spaces(spaces.Box(-5.0, 5.0, (3,), dtype=np.float32), spaces.Discrete(2),
                                  generator=torch.Generator().manual_seed(0), obs_normalization=normalize)


def test_running_statistics_match_numpy_and_travel_with_the_weights(tmp_path):
    rng = np.random.default_rng(0)
    a, b = rng.normal(3.0, 2.0, (50, 3)), rng.normal(-1.0, 0.5, (7, 3))
    agent = _agent(True)
    agent.update_observation_stats(a)
    agent.update_observation_stats(b)
    both = np.vstack([a, b])
    np.testing.assert_allclose(agent.obs_mean.numpy(), both.mean(0), rtol=1e-12)
    np.testing.assert_allclose(agent.obs_var.numpy(), both.var(0), rtol=1e-12)
    assert float(agent.obs_count[0]) == 57
    x = np.array([[3.0, 1e6, -1.0]], dtype=np.float32)
    expected = np.clip((x - both.mean(0)) / np.sqrt(both.var(0) + 1e-8), -OBS_CLIP, OBS_CLIP)
    np.testing.assert_allclose(agent.encode(x), expected, rtol=1e-5)
    assert agent.encode(x)[0, 1] == OBS_CLIP
    agent.save(tmp_path / "normed")
    loaded = ActorCritic.load(tmp_path / "normed")
    saved = json.loads((tmp_path / "normed.json").read_text())["config"]
    assert loaded.obs_normalization and saved["obs_normalization"] is True
    np.testing.assert_array_equal(loaded.encode(x), agent.encode(x))
    probe = rng.normal(0.0, 3.0, (20, 3)).astype(np.float32)
    assert loaded.act(probe, deterministic=True) == agent.act(probe, deterministic=True)


def test_models_without_normalisation_keep_their_files(tmp_path):
    plain = _agent(False)
    assert "obs_mean" not in plain.state_dict()
    x = np.array([[1.0, 2.0, 3.0]], dtype=np.float32)
    np.testing.assert_array_equal(plain.encode(x), x)
    plain.save(tmp_path / "plain")
    path = tmp_path / "plain.json"
    document = json.loads(path.read_text())
    del document["config"]["obs_normalization"]  # a file written before the option existed
    path.write_text(json.dumps(document))
    assert not ActorCritic.load(tmp_path / "plain").obs_normalization


def test_training_normalises_what_the_networks_see():
    result = train_ppo(lambda: Line(), 1024, PPOConfig(seed=0, normalize_observations=True, **SMALL))
    policy = result.policy
    assert float(policy.obs_count[0]) == result.steps  # every rollout observation joined the statistics
    assert 100.0 < float(policy.obs_mean[0]) < 106.0 and float(policy.obs_var[0]) > 0.5
    assert abs(float(policy.encode(np.array([103.0], dtype=np.float32))[0, 0])) < 3  # centred, not ~100


def test_value_normalisation_hands_back_critics_in_return_units():
    # plain PPO learns to jump (3 steps of -1); the critic's values at positions 0, 2, 4 must then be
    # the discounted returns -2.97, -1.99, -1, though it learned returns divided by their running scale
    result = train_ppo(lambda: Line(), 4096, PPOConfig(seed=0, normalize_values=True, normalize_observations=True,
                                                       **SMALL))
    policy = result.policy
    with torch.no_grad():
        values = policy.value(torch.as_tensor(policy.encode(np.array([[100.0], [102.0], [104.0]], np.float32))))
    assert evaluate(policy, Line(), 1).returns[0] == -3.0
    np.testing.assert_allclose(values.numpy(), [-2.9701, -1.99, -1.0], atol=0.15)
    assert all(len(h.return_scales) == 1 and h.return_scales[0] > 0 for h in result.history)


def test_rescaling_the_output_layer_scales_the_values():
    agent = _agent(False)
    agent.add_cost_critics(1)
    x = torch.randn(5, 3, generator=torch.Generator().manual_seed(1))
    with torch.no_grad():
        before = agent.value(x).clone(), agent.cost_values(x).clone()
        _rescale_critics(agent, 1, np.array([4.0, 0.25]))
        torch.testing.assert_close(agent.value(x), 4.0 * before[0])
        torch.testing.assert_close(agent.cost_values(x), 0.25 * before[1])


def test_the_reward_scale_floor_holds_a_collapsed_reward_at_its_largest_spread():
    """Returns that stop varying (every episode earns the most) shrink the reward's running scale
    towards 1 % of its peak; with ``reward_floor=1`` the scale the Lagrangian mixes in stays at the
    peak, each cost's floor is 1 % whatever the reward's, and the critics' unit is unchanged."""
    from symlearn.rl.ppo.update import RETURN_SCALE_FLOOR, _ReturnScales

    spread = np.array([[0.0, 0.0], [10.0, 4.0]])     # reward std 5, cost std 2
    settled = np.array([[10.0, 0.0], [10.0, 0.0]])   # both stopped varying
    running, held = _ReturnScales(), _ReturnScales(reward_floor=1.0)
    for scales in (running, held):
        scales.update(spread)
        for _ in range(200):
            scales.update(settled)
    floored = [5.0 * RETURN_SCALE_FLOOR, 2.0 * RETURN_SCALE_FLOOR]
    np.testing.assert_allclose(running.mix_scales(), floored)
    np.testing.assert_allclose(held.mix_scales(), [5.0, 2.0 * RETURN_SCALE_FLOOR])
    np.testing.assert_allclose(held.scales(), floored)   # the critics' unit is not held


@pytest.mark.parametrize("floor", [0.0, 1.5, float("nan"), True, "1"])
def test_reward_scale_floor_is_a_share(floor):
    with pytest.raises(SymlearnError, match="reward_scale_floor"):
        LagrangianConfig(cost_limit=0.0, reward_scale_floor=floor)


def test_the_cost_scale_floor_holds_a_cost_the_agent_stopped_paying_at_its_spread():
    """A cost the agent stopped paying: its running scale falls to 1 % of its peak (every remaining
    violation 100x dearer in the mix); ``cost_floor=1`` holds it at the peak in the mix only."""
    from symlearn.rl.ppo.update import RETURN_SCALE_FLOOR, _ReturnScales

    spread = np.array([[0.0, 0.0], [10.0, 4.0]])
    safe = np.array([[0.0, 0.0], [10.0, 0.0]])     # the reward still varies, the cost is 0 everywhere
    running, held = _ReturnScales(), _ReturnScales(cost_floor=1.0)
    for scales in (running, held):
        scales.update(spread)
        for _ in range(200):
            scales.update(safe)
    np.testing.assert_allclose(running.mix_scales(), [5.0, 2.0 * RETURN_SCALE_FLOOR], rtol=1e-6)
    np.testing.assert_allclose(held.mix_scales(), [5.0, 2.0], rtol=1e-6)
    np.testing.assert_allclose(held.scales(), running.scales())   # the critics' unit is not held
    assert LagrangianConfig(cost_limit=0.0).cost_scale_floor == RETURN_SCALE_FLOOR   # the default: as before
    with pytest.raises(SymlearnError, match="cost_scale_floor"):
        LagrangianConfig(cost_limit=0.0, cost_scale_floor=0.0)


def _run(reward_unit: float, cost_unit: float, scale: str, normalize_values: bool):
    return train_ppo(lambda: Line(reward_unit=reward_unit, cost_unit=cost_unit), 2048,
                     PPOConfig(seed=3, normalize_values=normalize_values, **SMALL),
                     LagrangianConfig(cost_limit=1.0 * cost_unit, update="adam", lr=0.1, advantage_scale=scale))


def _actor_weights(result) -> np.ndarray:
    return np.concatenate([p.detach().numpy().ravel() for p in result.policy.actor.parameters()])


def test_scale_free_multiplier_ignores_the_units_of_reward_and_cost():
    """With value normalisation and ``advantage_scale="returns"`` the run does not depend on the
    units of reward and cost (powers of two keep the arithmetic exact); with raw advantages the
    multiplier's useful range moves with their ratio and the run changes."""
    base = _run(1.0, 1.0, "returns", True)
    scaled = _run(4.0, 0.5, "returns", True)
    np.testing.assert_allclose([h.multipliers[0] for h in scaled.history],
                               [h.multipliers[0] for h in base.history], rtol=1e-5)
    np.testing.assert_allclose(_actor_weights(scaled), _actor_weights(base), rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(scaled.episodes.costs / 0.5, base.episodes.costs)
    np.testing.assert_allclose(scaled.history[-1].return_scales, np.array(base.history[-1].return_scales) * [4, 0.5])
    raw = _run(1.0, 1.0, "raw", False)
    raw_scaled = _run(4.0, 0.5, "raw", False)
    assert not np.allclose(_actor_weights(raw_scaled), _actor_weights(raw), rtol=1e-3, atol=1e-4)


@pytest.mark.slow
def test_ppo_lagrangian_takes_the_safe_route_on_the_toy():
    """The thesis' toy with a DNF learned from 30 demonstrations: PPO-Lagrangian (cost limit 0,
    the toy's settings) reaches the goal without leaving the true safe set (5/5 seeds in
    ``benchmarks/toy_dnf.py``); plain PPO cuts the corner."""
    from symlearn.backends.dnf_cost import DnfCostWrapper
    from symlearn.demo.dnf_pipeline import toy_lagrangian, toy_ppo_config
    from symlearn.envs.toy_navigation import ToyNavigationEnv, expert_demonstrations
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    dnf = OneClassTreeConstraint(max_depth=3).fit(expert_demonstrations(30, seed=0), ["x", "y"]).dnf_
    result = train_ppo(lambda: DnfCostWrapper(ToyNavigationEnv(), dnf, ["x", "y"]), 100_000, toy_ppo_config(0),
                       lagrangian=toy_lagrangian())
    greedy = evaluate(result.policy, ToyNavigationEnv(), 1)  # info["cost"] here is the true cost
    assert greedy.costs[0, 0] == 0 and greedy.lengths[0] < 100 and greedy.returns[0] > 2.0  # reached the goal
