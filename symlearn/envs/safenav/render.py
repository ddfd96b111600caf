"""A top-down RGB picture of a SafeNav world, drawn with numpy alone (no pygame, no MuJoCo).

Hazards are blue discs, the goal a green disc, the push box an orange disc, the robot a red
disc with a white dot marking its heading; the area outside the walls is grey.
"""

from __future__ import annotations

import math

import numpy as np

BACKGROUND = (235, 235, 235)
OUTSIDE = (160, 160, 160)
HAZARD = (70, 110, 230)
GOAL = (60, 190, 90)
BOX = (240, 150, 40)
AGENT = (220, 40, 40)
HEADING = (255, 255, 255)


class Raster:
    """Pixel centres of a square view ``[-half, half]^2`` (y up), built once per size."""

    def __init__(self, size: int = 256, half: float = 2.0) -> None:
        self.size, self.half = size, half
        coords = (np.arange(size) + 0.5) / size * 2 * half - half
        self.x = coords[None, :]
        self.y = coords[::-1, None]

    def blank(self, wall: float | None) -> np.ndarray:
        image = np.empty((self.size, self.size, 3), dtype=np.uint8)
        image[:] = BACKGROUND
        if wall is not None:
            outside = (np.abs(self.x) > wall) | (np.abs(self.y) > wall)
            image[outside] = OUTSIDE
        return image

    def disc(self, image: np.ndarray, x: float, y: float, radius: float, color: tuple[int, int, int]) -> None:
        radius = max(radius, self.half / self.size)  # at least one pixel
        image[(self.x - x) ** 2 + (self.y - y) ** 2 <= radius * radius] = color


def draw(raster: Raster, *, wall: float | None, hazards: np.ndarray, hazard_radius: float, goal: np.ndarray,
         goal_radius: float, box: np.ndarray | None, box_radius: float | None, agent_xy: tuple[float, float],
         heading: float, agent_radius: float) -> np.ndarray:
    """The picture as an ``(H, W, 3)`` ``uint8`` array."""
    image = raster.blank(wall)
    raster.disc(image, goal[0], goal[1], goal_radius, GOAL)
    for hx, hy in hazards:
        raster.disc(image, hx, hy, hazard_radius, HAZARD)
    if box is not None:
        raster.disc(image, box[0], box[1], box_radius or 0.2, BOX)
    ax, ay = agent_xy
    raster.disc(image, ax, ay, agent_radius, AGENT)
    tip = 0.6 * agent_radius
    raster.disc(image, ax + tip * math.cos(heading), ay + tip * math.sin(heading), 0.3 * agent_radius, HEADING)
    return image


__all__ = ["Raster", "draw"]
