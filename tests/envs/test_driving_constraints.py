"""The traffic constraints of thesis section 2.5.3 on the driving environment: a speed cap and a
minimum gap as ``info["cost"]``, the ground truth ``learn icrl`` measures recovery against, and the
IDM/MOBIL demonstrator that obeys them. Skipped without the ``highway`` extra."""

import numpy as np
import pytest

from symlearn import optional
from symlearn.errors import DataError

needs_highway = pytest.mark.skipif(not optional.available("highway"), reason="highway-env not installed")


def fresh(**kwargs):
    from symlearn.envs.driving import DrivingEnv

    env = DrivingEnv(**kwargs)
    env.reset(seed=0)
    return env


@needs_highway
@pytest.mark.parametrize("speed, cost", [(15.0, 0.0), (19.9, 0.0), (20.5, 1.0), (29.0, 1.0)])
def test_the_velocity_constraint_charges_speeding_only(speed, cost):
    env = fresh(constraint="velocity")
    observation, info = env.place(lane=1, speed=speed, others=[])
    assert info["cost"] == cost and not info["collision"]
    assert bool(env.unwrapped.is_unsafe(observation)) == bool(cost)
    # a step keeps the rule: the speed is what the next state has
    _, _, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    assert info["cost"] == float(info["features"][0] > 20.0)


@needs_highway
@pytest.mark.parametrize("ahead, cost", [(12.0, 1.0), (14.9, 1.0), (16.0, 0.0), (60.0, 0.0)])
def test_the_distance_constraint_charges_a_short_gap_in_the_own_lane(ahead, cost):
    # a gap is bumper to bumper: centres `ahead` metres apart, minus one 5 m car
    env = fresh(constraint="distance")
    observation, info = env.place(lane=1, speed=20.0, others=[(1, ahead, 20.0), (0, 6.0, 20.0)])
    assert info["cost"] == cost
    assert bool(env.unwrapped.is_unsafe(observation)) == bool(cost)


@needs_highway
def test_the_velocity_task_starts_at_the_cap():
    # highway-env starts the ego at 25 m/s: above the cap, every episode would pay for its first
    # second whatever the driver did, and PPO-Lagrangian learned to crash to end episodes early
    env = fresh(constraint="velocity")
    _, info = env.reset(seed=1)
    assert info["features"][0] == pytest.approx(20.0) and info["cost"] == 0.0
    assert fresh(constraint="velocity", bound=28.0).ego.speed == pytest.approx(25.0)


@needs_highway
def test_is_unsafe_is_vectorised_and_only_constrained_roads_have_it():
    env = fresh(constraint="velocity", bound=20.0)
    rows = np.zeros((3, 10), dtype=np.float32)
    rows[:, 0] = [0.5, 0.66, 0.7]            # v_x / 30: 15, 19.8 and 21 m/s
    assert env.is_unsafe(rows).tolist() == [False, False, True]
    plain = fresh()
    assert not hasattr(plain, "is_unsafe")
    _, info = plain.place(lane=1, speed=35.0, others=[])
    assert info["cost"] == 0.0               # the DNF experiment's cost: collisions and leaving the road


def test_bad_constraints_are_clear_errors():
    from symlearn.envs.driving import traffic_constraints

    with pytest.raises(DataError, match="unknown traffic constraint 'speed'"):
        traffic_constraints.check("speed", None)
    with pytest.raises(DataError, match="must be a positive number"):
        traffic_constraints.check("velocity", -3)
    with pytest.raises(DataError, match="needs a constraint"):
        traffic_constraints.check(None, 10.0)
    assert traffic_constraints.check("distance", None) == 10.0


@needs_highway
@pytest.mark.parametrize("constraint", ["velocity", "distance"])
def test_the_demonstrator_records_observations_and_obeys_the_constraint(constraint):
    from symlearn.envs.experts import driving_constrained

    demos = driving_constrained(2, seed=3, constraint=constraint)
    env = fresh(constraint=constraint)
    for trajectory in demos:
        assert trajectory.states.shape == (len(trajectory.actions) + 1, 10)
        assert env.observation_space.contains(trajectory.states[0].astype(np.float32))
        assert not (trajectory.info["collision"] or trajectory.info["offroad"])
    assert demos.metadata["constraint"] == constraint and demos.metadata["expert_violation_rate"] <= 0.05
    if constraint == "velocity":   # starting at the cap, IDM keeps below it (its desired speed is)
        assert all((t.states[:, 0] * 30.0 <= 20.0 + 1e-6).all() for t in demos)
        assert demos.metadata["expert_violation_rate"] == 0


def test_the_tasks_are_bundled_for_neural_icrl():
    from symlearn.envs.registry import get

    for name in ("driving-velocity", "driving-distance"):
        entry = get(name)
        assert "mce-icrl" in entry.methods and entry.gym_id == f"symlearn/{name}-v0"
