"""The IDM/MOBIL demonstrator of the driving environment, and demonstrations recorded with it.

The thesis learns its driving constraints from human highD trajectories, which need a licence.
Our demonstrator is the traffic model highway-env's own cars drive by: IDM (Treiber et al.,
2000) for the acceleration, MOBIL (Kesting et al., 2007) for lane changes, highway-env's
lateral controller for the steering. It drives the ego *through the environment's continuous
action*, so a demonstration is exactly what an agent could have done:

* every step, a highway-env ``IDMVehicle`` (the *planner*) takes the ego's position, heading,
  speed and lane, decides as if it were the ego (it stands in for the ego in the road's vehicle
  list while deciding, so the ego does not see itself as the car ahead), and its acceleration
  and steering, divided by the action ranges and clipped to ``[-1, 1]``, are the action;
* its lane-change state (target lane, MOBIL's timer) carries over between steps, as in a
  highway-env car; its desired speed is drawn per episode from ``target_speeds`` (m/s);
* ``noise`` adds Gaussian noise of that standard deviation to both action entries (then
  clipped), the recorded action being the noisy one. The clean driver keeps ``v_y`` at exactly
  0 between lane changes and the lane centres exactly, so a tree fitted to it calls any sway
  unsafe; a little noise stands in for a human's imprecision.

:func:`expert_demonstrations` records ``n`` episodes as :class:`~symlearn.data.Demonstrations`:
states are ``info["features"]`` (the 10 features, the reset's first), actions the 2-D actions,
rewards the environment's, labels ``{"collision"}`` / ``{"offroad"}`` on the states where the
ground truth fired; each trajectory's ``info`` has its seed, desired speed, lane changes and
whether it ended in a collision or off the road. IDM/MOBIL is not collision-free here (highway-
env's other cars also change lanes, and MOBIL does not foresee two cars taking one gap), so
with ``safe_only=True`` (default) an episode that ends in a collision or off the road is
replaced by a fresh one: the thesis' premise is demonstrations of *safe* behaviour. The
metadata counts the replaced episodes.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.driving.env import DrivingEnv
from symlearn.envs.expert_episode import record_episode
from symlearn.errors import DataError
from symlearn.progress import progress


class IdmMobilExpert:
    """``IdmMobilExpert(env, target_speed)``: call :meth:`reset` after each ``env.reset``, then
    ``expert()`` gives the next action."""

    def __init__(self, env: DrivingEnv, target_speed: float = 30.0, *, noise: float = 0.0,
                 rng: np.random.Generator | None = None) -> None:
        if noise < 0:
            raise DataError(f"noise must be >= 0, got {noise}")
        self.env = env
        self.target_speed = float(target_speed)
        self.noise = float(noise)
        self.rng = rng if rng is not None else np.random.default_rng()
        self.planner: Any = None
        self.lane_changes = 0

    def reset(self, target_speed: float | None = None) -> None:
        from highway_env.vehicle.behavior import IDMVehicle

        if target_speed is not None:
            self.target_speed = float(target_speed)
        ego = self.env.ego
        self.planner = IDMVehicle(self.env.scene.road, ego.position.copy(), ego.heading, ego.speed,
                                  target_lane_index=ego.lane_index, target_speed=self.target_speed)
        self.lane_changes = 0

    def __call__(self) -> np.ndarray:
        if self.planner is None:
            raise DataError("call reset() after the environment's reset, before asking for actions")
        env, planner, ego = self.env, self.planner, self.env.ego
        road = env.scene.road
        planner.road = road  # a reset builds a new road
        planner.position = ego.position.copy()
        planner.heading, planner.speed = ego.heading, ego.speed
        planner.lane_index, planner.lane = ego.lane_index, ego.lane
        planner.crashed = False
        before = planner.target_lane_index
        where = next(i for i, v in enumerate(road.vehicles) if v is ego)
        road.vehicles[where] = planner
        try:
            planner.act()
        finally:
            road.vehicles[where] = ego
        if planner.target_lane_index != before:
            self.lane_changes += 1
        # IDMVehicle.step advances MOBIL's timer; the planner never steps, so we do it
        planner.timer += 1.0 / env.frequency
        command = planner.action
        action = np.array([command["acceleration"] / env.acceleration_range, command["steering"] / env.steering_range])
        if self.noise > 0:
            action = action + self.rng.normal(0.0, self.noise, size=2)
        return np.clip(action, -1.0, 1.0)


def expert_demonstrations(n: int = 10, seed: int | None = 0, *, target_speeds: tuple[float, float] = (24.0, 30.0),
                          noise: float = 0.0, safe_only: bool = True, max_attempts: int | None = None,
                          env: DrivingEnv | None = None, **env_kwargs: Any) -> Demonstrations:
    """``n`` IDM/MOBIL episodes of ``symlearn/driving-v0`` (see the module docstring).

    ``max_attempts`` bounds the episodes tried when ``safe_only`` replaces unsafe ones (default
    ``2 n + 10``); running out is a :class:`~symlearn.errors.DataError`.
    """
    if n < 1:
        raise DataError(f"n must be at least 1, got {n}")
    low, high = (float(v) for v in target_speeds)
    if not 0 < low <= high:
        raise DataError(f"target_speeds must be (low, high) with 0 < low <= high, got {target_speeds}")
    env = env or DrivingEnv(**env_kwargs)
    rng = np.random.default_rng(seed)
    expert = IdmMobilExpert(env, noise=noise, rng=np.random.default_rng(rng.integers(2**63)))
    attempts = max_attempts if max_attempts is not None else 2 * n + 10
    trajectories, replaced, tried = [], 0, 0
    bar = progress(range(n), total=n, desc="driving IDM/MOBIL expert", unit="episode")
    for _ in bar:
        while True:
            if tried >= attempts:
                raise DataError(f"only {len(trajectories)} of {n} safe episodes in {attempts} attempts",
                                hint="raise max_attempts, or pass safe_only=False")
            tried += 1
            trajectory = _episode(env, expert, int(rng.integers(2**31)), float(rng.uniform(low, high)))
            if not safe_only or not (trajectory.info["collision"] or trajectory.info["offroad"]):
                break
            replaced += 1
        trajectories.append(trajectory)
    metadata = {"env": "symlearn/driving-v0", "expert": "IDM/MOBIL (highway-env IDMVehicle)", "seed": seed,
                "n_episodes": n, "target_speeds": [low, high], "noise": noise, "safe_only": safe_only, "replaced_unsafe": replaced,
                "features": list(env.feature_names)}
    return Demonstrations(trajectories, metadata=metadata)


def constrained_demonstrations(n: int = 20, seed: int | None = 0, *, constraint: str,
                               env: DrivingEnv | None = None, **env_kwargs: Any) -> Demonstrations:
    """``n`` IDM/MOBIL episodes on ``DrivingEnv(constraint=...)`` for neural ICRL (thesis section
    2.5.3): states are the policy's *observations* (what ``learn icrl`` compares the policy's
    with), not ``info["features"]``. The demonstrator obeys the constraint the way a driver
    would: under the ``velocity`` cap it wants 1-5 m/s less than the cap (IDM never overshoots
    its desired speed), under the ``distance`` rule it drives as usual (IDM's spacing keeps the
    gap above 10 m at highway speeds). Episodes ending in a collision or off the road are
    replaced; steps on which the constraint is broken anyway (a car cutting in ahead) are kept and
    counted in the metadata (``expert_violation_rate``), as the thesis' experts break theirs too.
    """
    if n < 1:
        raise DataError(f"n must be at least 1, got {n}")
    env = env or DrivingEnv(constraint=constraint, **env_kwargs)
    if env.constraint != constraint:
        raise DataError(f"the environment's constraint is {env.constraint!r}, not {constraint!r}")
    low, high = ((env.bound - 5.0, env.bound - 1.0) if constraint == "velocity" else (24.0, 30.0))
    if low <= 0:
        raise DataError(f"a velocity cap of {env.bound} m/s leaves the demonstrator no speed to drive at",
                        hint="a cap above 6 m/s")
    rng = np.random.default_rng(seed)
    expert = IdmMobilExpert(env, rng=np.random.default_rng(rng.integers(2**63)))
    trajectories, replaced, violations, steps = [], 0, 0, 0
    for _ in progress(range(n), total=n, desc=f"driving IDM/MOBIL expert ({constraint})", unit="episode"):
        for _attempt in range(50):
            trajectory, broken = _observed_episode(env, expert, int(rng.integers(2**31)), float(rng.uniform(low, high)))
            if not (trajectory.info["collision"] or trajectory.info["offroad"]):
                break
            replaced += 1
        else:
            raise DataError("the demonstrator crashed in 50 episodes in a row")
        trajectories.append(trajectory)
        violations, steps = violations + broken, steps + len(trajectory.actions)
    metadata = {"env": f"symlearn/driving-{constraint}-v0", "expert": "IDM/MOBIL (highway-env IDMVehicle)",
                "seed": seed, "n_episodes": n, "target_speeds": [low, high], "constraint": constraint,
                "bound": env.bound, "replaced_unsafe": replaced, "expert_violation_rate": violations / max(steps, 1),
                "observation_names": list(env.observation_names)}
    return Demonstrations(trajectories, metadata=metadata)


def _observed_episode(env: DrivingEnv, expert: IdmMobilExpert, seed: int,
                      target_speed: float) -> tuple[Trajectory, int]:
    """One episode with the observations as states, and how many of its steps paid the cost."""
    observation, info = env.reset(seed=seed)
    expert.reset(target_speed)
    states, actions, rewards, broken = [observation], [], [], 0
    done = False
    while not done:
        action = expert()
        observation, reward, terminated, truncated, info = env.step(action)
        done = terminated or truncated
        states.append(observation)
        actions.append(action)
        rewards.append(reward)
        broken += info["cost"] > 0
    trajectory = Trajectory(np.array(states), np.array(actions), rewards,
                            info={"seed": seed, "target_speed": target_speed, "lane_changes": expert.lane_changes,
                                  "collision": bool(info["collision"]), "offroad": bool(info["offroad"])})
    return trajectory, int(broken)


def _episode(env: DrivingEnv, expert: IdmMobilExpert, seed: int, target_speed: float) -> Trajectory:
    states, actions, rewards, labels, info = record_episode(env, expert, seed, _label,
                                                            start=lambda: expert.reset(target_speed))
    return Trajectory(states, actions, rewards, labels,
                      info={"seed": seed, "target_speed": target_speed, "lane_changes": expert.lane_changes,
                            "collision": bool(info["collision"]), "offroad": bool(info["offroad"])})


def _label(info: dict[str, Any]) -> tuple[str, ...]:
    return tuple(name for name in ("collision", "offroad") if info[name])


__all__ = ["IdmMobilExpert", "constrained_demonstrations", "expert_demonstrations"]
