"""Running a trained policy: :func:`evaluate` plays episodes one after another and reports them as
:class:`~symlearn.rl.ppo.records.EpisodeStats`, costs read from ``info["cost"]`` as in training."""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.rl.ppo.networks import ActorCritic
from symlearn.rl.ppo.records import EpisodeStats
from symlearn.rl.ppo.rollouts import FinishedEpisode, _CostReader, episode_stats


def evaluate(policy: ActorCritic, env: Any, n_episodes: int = 10, *, seed: int | None = None,
             deterministic: bool = True, max_steps: int = 100_000) -> EpisodeStats:
    """Run ``n_episodes`` with ``policy`` (the mean/most likely action when ``deterministic``);
    episode ``i`` is reset with ``seed + i``. Costs are read from ``info["cost"]`` as in training."""
    rng = np.random.default_rng(seed)
    reader = _CostReader(None)
    rows: list[FinishedEpisode] = []
    step = 0
    actor = policy.numpy_actor()
    for episode in range(n_episodes):
        o, _ = env.reset(seed=None if seed is None else seed + episode)
        total, length, cost_sum = 0.0, 0, np.zeros(0)
        for _ in range(max_steps):
            x = policy.encode(np.asarray(o)[None])
            row = actor.mode(x)[0] if deterministic else actor.sample(x, rng)[0]
            o, r, term, trunc, info = env.step(policy.env_action(row))
            total, length, step = total + float(r), length + 1, step + 1
            cost = reader.read(info, 0, step)
            if cost is not None:
                cost_sum = cost if cost_sum.size == 0 else cost_sum + cost
            if term or trunc:
                break
        rows.append(FinishedEpisode(total, length, cost_sum, step))
    return episode_stats(rows, reader.n or 0)
