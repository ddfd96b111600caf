"""Visual features of demonstration frames: pixels -> PCA (default), or any encoder you bring.

A *feature extractor* has ``fit(frames) -> self``, ``transform(frames) -> (N, d)`` float array and
``config()`` (JSON). Frames are ``(N, H, W, C)`` arrays (uint8 0..255 or floats 0..1).

* :class:`PCAFeatures` (default): each frame divided channel by channel by its own mean (a
  change of brightness or colour of the light scales a channel; dividing it out makes lighting
  jitter vanish instead of dominating the first components), flattened, projected on the
  leading principal components of the demonstration frames (scikit-learn). Saved as safetensors
  (numpy arrays, no code) beside a JSON config.
* :class:`CallableFeatures`: ``feature_extractor=`` any function from a frame batch to vectors,
  e.g. a torchvision/timm model loaded from a local checkpoint with ``weights_only=True``
  (README, "Reward machines from videos"). It cannot be saved: give it again when the labeling is loaded.
* ``features="autoencoder"``: :class:`~symlearn.learners.reward_machines.autoencoder.AutoencoderFeatures`
  (a small convolutional autoencoder trained on the frames, CPU).

:func:`extract` caches features per dataset: the key is a hash of the frames' bytes and the
extractor's configuration, so fitting again on the same demonstrations (another eps, another
kappa, the benchmark's sensitivity sweep) does not recompute them.

>>> import numpy as np
>>> frames = np.random.default_rng(0).integers(0, 255, (12, 8, 8, 3), dtype=np.uint8)
>>> pca = PCAFeatures(n_components=4).fit(frames)
>>> pca.transform(frames).shape
(12, 4)
"""

from __future__ import annotations

import hashlib
import json
from collections import OrderedDict
from collections.abc import Callable
from typing import Any

import numpy as np

from symlearn.errors import DataError, ModelError, clipped

MAX_COMPONENTS = 20  # enough for a handful of sub-goals; noise spreads over the rest
EXPLAINED = 0.9  # components kept by default: the fewest explaining this share of the variance
TARGET_SIDE = 16  # pixels: pooling to about this size keeps whole blocks and averages noise and edges


def as_frames(frames: Any, what: str = "frames") -> np.ndarray:
    """A validated ``(N, H, W, C)`` float32 array in 0..1 (C = 1 added for grey images)."""
    array = np.asarray(frames)
    if array.dtype == object or not (np.issubdtype(array.dtype, np.number) or array.dtype == bool):
        raise DataError(f"{what} must be numeric image arrays, got dtype {array.dtype}")
    if array.ndim == 3:
        array = array[..., None]
    if array.ndim != 4:
        raise DataError(f"{what} must be images (N, H, W[, C]); got an array of shape {array.shape}",
                        hint="give image demonstrations (the NPZ 'image' kind), not vectors")
    if array.shape[-1] not in (1, 3, 4) or min(array.shape[1:3]) < 4:
        raise DataError(f"{what} of shape {array.shape[1:]} do not look like images (H, W >= 4; 1, 3 or 4 channels)")
    check_pixel_values(array, what)
    if np.issubdtype(array.dtype, np.integer):
        return array.astype(np.float32) / 255.0
    return array.astype(np.float32)


def check_pixel_values(array: np.ndarray, what: str = "frames") -> None:
    """Integer pixels are 0..255 (uint8 values: they are divided by 255), float pixels 0..1 and
    finite; anything else would be scaled wrongly without a word."""
    if array.size == 0 or array.dtype == bool:
        return
    if np.issubdtype(array.dtype, np.integer):
        lo, hi = int(array.min()), int(array.max())
        if lo < 0 or hi > 255:
            raise DataError(f"integer {what} must lie in 0..255 (8-bit pixel values), got [{lo}, {hi}]",
                            hint="give uint8 images (e.g. 16-bit values >> 8) or floats scaled to 0..1")
        return
    if not np.all(np.isfinite(array)):
        raise DataError(f"{what} contain NaN or infinite pixels")
    lo, hi = float(array.min()), float(array.max())
    if lo < 0 or hi > 1:
        # negative values are rarely pixels: a table of features stored per step (highway-env's
        # kinematics, (5, 5) of positions and speeds) reads as a tiny picture, and "scale to 0..1"
        # misleads there
        table = lo < 0 and array.ndim >= 3 and min(array.shape[1:3]) < 16
        raise DataError(f"float {what} must lie in [0, 1], got [{lo:.3g}, {hi:.3g}]",
                        hint=("give uint8 images or floats scaled to 0..1"
                              + ("; these look like tables of features, not camera frames "
                                 f"({array.shape[1]} x {array.shape[2]}, negative values): learn rm reads pictures, "
                                 "learn dnf / learn pdfa read features" if table else "")))


def pool_factor(shape: tuple[int, ...]) -> int:
    """Average-pooling factor that leaves the shorter image side at 16 pixels or more."""
    return max(1, min(shape[1], shape[2]) // TARGET_SIDE)


def pooled(frames: np.ndarray, factor: int) -> np.ndarray:
    """Mean over ``factor x factor`` pixel blocks (edge rows/columns that do not fill one are dropped)."""
    if factor <= 1:
        return frames
    n, h, w, c = frames.shape
    h, w = h // factor * factor, w // factor * factor
    return frames[:, :h, :w].reshape(n, h // factor, factor, w // factor, factor, c).mean(axis=(2, 4))


def lighting_normalised(frames: np.ndarray) -> np.ndarray:
    """Each frame's channels divided by their mean (see the module docstring), flattened."""
    means = frames.mean(axis=(1, 2), keepdims=True)
    return (frames / np.maximum(means, 1e-3)).reshape(len(frames), -1)


class PCAFeatures:
    """Pooled, lighting-normalised pixels projected on their principal components.

    ``pool`` (default: to about 16 pixels a side) averages pixel blocks first: sub-goals differ
    by whole blocks, while noise and the sub-pixel placement errors of a demonstrator live at the
    pixel scale. ``n_components`` defaults to the fewest components explaining 90 % of the
    variance (at least 2, at most 20): a few block moves explain nearly all of it, and leaving
    the remaining noise directions out keeps the clusters tight.
    """

    kind = "pca"

    def __init__(self, n_components: int | None = None, pool: int | None = None, random_state: int = 0) -> None:
        self.n_components = n_components
        self.pool = pool
        self.random_state = random_state

    def _inputs(self, frames: np.ndarray) -> np.ndarray:
        return lighting_normalised(pooled(frames, self.pool_))

    def fit(self, frames: np.ndarray) -> PCAFeatures:
        from sklearn.decomposition import PCA

        frames = as_frames(frames)
        self.pool_ = int(self.pool) if self.pool else pool_factor(frames.shape)
        x = self._inputs(frames)
        limit = min(len(x), x.shape[1])
        if self.n_components is not None and not 1 <= self.n_components <= limit:
            raise DataError(f"PCA needs 1 <= n_components <= {limit} for {len(x)} frames, got {self.n_components}")
        if limit < 2:
            raise DataError(f"{len(x)} frame(s) are too few for PCA features", hint="give at least two frames")
        pca = PCA(n_components=self.n_components or min(MAX_COMPONENTS, limit - 1, x.shape[1]),
                  random_state=self.random_state).fit(x)
        k = self.n_components or int(np.clip(np.searchsorted(np.cumsum(pca.explained_variance_ratio_), EXPLAINED) + 1,
                                             2, len(pca.components_)))
        self.mean_ = np.ascontiguousarray(pca.mean_, dtype=np.float32)
        self.components_ = np.ascontiguousarray(pca.components_[:k], dtype=np.float32)
        self.explained_ = float(pca.explained_variance_ratio_[:k].sum())
        return self

    def transform(self, frames: np.ndarray) -> np.ndarray:
        if "components_" not in self.__dict__:
            raise ModelError("PCAFeatures is not fitted")
        x = self._inputs(as_frames(frames))
        if x.shape[1] != self.mean_.shape[0]:
            raise DataError(f"frames give {x.shape[1]} values each, the features were fitted on {self.mean_.shape[0]}",
                            hint="render the frames at the size of the demonstrations")
        return (x - self.mean_) @ self.components_.T

    def config(self) -> dict[str, Any]:
        return {"kind": self.kind, "n_components": int(self.components_.shape[0]), "pool": self.pool_,
                "inputs": int(self.mean_.shape[0])}

    def arrays(self) -> dict[str, np.ndarray]:
        # contiguous copies: safetensors writes raw buffers (sklearn may hand out Fortran order)
        return {"mean": np.ascontiguousarray(self.mean_), "components": np.ascontiguousarray(self.components_)}

    @classmethod
    def from_arrays(cls, config: dict, arrays: dict[str, np.ndarray]) -> PCAFeatures:
        mean, components = arrays.get("mean"), arrays.get("components")
        if mean is None or components is None or mean.ndim != 1 or components.ndim != 2 \
                or components.shape[1] != mean.shape[0]:
            raise ModelError("a PCA features file needs 'mean' (d,) and 'components' (k, d)")
        pool = config.get("pool")
        if isinstance(pool, bool) or not isinstance(pool, int) or pool < 1:
            raise ModelError(f"a PCA features configuration needs a positive integer 'pool', got {pool!r}")
        # the configuration states the shapes it was saved with: one that contradicts the arrays
        # is a hand-edited or mixed-up file, refused rather than read by the arrays alone
        for key, size in (("n_components", components.shape[0]), ("inputs", mean.shape[0])):
            if key in config and (type(config[key]) is not int or config[key] != size):
                raise ModelError(f"the PCA features configuration says {key} = {clipped(repr(config[key]))}, "
                                 f"its arrays hold {size}")
        features = cls(n_components=int(components.shape[0]), pool=pool)
        features.pool_ = pool
        features.mean_, features.components_ = mean.astype(np.float32), components.astype(np.float32)
        features.explained_ = float("nan")
        return features


class CallableFeatures:
    """A user's encoder: ``function(frames (N, H, W, C) float 0..1) -> (N, d)``; fitting does nothing."""

    kind = "callable"

    def __init__(self, function: Callable[[np.ndarray], Any], name: str | None = None) -> None:
        if not callable(function):
            raise DataError(f"feature_extractor must be callable, got {type(function).__name__}")
        self.function = function
        self.name = name or getattr(function, "__name__", type(function).__name__)

    def fit(self, frames: np.ndarray) -> CallableFeatures:
        return self

    def transform(self, frames: np.ndarray) -> np.ndarray:
        values = self.function(as_frames(frames))
        if hasattr(values, "detach"):  # a torch tensor
            values = values.detach().cpu().numpy()
        values = np.asarray(values, dtype=np.float64)
        if values.ndim != 2 or len(values) != len(frames):
            raise DataError(f"feature_extractor returned shape {values.shape} for {len(frames)} frames; "
                            "expected (frames, features)")
        if not np.all(np.isfinite(values)):
            raise DataError("feature_extractor returned NaN or infinite features")
        return values

    def config(self) -> dict[str, Any]:
        return {"kind": self.kind, "name": self.name}


def make_extractor(features: str | Callable | Any, *, n_components: int | None = None, random_state: int = 0):
    """The extractor a learner's ``features=`` / ``feature_extractor=`` names."""
    if callable(features) and not hasattr(features, "transform"):
        return CallableFeatures(features)
    if hasattr(features, "fit") and hasattr(features, "transform"):
        return features
    if features == "pca":
        return PCAFeatures(n_components=n_components, random_state=random_state)
    if features == "autoencoder":
        from symlearn.learners.reward_machines.autoencoder import AutoencoderFeatures

        return AutoencoderFeatures(latent=n_components or 16, random_state=random_state)
    if features == "random-cnn":
        from symlearn.learners.reward_machines.autoencoder import RandomCNNFeatures

        return RandomCNNFeatures(random_state=random_state)
    raise DataError(f"unknown features {features!r}", hint="use pca, autoencoder, random-cnn or a callable")


# --- the per-dataset cache -------------------------------------------------------------------------
_CACHE: OrderedDict[str, tuple[Any, np.ndarray]] = OrderedDict()
CACHE_SIZE = 16


def dataset_key(frames: np.ndarray) -> str:
    """A hash of the frames (shape, dtype and bytes)."""
    digest = hashlib.sha256(repr((frames.shape, str(frames.dtype))).encode())
    digest.update(np.ascontiguousarray(frames).data)
    return digest.hexdigest()


def extract(extractor, frames: np.ndarray, *, cache: bool = True) -> tuple[Any, np.ndarray, bool]:
    """Fit ``extractor`` on ``frames`` and transform them: ``(fitted extractor, features, from cache)``.

    Callables are cached by identity (a function object may change behind the same name)."""
    key = None
    if cache:
        described = {"id": id(extractor.function)} if isinstance(extractor, CallableFeatures) else {}
        params = {k: v for k, v in vars(extractor).items() if isinstance(v, (int, float, str, type(None)))}
        key = dataset_key(frames) + json.dumps([type(extractor).__name__, params, described], sort_keys=True, default=str)
        if key in _CACHE:
            _CACHE.move_to_end(key)
            fitted, values = _CACHE[key]
            return fitted, values.copy(), True
    fitted = extractor.fit(frames)
    values = np.asarray(fitted.transform(frames), dtype=np.float64)
    if key is not None:
        _CACHE[key] = (fitted, values.copy())
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.popitem(last=False)
    return fitted, values, False


def clear_cache() -> None:
    _CACHE.clear()


__all__ = ["CallableFeatures", "PCAFeatures", "as_frames", "clear_cache", "dataset_key", "extract",
           "lighting_normalised", "make_extractor"]
