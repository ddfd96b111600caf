"""Re-export: the PPO-Lagrangian expert generator moved to :mod:`symlearn.rl.lagrangian_expert` (it
trains an expert and records demonstrations; it learns nothing from them); this name keeps older
imports working."""

from symlearn.rl.lagrangian_expert import (
    CACHE_VERSION,
    EXPERT_LAGRANGIAN,
    EXPERT_PPO,
    VIOLATION_WARNING,
    cache_name,
    default_cache_dir,
    lagrangian_expert,
)

__all__ = ["CACHE_VERSION", "EXPERT_LAGRANGIAN", "EXPERT_PPO", "VIOLATION_WARNING", "cache_name",
           "default_cache_dir", "lagrangian_expert"]
