"""What training reports: one :class:`PPOIteration` per iteration, the finished episodes
(:class:`~symlearn.rl.episode_stats.EpisodeStats`, named here too) and the run as a whole (:class:`PPOResult`, which saves the policy with the
run's settings); ``as_dict()`` gives JSON-able values (NaN as null)."""

from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass, field, fields
from typing import Any

import numpy as np

from symlearn.rl.episode_stats import EpisodeStats
from symlearn.rl.episode_stats import plain as _plain
from symlearn.rl.ppo.config import LagrangianConfig, PPOConfig
from symlearn.rl.ppo.networks import ActorCritic


@dataclass(frozen=True)
class PPOIteration:
    """One iteration: rollout statistics (episodes that *ended* in it; NaN when none did), the
    multipliers used for its update, and the update's diagnostics (means over its minibatches)."""

    iteration: int
    steps: int  # environment steps so far (over all copies)
    episodes: int
    mean_return: float
    mean_length: float
    mean_cost: tuple[float, ...]  # per constraint
    multipliers: tuple[float, ...]
    policy_loss: float
    value_loss: float
    cost_value_loss: tuple[float, ...]
    entropy: float
    approx_kl: float
    clip_fraction: float
    explained_variance: float
    epochs: float  # passes actually made (fractional when stopped by target_kl)
    stopped_early: bool
    learning_rate: float
    steps_per_second: float
    seconds: float
    # running standard deviation of the returns of the reward, then of each cost (PPO-Lagrangian;
    # the divisors of the advantages under ``advantage_scale="returns"``)
    return_scales: tuple[float, ...] = ()
    # J_c per constraint the multipliers were updated from in this iteration (empty: no update)
    cost_estimate: tuple[float, ...] = ()
    # the environment's own info["cost"] per episode, summed over constraints (rollout cost per step
    # x mean episode length), also when a learned cost drives training; NaN when it reports none
    true_cost: float = math.nan
    # the actor was given fresh weights before this iteration's update (LagrangianConfig.reset_actor)
    actor_reset: bool = False
    # ... and the actor it replaced was put back (the fresh one did worse by the Lagrangian)
    actor_restored: bool = False

    def as_dict(self) -> dict[str, Any]:
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}


@dataclass
class PPOResult:
    """What :func:`~symlearn.rl.ppo.train_ppo` returns; ``save(path)`` writes the policy with this run's settings."""

    policy: ActorCritic
    config: PPOConfig
    lagrangian: LagrangianConfig | None
    history: list[PPOIteration]
    episodes: EpisodeStats
    multipliers: np.ndarray  # final values, (n_constraints,) (empty for plain PPO)
    steps: int
    seconds: float
    provenance: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | os.PathLike[str]) -> os.PathLike[str]:
        lagrangian = None if self.lagrangian is None else asdict(self.lagrangian)
        training = {"ppo": asdict(self.config), "lagrangian": lagrangian,
                    "steps": self.steps, "seconds": self.seconds, "multipliers": _plain(self.multipliers),
                    **self.provenance}
        return self.policy.save(path, {"training": _plain(training)})
