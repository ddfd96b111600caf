"""Cell functions the sweep tests run (loaded by path from the sweep files the tests write)."""

from __future__ import annotations

import os
import random
import signal
import time
from pathlib import Path


def square(x, seed, delay=0.0):
    """A deterministic cell: x squared plus the seed, and a short curve."""
    if delay:
        time.sleep(delay)
    return {"value": x * x + seed, "curve": [x, x + seed, x + 2 * seed]}


def sometimes_raises(x, seed, bad=3):
    if x == bad:
        raise ValueError(f"x = {x} is the bad value")
    return {"value": float(x)}


def dies_once(x, seed, marker_dir):
    """Kills its own worker process on the first attempt of every cell, answers on the next."""
    marker = Path(marker_dir) / f"{x}-{seed}"
    if not marker.exists():
        marker.write_text("died")
        os.kill(os.getpid(), signal.SIGKILL)
    return {"value": x + seed}


def hangs_once(x, seed, marker_dir):
    """Overruns any time limit on its first attempt."""
    marker = Path(marker_dir) / f"{x}-{seed}"
    if not marker.exists():
        marker.write_text("hung")
        time.sleep(60)
    return {"value": x}


def logged(x, seed, log, delay=0.3):
    """Appends 'x seed' to ``log`` when it starts (to count executions), then works a while."""
    with open(log, "a") as handle:
        handle.write(f"{x} {seed}\n")
    time.sleep(delay)
    return {"value": x * 10 + seed}


def global_random(x, seed):
    """Uses the global generators (Python's and numpy's), which the sweep seeds per cell."""
    import numpy as np

    return {"python": random.random(), "numpy": float(np.random.rand()),
            "own": float(np.random.default_rng(seed).normal())}


def returns_text(x, seed):
    return "not a mapping"


def no_seed(x):
    return {"value": x}
