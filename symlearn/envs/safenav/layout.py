"""Random SafeNav layouts: where the agent, the goal, the push box and the hazards start.

Like Safety-Gym level 1, every reset draws a fresh layout inside ``[-extent, extent]^2``
(``extent = 1.5``) by rejection sampling with keep-out distances, all from the environment's
seeded generator:

* the agent starts at least ``hazard_radius + 0.4`` from every hazard centre (Safety-Gym's robot
  keep-out 0.4), so it never starts inside a hazard;
* no hazard overlaps the goal circle or the push box, nor another hazard (centres at least
  ``2 * hazard_radius + 0.05`` apart), so the goal can always be reached without cost;
* the goal lies at least ``goal_radius + 0.4`` from the agent (it is not reached at once).

Safety-Gym's keep-outs allow slight overlaps; ours forbid them, which keeps the ground truth
"inside some hazard disc" unambiguous and every goal reachable.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symlearn.errors import ModelError

MAX_TRIES = 10_000


@dataclass
class Layout:
    """Initial positions: agent, goal, box (``None`` without a push task), hazards ``(n, 2)``."""

    agent: np.ndarray
    goal: np.ndarray
    box: np.ndarray | None
    hazards: np.ndarray


def _far_from(point: np.ndarray, others: list[tuple[np.ndarray, float]]) -> bool:
    return all(float(np.hypot(*(point - where))) >= gap for where, gap in others)


def sample_point(rng: np.random.Generator, extent: float, keep_away: list[tuple[np.ndarray, float]],
                 what: str = "object") -> np.ndarray:
    """A uniform point of ``[-extent, extent]^2`` at least ``gap`` from each ``(where, gap)``."""
    for _ in range(MAX_TRIES):
        point = rng.uniform(-extent, extent, size=2)
        if _far_from(point, keep_away):
            return point
    raise ModelError(f"could not place the {what} in {MAX_TRIES} tries",
                     hint="use fewer or smaller hazards, or a larger extent")


def sample_layout(rng: np.random.Generator, *, n_hazards: int = 8, hazard_radius: float = 0.2,
                  goal_radius: float = 0.3, box_radius: float | None = None, extent: float = 1.5,
                  agent_keepout: float = 0.4) -> Layout:
    """A layout with the keep-outs of the module docstring (the agent first, the hazards last)."""
    for _ in range(100):
        try:
            agent = rng.uniform(-extent, extent, size=2)
            goal = sample_point(rng, extent, [(agent, goal_radius + agent_keepout)], "goal")
            placed = [(agent, hazard_radius + agent_keepout), (goal, goal_radius + hazard_radius + 0.05)]
            box = None
            if box_radius is not None:
                box = sample_point(rng, extent, [(agent, box_radius + agent_keepout),
                                                 (goal, goal_radius + box_radius + 0.2)], "box")
                placed.append((box, box_radius + hazard_radius + 0.05))
            hazards = []
            for _ in range(n_hazards):
                hazard = sample_point(rng, extent, placed, "hazards")
                hazards.append(hazard)
                placed.append((hazard, 2 * hazard_radius + 0.05))
            return Layout(agent, goal, box, np.array(hazards, dtype=np.float64).reshape(n_hazards, 2))
        except ModelError:
            continue  # an unlucky early placement crowded the arena: start over
    raise ModelError(f"could not place {n_hazards} hazards of radius {hazard_radius} in [-{extent}, {extent}]^2",
                     hint="use fewer or smaller hazards, or a larger extent")


__all__ = ["Layout", "sample_layout", "sample_point"]
