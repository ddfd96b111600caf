"""The one evaluation loop: a policy plays episodes one after another, and their sums are kept.

:func:`run_episodes` takes any ``act(observation) -> action`` -- our PPO's actor
(:func:`symlearn.rl.ppo.evaluate`), a stable-baselines3 model's ``predict`` (``train --algo
sb3-*``) -- and returns :class:`~symlearn.rl.episode_stats.EpisodeStats`: returns, lengths and the
summed ``info["cost"]``, read by the :class:`~symlearn.rl.episode_stats.CostReader` training reads
it with (``costs`` has no columns when the environment reports none). Episode ``i`` is reset with
``seed + i``, so the same seed and policy give the same numbers whoever calls it.

Other episode loops do other jobs and stay where they are: :func:`symlearn.rl.episodes.sample_episodes`
keeps every step of ``E`` episodes side by side as padded arrays (feature expectations, ICRL's
metrics; one batched policy call per step), :func:`symlearn.data.record` and the scripted experts'
``record_episode`` store trajectories with labels as demonstrations, the ``dnf``/``safenav`` demos
(``demo/continuous_common.episodes``) keep the routes they draw, and DQRM's greedy evaluation
steps a reward machine beside the environment.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from symlearn.rl.episode_stats import CostReader, EpisodeStats, FinishedEpisode, episode_stats

#: the longest an evaluated episode may run when the environment has no time limit of its own
MAX_EPISODE_STEPS = 100_000


def run_episodes(env: Any, act: Callable[[Any], Any], n_episodes: int = 10, *, seed: int | None = None,
                 max_steps: int = MAX_EPISODE_STEPS) -> EpisodeStats:
    """Play ``n_episodes`` on ``env`` with ``act``, one after another; episode ``i`` is reset with
    ``seed + i`` (unseeded when ``seed`` is None) and ends when it terminates, is truncated or
    reaches ``max_steps``. ``end_steps`` count the steps of all episodes so far."""
    reader = CostReader(None)
    rows: list[FinishedEpisode] = []
    step = 0
    for episode in range(n_episodes):
        observation, _ = env.reset(seed=None if seed is None else seed + episode)
        total, length, cost_sum = 0.0, 0, np.zeros(0)
        for _ in range(max_steps):
            observation, reward, terminated, truncated, info = env.step(act(observation))
            total, length, step = total + float(reward), length + 1, step + 1
            cost = reader.read(info, where=lambda: f"evaluation episode {episode}, step {length - 1}")
            if cost is not None:
                cost_sum = cost if cost_sum.size == 0 else cost_sum + cost
            if terminated or truncated:
                break
        rows.append(FinishedEpisode(total, length, cost_sum, step))
    return episode_stats(rows, reader.n or 0)


__all__ = ["MAX_EPISODE_STEPS", "run_episodes"]
