"""The multipliers' cost estimate (LagrangianConfig.cost_estimate), the per-iteration true cost,
and the library defaults that match ``symlearn train``'s."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

pytest.importorskip("torch")

from symlearn.errors import SymlearnError  # noqa: E402
from symlearn.rl.ppo import CLEANRL_PLAIN, LagrangianConfig, PPOConfig, train_ppo  # noqa: E402


class LongCostly(gym.Env):
    """Episodes of ``length`` steps, every step costs ``rate`` (reported as ``info["cost"]``)."""

    def __init__(self, length: int = 1000, rate: float = 0.5, report: bool = True, every: int = 1):
        self.length, self.rate, self.report, self.every = length, rate, report, every
        self.observation_space = spaces.Box(-1.0, 1.0, (1,), dtype=np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return np.zeros(1, dtype=np.float32), {}

    def step(self, action):
        self.t += 1
        # every > 1: info["cost"] only on every so many steps, absent (nothing paid) between them
        info = {"cost": self.rate} if self.report and self.t % self.every == 0 else {}
        return np.zeros(1, dtype=np.float32), 0.0, False, self.t >= self.length, info


SMALL = dict(n_envs=2, n_steps=64, batch_size=64, n_epochs=1)


def test_rollout_estimate_updates_every_iteration_before_any_episode_ends():
    # 1000-step episodes, 2 x 64-step rollouts: no episode ends in 4 iterations
    result = train_ppo(lambda: LongCostly(), 512, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.01))
    assert [h.episodes for h in result.history] == [0, 0, 0, 0]
    lambdas = [h.multipliers[0] for h in result.history]
    assert all(b > a for a, b in zip([0.0] + lambdas, lambdas))  # rose in every iteration
    # no episode has ended and the environment declares no time limit: the longest running one
    # (64, 128, ... steps) is the length, so J_c = 0.5 per step x that length
    assert [h.cost_estimate[0] for h in result.history] == pytest.approx([32.0, 64.0, 96.0, 128.0])
    assert result.history[-1].true_cost == pytest.approx(128.0)


def test_time_limit_is_the_length_before_an_episode_ends():
    # registered with a 1000-step limit: before an episode ends, J_c = 0.5 per step x 1000
    gym.register("symlearn-test/LongCostly-v0", entry_point=lambda: LongCostly(length=10_000), max_episode_steps=1000)
    try:
        result = train_ppo("symlearn-test/LongCostly-v0", 256, PPOConfig(seed=0, **SMALL),
                           LagrangianConfig(cost_limit=0.0))
    finally:
        gym.registry.pop("symlearn-test/LongCostly-v0")
    assert [h.cost_estimate[0] for h in result.history] == pytest.approx([500.0, 500.0])


def test_episodes_estimate_keeps_the_old_behaviour():
    result = train_ppo(lambda: LongCostly(length=200), 1024, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=0.0, cost_estimate="episodes"))
    updated = [bool(h.cost_estimate) for h in result.history]
    ended = [h.episodes > 0 for h in result.history]
    assert updated == ended and any(ended) and not all(ended)
    for h in result.history:
        if h.cost_estimate:
            assert h.cost_estimate[0] == pytest.approx(100.0)  # 200 steps x 0.5, the finished episodes'


def test_ratio_estimate_equals_the_finished_episodes_mean_when_they_fill_the_rollout():
    # 64-step episodes and 64-step rollouts: each rollout is exactly one episode per copy
    result = train_ppo(lambda: LongCostly(length=64, rate=0.25), 512, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=1.0))
    for h in result.history:
        assert h.cost_estimate[0] == pytest.approx(h.mean_cost[0]) == pytest.approx(16.0)


def test_true_cost_is_reported_beside_a_learned_cost_and_nan_without_one():
    def learned(rollout):
        return np.ones(rollout.rewards.shape)

    result = train_ppo(lambda: LongCostly(length=64, rate=0.25), 256, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=0.0), cost_fn=learned)
    assert all(h.mean_cost[0] == pytest.approx(64.0) for h in result.history)  # the learned cost
    assert all(h.true_cost == pytest.approx(16.0) for h in result.history)     # the environment's
    silent = train_ppo(lambda: LongCostly(length=64, report=False), 256, PPOConfig(seed=0, **SMALL))
    assert all(math.isnan(h.true_cost) for h in silent.history)


def test_a_cost_reported_only_where_it_is_paid_counts_the_other_steps_as_zero():
    """info["cost"] on every 4th step only: beside a learned cost the steps without it cost 0
    (as they do when info["cost"] trains), not left out of the per-episode estimate."""
    def learned(rollout):
        return np.zeros(rollout.rewards.shape)

    result = train_ppo(lambda: LongCostly(length=64, rate=1.0, every=4), 256, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=0.0), cost_fn=learned)
    assert all(h.true_cost == pytest.approx(16.0) for h in result.history)   # 64 steps / 4, not 64
    trained = train_ppo(lambda: LongCostly(length=64, rate=1.0, every=4), 256, PPOConfig(seed=0, **SMALL),
                        LagrangianConfig(cost_limit=0.0))
    assert all(h.true_cost == pytest.approx(16.0) for h in trained.history)


def test_library_defaults_are_the_cli_defaults():
    lag = LagrangianConfig(cost_limit=0.0)
    assert (lag.update, lag.lr, lag.advantage_scale, lag.cost_estimate) == ("adam", 0.1, "returns", "rollout")
    from symlearn.cli.main import build_parser

    args = build_parser().parse_args(["train", "--env", "toy-navigation"])
    # None: train passes nothing, so LagrangianConfig's own defaults apply
    assert (args.multiplier_update, args.multiplier_lr, args.cost_estimate) == (None, None, lag.cost_estimate)
    config = PPOConfig()
    # one configuration, with a Lagrangian or without (plain PPO had CleanRL's until measured)
    assert (config.resolved().learning_rate, config.resolved().log_std_init) == (1e-3, -1.0)
    assert config.resolved().normalize_observations is True and config.resolved().normalize_values is True
    assert PPOConfig(learning_rate=3e-4).resolved().learning_rate == 3e-4
    assert PPOConfig(normalize_values=False).resolved().normalize_values is False
    old = PPOConfig(**CLEANRL_PLAIN).resolved()
    assert (old.learning_rate, old.log_std_init, old.normalize_observations, old.normalize_values) == (
        2.5e-4, 0.0, False, False)
    constrained = train_ppo(lambda: LongCostly(length=64), 128, PPOConfig(seed=0, **SMALL), lag)
    plain = train_ppo(lambda: LongCostly(length=64), 128, PPOConfig(seed=0, **SMALL))
    assert constrained.config.normalize_observations and constrained.policy.obs_normalization
    assert plain.config.normalize_observations and plain.policy.obs_normalization


@pytest.mark.parametrize("kwargs, message", [
    ({"cost_estimate": "finished"}, "cost_estimate must be one of"),
])
def test_bad_estimate_is_refused(kwargs, message):
    with pytest.raises(SymlearnError, match=message):
        LagrangianConfig(cost_limit=0.0, **kwargs)


def test_bad_normalisation_setting_is_refused():
    with pytest.raises(SymlearnError, match="normalize_values must be True, False or None"):
        PPOConfig(normalize_values="yes")
    with pytest.raises(SymlearnError, match="learning_rate must be a finite number or None"):
        PPOConfig(learning_rate=float("nan"))
    with pytest.raises(SymlearnError, match="log_std_init must be a finite number or None"):
        PPOConfig(log_std_init="-1")


def test_a_continued_policy_keeps_its_observation_normalisation_under_a_lagrangian():
    nominal = train_ppo(lambda: LongCostly(length=64), 128, PPOConfig(seed=0, **SMALL, normalize_observations=False))
    assert not nominal.policy.obs_normalization
    continued = train_ppo(lambda: LongCostly(length=64), 128, PPOConfig(seed=0, **SMALL),
                          LagrangianConfig(cost_limit=0.0), policy=nominal.policy)
    assert continued.policy is nominal.policy and not continued.config.normalize_observations
    assert continued.config.normalize_values  # the rest of the Lagrangian defaults still apply
