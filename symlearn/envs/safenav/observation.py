"""What a SafeNav agent observes, and the thesis' 20 features.

The observation is one flat ``float32`` vector; its first 20 entries **are** the thesis'
features (section 4.4.1), so a constraint learned on ``info["features"]`` also reads the
observation:

==========  =====================  ============================================================
index       name                   meaning
==========  =====================  ============================================================
0, 1        ``a_x``, ``a_y``       accelerometer: change of velocity per second, robot frame
                                   (x ahead, y to the left); contacts with walls/box included;
                                   clipped to +-50 (:data:`SENSOR_LIMITS`)
2, 3        ``v_x``, ``v_y``       velocimeter: velocity in the robot frame (m/s), clipped to +-5
4 .. 19     ``d_0`` .. ``d_15``    hazard lidar (:mod:`~symlearn.envs.safenav.lidar`), 1 = inside
20          ``gyro``               yaw rate (rad/s, counter-clockwise), clipped to +-10
21 .. 36    ``goal_0`` ..          goal lidar (closeness of the goal centre per bin)
37, 38      ``goal_cos/sin``       compass: unit vector to the goal in the robot frame
39          ``goal_dist``          ``exp(-distance to the goal centre)`` (Safety-Gym's form)
40 .. 55    ``box_0`` .. (Push)    box lidar
56, 57      ``box_cos/sin``        compass to the box
58          ``box_dist``           ``exp(-distance to the box centre)``
==========  =====================  ============================================================

Goal tasks observe 40 values, Push tasks 59. Safety-Gym also observes a magnetometer and
3-D sensors; the planar ones above carry the same information for a robot on a plane.
"""

from __future__ import annotations

import math

import numpy as np

from symlearn.envs.safenav.lidar import N_BINS

FEATURE_NAMES: tuple[str, ...] = ("a_x", "a_y", "v_x", "v_y", *(f"d_{k}" for k in range(N_BINS)))
N_FEATURES = len(FEATURE_NAMES)


def _target_names(prefix: str) -> tuple[str, ...]:
    return (*(f"{prefix}_{k}" for k in range(N_BINS)), f"{prefix}_cos", f"{prefix}_sin", f"{prefix}_dist")


def observation_names(push: bool) -> tuple[str, ...]:
    """Names of the observation entries, in order (see the module docstring)."""
    return FEATURE_NAMES + ("gyro",) + _target_names("goal") + (_target_names("box") if push else ())


#: Motion sensors saturate like real ones: readings are clipped to these magnitudes (a robot at
#: full speed stopped by a wall in one step reads about 50 m/s^2; top speeds are about 1 m/s).
SENSOR_LIMITS = {"a_x": 50.0, "a_y": 50.0, "v_x": 5.0, "v_y": 5.0, "gyro": 10.0}


def observation_bounds(push: bool) -> tuple[np.ndarray, np.ndarray]:
    """``(low, high)`` of the observation space: the sensor limits, lidars ``[0, 1]``, compass ``[-1, 1]``."""
    names = observation_names(push)
    low = np.zeros(len(names), dtype=np.float32)
    high = np.ones(len(names), dtype=np.float32)
    for i, name in enumerate(names):
        if name in SENSOR_LIMITS:
            low[i], high[i] = -SENSOR_LIMITS[name], SENSOR_LIMITS[name]
        elif name.endswith(("_cos", "_sin")):
            low[i] = -1.0
    return low, high


def clip(value: float, limit: float) -> float:
    return -limit if value < -limit else limit if value > limit else value


def compass(x: float, y: float, heading: float, target: np.ndarray) -> tuple[float, float, float]:
    """(cos, sin) of the direction to ``target`` in the robot frame, and ``exp(-distance)``."""
    dx, dy = float(target[0]) - x, float(target[1]) - y
    distance = math.hypot(dx, dy)
    if distance < 1e-12:
        return 1.0, 0.0, 1.0
    c, s = math.cos(heading), math.sin(heading)
    return (c * dx + s * dy) / distance, (-s * dx + c * dy) / distance, math.exp(-distance)


__all__ = ["FEATURE_NAMES", "N_FEATURES", "SENSOR_LIMITS", "clip", "compass", "observation_bounds",
           "observation_names"]
