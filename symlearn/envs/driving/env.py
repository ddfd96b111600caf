"""``DrivingEnv``: highway-env's highway with a continuous action and the driving features.

The thesis' driving experiment (section 4.4.2, Figure 4.5) uses highD scenarios in
CommonRoad-RL; highD needs a licence, so this environment re-creates the setting on
highway-env's highway task (the ``highway`` extra): a straight road, IDM/MOBIL traffic, and an
ego driven by a continuous action, so it *can* leave the road.

* **Action**: ``Box(-1, 1, (2,))`` = (acceleration, steering), mapped linearly to
  ``+-acceleration_range`` m/s^2 (5) and ``+-steering_range`` rad (0.2); speeds stay in
  ``[0, 40]`` m/s (highway-env would let the car reverse). highway-env's own
  default, pi/4, turns a car at 25 m/s by 4.5 rad a second (0.2: by 1): random actions leave the road
  within a second. With 0.2 the IDM/MOBIL demonstrator saturates the steering on 1 % of its
  steps and its lane changes end on the lane centre; with 0.1 they overshoot to 0.6 m from the
  road edge, with 0.05 it left the road (30 episodes each, measured).
* **Observation**: the 10 features of :mod:`~symlearn.envs.driving.features`, scaled to about
  ``[-1, 1]`` (``float32``); ``info["features"]`` holds them in metres and m/s (``float64``,
  names in ``feature_names``), the input of the DNF learner and of
  :class:`~symlearn.backends.dnf_cost.DnfCostWrapper`.
* **Reward**: progress, ``clip(v_x / speed_limit, 0, 1)`` per step (1 at the 30 m/s speed
  limit, nothing for speeding), 0 on the step of a collision or of leaving the road. Neither
  event is penalised: that is the engineered-penalty baseline's job (``DnfCostWrapper``-style
  ``reward - penalty * cost`` in ``benchmarks/driving.py``).
* **Ground truth**: ``info["collision"]`` (highway-env's ``crashed``: the ego's rectangle
  touched another car's), ``info["offroad"]`` (highway-env's ``on_road`` is false: the ego's
  centre is beyond a road edge) and ``info["cost"] = 1.0`` if either, else 0.0 -- as SafeNav's
  ``info["cost"]`` is its true cost; a :class:`DnfCostWrapper` on top moves it to
  ``info["env_cost"]`` and puts the learned formula's cost in ``info["cost"]``.
* **Traffic constraints** (thesis section 2.5.3, the neural-ICRL experiment):
  ``constraint="velocity"`` or ``"distance"`` (with ``bound``) makes ``info["cost"]`` that
  constraint instead, and gives the environment ``is_unsafe(observations)`` for the recovery
  figures of ``learn icrl`` (:mod:`~symlearn.envs.driving.traffic_constraints`); registered as
  ``driving-velocity`` / ``driving-distance``.
* **Episodes** terminate on a collision or on leaving the road (``offroad_terminal``, as
  CommonRoad-RL does) and are truncated after ``duration`` seconds (30, highway-env's fast
  highway): 150 steps at 5 Hz.

**Speed** (see :mod:`~symlearn.envs.driving.scene`): no rendering, highway-env's
``HighwayEnvFast`` (3 lanes, 20 vehicles, collisions checked only against the ego), one
simulation step per action (policy = simulation frequency = 5 Hz, the fast highway's
simulation frequency), highway-env's own observation and reward skipped, and a vectorised
neighbour search. Measured steps/s (3.3x highway-env's own step, same run): ``benchmarks/driving.py
--speed-only``.

Every ``reset(seed=s)`` replays exactly (highway-env draws the traffic from the env's seeded
generator). :meth:`DrivingEnv.place` builds scenes for tests and figures.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.envs.driving.features import (
    FEATURE_NAMES, N_FEATURES, OBSERVATION_CLIP, driving_features, observation_scales,
)
from symlearn.envs.driving import traffic_constraints
from symlearn.envs.driving.scene import make_scene
from symlearn.errors import DataError
from symlearn.optional import require

LANE_WIDTH = 4.0  # highway-env's StraightLane.DEFAULT_WIDTH
SPEED_LIMIT = 30.0  # highway-env's highway lanes
MAX_SPEED = 40.0  # highway-env's Vehicle.MAX_SPEED


class DrivingEnv(gym.Env):
    """``DrivingEnv(lanes=3, vehicles=20, duration=30, frequency=5, steering_range=0.2,
    acceleration_range=5, sensor_range=100, density=1, offroad_terminal=True, constraint=None,
    bound=None)`` (see the module docstring)."""

    metadata = {"render_modes": []}

    def __init__(self, *, lanes: int = 3, vehicles: int = 20, duration: float = 30.0, frequency: int = 5,
                 simulation_frequency: int | None = None, steering_range: float = 0.2,
                 acceleration_range: float = 5.0, sensor_range: float = 100.0, density: float = 1.0,
                 offroad_terminal: bool = True, constraint: str | None = None, bound: float | None = None,
                 render_mode: str | None = None) -> None:
        self.constraint, self.bound = constraint, traffic_constraints.check(constraint, bound)
        require("highway", "the driving environment")
        if render_mode is not None:
            raise DataError(f"the driving environment does not render (render_mode={render_mode!r})",
                            hint="leave render_mode unset")
        if lanes < 1 or vehicles < 0 or duration <= 0 or frequency < 1:
            raise DataError(f"need lanes >= 1, vehicles >= 0, duration > 0 and frequency >= 1; got {lanes}, "
                            f"{vehicles}, {duration} and {frequency}")
        simulation_frequency = frequency if simulation_frequency is None else simulation_frequency
        if simulation_frequency < frequency or simulation_frequency % frequency:
            raise DataError(f"the simulation frequency ({simulation_frequency} Hz) must be a multiple of the "
                            f"policy frequency ({frequency} Hz)")
        if not (0 < steering_range <= np.pi / 2 and acceleration_range > 0 and sensor_range > 0 and density > 0):
            raise DataError("need 0 < steering_range <= pi/2, and acceleration_range, sensor_range, density > 0")
        self.lanes, self.n_vehicles, self.duration = int(lanes), int(vehicles), float(duration)
        self.frequency, self.simulation_frequency = int(frequency), int(simulation_frequency)
        self.steering_range, self.acceleration_range = float(steering_range), float(acceleration_range)
        self.sensor_range, self.offroad_terminal = float(sensor_range), bool(offroad_terminal)
        self.render_mode = None
        self.feature_names = FEATURE_NAMES
        self.observation_names = FEATURE_NAMES  # the observation is the features, scaled
        self.lane_width = LANE_WIDTH
        self.speed_limit = SPEED_LIMIT
        self._scales = observation_scales(lanes=self.lanes, lane_width=LANE_WIDTH, sensor_range=self.sensor_range,
                                          speed_limit=SPEED_LIMIT)
        self.observation_space = spaces.Box(-OBSERVATION_CLIP, OBSERVATION_CLIP, shape=(N_FEATURES,),
                                            dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)
        self.scene = make_scene({
            "action": {"type": "ContinuousAction", "acceleration_range": (-self.acceleration_range,
                                                                         self.acceleration_range),
                       "steering_range": (-self.steering_range, self.steering_range),
                       # highway-env lets a car reverse down to -40 m/s; on a highway it stops at 0
                       "speed_range": (0.0, MAX_SPEED)},
            "lanes_count": self.lanes, "vehicles_count": self.n_vehicles, "vehicles_density": float(density),
            "duration": self.duration, "policy_frequency": self.frequency,
            "simulation_frequency": self.simulation_frequency, "offroad_terminal": self.offroad_terminal,
        })
        self.steps = 0
        if constraint is not None:  # the ground truth learn icrl measures a learned cost's recovery against
            self.is_unsafe = self._breaks_constraint

    # --- gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        # highway-env seeds its own generator; drawing its seed from ours keeps reset() without a
        # seed reproducible after one seeded reset
        self.scene.reset(seed=int(self.np_random.integers(2**31)))
        if self.constraint == "velocity" and self.ego.speed > self.bound:
            # start at the cap, not above it (traffic_constraints says why)
            self.ego.speed = self.bound
        self.steps = 0
        return self._observe(collision=False, offroad=False)

    def step(self, action):
        action = np.asarray(action, dtype=np.float64).reshape(-1)
        if action.shape != (2,) or not np.isfinite(action).all():
            raise DataError(f"a driving action is 2 finite numbers (acceleration, steering), got {action.tolist()}")
        scene = self.scene
        scene.time += 1.0 / self.frequency
        scene._simulate(action)  # highway-env's stepping without its observation and reward (module doc)
        self.steps += 1
        ego = scene.vehicle
        collision, offroad = bool(ego.crashed), not ego.on_road
        observation, info = self._observe(collision=collision, offroad=offroad)
        v_x = info["features"][0]
        reward = 0.0 if collision or offroad else float(np.clip(v_x / self.speed_limit, 0.0, 1.0))
        terminated = collision or (offroad and self.offroad_terminal)
        truncated = not terminated and scene.time >= self.duration - 1e-9
        return observation, reward, terminated, truncated, info

    def close(self) -> None:
        self.scene.close()

    # --- features and ground truth ------------------------------------------------------------
    @property
    def ego(self) -> Any:
        """highway-env's controlled vehicle."""
        return self.scene.vehicle

    def features(self) -> np.ndarray:
        """The 10 features of the current state (physical units)."""
        return driving_features(self.scene.road, self.ego, lanes=self.lanes, lane_width=LANE_WIDTH,
                                sensor_range=self.sensor_range)

    def _observe(self, *, collision: bool, offroad: bool) -> tuple[np.ndarray, dict[str, Any]]:
        features = self.features()
        observation = np.clip(features / self._scales, -OBSERVATION_CLIP, OBSERVATION_CLIP).astype(np.float32)
        if self.constraint is None:
            cost = 1.0 if collision or offroad else 0.0
        else:
            cost = float(traffic_constraints.violated(self.constraint, self.bound, features))
        info = {"cost": cost, "collision": collision, "offroad": offroad,
                "features": features, "lane": int(self.ego.lane_index[2]), "speed": float(self.ego.speed)}
        return observation, info

    def _breaks_constraint(self, observations: Any) -> np.ndarray | bool:
        """Whether observations (rows of the policy's scaled features) break the constraint."""
        return traffic_constraints.violated_observations(self.constraint, self.bound, observations, self._scales)

    # --- scenes for tests and figures ---------------------------------------------------------
    def place(self, *, lane: int | None = None, speed: float | None = None, heading: float = 0.0,
              lateral: float = 0.0, others: Any = None) -> tuple[np.ndarray, dict[str, Any]]:
        """Rebuild the scene around the ego (after a reset); returns ``(observation, info)``.

        The ego keeps its distance along the road, moves to the centre of ``lane`` (default: its
        own) shifted by ``lateral`` metres (positive: to the right), with ``heading`` (rad,
        positive: turning right) and ``speed`` (m/s, default: its own). ``others`` replaces the
        traffic: ``(lane, ahead, speed)`` per car, ``ahead`` in metres from the ego's centre
        (negative: behind); these cars keep their lane and speed (no IDM: a test wants to know
        where they will be; 0 m/s is a car standing on the road).
        """
        from highway_env.vehicle.kinematics import Vehicle

        scene, ego = self.scene, self.ego
        road = scene.road
        start, end, own = ego.lane_index
        lane = own if lane is None else int(lane)
        if not 0 <= lane < self.lanes:
            raise DataError(f"lane {lane} does not exist (lanes 0..{self.lanes - 1}, 0 leftmost)")
        x = float(ego.position[0])
        ego.position = np.array([x, lane * LANE_WIDTH + float(lateral)], dtype=np.float64)
        ego.heading = float(heading)
        if speed is not None:
            ego.speed = float(speed)
        ego.crashed = False
        ego.on_state_update()
        if others is not None:
            road.vehicles = [ego]
            for other_lane, ahead, other_speed in others:
                index = (start, end, int(other_lane))
                car = Vehicle(road, road.network.get_lane(index).position(x + float(ahead), 0.0), 0.0,
                              float(other_speed))
                car.check_collisions = False  # as the fast highway's traffic: collisions only with the ego
                road.vehicles.append(car)
        return self._observe(collision=False, offroad=not ego.on_road)


def make_driving(**kwargs: Any) -> DrivingEnv:
    """The registry's factory."""
    return DrivingEnv(**kwargs)


__all__ = ["DrivingEnv", "FEATURE_NAMES", "LANE_WIDTH", "SPEED_LIMIT", "make_driving"]
