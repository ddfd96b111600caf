"""highway-env's highway task, set up for speed.

The classes here subclass highway-env's, so they are built by :func:`scene_classes` on first
use, after :func:`symlearn.optional.require` has checked the ``highway`` extra: this module
imports without highway-env (pytest's doctest collection imports every module of the package,
and the core test suite must pass without the extra), and a missing package is a clear
:class:`~symlearn.errors.MissingDependencyError`, not an ``ImportError``.

* ``HighwayScene`` is highway-env's ``HighwayEnvFast`` (IDM/MOBIL traffic, collisions checked
  only against the controlled vehicle) with highway-env's ``ContinuousAction`` and a
  ``StraightRoad``. We step it through its ``_simulate`` and never call its ``step``: that
  would also compute highway-env's own observation (a pandas frame per step, half the time of
  a step, measured) and reward, neither of which we use. Its reset still asks for an
  observation, so the scene's observation type is ``NoObservation`` (the Kinematics frame was
  75 % of a 10 ms reset, and a learner's early episodes last a dozen steps).
* ``StraightRoad`` answers ``neighbour_vehicles`` -- the query behind IDM, MOBIL and our gap
  features, called ~40 times per simulated step with 20 vehicles, 45 % of a step in a profile
  -- with numpy over all vehicles at once instead of a Python loop over them (about 2x faster
  steps). Same answer as highway-env's loop (``tests/envs/test_driving.py`` compares them on
  random scenes); anything it does not cover (curved lanes, connected-lane search, road
  objects) goes to highway-env's own method.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np

from symlearn.optional import require


@cache
def scene_classes() -> tuple[type, type, type]:
    """``(StraightRoad, NoObservation, HighwayScene)``, built once (needs the ``highway`` extra)."""
    require("highway", "the driving environment")
    from gymnasium import spaces
    from highway_env.envs.common.observation import ObservationType
    from highway_env.envs.highway_env import HighwayEnvFast
    from highway_env.road.lane import StraightLane
    from highway_env.road.road import Road, RoadNetwork

    class StraightRoad(Road):
        """A ``Road`` whose ``neighbour_vehicles`` is vectorised for straight lanes.

        During ``act`` (every vehicle decides, nobody moves) the vehicles' positions are read
        once and reused by every query; outside it they are read per query.
        """

        _positions: np.ndarray | None = None

        def act(self) -> None:
            self._positions = self._read_positions()
            try:
                super().act()
            finally:
                self._positions = None

        def _read_positions(self) -> np.ndarray:
            return np.array([v.position for v in self.vehicles], dtype=np.float64).reshape(-1, 2)

        def neighbour_vehicles(self, vehicle: Any, lane_index: Any = None) -> tuple[Any, Any]:
            lane_index = lane_index or vehicle.lane_index
            if not lane_index:
                return None, None
            lane = self.network.get_lane(lane_index)
            if self.objects or self.neighbour_vehicles_connected_lanes or type(lane) is not StraightLane:
                return super().neighbour_vehicles(vehicle, lane_index)
            positions = self._positions if self._positions is not None else self._read_positions()
            delta = positions - lane.start
            s_all = delta @ lane.direction
            lateral = delta @ lane.direction_lateral
            # highway-env's lane membership for this query: on_lane(margin=1)
            member = (np.abs(lateral) <= lane.width / 2 + 1) & (s_all >= -lane.VEHICLE_LENGTH) & \
                     (s_all < lane.length + lane.VEHICLE_LENGTH)
            own = [i for i, v in enumerate(self.vehicles) if v is vehicle]
            if own:
                member[own] = False
            s = float((np.asarray(vehicle.position, dtype=np.float64) - lane.start) @ lane.direction)
            ahead = member & (s_all >= s)
            behind = member & (s_all < s)
            front = rear = None
            if ahead.any():
                # highway-env keeps the *last* of equally near vehicles ahead (<=), the first behind (>)
                nearest = s_all[ahead].min()
                front = self.vehicles[int(np.flatnonzero(ahead & (s_all == nearest))[-1])]
            if behind.any():
                nearest = s_all[behind].max()
                rear = self.vehicles[int(np.flatnonzero(behind & (s_all == nearest))[0])]
            return front, rear

    class NoObservation(ObservationType):
        """An empty observation: ``DrivingEnv`` computes its own."""

        def space(self) -> spaces.Box:
            return spaces.Box(0.0, 0.0, shape=(0,), dtype=np.float32)

        def observe(self) -> np.ndarray:
            return np.zeros(0, dtype=np.float32)

    class HighwayScene(HighwayEnvFast):
        """highway-env's fast highway with a ``StraightRoad`` and ``NoObservation``."""

        def define_spaces(self) -> None:
            super().define_spaces()
            self.observation_type = NoObservation(self)
            self.observation_space = self.observation_type.space()

        def _create_road(self) -> None:
            self.road = StraightRoad(
                network=RoadNetwork.straight_road_network(self.config["lanes_count"], speed_limit=30),
                np_random=self.np_random, record_history=False,
                neighbour_vehicles_connected_lanes=self.config["neighbour_vehicles_connected_lanes"])

    return StraightRoad, NoObservation, HighwayScene


def make_scene(config: dict[str, Any]) -> Any:
    """A ``HighwayScene`` with ``config`` (highway-env's configuration keys)."""
    return scene_classes()[2](config=config)


__all__ = ["make_scene", "scene_classes"]
