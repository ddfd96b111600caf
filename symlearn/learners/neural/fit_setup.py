"""What every neural ICRL learner does before it learns: the environment, its spaces, the
demonstrations checked against them, the observation entries the cost reads, a seeded generator.

MCE-ICRL, ME-ICRL, VME-ICRL and GACL differ in their updates, not in how they read their inputs;
one function keeps those checks (and their error messages) the same for all four.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from symlearn.errors import DataError, SymlearnError
from symlearn.learners.neural.episodes import EpisodeBatch, demonstration_batch
from symlearn.learners.neural.feature_network import INPUTS
from symlearn.learners.neural.neural_cost import encode, space_spec, spec_width


def environment_factory(env: Any) -> Callable[[], Any]:
    """A function returning a fresh environment, from such a function, a gymnasium id, or an
    environment (deep-copied)."""
    if isinstance(env, str):
        import gymnasium

        return lambda: gymnasium.make(env)
    if isinstance(env, type):  # an environment class: its constructor makes fresh ones
        return env
    if hasattr(env, "reset") and hasattr(env, "step"):
        template = copy.deepcopy(env)
        return lambda: copy.deepcopy(template)
    if callable(env):
        return env
    raise DataError(f"need an environment, a function returning one, or a gymnasium id; got {env!r}")


@dataclass
class FitSetup:
    """The inputs of one fit, checked: ``probe`` is one environment (spaces, cost construction)."""

    env_fn: Callable[[], Any]
    probe: Any
    obs_spec: dict[str, Any]
    act_spec: dict[str, Any]
    expert: EpisodeBatch
    expert_x: np.ndarray      # the demonstrations' observations, encoded (shape and NaN checked)
    expert_a: np.ndarray      # and their actions
    obs_dims: list[int]       # the observation entries the cost reads
    generator: torch.Generator


def fit_setup(demonstrations: Any, domain: Any, obs_dims: Sequence[int] | None,
              random_state: int | None) -> FitSetup:
    env_fn = environment_factory(domain)
    probe = env_fn()
    obs_spec, act_spec = space_spec(probe.observation_space), space_spec(probe.action_space, bounds=True)
    expert = demonstration_batch(demonstrations)
    expert_obs, expert_act = expert.pairs()
    expert_x = encode(expert_obs, obs_spec, "demonstration observations")  # shape and NaN checks
    expert_a = encode(expert_act, act_spec, "demonstration actions")
    width = spec_width(obs_spec)
    dims = list(range(width)) if obs_dims is None else [int(i) for i in obs_dims]
    if not dims or min(dims) < 0 or max(dims) >= width:
        raise SymlearnError(f"obs_dims {dims} outside the observation's {width} entries")
    generator = torch.Generator().manual_seed(0 if random_state is None else int(random_state))
    return FitSetup(env_fn, probe, obs_spec, act_spec, expert, expert_x, expert_a, dims, generator)


def check_common(learner: Any, integers: Sequence[str], *, zero_allowed: Sequence[str] = (),
                 beta_hint: str | None = None) -> None:
    """The checks every neural learner makes of its parameters: ``beta`` a finite number >= 0
    (> 0 when ``beta_hint`` is given: MCE-ICRL needs some entropy), ``features`` one of
    :data:`~symlearn.learners.neural.feature_network.INPUTS`, the named counts positive integers
    (``zero_allowed`` ones may be 0), ``reset_actor`` one of :data:`RESET_ACTOR`."""
    beta = learner.beta
    positive = beta_hint is not None
    if not (isinstance(beta, (int, float)) and math.isfinite(beta) and (beta > 0 if positive else beta >= 0)):
        raise SymlearnError(f"beta must be a number {'>' if positive else '>='} 0, got {beta!r}", hint=beta_hint)
    if learner.features not in INPUTS:
        raise SymlearnError(f"unknown features {learner.features!r}", hint=f"use one of {list(INPUTS)}")
    for name in integers:
        value = getattr(learner, name)
        if not isinstance(value, (int, np.integer)) or value < (0 if name in zero_allowed else 1):
            raise SymlearnError(f"{name} must be a positive integer, got {value!r}")
    if learner.reset_actor not in RESET_ACTOR:
        raise SymlearnError(f"reset_actor must be one of {list(RESET_ACTOR)}, got {learner.reset_actor!r}")


#: when the policy phases start from a fresh actor (NeuralMCEICRL's docstring says why)
RESET_ACTOR = ("never", "every", "last")


def resets_actor(setting: str, iteration: int, n_iterations: int) -> bool:
    """Whether iteration ``iteration`` (1-based) of ``n_iterations`` starts its policy phase from
    a fresh actor under the ``reset_actor`` setting."""
    return setting == "every" or (setting == "last" and iteration == n_iterations)


__all__ = ["RESET_ACTOR", "FitSetup", "check_common", "environment_factory", "fit_setup", "resets_actor"]
