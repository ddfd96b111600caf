"""Expert demonstrations for environments without a scripted expert: PPO-Lagrangian on the true cost.

The blocked MuJoCo tasks of thesis section 2.5.2 have no hand-written expert; the benchmarks the
thesis follows downloaded theirs. Here the expert is trained on the spot, from a seed:
PPO-Lagrangian on the environment's ground-truth ``info["cost"]`` with cost limit 0, then
``n_demos`` episodes with its mean action are the demonstrations. Training one takes minutes
(HalfCheetah, 1M steps: ~2 CPU minutes), so the result is cached as an ``.npz`` under a name
derived from everything that determines it (the caller's key -- environment and its arguments
--, steps, seed, number of episodes and all PPO settings); a changed setting is a new file, never
a stale one.

The default settings (:data:`EXPERT_PPO`, :data:`EXPERT_LAGRANGIAN`) are the ones measured on
blocked HalfCheetah: with PPO-Lagrangian's plain defaults (raw-unit advantages, multiplier from
0) the "expert" still ran backward through the wall on 97 % of its steps after 1M steps (the
multiplier never outgrew the ~6.5 reward per step); with advantages in units of returns and the
multiplier starting at 1 it stayed in front of it (violation rate 0.000 on two seeds).
An expert that still violates is returned with a warning naming its violation rate: a cost
learned from it would mark part of the unsafe set as the expert's, i.e. safe.

It is not a learner (it learns no artefact from demonstrations; it makes them), so it lives in
``rl`` beside the PPO it trains, taking the environment as a function, as ``train_ppo`` does:
``recipes.experts`` (the ``trained_expert`` of a registry entry), ``learn icrl`` and the benchmarks
call it. ``symlearn.learners.neural.lagrangian_expert``, its former place, re-exports it.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError

#: PPO settings of the expert (longer rollouts than the point tasks, both normalisations)
EXPERT_PPO: dict[str, Any] = {"n_envs": 4, "n_steps": 512, "batch_size": 256, "n_epochs": 10,
                              "learning_rate": 3e-4, "anneal_lr": False, "normalize_observations": True,
                              "normalize_values": True, "log_std_init": -0.5}
#: PPO-Lagrangian settings of the expert (module docstring)
# the multiplier rule the cached experts were trained with (the library's defaults moved since)
EXPERT_LAGRANGIAN: dict[str, Any] = {"cost_limit": 0.0, "advantage_scale": "returns", "init": 1.0, "update": "adam",
                                     "adam_beta2": 0.999, "lr": 0.035, "cost_estimate": "episodes"}
#: bumped when what is cached changes meaning
CACHE_VERSION = 1
#: an expert violating on more than this share of its steps is reported with a warning
VIOLATION_WARNING = 0.01


def default_cache_dir() -> Path:
    """``$SYMLEARN_CACHE_DIR/experts``, else ``$XDG_CACHE_HOME/symlearn/experts``, else
    ``~/.cache/symlearn/experts``."""
    root = os.environ.get("SYMLEARN_CACHE_DIR")
    if root:
        return Path(root) / "experts"
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "symlearn" / "experts"


def cache_name(key: Mapping[str, Any], *, steps: int, seed: int, n_demos: int, ppo: Mapping[str, Any],
               lagrangian: Mapping[str, Any]) -> str:
    """The cache file's name: a readable prefix and a hash of every setting that shapes the result."""
    recipe = {"version": CACHE_VERSION, "key": dict(key), "steps": int(steps), "seed": int(seed),
              "n_demos": int(n_demos), "ppo": dict(ppo), "lagrangian": dict(lagrangian)}
    digest = hashlib.sha256(json.dumps(recipe, sort_keys=True, default=str).encode()).hexdigest()[:16]
    label = "".join(c if c.isalnum() or c in "-_" else "-" for c in str(key.get("env", "env")))[:40]
    return f"{label}_s{int(seed)}_{int(steps)}_{digest}.npz"


def lagrangian_expert(env_fn: Callable[[], Any], n_demos: int, *, steps: int = 1_000_000, seed: int = 0,
                      ppo: Mapping[str, Any] | None = None, lagrangian: Mapping[str, Any] | None = None,
                      key: Mapping[str, Any] | None = None,
                      cache_dir: str | os.PathLike[str] | None = None) -> tuple[Demonstrations, dict[str, Any]]:
    """``n_demos`` mean-action episodes of a PPO-Lagrangian expert trained for ``steps`` on
    ``env_fn``'s ``info["cost"]``, and a report (reward, violation rate, seconds, cache file).

    ``ppo``/``lagrangian`` override fields of :data:`EXPERT_PPO`/:data:`EXPERT_LAGRANGIAN`.
    With ``key`` (what identifies the environment, e.g. ``{"env": NAME, "kwargs": {...}}``) and
    a ``cache_dir``, the demonstrations are read from / written to the cache (module docstring).
    """
    from symlearn.rl.episode_metrics import episode_metrics
    from symlearn.rl.episodes import sample_episodes
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, train_ppo

    if not isinstance(n_demos, int) or n_demos < 1:
        raise DataError(f"the expert needs at least one episode to record, got n_demos={n_demos!r}")
    if not isinstance(steps, int) or steps < 1:
        raise DataError(f"the expert's PPO steps must be a positive integer, got {steps!r}")
    ppo_settings = {**EXPERT_PPO, **(ppo or {})}
    lagrangian_settings = {**EXPERT_LAGRANGIAN, **(lagrangian or {})}
    path = None
    if key is not None and cache_dir is not None:
        path = Path(cache_dir) / cache_name(key, steps=steps, seed=seed, n_demos=n_demos, ppo=ppo_settings,
                                            lagrangian=lagrangian_settings)
        if path.is_file():
            from symlearn.data import load
            from symlearn.rl.episodes import demonstration_batch

            demos = load(path)
            report = {"cached": str(path), "seconds": 0.0, **episode_metrics(demonstration_batch(demos)).as_dict()}
            _warn_if_unsafe(report)
            return demos, report
    started = time.perf_counter()
    result = train_ppo(env_fn, steps, PPOConfig(**ppo_settings, seed=seed), LagrangianConfig(**lagrangian_settings))
    batch = sample_episodes(result.policy, env_fn, n_demos, seed=seed + 1_000, deterministic=True)
    trajectories = []
    for e in range(batch.n_episodes):
        n = int(batch.mask[e].sum())
        trajectories.append(Trajectory(batch.obs[e, :n], batch.actions[e, :n], batch.rewards[e, :n],
                                       info={"violations": int((batch.costs[e, :n] > 0).sum())}))
    demos = Demonstrations(trajectories, metadata={
        **({"key": dict(key)} if key is not None else {}), "seed": seed,
        "expert": f"PPO-Lagrangian on the true cost, {steps} steps", "lagrangian": lagrangian_settings})
    report = {"cached": None, "seconds": time.perf_counter() - started,
              "multipliers": [float(x) for x in result.multipliers], **episode_metrics(batch).as_dict()}
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        demos.save(path)  # atomic
        report["cached"] = str(path)
    _warn_if_unsafe(report)
    return demos, report


def _warn_if_unsafe(report: Mapping[str, Any]) -> None:
    rate = float(report.get("violation_rate", 0.0))
    if rate > VIOLATION_WARNING:
        warnings.warn(f"the PPO-Lagrangian expert violates the constraint on {rate:.1%} of its steps; a cost "
                      f"learned from its demonstrations will treat part of the unsafe set as safe "
                      f"(train it longer: more expert steps)", RuntimeWarning, stacklevel=3)


__all__ = ["CACHE_VERSION", "EXPERT_LAGRANGIAN", "EXPERT_PPO", "cache_name", "default_cache_dir",
           "lagrangian_expert"]
