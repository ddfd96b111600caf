"""What every neural ICRL learner does before it learns: the environment, its spaces, the
demonstrations checked against them, the observation entries the cost reads, a seeded generator.

MCE-ICRL, ME-ICRL, VME-ICRL and GACL differ in their updates, not in how they read their inputs;
one function keeps those checks (and their error messages) the same for all four.

**Which observation entries the cost reads** (``obs_dims``, :func:`cost_inputs`): a list of
indices as given; ``"all"`` every entry; ``None`` (the default) the entries the environment
declares its constraints to be about -- its ``feature_names`` (the names of ``info["features"]``,
what the DNF learners read: docs/FORMATS.md), where every one of them names an entry of its
``observation_names`` --, else every entry. Why a default that reads the environment's
declaration rather than one found in the data: a cost reading the whole observation is free to
separate expert from policy by whatever differs most, and on BlockedPoint that is the velocity
(the expert never moves toward the wall, so "never move toward the wall" explains the
demonstrations at least as well as the wall does: ``vx`` alone tells expert from nominal states
with a held-out AUC of 0.9996, ``x`` alone with 0.993, and the input selection of
:mod:`~symlearn.learners.neural.input_selection` keeps ``vx``; measured in docs/BENCHMARKS.md,
"Neural ICRL: the cost's inputs"). No criterion on the demonstrations alone tells the two apart;
the environment's declaration of what its constraints read does, and the DNF learners already
rely on it. The selection then picks among the candidates.
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
from symlearn.learners.neural.feature_network import INPUTS
from symlearn.learners.neural.neural_cost import encode, space_spec, spec_width
from symlearn.rl.episodes import EpisodeBatch, demonstration_batch


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
    inputs_from: str = "given"  # where obs_dims came from: "given", "declared features" or "all"
    source: str | None = None   # the demonstrations' metadata["source"], one line (None: they do not say)

    def provenance(self, learner: Any, parameters: dict[str, Any]) -> dict[str, Any]:
        """What the learned cost's file says of its origin: the learner, its parameters and,
        where the demonstrations say where they came from, ``demonstrations`` (their
        ``metadata["source"]``, as the DNF file's header names it)."""
        return {"learner": type(learner).__name__, "parameters": parameters,
                **({"demonstrations": self.source} if self.source else {})}


def fit_setup(demonstrations: Any, domain: Any, obs_dims: Sequence[int] | None,
              random_state: int | None) -> FitSetup:
    env_fn = environment_factory(domain)
    probe = env_fn()
    obs_spec, act_spec = space_spec(probe.observation_space), space_spec(probe.action_space, bounds=True)
    expert = demonstration_batch(demonstrations)
    expert_obs, expert_act = expert.pairs()
    expert_x = encode(expert_obs, obs_spec, "demonstration observations")  # shape and NaN checks
    expert_a = encode(expert_act, act_spec, "demonstration actions")
    dims, inputs_from = cost_inputs(probe, obs_dims, spec_width(obs_spec))
    generator = torch.Generator().manual_seed(0 if random_state is None else int(random_state))
    return FitSetup(env_fn, probe, obs_spec, act_spec, expert, expert_x, expert_a, dims, generator, inputs_from,
                    demonstrations_source(demonstrations))


def demonstrations_source(demonstrations: Any) -> str | None:
    """The demonstrations' ``metadata["source"]`` (set by ``recipes.experts.demonstrations``: the
    ``--demos`` file, the expert it ran) on one line, or None where they carry none."""
    metadata = getattr(demonstrations, "metadata", None)
    source = metadata.get("source") if isinstance(metadata, dict) else None
    source = " ".join(source.split()) if isinstance(source, str) else ""
    return source or None


def declared_inputs(env: Any) -> list[int] | None:
    """The observation entries an environment declares its constraints to read: the indices of
    its ``feature_names`` in its ``observation_names`` (both attributes of the unwrapped
    environment), or None when it lacks either or a feature is no observation entry."""
    unwrapped = getattr(env, "unwrapped", env)
    features, names = getattr(unwrapped, "feature_names", None), getattr(unwrapped, "observation_names", None)
    if not features or not names:
        return None
    # a lone string is one name (iterating "xy" would give the names "x" and "y")
    features = [features] if isinstance(features, str) else features
    names = [names] if isinstance(names, str) else names
    names = [str(n) for n in names]
    if any(str(f) not in names for f in features):
        return None
    return [names.index(str(f)) for f in features]


def cost_inputs(env: Any, obs_dims: Sequence[int] | str | None, width: int) -> tuple[list[int], str]:
    """The observation entries a cost reads and where they came from (module docstring):
    ``(indices, "given" | "declared features" | "all")``."""
    if isinstance(obs_dims, str):
        if obs_dims != "all":
            raise SymlearnError(f"obs_dims must be a list of indices, 'all' or None, got {obs_dims!r}")
        return list(range(width)), "all"
    if obs_dims is None:
        declared = declared_inputs(env)
        if declared is not None and all(0 <= i < width for i in declared):
            return declared, "declared features"
        return list(range(width)), "all"
    dims = [int(i) for i in obs_dims]
    if not dims or min(dims) < 0 or max(dims) >= width:
        raise SymlearnError(f"obs_dims {dims} outside the observation's {width} entries")
    return dims, "given"


def check_common(learner: Any, integers: Sequence[str], *, zero_allowed: Sequence[str] = (),
                 beta_hint: str | None = None) -> None:
    """The checks every neural learner makes of its parameters: ``beta`` a finite number >= 0
    (> 0 when ``beta_hint`` is given: MCE-ICRL needs some entropy), ``features`` one of
    :data:`~symlearn.learners.neural.feature_network.INPUTS`, the named counts positive integers
    (``zero_allowed`` ones may be 0), ``reset_actor`` one of :data:`RESET_ACTOR`, ``select_inputs``
    a tolerance in ``[0, 0.5]``."""
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
    if not check_tolerance(learner.select_inputs):
        raise SymlearnError(f"select_inputs must be a number in [0, 0.5] (0 = every candidate entry), got "
                            f"{learner.select_inputs!r}")


def check_tolerance(value: Any) -> bool:
    """Whether ``select_inputs`` is a finite number in ``[0, 0.5]`` (0: selection off; an AUC
    gain above 0.5 is impossible)."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
            and 0 <= value <= 0.5)


#: when the policy phases start from a fresh actor (NeuralMCEICRL's docstring says why)
RESET_ACTOR = ("never", "every", "last", "auto")


def resets_actor(setting: str, iteration: int, n_iterations: int) -> bool:
    """Whether iteration ``iteration`` (1-based) of ``n_iterations`` starts its policy phase from
    a fresh actor under the ``reset_actor`` setting."""
    return setting == "every" or (setting == "last" and iteration == n_iterations)


__all__ = ["RESET_ACTOR", "FitSetup", "check_common", "check_tolerance", "cost_inputs", "declared_inputs",
           "demonstrations_source", "environment_factory", "fit_setup",
           "resets_actor"]
