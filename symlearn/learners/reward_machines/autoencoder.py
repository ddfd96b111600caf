"""Learned and random convolutional features of frames (torch, CPU; no downloaded weights).

* :class:`AutoencoderFeatures`: a small convolutional autoencoder trained on the demonstration
  frames themselves (three stride-2 convolutions down to a ``latent``-sized code, a mirrored
  decoder, mean squared reconstruction error, Adam); the code is the feature vector. Saved as
  safetensors + JSON through :mod:`symlearn.rl.model_files`.
* :class:`RandomCNNFeatures`: the same encoder with random weights and no training, pooled to a
  4 x 4 grid: the stand-in for "a network you have on disk" in tests and the baseline that shows
  what training (or PCA) adds.

Inputs are pooled and lighting-normalised like the PCA features (average pooling to about 16
pixels a side, each channel divided by its mean), so the three extractors differ only in the map
from pixels to vectors. ``torch.set_num_threads(1)`` while
working (measured faster on the 2-core machines this runs on).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, ModelError
from symlearn.learners.reward_machines.features import as_frames, pool_factor, pooled
from symlearn.progress import progress


def _inputs(frames: np.ndarray, pool: int):
    import torch

    x = pooled(as_frames(frames), pool)
    x = x / np.maximum(x.mean(axis=(1, 2), keepdims=True), 1e-3) / 3.0
    return torch.from_numpy(np.ascontiguousarray(x.transpose(0, 3, 1, 2), dtype=np.float32))


def _encoder(channels: int, latent: int | None):
    from torch import nn

    layers = [nn.Conv2d(channels, 8, 4, 2, 1), nn.ReLU(), nn.Conv2d(8, 16, 4, 2, 1), nn.ReLU(),
              nn.Conv2d(16, 32, 4, 2, 1), nn.ReLU(), nn.AdaptiveAvgPool2d(4), nn.Flatten()]
    if latent is not None:
        layers.append(nn.Linear(32 * 16, latent))
    return nn.Sequential(*layers)


class _Autoencoder:
    """Encoder + decoder for ``size x size`` frames (size divisible by 8)."""

    @staticmethod
    def build(config: dict[str, Any]):
        from torch import nn

        size, channels, latent = int(config["size"]), int(config["channels"]), int(config["latent"])
        side = size // 8
        decoder = nn.Sequential(
            nn.Linear(latent, 32 * side * side), nn.ReLU(), nn.Unflatten(1, (32, side, side)),
            nn.ConvTranspose2d(32, 16, 4, 2, 1), nn.ReLU(), nn.ConvTranspose2d(16, 8, 4, 2, 1), nn.ReLU(),
            nn.ConvTranspose2d(8, channels, 4, 2, 1))
        return nn.ModuleDict({"encoder": _encoder(channels, latent), "decoder": decoder})


class AutoencoderFeatures:
    """Codes of a convolutional autoencoder trained on the frames (see the module docstring)."""

    kind = "autoencoder"

    def __init__(self, latent: int = 16, epochs: int = 40, batch_size: int = 32, learning_rate: float = 3e-3,
                 random_state: int = 0) -> None:
        self.latent = latent
        self.epochs = epochs
        self.batch_size = batch_size
        self.learning_rate = learning_rate
        self.random_state = random_state

    def fit(self, frames: np.ndarray) -> AutoencoderFeatures:
        import torch

        frames = as_frames(frames)
        pool = pool_factor(frames.shape)
        n, h, w, c = pooled(frames[:1], pool).shape
        n = len(frames)
        if h != w or h % 8:
            raise DataError(f"the autoencoder needs square frames whose side, pooled by {pool}, is divisible by 8; "
                            f"got {frames.shape[1]} x {frames.shape[2]} (pooled {h} x {w})",
                            hint="crop or resize the frames (e.g. to 64 x 64), or use PCA features")
        threads = torch.get_num_threads()
        torch.set_num_threads(1)
        try:
            torch.manual_seed(self.random_state)
            self.config_ = {"size": h, "channels": c, "latent": int(self.latent), "pool": pool}
            model = _Autoencoder.build(self.config_)
            x = _inputs(frames, pool)
            optimiser = torch.optim.Adam(model.parameters(), lr=self.learning_rate)
            generator = torch.Generator().manual_seed(self.random_state)
            self.losses_ = []
            for _ in progress(range(self.epochs), total=self.epochs, desc="autoencoder"):
                order = torch.randperm(n, generator=generator)
                total = 0.0
                for start in range(0, n, self.batch_size):
                    batch = x[order[start:start + self.batch_size]]
                    loss = torch.mean((model["decoder"](model["encoder"](batch)) - batch) ** 2)
                    optimiser.zero_grad()
                    loss.backward()
                    optimiser.step()
                    total += float(loss.detach()) * len(batch)
                self.losses_.append(total / n)
            self.model_ = model.eval()
        finally:
            torch.set_num_threads(threads)
        return self

    def transform(self, frames: np.ndarray) -> np.ndarray:
        import torch

        if "model_" not in self.__dict__:
            raise ModelError("AutoencoderFeatures is not fitted")
        x = _inputs(frames, int(self.config_["pool"]))
        if tuple(x.shape[1:]) != (self.config_["channels"], self.config_["size"], self.config_["size"]):
            raise DataError(f"frames of shape {tuple(x.shape[2:])} x {x.shape[1]} channels do not match the "
                            f"autoencoder's {self.config_['size']} x {self.config_['size']} x {self.config_['channels']}")
        with torch.no_grad():
            return self.model_["encoder"](x).numpy().astype(np.float64)

    def config(self) -> dict[str, Any]:
        return {"kind": self.kind, **getattr(self, "config_", {"latent": self.latent})}

    def save(self, path: str | os.PathLike[str]) -> list[Path]:
        from symlearn.rl.model_files import model_paths, save_torch_module

        save_torch_module(path, self.model_, self.config_, kind="symlearn-autoencoder")
        return list(model_paths(path))

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> AutoencoderFeatures:
        from symlearn.rl.model_files import load_torch_module

        model, config = load_torch_module(path, _Autoencoder.build, kind="symlearn-autoencoder")
        features = cls(latent=int(config["latent"]))
        features.model_, features.config_ = model.eval(), dict(config)
        return features


class RandomCNNFeatures:
    """A randomly initialised convolutional encoder (no training), pooled to 4 x 4 x 32 values."""

    kind = "random-cnn"

    def __init__(self, random_state: int = 0) -> None:
        self.random_state = random_state

    def fit(self, frames: np.ndarray) -> RandomCNNFeatures:
        import torch

        torch.manual_seed(self.random_state)
        first = as_frames(frames[:1])
        self.pool_ = pool_factor(first.shape)
        self.model_ = _encoder(first.shape[-1], None).eval()
        return self

    def transform(self, frames: np.ndarray) -> np.ndarray:
        import torch

        threads = torch.get_num_threads()
        torch.set_num_threads(1)
        try:
            with torch.no_grad():
                return self.model_(_inputs(frames, self.pool_)).numpy().astype(np.float64)
        finally:
            torch.set_num_threads(threads)

    def config(self) -> dict[str, Any]:
        return {"kind": self.kind, "random_state": self.random_state}


__all__ = ["AutoencoderFeatures", "RandomCNNFeatures"]
