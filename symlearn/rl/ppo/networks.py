"""The policy and its critics: :class:`ActorCritic` (torch, what learns and is saved) and
:class:`NumpyActor` (its actor's forward pass in numpy, what samples actions during rollouts).

Two separate MLPs, actor and reward critic (64 x 64 tanh by default), and one cost critic per
constraint; orthogonal initialisation as CleanRL and SB3. Discrete actions: a categorical policy;
``Box`` actions: a Gaussian with a state-independent log standard deviation (the sampled action is
learned from, the one sent to the environment is clipped to the bounds). Observations are encoded
by :mod:`symlearn.rl.spaces` (``Box`` flattened, ``Discrete`` one-hot), then optionally
standardised by running statistics saved with the weights.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.rl.model_files import load_torch_module, save_torch_module
from symlearn.rl.ppo.config import ACTIVATIONS
from symlearn.rl.spaces import SPACE_KINDS, one_hot, space_spec, spec_width

MODEL_KIND = "ppo-actor-critic"
OBS_CLIP = 10.0  # normalised observations are clipped to +-OBS_CLIP (as SB3's VecNormalize)
OBS_EPSILON = 1e-8  # added to the running variance before the square root


def _space_spec(space: Any, role: str) -> dict[str, Any]:
    """A JSON description of a Box or Discrete space (what the networks need to know): the
    :func:`~symlearn.rl.spaces.space_spec` of ``space``, with bounds for an action space, which
    must be 1-D when it is a Box."""
    kind = type(space).__name__
    if kind not in SPACE_KINDS:
        hint = ("flatten dict/tuple spaces with a gymnasium wrapper (e.g. FlattenObservation)" if role == "observation"
                else "wrap the environment so that it acts in a Box or Discrete space (a gymnasium ActionWrapper); "
                     "MultiDiscrete and MultiBinary: symlearn.recipes.action_spaces.JointDiscreteActions")
        raise SymlearnError(f"PPO supports Box and Discrete {role} spaces, got {kind}", hint=hint)
    if role == "action" and kind == "Box" and len(space.shape) != 1:
        raise SymlearnError(f"PPO needs a 1-D Box action space, got shape {space.shape}")
    return space_spec(space, bounds=role == "action")


def _mlp(sizes: Sequence[int], activation: str, out_gain: float, generator: torch.Generator | None) -> nn.Sequential:
    """Linear layers with ``activation`` between them, orthogonal initialisation (gain sqrt(2),
    the last layer ``out_gain``), zero biases: the initialisation of CleanRL and SB3."""
    layers: list[nn.Module] = []
    for i, (n_in, n_out) in enumerate(zip(sizes[:-1], sizes[1:])):
        last = i == len(sizes) - 2
        layer = nn.Linear(n_in, n_out)
        nn.init.orthogonal_(layer.weight, out_gain if last else math.sqrt(2), generator=generator)
        nn.init.zeros_(layer.bias)
        layers.append(layer)
        if not last:
            layers.append(ACTIVATIONS[activation]())
    return nn.Sequential(*layers)


def _actor(obs_dim: int, hidden_sizes: Sequence[int], n_out: int, activation: str,
           generator: torch.Generator | None) -> nn.Sequential:
    """The policy network as a new model has it (last layer's gain 0.01: actions start near-uniform
    / near the mean 0); shared by the constructor and :meth:`ActorCritic.reset_actor`."""
    return _mlp([obs_dim, *hidden_sizes, n_out], activation, 0.01, generator)


class ActorCritic(nn.Module):
    """The policy (``actor``), the reward critic and one cost critic per constraint.

    ``act(observation)`` is the numpy interface for using a trained policy; ``save``/``load``
    write and read ``NAME.safetensors`` + ``NAME.json``.
    """

    def __init__(self, observation: dict[str, Any], action: dict[str, Any], hidden_sizes: Sequence[int] = (64, 64),
                 activation: str = "tanh", n_costs: int = 0, log_std_init: float = 0.0,
                 generator: torch.Generator | None = None, *, obs_normalization: bool = False) -> None:
        super().__init__()
        self.observation_spec, self.action_spec = observation, action
        self.hidden_sizes, self.activation, self.log_std_init = tuple(hidden_sizes), activation, float(log_std_init)
        self.discrete = action["kind"] == "discrete"
        self.obs_dim = spec_width(observation)
        n_out = action["n"] if self.discrete else action["shape"][0]
        sizes = [self.obs_dim, *self.hidden_sizes]
        self.actor = _actor(self.obs_dim, self.hidden_sizes, n_out, activation, generator)
        self.critic = _mlp([*sizes, 1], activation, 1.0, generator)
        self.cost_critics = nn.ModuleList()
        self.add_cost_critics(n_costs, generator)
        if not self.discrete:
            self.log_std = nn.Parameter(torch.full((n_out,), float(log_std_init)))
            low = [-np.inf if x is None else x for x in action["low"]]
            high = [np.inf if x is None else x for x in action["high"]]
            self._low, self._high = np.asarray(low, np.float32), np.asarray(high, np.float32)
            self._centre_actions()
        # running mean and variance of the observation features (saved with the weights)
        self.obs_normalization = bool(obs_normalization)
        if self.obs_normalization:
            self.register_buffer("obs_mean", torch.zeros(self.obs_dim, dtype=torch.float64))
            self.register_buffer("obs_var", torch.ones(self.obs_dim, dtype=torch.float64))
            self.register_buffer("obs_count", torch.zeros(1, dtype=torch.float64))
        self._normalizer: tuple[np.ndarray, np.ndarray] | None = None  # numpy (mean, 1 / std), rebuilt on change

    def _centre_actions(self) -> None:
        """Start the Gaussian's mean inside the action box where 0 is not: a new policy's mean is
        about 0, which for ``Box(0, 10)`` is the lower bound -- half the samples clipped to it and
        the mean barely moved in 4,096 steps (a user's throttle). The last layer's bias starts at
        the centre of such a dimension's finite bounds; boxes around 0 keep it at 0 (unchanged)."""
        off = np.isfinite(self._low) & np.isfinite(self._high) & ((self._low >= 0) | (self._high <= 0))
        if not np.any(off):
            return
        low, high = self._low.astype(np.float64), self._high.astype(np.float64)
        centre = np.where(off, (low + high) / 2, 0.0)
        # and its spread in the box's units (log_std_init is for a half-width of 1, as [-1, 1])
        spread = np.where(off, np.log(np.maximum((high - low) / 2, 1e-6)), 0.0)
        with torch.no_grad():
            self.actor[-1].bias.add_(torch.as_tensor(centre, dtype=self.actor[-1].bias.dtype))
            self.log_std.add_(torch.as_tensor(spread, dtype=self.log_std.dtype))

    @classmethod
    def for_spaces(cls, observation_space: Any, action_space: Any, **kwargs: Any) -> ActorCritic:
        return cls(_space_spec(observation_space, "observation"), _space_spec(action_space, "action"), **kwargs)

    def add_cost_critics(self, n: int, generator: torch.Generator | None = None) -> list[nn.Parameter]:
        """Append ``n`` cost critics (same shape as the reward critic); returns their parameters."""
        new = [_mlp([self.obs_dim, *self.hidden_sizes, 1], self.activation, 1.0, generator) for _ in range(n)]
        self.cost_critics.extend(new)
        return [p for critic in new for p in critic.parameters()]

    @property
    def n_costs(self) -> int:
        return len(self.cost_critics)

    def reset_actor(self, generator: torch.Generator | None = None) -> None:
        """Give the policy a new model's initial weights (and, for Box actions, ``log_std_init``),
        keeping the critics and the observation statistics.

        Continuing a policy that has become nearly deterministic under one reward does not find a
        behaviour several consecutive deviations away when the reward changes: every single
        deviation scores worse, and its entropy only falls further (measured on the gridworld of
        thesis Fig. 2.1: 40k PPO steps on the true cost left a continued policy on the forbidden
        shortest path, a policy with a fresh actor and the old critic took the detour). The
        critics keep their values, which speeds the new actor's first updates."""
        fresh = _actor(self.obs_dim, self.hidden_sizes, self.actor[-1].out_features, self.activation,
                       generator).to(self.actor[-1].weight.device)
        with torch.no_grad():
            self.actor.load_state_dict(fresh.state_dict())
            if not self.discrete:
                self.log_std.fill_(self.log_std_init)
        if not self.discrete:
            self._centre_actions()

    def actor_parameters(self) -> list[nn.Parameter]:
        """The policy's parameters (the actor network and, for Box actions, ``log_std``): what
        :meth:`reset_actor` renews, so an optimiser can forget their moments."""
        return [*self.actor.parameters(), *([] if self.discrete else [self.log_std])]

    # --- observations and actions as arrays --------------------------------------------------------

    def encode(self, observations: Any) -> np.ndarray:
        """A batch of raw observations -> the networks' float32 input ``(B, obs_dim)``: the
        :meth:`features`, standardised when the model normalises observations."""
        return self.normalize(self.features(observations))

    def normalize(self, features: np.ndarray) -> np.ndarray:
        """``(features - mean) / std`` by the running statistics, clipped to +-:data:`OBS_CLIP`
        (the features themselves when the model does not normalise observations)."""
        if not self.obs_normalization:
            return features
        if self._normalizer is None:
            mean = self.obs_mean.detach().cpu().numpy()
            scale = 1.0 / np.sqrt(self.obs_var.detach().cpu().numpy() + OBS_EPSILON)
            self._normalizer = (mean.astype(np.float32), scale.astype(np.float32))
        mean, scale = self._normalizer
        return np.clip((features - mean) * scale, -OBS_CLIP, OBS_CLIP).astype(np.float32, copy=False)

    def update_observation_stats(self, features: np.ndarray) -> None:
        """Fold a batch of :meth:`features` ``(B, obs_dim)`` into the running mean and variance
        (the parallel update of Chan et al., in float64)."""
        x = np.asarray(features, dtype=np.float64).reshape(-1, self.obs_dim)
        if not self.obs_normalization or not len(x):
            return
        count, mean, var = float(self.obs_count[0]), self.obs_mean.cpu().numpy(), self.obs_var.cpu().numpy()
        batch_mean, batch_var, n = x.mean(axis=0), x.var(axis=0), len(x)
        total = count + n
        delta = batch_mean - mean
        new_mean = mean + delta * (n / total)
        new_var = (var * count + batch_var * n + delta**2 * (count * n / total)) / total
        with torch.no_grad():
            self.obs_mean.copy_(torch.from_numpy(new_mean))
            self.obs_var.copy_(torch.from_numpy(new_var))
            self.obs_count.fill_(total)
        self._normalizer = None

    def load_state_dict(self, state_dict: Any, strict: bool = True, assign: bool = False) -> Any:
        self._normalizer = None  # the statistics may change
        return super().load_state_dict(state_dict, strict=strict, assign=assign)

    def features(self, observations: Any) -> np.ndarray:
        """A batch of raw observations -> float32 ``(B, obs_dim)`` (Box: flattened; Discrete: one-hot),
        the encoding of :mod:`symlearn.rl.spaces` without :func:`~symlearn.rl.spaces.encode`'s
        shape and NaN checks: it runs on every environment step, on values the environment made."""
        if self.observation_spec["kind"] == "discrete":
            ids = np.asarray(observations, dtype=np.int64).reshape(-1) - self.observation_spec["start"]
            if ids.size and (ids.min() < 0 or ids.max() >= self.obs_dim):
                raise DataError(f"observation ids {ids.tolist()} outside the space of {self.obs_dim}")
            return one_hot(ids, self.obs_dim)
        return np.asarray(observations, dtype=np.float32).reshape(-1, self.obs_dim)

    def env_action(self, action: np.ndarray) -> Any:
        """One sampled action as the environment takes it (Discrete: an int; Box: clipped)."""
        if self.discrete:
            return int(action) + self.action_spec["start"]
        return np.clip(action, self._low, self._high)

    # --- the torch side ------------------------------------------------------------------------------

    def value(self, obs: torch.Tensor) -> torch.Tensor:
        return self.critic(obs).squeeze(-1)

    def cost_values(self, obs: torch.Tensor) -> torch.Tensor:
        """``(B, n_costs)``."""
        if not self.n_costs:
            return obs.new_zeros((obs.shape[0], 0))
        return torch.cat([critic(obs) for critic in self.cost_critics], dim=-1)

    def log_prob_entropy(self, obs: torch.Tensor, actions: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Log-probability of ``actions`` and the policy's entropy, per row (written out instead of
        ``torch.distributions``, whose argument checks cost more than the arithmetic here)."""
        out = self.actor(obs)
        if self.discrete:
            log_p = torch.log_softmax(out, dim=-1)
            return log_p.gather(-1, actions.long().unsqueeze(-1)).squeeze(-1), -(log_p.exp() * log_p).sum(-1)
        log_std = self.log_std.expand_as(out)
        z = (actions - out) * torch.exp(-log_std)
        log_p = (-0.5 * z.pow(2) - log_std - 0.5 * math.log(2 * math.pi)).sum(-1)
        entropy = (0.5 + 0.5 * math.log(2 * math.pi) + log_std).sum(-1)
        return log_p, entropy

    def numpy_actor(self) -> NumpyActor:
        return NumpyActor(self)

    def act(self, observation: Any, deterministic: bool = False, rng: np.random.Generator | None = None) -> Any:
        """The environment action for one observation, or a list of them for a batch (sampled, or
        the most likely / mean action when ``deterministic``), from the current weights."""
        single = np.shape(observation) == tuple(self.observation_spec.get("shape", ()))
        x = self.encode(observation)
        actor = self.numpy_actor()
        rows = actor.mode(x) if deterministic else actor.sample(x, rng or np.random.default_rng())
        actions = [self.env_action(row) for row in rows]
        return actions[0] if single else actions

    # --- files ---------------------------------------------------------------------------------------

    def model_config(self) -> dict[str, Any]:
        return {"observation": self.observation_spec, "action": self.action_spec,
                "hidden_sizes": list(self.hidden_sizes), "activation": self.activation, "n_costs": self.n_costs,
                "log_std_init": self.log_std_init, "obs_normalization": self.obs_normalization}

    @classmethod
    def from_config(cls, config: dict[str, Any]) -> ActorCritic:
        try:
            return cls(config["observation"], config["action"], config["hidden_sizes"], config["activation"],
                       config["n_costs"], config.get("log_std_init", 0.0),
                       obs_normalization=bool(config.get("obs_normalization", False)))
        except (KeyError, TypeError, IndexError) as exc:
            raise ModelError(f"not a PPO actor-critic configuration ({type(exc).__name__}: {exc})") from None

    def save(self, path: str | os.PathLike[str], extra: dict[str, Any] | None = None) -> os.PathLike[str]:
        """Write ``path`` (``.safetensors``) and the JSON beside it; ``extra`` goes into the JSON."""
        return save_torch_module(path, self, {**self.model_config(), **(extra or {})}, kind=MODEL_KIND)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> ActorCritic:
        module, _ = load_torch_module(path, cls.from_config, kind=MODEL_KIND)
        return module


class NumpyActor:
    """The actor's forward pass in numpy, for sampling actions during rollouts (a snapshot of the
    weights: take a new one after every update)."""

    def __init__(self, agent: ActorCritic) -> None:
        linears = [m for m in agent.actor if isinstance(m, nn.Linear)]
        self.layers = [(m.weight.detach().cpu().numpy().T.copy(), m.bias.detach().cpu().numpy().copy())
                       for m in linears]
        self.activation = np.tanh if agent.activation == "tanh" else (lambda h: np.maximum(h, 0.0))
        self.std = None if agent.discrete else np.exp(agent.log_std.detach().cpu().numpy())

    def forward(self, x: np.ndarray) -> np.ndarray:
        for weight, bias in self.layers[:-1]:
            x = self.activation(x @ weight + bias)
        weight, bias = self.layers[-1]
        return x @ weight + bias

    def sample(self, x: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        out = self.forward(x)
        if self.std is None:  # Gumbel-max: argmax(logits + Gumbel noise) is a categorical sample
            return (out - np.log(-np.log(rng.random(out.shape)))).argmax(axis=1)
        return (out + self.std * rng.standard_normal(out.shape)).astype(np.float32)

    def mode(self, x: np.ndarray) -> np.ndarray:
        out = self.forward(x)
        return out.argmax(axis=1) if self.std is None else out.astype(np.float32)
