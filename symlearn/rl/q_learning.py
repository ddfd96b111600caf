"""Tabular Q-learning with an optional action mask and epsilon-greedy exploration.

Works on any gymnasium environment with discrete observations and actions. When the
environment reports ``info["action_mask"]`` (a 0/1 vector over actions, the convention of
:class:`symlearn.backends.shield.Shield` and of other libraries that read action masks), both
exploration and the greedy choice are limited to the allowed actions, and bootstrapping uses
the best *allowed* action of the next state. Costs reported in ``info["cost"]`` are summed per
episode (and, with ``cost_weight``, subtracted from the reward the agent learns from).

>>> from symlearn.envs.gridworld import make_gridworld
>>> result = q_learning(make_gridworld(0.0), n_episodes=300, learning_rate=0.5, discount=0.95, seed=0)
>>> int(result.returns[-20:].mean()), bool(result.violations[-20:].mean() > 0)  # straight through the block
(-4, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import SymlearnError
from symlearn.rl.episode_stats import summed_cost


@dataclass(frozen=True)
class QLearningResult:
    q_values: np.ndarray  # (S, A)
    returns: np.ndarray  # per episode, the environment's reward
    lengths: np.ndarray  # steps per episode
    costs: np.ndarray  # per episode, the sum of info["cost"] (0 when not reported)
    violations: np.ndarray  # per episode, steps with info["violation"] true

    def greedy_policy(self, mask: np.ndarray | None = None) -> np.ndarray:
        q = self.q_values if mask is None else np.where(np.asarray(mask, bool), self.q_values, -np.inf)
        return q.argmax(axis=1)


def _mask(info: dict[str, Any], n_actions: int) -> np.ndarray:
    raw = info.get("action_mask")
    if raw is None:
        return np.ones(n_actions, dtype=bool)
    mask = np.asarray(raw).astype(bool)
    if mask.shape != (n_actions,):
        raise SymlearnError(f"info['action_mask'] must have {n_actions} entries, got shape {mask.shape}")
    return mask if mask.any() else np.ones(n_actions, dtype=bool)  # a dead end: nothing to choose from


def _greedy(q_row: np.ndarray, mask: np.ndarray, rng: np.random.Generator) -> int:
    values = np.where(mask, q_row, -np.inf)
    best = np.flatnonzero(values == values.max())
    return int(rng.choice(best))  # random tie-breaking, so an untrained agent does not stick to action 0


def q_learning(
    env: Any,
    n_episodes: int,
    *,
    learning_rate: float = 0.9,
    discount: float = 0.75,
    epsilon: float = 0.05,
    seed: int | None = None,
    max_steps: int | None = None,
    use_action_mask: bool = True,
    cost_weight: float = 0.0,
    q_init: float = 0.0,
) -> QLearningResult:
    """Train for ``n_episodes`` (episode ``i`` is reset with a seed drawn from ``seed``)."""
    if n_episodes < 1:
        raise SymlearnError(f"n_episodes must be at least 1, got {n_episodes}")
    if not (0 < learning_rate <= 1 and 0 <= discount <= 1 and 0 <= epsilon <= 1):
        raise SymlearnError("need 0 < learning_rate <= 1, 0 <= discount <= 1 and 0 <= epsilon <= 1")
    try:
        S, A = int(env.observation_space.n), int(env.action_space.n)
    except AttributeError:
        raise SymlearnError("tabular Q-learning needs Discrete observation and action spaces") from None
    rng = np.random.default_rng(seed)
    episode_seeds = np.random.SeedSequence(seed).generate_state(n_episodes).tolist()
    limit = max_steps or getattr(getattr(env, "spec", None), "max_episode_steps", None) or 10_000
    q = np.full((S, A), float(q_init))
    returns, lengths, costs, violations = (np.zeros(n_episodes) for _ in range(4))
    for episode, episode_seed in enumerate(episode_seeds):
        state, info = env.reset(seed=int(episode_seed))
        mask = _mask(info, A) if use_action_mask else np.ones(A, bool)
        for step in range(limit):
            s = int(state)
            if rng.random() < epsilon:
                action = int(rng.choice(np.flatnonzero(mask)))
            else:
                action = _greedy(q[s], mask, rng)
            state, reward, terminated, truncated, info = env.step(action)
            cost = summed_cost(info, where=lambda: f"episode {episode}, step {step}") or 0.0
            returns[episode] += reward
            costs[episode] += cost
            violations[episode] += bool(info.get("violation", False))
            mask = _mask(info, A) if use_action_mask else np.ones(A, bool)
            target = reward - cost_weight * cost
            if not terminated:
                target += discount * np.max(np.where(mask, q[int(state)], -np.inf))
            q[s, action] += learning_rate * (target - q[s, action])
            if terminated or truncated:
                break
        lengths[episode] = step + 1
    return QLearningResult(q, returns, lengths, costs, violations)
