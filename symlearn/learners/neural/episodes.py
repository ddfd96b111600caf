"""Re-export: episodes as padded arrays moved to :mod:`symlearn.rl.episodes` (the PPO-Lagrangian
expert in ``rl`` samples them too); this name keeps older imports working."""

from symlearn.rl.episodes import EpisodeBatch, Policy, demonstration_batch, policy_actions, sample_episodes

__all__ = ["EpisodeBatch", "Policy", "demonstration_batch", "policy_actions", "sample_episodes"]
