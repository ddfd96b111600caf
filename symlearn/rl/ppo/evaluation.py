"""Running a trained policy: :func:`evaluate` plays episodes one after another with the actor's mean
(or sampled) action, through the one evaluation loop :func:`symlearn.rl.evaluation.run_episodes`,
and reports them as :class:`~symlearn.rl.episode_stats.EpisodeStats`, costs read from
``info["cost"]`` as in training."""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.rl.episode_stats import EpisodeStats
from symlearn.rl.evaluation import MAX_EPISODE_STEPS, run_episodes
from symlearn.rl.ppo.networks import ActorCritic


def evaluate(policy: ActorCritic, env: Any, n_episodes: int = 10, *, seed: int | None = None,
             deterministic: bool = True, max_steps: int = MAX_EPISODE_STEPS) -> EpisodeStats:
    """Run ``n_episodes`` with ``policy`` (the mean/most likely action when ``deterministic``);
    episode ``i`` is reset with ``seed + i``. Costs are read from ``info["cost"]`` as in training."""
    rng = np.random.default_rng(seed)   # one generator for all episodes: sampled actions follow from the seed
    actor = policy.numpy_actor()

    def act(observation: Any) -> Any:
        x = policy.encode(np.asarray(observation)[None])
        row = actor.mode(x)[0] if deterministic else actor.sample(x, rng)[0]
        return policy.env_action(row)

    return run_episodes(env, act, n_episodes, seed=seed, max_steps=max_steps)
