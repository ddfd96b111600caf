"""Features that are settings of an episode, not choices of the expert.

A goal's position, the weather, a map's seed: a feature constant within every demonstration but
different between them. A learner that reads demonstrated states as a sample of where the expert
goes (a one-class tree's safe boxes, the sub-goal clusters) splits on such a feature by which
settings the demonstrations happened to have -- rules and sub-goals that say nothing about the
expert's behaviour. The learners name such features in a warning, with what leaves them out.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np


def episode_settings(episodes: Sequence[np.ndarray]) -> list[int]:
    """The columns of the ``(T_i, k)`` arrays ``episodes`` (one per demonstration) that are constant
    within every episode of at least two rows (NaN, an unobserved value, ignored) and take at least
    two values across them. Fewer than two such episodes: none (nothing to compare)."""
    spans, values = [], []
    for episode in episodes:
        x = np.asarray(episode, dtype=np.float64)
        if x.ndim != 2 or len(x) < 2:
            continue
        observed = ~np.isnan(x)
        with np.errstate(invalid="ignore"):
            high = np.where(observed, x, -np.inf).max(axis=0)
            low = np.where(observed, x, np.inf).min(axis=0)
        seen = observed.any(axis=0)
        spans.append(np.where(seen, high - low, 0.0))
        values.append(np.where(seen, low, np.nan))
    if len(spans) < 2:
        return []
    spans, values = np.array(spans), np.array(values)
    constant = (spans == 0).all(axis=0)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        # a feature never observed in any episode is all NaN: nanmax/nanmin warn and give NaN,
        # which compares false (not a setting) -- no warning line for it
        warnings.simplefilter("ignore", RuntimeWarning)
        differ = np.nanmax(values, axis=0) > np.nanmin(values, axis=0)
    return [int(d) for d in np.flatnonzero(constant & differ)]


__all__ = ["episode_settings"]
