"""Two cameras on the block world, rasterised with numpy: a front view and a top-down view.

* :func:`front_view` (demonstrations, sub-goal inference): an oblique view from the front and
  above; every block shows its front face and its top face, drawn far to near and bottom to top,
  so nearer and higher blocks occlude the others. A block being carried (``lift`` > 0) is drawn
  above the table with its shadow below it.
* :func:`top_down_view` (the policy's observation and the pick/place pixels): one square per
  block, brighter the higher it stands, so a stack differs from a block on the table.

Both are drawn at twice the resolution and averaged 2 x 2 (smooth edges at sub-pixel positions),
then :class:`Lighting` applies a per-frame brightness and colour gain and Gaussian pixel noise:
the "rendering noise and lighting jitter" a learner has to be robust to. ``palette`` and
``table``/``wall`` colours are parameters, so tests can render the same scenes differently.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from symlearn.envs.rendered_blocks.world import BLOCK

PALETTE: dict[str, tuple[float, float, float]] = {
    "red": (0.85, 0.15, 0.12), "green": (0.15, 0.7, 0.2), "blue": (0.15, 0.3, 0.85),
    "yellow": (0.9, 0.8, 0.15), "purple": (0.6, 0.25, 0.7), "orange": (0.95, 0.5, 0.1),
}
TABLE = (0.78, 0.66, 0.5)
WALL = (0.55, 0.57, 0.6)


@dataclass(frozen=True)
class Lighting:
    """Per-frame jitter: gain ``1 +- brightness``, per-channel gain ``1 +- colour``, pixel noise ``noise``."""

    brightness: float = 0.08
    colour: float = 0.04
    noise: float = 0.03

    def apply(self, image: np.ndarray, rng: np.random.Generator | None) -> np.ndarray:
        if rng is not None:
            gain = rng.uniform(1 - self.brightness, 1 + self.brightness)
            gain = gain * rng.uniform(1 - self.colour, 1 + self.colour, size=3)
            image = image * gain + rng.normal(0.0, self.noise, size=image.shape)
        return (np.clip(image, 0.0, 1.0) * 255 + 0.5).astype(np.uint8)


NO_JITTER = Lighting(0.0, 0.0, 0.0)


def _fill(canvas: np.ndarray, top: float, bottom: float, left: float, right: float, colour) -> None:
    rows, cols = canvas.shape[:2]
    r0, r1 = max(int(round(top)), 0), min(int(round(bottom)), rows)
    c0, c1 = max(int(round(left)), 0), min(int(round(right)), cols)
    if r0 < r1 and c0 < c1:
        canvas[r0:r1, c0:c1] = colour


def _downsample(canvas: np.ndarray) -> np.ndarray:
    rows, cols, ch = canvas.shape
    return canvas.reshape(rows // 2, 2, cols // 2, 2, ch).mean(axis=(1, 3))


def front_view(names, positions: np.ndarray, *, size: int = 64, lift: Mapping[int, float] | None = None,
               palette: Mapping[str, tuple[float, float, float]] = PALETTE, table=TABLE, wall=WALL,
               lighting: Lighting = NO_JITTER, rng: np.random.Generator | None = None) -> np.ndarray:
    """``(size, size, 3)`` uint8 image from the front camera; ``lift[i]``: block ``i`` raised (table units)."""
    n = 2 * size
    canvas = np.empty((n, n, 3))
    horizon = 0.28 * n  # the table's far edge
    canvas[: int(horizon)] = wall
    canvas[int(horizon):] = table
    depth = 0.62 * n  # rows from the far to the near table edge
    height = 0.75 * n  # rows per table unit of height

    def row(y: float, z: float) -> float:
        return horizon + (1 - y) * depth - z * height

    lift = dict(lift or {})
    # shadows of carried blocks first (they lie on the table)
    for i, extra in lift.items():
        x, y, level = positions[i]
        shade = tuple(0.7 * c for c in table)
        _fill(canvas, row(y + BLOCK / 2, 0), row(y - BLOCK / 2, 0), (x - BLOCK / 2) * n, (x + BLOCK / 2) * n, shade)
    order = sorted(range(len(names)), key=lambda i: (-positions[i][1], positions[i][2] + lift.get(i, 0.0) / BLOCK))
    for i in order:
        x, y, level = positions[i]
        base = level * BLOCK + lift.get(i, 0.0)
        colour = np.asarray(palette[names[i]])
        left, right = (x - BLOCK / 2) * n, (x + BLOCK / 2) * n
        near, far = y - BLOCK / 2, y + BLOCK / 2
        _fill(canvas, row(far, base + BLOCK), row(near, base + BLOCK), left, right, np.minimum(colour * 1.15, 1))
        _fill(canvas, row(near, base + BLOCK), row(near, base), left, right, colour * 0.7)
    return lighting.apply(_downsample(canvas), rng)


def top_down_view(names, positions: np.ndarray, *, size: int = 48, lift: Mapping[int, float] | None = None,
                  palette: Mapping[str, tuple[float, float, float]] = PALETTE, table=TABLE,
                  lighting: Lighting = NO_JITTER, rng: np.random.Generator | None = None) -> np.ndarray:
    """``(size, size, 3)`` uint8 image from above; pixel ``(r, c)`` covers ``x = (c + .5)/size``,
    ``y = 1 - (r + .5)/size`` (see :func:`pixel_to_table`)."""
    n = 2 * size
    canvas = np.empty((n, n, 3))
    canvas[:] = table
    lift = dict(lift or {})
    for i in sorted(range(len(names)), key=lambda i: positions[i][2] + lift.get(i, 0.0) / BLOCK):
        x, y, level = positions[i]
        shade = min(0.65 + 0.25 * (level + lift.get(i, 0.0) / BLOCK), 1.25)
        colour = np.minimum(np.asarray(palette[names[i]]) * shade, 1)
        _fill(canvas, (1 - y - BLOCK / 2) * n, (1 - y + BLOCK / 2) * n, (x - BLOCK / 2) * n, (x + BLOCK / 2) * n, colour)
    return lighting.apply(_downsample(canvas), rng)


def pixel_to_table(row: int, col: int, size: int) -> tuple[float, float]:
    """Table point ``(x, y)`` at the centre of top-down pixel ``(row, col)``."""
    return (col + 0.5) / size, 1 - (row + 0.5) / size


def table_to_pixel(x: float, y: float, size: int) -> tuple[int, int]:
    """Top-down pixel ``(row, col)`` containing table point ``(x, y)``."""
    return (min(max(int((1 - y) * size), 0), size - 1), min(max(int(x * size), 0), size - 1))


__all__ = ["Lighting", "NO_JITTER", "PALETTE", "front_view", "pixel_to_table", "table_to_pixel", "top_down_view"]
