"""train_ppo's rollout hooks: reward_fn / cost_fn see whole rollouts, policy= continues training,
and a DNF cost computed per rollout equals the per-step cost wrapper's."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

from symlearn.backends.dnf_cost import DnfCostWrapper, DnfRolloutCost, RuleStats
from symlearn.errors import DataError, SymlearnError
from symlearn.logic.dnf import parse
from symlearn.rl.ppo import LagrangianConfig, PPOConfig, Rollout, evaluate, train_ppo

SMALL = dict(n_envs=2, n_steps=64, batch_size=64, n_epochs=2)


class Line(gym.Env):
    """x in [0, 1], actions move it by -0.1 / +0.1; reward 1 for moving right; 20-step episodes;
    info carries the position as a feature and the time step."""

    observation_space = spaces.Box(0.0, 1.0, (1,), dtype=np.float64)
    action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.5, 0
        return np.array([self.x]), {"features": [self.x]}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.1 if action else -0.1), 0.0, 1.0))
        self.t += 1
        # features as an array on odd steps, a list on even ones: both recording paths are taken
        features = np.array([self.x]) if self.t % 2 else [self.x]
        info = {"features": features, "t": self.t, "cost": float(self.x > 0.75)}
        return np.array([self.x]), float(action), False, self.t >= 20, info


def test_rollout_fields_and_next_obs_before_reset():
    seen: list[Rollout] = []

    def cost_fn(rollout):
        seen.append(rollout)
        return np.zeros(rollout.rewards.shape)

    cost_fn.info_keys = ("t", "features")
    train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL), cost_fn=cost_fn)
    r = seen[0]
    T, N = 64, 2
    assert r.obs.shape == r.next_obs.shape == (T, N, 1) and r.actions.shape == (T, N)
    assert r.info["t"].shape == (T, N) and r.info["features"].shape == (T, N, 1)
    # next_obs is the state the step reached, also where the episode ended (t = 20)
    assert np.allclose(r.next_obs[..., 0], r.info["features"][..., 0])
    ends = r.dones == 1
    assert ends.sum() == 6 and np.all(r.info["t"][ends] == 20)   # 64 steps: ends at t = 19, 39, 59
    # where no episode ended, the next step starts where this one went
    assert np.allclose(r.obs[1:][~ends[:-1]], r.next_obs[:-1][~ends[:-1]])
    assert np.all(r.obs[20, :, 0] == 0.5)                         # after a reset: the first state


def test_cost_fn_replaces_info_cost_and_drives_the_multiplier():
    # the environment charges x > 0.75; cost_fn charges 2 on every step where x < 0.45 (vector of 2)
    def left(rollout):
        low = (rollout.next_obs[..., 0] < 0.45).astype(float)
        return np.stack([2 * low, np.zeros_like(low)], axis=2)

    result = train_ppo(lambda: Line(), 1024, PPOConfig(seed=0, **SMALL),
                       LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.1, init=0.0), cost_fn=left)
    assert result.policy.n_costs == 2 and result.episodes.costs.shape == (len(result.episodes), 2)
    costs = result.episodes.costs
    assert np.all(costs[:, 0] % 2 == 0) and costs[:, 0].max() > 0 and np.all(costs[:, 1] == 0)
    assert result.history[-1].multipliers[0] > 0 and result.history[-1].multipliers[1] == 0


def test_reward_fn_is_learned_from_but_returns_stay_the_environments():
    def go_left(rollout):  # reward moving left instead
        return 1.0 - rollout.rewards

    result = train_ppo(lambda: Line(), 6000, PPOConfig(seed=0, **SMALL, learning_rate=1e-3), reward_fn=go_left)
    greedy = evaluate(result.policy, Line(), 2, seed=0)
    assert greedy.returns.max() <= 2      # environment return: it now (almost) never moves right
    assert result.episodes.returns[:5].mean() > 5    # a random start went right about half the time


def test_policy_continues_training_in_place():
    first = train_ppo(lambda: Line(), 512, PPOConfig(seed=0, **SMALL))
    weights = [p.detach().clone() for p in first.policy.parameters()]
    second = train_ppo(lambda: Line(), 512, PPOConfig(seed=1, **SMALL), policy=first.policy)
    assert second.policy is first.policy
    assert any(not np.allclose(a, b.detach()) for a, b in zip(weights, second.policy.parameters()))


def test_continuing_with_normalised_values_keeps_the_critic_in_returns():
    config = PPOConfig(seed=0, **SMALL, normalize_values=True)
    first = train_ppo(lambda: Line(), 4096, config)
    obs = np.array([[0.5]], dtype=np.float32)
    import torch
    before = float(first.policy.value(torch.as_tensor(obs)).detach())
    second = train_ppo(lambda: Line(), 128, config, policy=first.policy)
    after = float(second.policy.value(torch.as_tensor(obs)).detach())
    assert before > 1 and abs(after - before) < 0.5 * abs(before)   # one short iteration moves it little


def test_hook_errors():
    with pytest.raises(DataError, match="shape"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL), cost_fn=lambda r: np.zeros(3))
    with pytest.raises(DataError, match="NaN"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL),
                  reward_fn=lambda r: np.full(r.rewards.shape, np.nan))
    with pytest.raises(DataError, match="expected"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL),
                  reward_fn=lambda r: np.zeros((*r.rewards.shape, 2)))

    def needs_missing(rollout):
        return np.zeros(rollout.rewards.shape)

    needs_missing.info_keys = ("nowhere",)
    with pytest.raises(DataError, match="nowhere"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL), cost_fn=needs_missing)
    with pytest.raises(SymlearnError, match="callable"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL), cost_fn=3)
    other = train_ppo("CartPole-v1", 128, PPOConfig(seed=0, **SMALL, normalize_observations=False))
    with pytest.raises(SymlearnError, match="other spaces"):
        train_ppo(lambda: Line(), 128, PPOConfig(seed=0, **SMALL), policy=other.policy)
    with pytest.raises(SymlearnError, match="normalisation"):
        train_ppo("CartPole-v1", 128, PPOConfig(seed=0, **SMALL, normalize_observations=True), policy=other.policy)
    counts = iter([1, 2])
    with pytest.raises(DataError, match="cost"):
        train_ppo(lambda: Line(), 256, PPOConfig(seed=0, **SMALL), LagrangianConfig(cost_limit=0.0),
                  cost_fn=lambda r: np.zeros((*r.rewards.shape, next(counts))))


@pytest.mark.parametrize("per_rule", [False, True])
def test_rollout_dnf_cost_equals_the_wrapper(per_rule):
    """Same trajectory, same formula: the per-rollout cost and rule counts equal the wrapper's."""
    dnf = parse("x > 0.75\nx < 0.25 & x > 0.05\nx <= 0.05\n")
    rng = np.random.default_rng(0)
    stats_step = RuleStats(dnf, ["x"])
    env = DnfCostWrapper(Line(), dnf, ["x"], per_rule=per_rule, stats=stats_step)
    env.reset(seed=0)
    feats, costs = [], []
    for _ in range(200):
        _, _, _, trunc, info = env.step(int(rng.integers(2)))
        feats.append(info["features"])
        costs.append(info["cost"])
        if trunc:
            env.reset()
    batch = DnfRolloutCost(dnf, ["x"], per_rule=per_rule)
    X = np.asarray(feats, dtype=np.float64).reshape(100, 2, 1)
    rollout = Rollout(obs=X.astype(np.float32), actions=np.zeros((100, 2)), next_obs=X.astype(np.float32),
                      rewards=np.zeros((100, 2)), dones=np.zeros((100, 2)), info={"features": X})
    out = batch(rollout)
    assert out.shape == ((100, 2, 3) if per_rule else (100, 2))
    assert np.array_equal(out.reshape(200, -1).squeeze(), np.asarray(costs, dtype=float).reshape(200, -1).squeeze())
    assert np.array_equal(batch.stats.evaluated, stats_step.evaluated)
    assert np.array_equal(batch.stats.fired, stats_step.fired)
    assert stats_step.fired.sum() > 0 and batch.info_keys == ("features",)


def test_rollout_dnf_cost_in_training_and_errors():
    dnf = parse("x > 0.75\n")
    cost = DnfRolloutCost(dnf, ["x"])
    result = train_ppo(lambda: Line(), 1024, PPOConfig(seed=0, **SMALL), LagrangianConfig(cost_limit=0.0),
                       cost_fn=cost)
    assert cost.stats.evaluated.sum() == 1024 and result.policy.n_costs == 1
    assert np.isclose(result.episodes.costs.sum(), cost.stats.fired.sum() - 0, atol=cost.stats.fired.sum())
    with pytest.raises(DataError, match="does not provide"):
        DnfRolloutCost(parse("y > 1\n"), ["x"])
    with pytest.raises(SymlearnError, match="source"):
        DnfRolloutCost(dnf, ["x"], source="elsewhere")
    bad = Rollout(obs=np.zeros((2, 1, 1), np.float32), actions=np.zeros((2, 1)), next_obs=np.zeros((2, 1, 1), np.float32),
                  rewards=np.zeros((2, 1)), dones=np.zeros((2, 1)), info={"features": np.full((2, 1, 1), np.nan)})
    with pytest.raises(DataError, match="finite"):
        cost(bad)
    wide = Rollout(obs=np.zeros((2, 1, 1), np.float32), actions=np.zeros((2, 1)), next_obs=np.zeros((2, 1, 1), np.float32),
                   rewards=np.zeros((2, 1)), dones=np.zeros((2, 1)), info={"features": np.zeros((2, 1, 3))})
    with pytest.raises(DataError, match="expected 1 features"):
        cost(wide)
