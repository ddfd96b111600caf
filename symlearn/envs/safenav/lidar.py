"""Safety-Gym's pseudo-lidar: per angular bin, how close the nearest object of one kind is.

The robot's surroundings are cut into ``n_bins`` (16) equal sectors, egocentric and
counter-clockwise: bin ``k`` covers the directions ``[k, k + 1) * 360 / n_bins`` degrees to the
left of the heading, so an object **straight ahead lies at the start of bin 0** and one straight
to the left at the start of bin ``n_bins / 4``. Every object adds to the bin of its direction the
closeness

    ``max(0, 1 - distance / max_dist)``  (``max_dist = 3``, Safety-Gym's benchmark setting)

and a bin keeps the largest closeness it receives. As in Safety-Gym (``lidar_alias``), an object
also lights its two neighbouring bins, weighted by where its direction falls inside its own bin
(``frac * closeness`` for the next bin, ``(1 - frac) * closeness`` for the previous one), so the
readings change smoothly as the robot turns.

One deliberate difference: for discs with a radius (the hazards) ``distance`` is measured to the
disc's **edge**, not its centre (Safety-Gym's pseudo-lidar measures to the centre; its natural
lidar ray-casts to the surface). So a reading of 1 means "touching or inside the hazard", which is
what the thesis (section 4.4.1) says of its lidar features, and the ground-truth constraint
"inside a hazard" is exactly expressible over them. Goal and box lidars use radius 0 (centres).
"""

from __future__ import annotations

import math

import numpy as np

N_BINS = 16
MAX_DIST = 3.0
TWO_PI = 2 * math.pi


def pseudo_lidar(x: float, y: float, heading: float, centers: np.ndarray, radius: float = 0.0, *,
                 n_bins: int = N_BINS, max_dist: float = MAX_DIST, alias: bool = True,
                 out: np.ndarray | None = None) -> np.ndarray:
    """Closeness per bin (``(n_bins,)`` floats in ``[0, 1]``) of the discs at ``centers`` (``(n, 2)``)."""
    obs = np.zeros(n_bins) if out is None else out
    if out is not None:
        obs.fill(0.0)
    dx = centers[:, 0] - x
    dy = centers[:, 1] - y
    surface = np.maximum(np.hypot(dx, dy) - radius, 0.0)
    sensor = np.maximum(1.0 - surface / max_dist, 0.0)
    position = ((np.arctan2(dy, dx) - heading) % TWO_PI) * (n_bins / TWO_PI)
    # Few objects: a Python loop over them is faster than numpy's unbuffered maximum.at.
    for p, s in zip(position.tolist(), sensor.tolist()):
        if s <= 0.0:
            continue
        b = int(p) % n_bins
        if s > obs[b]:
            obs[b] = s
        if alias:
            frac = p - math.floor(p)
            up, down = (b + 1) % n_bins, (b - 1) % n_bins
            if frac * s > obs[up]:
                obs[up] = frac * s
            if (1.0 - frac) * s > obs[down]:
                obs[down] = (1.0 - frac) * s
    return obs


def bin_of(angle: float, n_bins: int = N_BINS) -> int:
    """The bin an egocentric direction ``angle`` (radians, counter-clockwise from ahead) falls in."""
    return int((angle % TWO_PI) * n_bins / TWO_PI) % n_bins


__all__ = ["MAX_DIST", "N_BINS", "bin_of", "pseudo_lidar"]
