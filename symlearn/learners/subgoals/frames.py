"""Demonstrations as float frames, where NaN means "not observed".

Sub-goal learning reads states as feature vectors. A camera that misses an object yields NaN for
its coordinates in that frame; symlearn's :class:`~symlearn.data.Demonstrations` refuse NaN (a
learner fed NaN by mistake would learn nonsense), so this learner also takes plain arrays, where
NaN is allowed and means *unknown*. Accepted forms:

* a :class:`~symlearn.data.Demonstrations` with vector or feature-dict states (a matrix
  state, a ``(2, 2)`` observation, is its entries in row-major order; pictures ``(H, W, C)`` are refused);
* a sequence of ``(T_i, k)`` arrays (one per demonstration; ``T_i`` may differ);
* one ``(N, T, k)`` array.

Infinite values are refused (they are not "unknown", they are broken data); so is a frame
with a different number of features from the first one.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from symlearn.errors import DataError


def _feature_rows(states: Sequence[dict], keys: tuple[str, ...], index: int) -> np.ndarray:
    """Feature-dict states as rows of the ``keys`` columns (read by name, never by position)."""
    missing = [k for k in keys if k not in states[0]]
    if missing:
        raise DataError(f"demonstration {index}: the states have no feature {missing[0]!r} (their features: "
                        f"{', '.join(sorted(states[0]))})",
                        hint="feature-dict states are read by their own keys: --features must name those keys")
    for step, state in enumerate(states):
        for k in keys:
            if isinstance(state[k], str):
                raise DataError(f"demonstration {index}, step {step}: feature {k!r} is the text {state[k]!r}",
                                hint="sub-goals are clustered on numeric features")
    return np.asarray([[s[k] for k in keys] for s in states], dtype=np.float64)


def demonstration_frames(demonstrations: Any, features: Any = None) -> tuple[list[np.ndarray], tuple[str, ...]]:
    """``(frames, feature_names)``: one float64 ``(T_i, k)`` array per demonstration.

    ``features``: a :class:`~symlearn.grounding.FeatureMap` (states are mapped through it), a
    list of names, or None (``x0 .. x{k-1}``; the sorted keys of feature-dict states).
    """
    from symlearn.data.demonstrations import Demonstrations
    from symlearn.grounding.features import FeatureMap

    names: tuple[str, ...] | None = None
    if isinstance(features, FeatureMap):
        names = features.names
    elif features is not None:
        names = tuple(str(n) for n in features)
    if isinstance(demonstrations, Demonstrations):
        shape = np.shape(demonstrations[0].states)[1:] if demonstrations.state_kind == "image" else ()
        if demonstrations.state_kind == "symbol" or len(shape) > 2:
            what = f"pictures {shape}" if shape else "symbol states"
            raise DataError(f"the demonstrations hold {what}; sub-goals are clustered on numeric feature vectors",
                            hint="give vector or feature-dict states (or a frame archive); `learn rm` finds "
                                 "sub-goals in pictures")
        runs = []
        for trajectory in demonstrations:
            states = trajectory.states
            if isinstance(features, FeatureMap):
                runs.append(features.matrix(list(states)))
            elif len(states) and isinstance(states[0], dict):
                keys = names or tuple(sorted(states[0]))
                names = keys
                runs.append(_feature_rows(states, keys, len(runs)))
            else:
                # a multi-dimensional state (a (2, 1) Box observation) is its entries in row-major
                # order, x0, x1, ..., as learn dnf and train --cost read it
                run = np.asarray(states, dtype=np.float64)
                runs.append(run.reshape(len(run), -1) if run.ndim > 2 else run)
    elif isinstance(demonstrations, np.ndarray) and demonstrations.ndim == 3:
        runs = list(np.asarray(demonstrations, dtype=np.float64))
    elif isinstance(demonstrations, (Sequence, np.ndarray)) and not isinstance(demonstrations, (str, bytes)):
        try:
            runs = [np.asarray(d, dtype=np.float64) for d in demonstrations]
        except (TypeError, ValueError) as exc:
            raise DataError(f"demonstrations must be numeric frames ({exc})") from None
    else:
        raise DataError(f"cannot read demonstrations from a {type(demonstrations).__name__}",
                        hint="give Demonstrations, a list of (T, k) arrays or an (N, T, k) array (load a file "
                             "with symlearn.data.load or symlearn.data.frame_archive.load_frames)")
    if not runs:
        raise DataError("no demonstrations")
    frames = []
    for i, run in enumerate(runs):
        if run.ndim == 1:
            run = run[:, None]
        if run.ndim != 2:
            raise DataError(f"demonstration {i}: frames must be a (T, k) array, got shape {run.shape}")
        if len(run) == 0:
            raise DataError(f"demonstration {i} has no frames")
        if run.shape[1] != (frames[0].shape[1] if frames else run.shape[1]):
            raise DataError(f"demonstration {i} has {run.shape[1]} features per frame, "
                            f"demonstration 0 has {frames[0].shape[1]}")
        if np.isinf(run).any():
            t = int(np.flatnonzero(np.isinf(run).any(axis=1))[0])
            raise DataError(f"demonstration {i}, frame {t}: infinite feature value",
                            hint="NaN marks an unobserved feature; infinity is not allowed")
        frames.append(run)
    k = frames[0].shape[1]
    if names is None:
        names = tuple(f"x{j}" for j in range(k))
    elif len(names) != k:
        raise DataError(f"{len(names)} feature names for {k} features per frame")
    return frames, names
