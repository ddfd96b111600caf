"""The feature network ``phi_zeta(s, a)`` of neural MCE-ICRL and its autoencoder pre-training.

``phi`` is a plain MLP (thesis section 2.7.5): ReLU hidden layers and a sigmoid output, so every
feature lies in ``(0, 1)`` (costs ``lambda . phi`` are then non-negative for ``lambda >= 0``). Its
input is a chosen subset of the observation's entries (``obs_dims``; all by default), followed by
the action when the features are ``"state_action"``. The input is standardised by a mean and
scale fixed when the network is built from data (buffers, saved with the weights), so the
network's first layer meets numbers near 0 whatever the units of the observation.

:func:`pretrain_autoencoder` trains ``phi`` as the encoder of an autoencoder (a mirror-image MLP
decoder, MSE reconstruction of the standardised input) on nominal and expert pairs, as the thesis
does before the first ICRL iteration (section 2.4.3.2): the features then start out describing
where the data lie, rather than as random projections.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.errors import DataError, ModelError

INPUTS = ("state", "state_action")
SCALE_FLOOR = 1e-6  # an input that never varies is divided by 1 instead of by ~0


class FeatureNetwork(nn.Module):
    """``phi``: ``(B, n_in) -> (B, n_features)`` in ``(0, 1)``.

    ``obs_dims``: the observation entries it reads (indices into the flattened observation),
    ``action_dim``: the width of the action it also reads (0 for state features).
    """

    def __init__(self, obs_dims: Sequence[int], action_dim: int, n_features: int,
                 hidden_sizes: Sequence[int] = (64, 64), generator: torch.Generator | None = None) -> None:
        super().__init__()
        # counts from a configuration file must be whole numbers: int() would read 64.5 as 64
        values = [*obs_dims, action_dim, n_features, *hidden_sizes]
        if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool)
                   or isinstance(v, float) and v.is_integer() for v in values):
            raise ModelError(f"a feature network's sizes and inputs must be whole numbers, got obs_dims "
                             f"{list(obs_dims)!r}, action_dim {action_dim!r}, n_features {n_features!r}, "
                             f"hidden_sizes {list(hidden_sizes)!r}")
        self.obs_dims = tuple(int(i) for i in obs_dims)
        self.action_dim = int(action_dim)
        self.n_features = int(n_features)
        self.hidden_sizes = tuple(int(h) for h in hidden_sizes)
        if not self.obs_dims or self.n_features < 1 or any(h < 1 for h in self.hidden_sizes):
            raise ModelError("a feature network needs at least one input, one feature and positive layer widths")
        n_in = len(self.obs_dims) + self.action_dim
        self.register_buffer("input_mean", torch.zeros(n_in))
        self.register_buffer("input_scale", torch.ones(n_in))
        self.register_buffer("obs_index", torch.tensor(self.obs_dims, dtype=torch.int64))
        self.body = _mlp([n_in, *self.hidden_sizes, self.n_features], generator)

    @property
    def n_inputs(self) -> int:
        return len(self.obs_dims) + self.action_dim

    def inputs(self, obs: torch.Tensor, actions: torch.Tensor | None) -> torch.Tensor:
        """The standardised network input of a batch ``(B, obs_dim)`` of flattened observations
        (and ``(B, action_dim)`` actions: continuous ones as they are, discrete ones one-hot)."""
        x = obs.index_select(-1, self.obs_index)
        if self.action_dim:
            if actions is None:
                raise DataError("these features read the action too (state_action), but no actions were given")
            x = torch.cat([x, actions.to(x.dtype).reshape(x.shape[0], -1)], -1)
        return (x - self.input_mean) / self.input_scale

    def forward(self, obs: torch.Tensor, actions: torch.Tensor | None = None) -> torch.Tensor:
        return torch.sigmoid(self.body(self.inputs(obs, actions)))

    def fit_standardisation(self, obs: np.ndarray, actions: np.ndarray | None) -> None:
        """Fix the input's mean and scale from data (before any training)."""
        with torch.no_grad():
            x = self.inputs(torch.as_tensor(obs, dtype=torch.float32),
                            None if actions is None else torch.as_tensor(actions, dtype=torch.float32))
            x = x * self.input_scale + self.input_mean  # back to raw units
            self.input_mean.copy_(x.mean(0))
            self.input_scale.copy_(x.std(0).clamp_min(SCALE_FLOOR) if len(x) > 1 else torch.ones(x.shape[1]))

    def config(self) -> dict[str, Any]:
        return {"obs_dims": list(self.obs_dims), "action_dim": self.action_dim, "n_features": self.n_features,
                "hidden_sizes": list(self.hidden_sizes)}

    @classmethod
    def from_config(cls, config: dict[str, Any]) -> FeatureNetwork:
        try:
            return cls(config["obs_dims"], config["action_dim"], config["n_features"], config["hidden_sizes"])
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(f"not a feature-network configuration ({type(exc).__name__}: {exc})") from None


def _mlp(sizes: Sequence[int], generator: torch.Generator | None) -> nn.Sequential:
    """Linear layers with ReLU between them (no activation after the last: the sigmoid is applied
    in :meth:`FeatureNetwork.forward`); Kaiming-uniform weights as torch's default, drawn from
    ``generator`` so a seed fixes them."""
    layers: list[nn.Module] = []
    for i, (n_in, n_out) in enumerate(zip(sizes[:-1], sizes[1:])):
        layer = nn.Linear(n_in, n_out)
        bound = 1.0 / math.sqrt(n_in)
        with torch.no_grad():
            layer.weight.uniform_(-bound, bound, generator=generator)
            layer.bias.uniform_(-bound, bound, generator=generator)
        layers.append(layer)
        if i < len(sizes) - 2:
            layers.append(nn.ReLU())
    return nn.Sequential(*layers)


@dataclass(frozen=True)
class PretrainRecord:
    """What autoencoder pre-training did: epochs, reconstruction MSE before and after, seconds."""

    epochs: int
    samples: int
    mse_before: float
    mse_after: float
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        return {"epochs": self.epochs, "samples": self.samples, "mse_before": self.mse_before,
                "mse_after": self.mse_after, "seconds": self.seconds}


def pretrain_autoencoder(phi: FeatureNetwork, obs: np.ndarray, actions: np.ndarray | None, *, epochs: int = 50,
                         batch_size: int = 256, learning_rate: float = 1e-3,
                         generator: torch.Generator | None = None) -> PretrainRecord:
    """Train ``phi`` (in place) as the encoder of an autoencoder on the rows ``obs``/``actions``.

    The decoder mirrors the encoder (``n_features -> reversed hidden sizes -> n_inputs``, ReLU
    hidden layers, linear output) and is thrown away afterwards. The loss is the mean squared
    error between the standardised input and its reconstruction; Adam, shuffled minibatches.
    """
    import time

    started = time.perf_counter()
    obs_t = torch.as_tensor(obs, dtype=torch.float32)
    act_t = None if actions is None else torch.as_tensor(actions, dtype=torch.float32)
    with torch.no_grad():
        target = phi.inputs(obs_t, act_t)
    decoder = _mlp([phi.n_features, *reversed(phi.hidden_sizes), phi.n_inputs], generator)
    params = list(phi.parameters()) + list(decoder.parameters())
    optimizer = torch.optim.Adam(params, lr=learning_rate)

    def mse() -> float:
        with torch.no_grad():
            return float((decoder(phi(obs_t, act_t)) - target).pow(2).mean())

    before = mse()
    n = len(target)
    for _ in range(epochs):
        order = torch.randperm(n, generator=generator)
        for start in range(0, n, batch_size):
            idx = order[start:start + batch_size]
            loss = (decoder(phi(obs_t[idx], None if act_t is None else act_t[idx])) - target[idx]).pow(2).mean()
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            optimizer.step()
    return PretrainRecord(epochs, n, before, mse(), time.perf_counter() - started)


__all__ = ["INPUTS", "FeatureNetwork", "PretrainRecord", "pretrain_autoencoder"]
