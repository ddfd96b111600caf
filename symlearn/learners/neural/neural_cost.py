"""A learned cost ``C(s, a) = lambda . phi_zeta(s, a)``: callable on arrays, saved without pickle.

:class:`NeuralCost` holds the feature network (:mod:`~symlearn.learners.neural.feature_network`),
the multipliers ``lambda`` and a description of the observation (and action) space it was
learned for. ``cost(obs, actions)`` evaluates a whole batch in one torch forward pass.
What an agent is given is built in :mod:`symlearn.backends.neural_cost` (beside the DNF cost's
forms): :meth:`NeuralCost.reward_fn` and :meth:`NeuralCost.cost_fn` return its per-rollout
callables for :func:`symlearn.rl.ppo.train_ppo` (``r - C`` to learn from, or ``C`` as the cost of
PPO-Lagrangian when a learned cost trains a fresh agent), :meth:`NeuralCost.step_cost` its
per-step form for stable-baselines3.

Files: ``NAME.safetensors`` (the network's weights and standardisation, and ``lambda``) and
``NAME.json`` (kind ``neural-icrl-cost``: the network's shape, the spaces, the observation entry
names when the environment has them, provenance: the learner, its parameters and, where the
demonstrations said, their ``metadata["source"]`` -- :attr:`NeuralCost.learned_from` --, and
``expert_cost``, what the final cost charges the demonstrations per episode -- the budget
:attr:`NeuralCost.expert_level` an agent trained on the cost is held to by default) through
:mod:`symlearn.rl.model_files`; loading
reads numbers and JSON only. :meth:`NeuralCost.check_environment` refuses an environment whose
observation space (kind, shape; entry names where both sides have them) or action space differs
from the one the cost was learned in.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.errors import DataError, ModelError
from symlearn.learners.neural.feature_network import FeatureNetwork
from symlearn.rl.model_files import load_torch_module, save_torch_module
from symlearn.rl.spaces import SPACE_KINDS, encode, spec_width
from symlearn.rl.spaces import space_spec as rl_space_spec

MODEL_KIND = "neural-icrl-cost"


def space_spec(space: Any, bounds: bool = False) -> dict[str, Any]:
    """What a cost needs to know of a gymnasium Box or Discrete space, as JSON: the encoding of
    :mod:`symlearn.rl.spaces` (the one PPO's networks use), any other kind of space refused."""
    if type(space).__name__ not in SPACE_KINDS:
        # FlattenObservation is no way out: it one-hot encodes Discrete parts, while record() stores
        # them as one column each, so the demonstrations would no longer fit the space
        raise DataError(f"a learned cost needs Box or Discrete spaces, got {type(space).__name__}",
                        hint="`symlearn learn icrl --env` reads such spaces as they are; in Python, build the "
                             "environment as symlearn.recipes.spaces.numeric_observations(env) (observations) and "
                             "symlearn.recipes.action_spaces.joint_discrete_actions(...) (MultiDiscrete/MultiBinary "
                             "actions), and record the demonstrations in that view")
    return rl_space_spec(space, bounds)


class NeuralCost(nn.Module):
    """``lambda . phi(s, a)`` for one observation/action space (see the module docstring)."""

    def __init__(self, phi: FeatureNetwork, observation: dict[str, Any], action: dict[str, Any],
                 observation_names: list[str] | None = None, provenance: dict[str, Any] | None = None) -> None:
        super().__init__()
        self.phi = phi
        self.observation_spec, self.action_spec = dict(observation), dict(action)
        self.observation_names = None if observation_names is None else [str(n) for n in observation_names]
        self.provenance = dict(provenance or {})
        self.register_buffer("lambdas", torch.zeros(phi.n_features, dtype=torch.float64))
        if self.observation_names is not None and len(self.observation_names) != spec_width(self.observation_spec):
            raise ModelError(f"{len(self.observation_names)} observation names for an observation of width "
                             f"{spec_width(self.observation_spec)}")
        if max(phi.obs_dims) >= spec_width(self.observation_spec) or min(phi.obs_dims) < 0:
            raise ModelError(f"the feature network reads observation entries {list(phi.obs_dims)}, but the "
                             f"observation has {spec_width(self.observation_spec)}")
        if phi.action_dim not in (0, spec_width(self.action_spec)):
            raise ModelError(f"the feature network reads actions of width {phi.action_dim}, the action space's "
                             f"is {spec_width(self.action_spec)}")

    @classmethod
    def for_env(cls, env: Any, phi: FeatureNetwork, **kwargs: Any) -> NeuralCost:
        names = getattr(getattr(env, "unwrapped", env), "observation_names", None)
        return cls(phi, space_spec(env.observation_space), space_spec(env.action_space, bounds=True),
                   None if names is None else list(names), **kwargs)

    @property
    def learned_from(self) -> str | None:
        """Where the demonstrations this cost was learned from came from (their
        ``metadata["source"]``, kept in the provenance as ``demonstrations``); None where they did
        not say, and in files written before it was recorded."""
        source = self.provenance.get("demonstrations")
        return source if isinstance(source, str) and source else None

    @property
    def expert_level(self) -> float | None:
        """The mean per-episode sum of this cost over the demonstrations it was learned from
        (undiscounted, the units of a PPO-Lagrangian ``cost_limit``), recorded in the provenance
        as ``expert_cost``; None in files written before it was recorded.

        Why a budget needs it: the cost is a sigmoid network's output times ``lambda``, so every
        state costs something and a limit of 0 is out of reach for every policy, the expert's
        included. The thesis' hard constraint is the least cost a policy can reach (budget
        ``c_min``, ch. 2), and the constraint its learner matched is the expert's feature
        expectation (eq. 2.2): the expert's level is the budget that both reads mean and that a
        policy is known to reach."""
        record = self.provenance.get("expert_cost")
        if record is None:
            return None
        level = record.get("mean") if isinstance(record, dict) else None
        if isinstance(level, bool) or not isinstance(level, (int, float)) or not np.isfinite(level) or level < 0:
            raise ModelError(f"provenance.expert_cost.mean must be a finite number >= 0, got {level!r}")
        return float(level)

    def record_expert_level(self, expert: Any) -> dict[str, Any]:
        """Store (and return) what this cost charges ``expert`` -- an
        :class:`~symlearn.rl.episodes.EpisodeBatch` of the demonstrations -- per episode:
        ``mean``, ``min``, ``max``, ``episodes``, ``mean_length`` (see :attr:`expert_level`)."""
        obs, actions = expert.pairs()
        per_step = self(obs, actions if self.uses_actions else None)
        lengths = expert.mask.sum(axis=1).astype(int)
        sums = np.array([part.sum() for part in np.split(per_step, np.cumsum(lengths)[:-1])]) if len(lengths) \
            else np.zeros(0)
        record = {"mean": float(sums.mean()) if len(sums) else 0.0,
                  "min": float(sums.min()) if len(sums) else 0.0,
                  "max": float(sums.max()) if len(sums) else 0.0,
                  "episodes": int(len(sums)), "mean_length": float(lengths.mean()) if len(lengths) else 0.0}
        self.provenance["expert_cost"] = record
        return record

    # --- evaluation -------------------------------------------------------------------------------

    @property
    def uses_actions(self) -> bool:
        return self.phi.action_dim > 0

    def set_lambdas(self, values: np.ndarray) -> None:
        with torch.no_grad():
            self.lambdas.copy_(torch.as_tensor(np.asarray(values, dtype=np.float64)))

    def tensors(self, obs: Any, actions: Any = None) -> tuple[torch.Tensor, torch.Tensor | None]:
        """Checked float32 tensors ``(B, obs_width)``, ``(B, action_width)`` (or None) of a batch."""
        x = torch.from_numpy(encode(obs, self.observation_spec, "observations"))
        if not self.uses_actions:
            return x, None
        if actions is None:
            raise DataError("this cost reads actions too (state_action features), but no actions were given")
        a = torch.from_numpy(encode(actions, self.action_spec, "actions"))
        if len(a) != len(x):
            raise DataError(f"{len(x)} observations but {len(a)} actions")
        return x, a

    def features(self, obs: Any, actions: Any = None) -> np.ndarray:
        """``phi`` of a batch, ``(B, k)``."""
        x, a = self.tensors(obs, actions)
        with torch.no_grad():
            return self.phi(x, a).double().numpy()

    def __call__(self, obs: Any, actions: Any = None) -> np.ndarray:  # type: ignore[override]
        """The cost ``lambda . phi`` of a batch, ``(B,)`` (one forward pass)."""
        return self.features(obs, actions) @ self.lambdas.numpy()

    # the agent-facing forms live in backends/neural_cost.py (beside the DNF cost's); these delegate,
    # importing it when asked: the backends package loads clingo and gymnasium, a cost needs neither

    def cost_of_rollout(self, rollout: Any) -> np.ndarray:
        """``[T, N]`` costs of a :class:`~symlearn.rl.ppo.Rollout` (its ``obs`` and ``actions``)."""
        from symlearn.backends.neural_cost import NeuralRolloutCost

        return NeuralRolloutCost(self)(rollout)

    def reward_fn(self) -> Any:
        """``rollout -> rewards - cost`` for ``train_ppo(reward_fn=...)``
        (:class:`~symlearn.backends.neural_cost.NeuralRolloutReward`)."""
        from symlearn.backends.neural_cost import NeuralRolloutReward

        return NeuralRolloutReward(self)

    def cost_fn(self) -> Any:
        """``rollout -> cost`` for ``train_ppo(cost_fn=...)`` (a learned cost under PPO-Lagrangian;
        :class:`~symlearn.backends.neural_cost.NeuralRolloutCost`)."""
        from symlearn.backends.neural_cost import NeuralRolloutCost

        return NeuralRolloutCost(self)

    def step_cost(self) -> Any:
        """``(observation, action, next_observation, info) -> (1,)`` for
        :class:`~symlearn.backends.lagrangian.StepCostWrapper` (stable-baselines3 learners;
        :class:`~symlearn.backends.neural_cost.NeuralStepCost`)."""
        from symlearn.backends.neural_cost import NeuralStepCost

        return NeuralStepCost(self)

    # --- compatibility -----------------------------------------------------------------------------

    def check_environment(self, env: Any, *, source: str | os.PathLike[str] | None = None) -> None:
        """Refuse an environment whose spaces differ from the ones this cost was learned in."""
        observation = space_spec(env.observation_space)  # the action space only matters to a cost reading actions
        where = {"file": None if source is None else str(source)}
        if observation != self.observation_spec:
            raise ModelError(f"this cost was learned for observations {_describe(self.observation_spec)}, "
                             f"the environment's are {_describe(observation)}", **where,
                             hint="a learned cost only applies to the observation space it was trained on")
        names = getattr(getattr(env, "unwrapped", env), "observation_names", None)
        if names is not None and self.observation_names is not None and list(names) != self.observation_names:
            raise ModelError(f"this cost reads observation entries {self.observation_names}, the environment's "
                             f"are {list(names)}", **where)
        if not self.uses_actions:
            return
        action = space_spec(env.action_space, bounds=True)
        if _shape_of(action) != _shape_of(self.action_spec):
            raise ModelError(f"this cost was learned for actions {_describe(self.action_spec)}, the environment's "
                             f"are {_describe(action)}", **where)

    # --- files -------------------------------------------------------------------------------------

    def model_config(self) -> dict[str, Any]:
        return {"phi": self.phi.config(), "observation": self.observation_spec, "action": self.action_spec,
                "observation_names": self.observation_names, "provenance": self.provenance}

    @classmethod
    def from_config(cls, config: dict[str, Any]) -> NeuralCost:
        try:
            phi = FeatureNetwork.from_config(config["phi"])
            return cls(phi, _checked_spec(config["observation"]), _checked_spec(config["action"]),
                       config.get("observation_names"), config.get("provenance"))
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise ModelError(f"not a learned-cost configuration ({type(exc).__name__}: {exc})") from None

    def save(self, path: str | os.PathLike[str]) -> os.PathLike[str]:
        """Write ``path`` (``.safetensors``) and the JSON configuration beside it, atomically."""
        return save_torch_module(path, self, self.model_config(), kind=MODEL_KIND)

    @classmethod
    def load(cls, path: str | os.PathLike[str], env: Any = None) -> NeuralCost:
        """Read a saved cost (numbers and JSON only); with ``env``, check it fits its spaces."""
        cost, _ = load_torch_module(path, cls.from_config, kind=MODEL_KIND)
        cost.eval()
        if not torch.isfinite(cost.lambdas).all() or (cost.lambdas < 0).any():
            raise ModelError("the multipliers must be finite and >= 0", file=str(path))
        # the tensors must agree with the configuration they were saved with, and be numbers
        if cost.phi.obs_index.tolist() != list(cost.phi.obs_dims):
            raise ModelError(f"phi.obs_index {cost.phi.obs_index.tolist()} contradicts the configuration's obs_dims "
                             f"{list(cost.phi.obs_dims)}", file=str(path),
                             hint="the .json and .safetensors files must come from the same save")
        bad = [name for name, tensor in cost.state_dict().items()
               if tensor.is_floating_point() and not torch.isfinite(tensor).all()]
        if bad or (cost.phi.input_scale <= 0).any():
            raise ModelError(f"the tensor {bad[0] if bad else 'phi.input_scale'} holds "
                             f"{'NaN or infinite' if bad else 'non-positive'} values", file=str(path))
        try:
            cost.expert_level  # a malformed record is refused here, not when an agent is trained
        except ModelError as exc:
            raise ModelError(exc.message, file=str(path)) from None
        if env is not None:
            cost.check_environment(env, source=path)
        return cost


def _checked_spec(spec: Any) -> dict[str, Any]:
    if not isinstance(spec, dict) or spec.get("kind") not in ("box", "discrete"):
        raise ValueError(f"a space must be a box or discrete description, got {spec!r}")
    if spec["kind"] == "box":
        shape = spec.get("shape")
        if not isinstance(shape, list) or not shape or not all(isinstance(n, int) and n >= 1 for n in shape):
            raise ValueError(f"box shape must be a list of positive integers, got {shape!r}")
        out: dict[str, Any] = {"kind": "box", "shape": shape}
        for side in ("low", "high"):
            if side in spec:
                values = spec[side]
                if not isinstance(values, list) or len(values) != int(np.prod(shape)) or not all(
                        v is None or (isinstance(v, (int, float)) and np.isfinite(v)) for v in values):
                    raise ValueError(f"box {side} must be a list of numbers or nulls, one per entry")
                out[side] = values
        return out
    if not isinstance(spec.get("n"), int) or spec["n"] < 1 or not isinstance(spec.get("start", 0), int):
        raise ValueError(f"discrete n must be a positive integer, got {spec.get('n')!r}")
    return {"kind": "discrete", "n": spec["n"], "start": spec.get("start", 0)}


def _shape_of(spec: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in spec.items() if k not in ("low", "high")}


def _describe(spec: dict[str, Any]) -> str:
    return f"Discrete({spec['n']})" if spec["kind"] == "discrete" else f"Box{tuple(spec['shape'])}"


__all__ = ["MODEL_KIND", "NeuralCost", "encode", "space_spec", "spec_width"]
