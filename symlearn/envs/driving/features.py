"""The driving features (thesis section 4.4.2, after its highD feature space), in physical units.

========================  ======================================================================
name                      meaning
========================  ======================================================================
``v_x``, ``v_y``          the ego's velocity along the road and across it [m/s]; ``v_y > 0``
                          moves toward the right road edge (highway-env's ``y`` axis)
``lead_left``,            bumper-to-bumper gap [m] to the nearest vehicle ahead of / behind the
``follow_left``           ego in the lane left of the ego's lane
``lead_same``,            the same in the ego's own lane (``<= 0``: the bumpers touch)
``follow_same``
``lead_right``,           the same in the lane to the right
``follow_right``
``d_left``, ``d_right``   distance [m] from the ego's centre to the left / right road edge;
                          negative beyond the edge (then the ego is off the road)
========================  ======================================================================

A gap is the distance between the two centres along the lane minus one vehicle length (all
vehicles of highway-env's highway are 5 m long), capped at the sensor range (100 m by
default; the thesis' highD sensor reads 0..500 m). With no vehicle in range, or no such lane
(left of the leftmost lane), the gap *is* the sensor range: nothing is near. A vehicle counts
in a lane when its centre lies within half a lane width + 1 m of that lane's centre line --
highway-env's own rule in ``Road.neighbour_vehicles``, so a car halfway through a lane change
is seen in both lanes, as IDM and MOBIL see it.

The policy's observation is the same vector divided by :func:`observation_scales` (speeds by
the speed limit, gaps by the sensor range, edge distances by the road width) and clipped to
``[-2, 2]``: our PPO does not normalise observations, and 100 m next to 0.3 m/s would leave the
small features unlearnable. ``info["features"]`` keeps the physical units, so a learned
formula reads ``lead_same < 7.5`` in metres.
"""

from __future__ import annotations

from typing import Any

import numpy as np

FEATURE_NAMES: tuple[str, ...] = ("v_x", "v_y", "lead_left", "follow_left", "lead_same", "follow_same",
                                  "lead_right", "follow_right", "d_left", "d_right")
N_FEATURES = len(FEATURE_NAMES)
VEHICLE_LENGTH = 5.0  # highway-env's Vehicle.LENGTH; every car on its highway has it
OBSERVATION_CLIP = 2.0


def observation_scales(*, lanes: int, lane_width: float, sensor_range: float, speed_limit: float,
                       lateral_speed: float = 5.0) -> np.ndarray:
    """Per-feature divisors turning the features into the policy's observation."""
    road = lanes * lane_width
    return np.array([speed_limit, lateral_speed] + [sensor_range] * 6 + [road, road], dtype=np.float64)


def gap(ego: Any, other: Any, lane: Any, sensor_range: float, *, ahead: bool) -> float:
    """Bumper-to-bumper gap from ``ego`` to ``other`` along ``lane`` (``sensor_range`` if none)."""
    if other is None:
        return sensor_range
    s_ego = lane.local_coordinates(ego.position)[0]
    s_other = lane.local_coordinates(other.position)[0]
    centre = s_other - s_ego if ahead else s_ego - s_other
    return min(centre - VEHICLE_LENGTH, sensor_range)


def driving_features(road: Any, ego: Any, *, lanes: int, lane_width: float, sensor_range: float) -> np.ndarray:
    """The 10 features of ``ego`` on ``road`` (a highway-env road of ``lanes`` straight lanes,
    lane 0 leftmost at ``y = 0``), ``float64`` in :data:`FEATURE_NAMES` order."""
    out = np.empty(N_FEATURES, dtype=np.float64)
    velocity = ego.velocity
    out[0], out[1] = float(velocity[0]), float(velocity[1])
    start, end, lane_id = ego.lane_index
    for k, offset in enumerate((-1, 0, 1)):
        target = lane_id + offset
        if 0 <= target < lanes:
            index = (start, end, target)
            lane = road.network.get_lane(index)
            front, rear = road.neighbour_vehicles(ego, index)
            out[2 + 2 * k] = gap(ego, front, lane, sensor_range, ahead=True)
            out[3 + 2 * k] = gap(ego, rear, lane, sensor_range, ahead=False)
        else:
            out[2 + 2 * k] = out[3 + 2 * k] = sensor_range
    y = float(ego.position[1])
    out[8] = y + lane_width / 2
    out[9] = (lanes - 0.5) * lane_width - y
    return out


__all__ = ["FEATURE_NAMES", "N_FEATURES", "OBSERVATION_CLIP", "VEHICLE_LENGTH", "driving_features", "gap",
           "observation_scales"]
