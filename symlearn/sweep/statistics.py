"""Aggregating a metric over seeds: mean, standard error, and a seeded bootstrap interval.

The standard error (sample standard deviation / sqrt(n)) is what the benchmark tables have
always printed ("mean ± s.e."); the percentile bootstrap (95 %, 2000 resamples, a fixed seed so
a report is reproducible) makes no normality assumption, which matters for rates near 0 or 1
and for few seeds. With one seed there is no spread: both are reported as missing, not as 0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_LEVEL = 0.95
BOOTSTRAP_SEED = 0


def mean_se(values: Sequence[float]) -> tuple[float, float | None]:
    """Mean and standard error of the mean (None for fewer than 2 values)."""
    n = len(values)
    if n == 0:
        raise ValueError("no values")
    mean = math.fsum(values) / n
    if n < 2:
        return mean, None
    variance = math.fsum((v - mean) ** 2 for v in values) / (n - 1)
    return mean, math.sqrt(variance / n)


def bootstrap_interval(values: Sequence[float], *, level: float = BOOTSTRAP_LEVEL,
                       resamples: int = BOOTSTRAP_RESAMPLES, seed: int = BOOTSTRAP_SEED) -> tuple[float, float] | None:
    """Percentile bootstrap interval of the mean (None for fewer than 2 values)."""
    import numpy as np

    data = np.asarray(values, dtype=float)
    if data.size < 2:
        return None
    rng = np.random.default_rng(seed)
    means = data[rng.integers(0, data.size, size=(resamples, data.size))].mean(axis=1)
    tail = (1.0 - level) / 2.0
    low, high = np.quantile(means, [tail, 1.0 - tail])
    return float(low), float(high)


def summarize(values: Sequence[float], *, interval: str = "se") -> dict:
    """``{"n", "mean", "se", "low", "high"}``: the band is mean ± s.e. (``interval="se"``) or the
    bootstrap interval (``"bootstrap"``); ``low``/``high`` are None with one value."""
    mean, se = mean_se(values)
    if interval == "bootstrap":
        bounds = bootstrap_interval(values)
        low, high = bounds if bounds else (None, None)
    elif interval == "se":
        low, high = (None, None) if se is None else (mean - se, mean + se)
    else:
        raise ValueError(f"unknown interval {interval!r} (se or bootstrap)")
    return {"n": len(values), "mean": mean, "se": se, "low": low, "high": high}


def summarize_curves(curves: Sequence[Sequence[float]], *, interval: str = "se") -> dict:
    """Pointwise :func:`summarize` of curves (one per seed), cut to the shortest one."""
    length = min(len(c) for c in curves)
    points = [summarize([c[i] for c in curves], interval=interval) for i in range(length)]
    return {"n": len(curves), "length": length, "cut": any(len(c) != length for c in curves),
            "mean": [p["mean"] for p in points], "low": [p["low"] for p in points],
            "high": [p["high"] for p in points]}
