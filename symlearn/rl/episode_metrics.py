"""What a policy's episodes score: reward, violation rate and feasible reward.

* **reward**: mean episode return (the environment's reward).
* **violation rate**: per episode the fraction of its steps whose ``info["cost"]`` is positive
  (the thesis' "fraction of all timesteps of a trajectory that violate at least one constraint",
  section 2.5), averaged over episodes.
* **feasible reward**: per episode the reward collected before the first violating step (that
  step's own reward excluded; the whole return when nothing was violated), averaged.

Computed on an :class:`~symlearn.rl.episodes.EpisodeBatch`: the ICRL learners report them for
their sampled policies, the PPO-Lagrangian expert for itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError
from symlearn.rl.episodes import EpisodeBatch


@dataclass(frozen=True)
class EpisodeMetrics:
    reward: float
    violation_rate: float
    feasible_reward: float
    episodes: int

    def as_dict(self) -> dict[str, Any]:
        return {"reward": self.reward, "violation_rate": self.violation_rate,
                "feasible_reward": self.feasible_reward, "episodes": self.episodes}


def episode_metrics(batch: EpisodeBatch) -> EpisodeMetrics:
    """Reward, violation rate and feasible reward of a batch of episodes (module docstring)."""
    mask = batch.mask
    lengths = mask.sum(axis=1)
    if not len(lengths) or lengths.min() == 0:
        raise DataError("metrics need at least one episode, each with at least one step")
    rewards = np.where(mask, batch.rewards, 0.0)
    violating = mask & (batch.costs > 0)
    # reward before the first violation: steps strictly before the first violating one
    first = np.where(violating.any(axis=1), violating.argmax(axis=1), lengths)
    before = np.arange(mask.shape[1])[None, :] < first[:, None]
    return EpisodeMetrics(reward=float(rewards.sum(axis=1).mean()),
                          violation_rate=float((violating.sum(axis=1) / lengths).mean()),
                          feasible_reward=float(np.where(before, rewards, 0.0).sum(axis=1).mean()),
                          episodes=int(len(lengths)))


__all__ = ["EpisodeMetrics", "episode_metrics"]
