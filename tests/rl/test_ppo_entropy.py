"""PPO's two entropy objectives and ActorCritic.reset_actor."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
from gymnasium import spaces

from symlearn.errors import SymlearnError
from symlearn.rl.ppo import ActorCritic, PPOConfig, train_ppo


class Bandit(gym.Env):
    """One step per episode, three actions paid ``REWARDS``; the observation is constant."""

    REWARDS = np.array([0.0, 0.5, 1.0])
    observation_space = spaces.Box(0.0, 1.0, (1,), dtype=np.float32)
    action_space = spaces.Discrete(3)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return np.zeros(1, np.float32), {}

    def step(self, action):
        return np.zeros(1, np.float32), float(self.REWARDS[int(action)]), True, False, {}


def action_probabilities(policy: ActorCritic) -> np.ndarray:
    with torch.no_grad():
        return torch.softmax(policy.actor(torch.zeros(1, 1)), -1)[0].numpy()


def test_entropy_in_the_reward_converges_to_the_soft_optimum():
    """With -beta log pi(a) in the reward, the fixed point of the policy gradient is the
    maximum-entropy policy pi(a) ~ exp(r(a) / beta), a temperature in reward units; the usual
    bonus (same coefficient) drives the policy to the best arm instead."""
    beta = 0.5
    # large rollouts and an annealed step: the sampled gradient is noisy around the fixed point
    settings = dict(n_envs=8, n_steps=128, batch_size=256, n_epochs=4, learning_rate=2e-3, ent_coef=beta, seed=0)
    soft = train_ppo(Bandit, 24_000, PPOConfig(**settings, entropy_mode="reward")).policy
    target = np.exp(Bandit.REWARDS / beta) / np.exp(Bandit.REWARDS / beta).sum()  # [0.09, 0.24, 0.67]
    np.testing.assert_allclose(action_probabilities(soft), target, atol=0.03)
    bonus = train_ppo(Bandit, 24_000, PPOConfig(**settings)).policy
    assert action_probabilities(bonus)[2] > 0.9


def test_unknown_entropy_mode_is_refused():
    with pytest.raises(SymlearnError, match="entropy_mode must be one of"):
        PPOConfig(entropy_mode="soft")


@pytest.mark.parametrize("space", [spaces.Discrete(3), spaces.Box(-1.0, 1.0, (2,), dtype=np.float32)])
def test_reset_actor_gives_a_fresh_policy_and_keeps_the_critic(space):
    obs_space = spaces.Box(-1.0, 1.0, (4,), dtype=np.float32)
    model = ActorCritic.for_spaces(obs_space, space, log_std_init=-0.5, generator=torch.Generator().manual_seed(0),
                                   obs_normalization=True)
    fresh = ActorCritic.for_spaces(obs_space, space, log_std_init=-0.5, generator=torch.Generator().manual_seed(1),
                                   obs_normalization=True)
    with torch.no_grad():  # a "trained" model: every weight moved, the statistics filled
        for p in model.parameters():
            p.add_(1.0)
    model.update_observation_stats(np.random.default_rng(0).normal(3.0, 2.0, (100, 4)))
    critic = {k: v.clone() for k, v in model.critic.state_dict().items()}
    stats = model.obs_mean.clone()
    model.reset_actor(torch.Generator().manual_seed(1))
    for key, value in model.actor.state_dict().items():  # the same initial weights as a new model's
        assert torch.equal(value, fresh.actor.state_dict()[key]), key
    for key, value in model.critic.state_dict().items():
        assert torch.equal(value, critic[key]), key
    assert torch.equal(model.obs_mean, stats)
    if not model.discrete:
        assert torch.equal(model.log_std.detach(), torch.full((2,), -0.5))
