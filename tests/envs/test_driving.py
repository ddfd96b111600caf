"""Driving: highway-env's highway with a continuous action -- features, ground-truth events, the
IDM/MOBIL demonstrator, a DNF learned from it, the CLI. Skipped without the ``highway`` extra
(except the test that its absence is a clear error)."""

import json

import numpy as np
import pytest

from cli_runner import run
from symlearn import optional
from symlearn.errors import DataError, MissingDependencyError

needs_highway = pytest.mark.skipif(not optional.available("highway"), reason="highway-env not installed")
NAMES = ("v_x", "v_y", "lead_left", "follow_left", "lead_same", "follow_same", "lead_right", "follow_right",
         "d_left", "d_right")
STRAIGHT = np.zeros(2, dtype=np.float32)


def test_missing_highway_env_is_a_clear_error(monkeypatch):
    from symlearn.envs.driving import DrivingEnv

    monkeypatch.setattr(optional, "available", lambda name: False)
    with pytest.raises(MissingDependencyError, match="driving environment needs highway") as info:
        DrivingEnv()
    assert "symlearn[highway]" in info.value.hint


def fresh(seed=0, **kwargs):
    from symlearn.envs.driving import DrivingEnv

    env = DrivingEnv(**kwargs)
    env.reset(seed=seed)
    return env


def value(info, name):
    return float(info["features"][NAMES.index(name)])


def drive(env, action, steps):
    """Step ``action`` until the episode ends or ``steps`` run out; the list of (reward, term, trunc, info)."""
    out = []
    for _ in range(steps):
        _, reward, terminated, truncated, info = env.step(action)
        out.append((reward, terminated, truncated, info))
        if terminated or truncated:
            break
    return out


# --- observation and features ---------------------------------------------------------------------

@needs_highway
def test_features_have_their_names_units_and_scaled_observation():
    env = fresh()
    assert env.feature_names == NAMES and env.observation_space.shape == (10,)
    observation, info = env.place(lane=0, speed=25.0, others=[])
    features = info["features"]
    assert features.shape == (10,) and features.dtype == np.float64
    assert value(info, "v_x") == pytest.approx(25.0) and value(info, "v_y") == pytest.approx(0.0)
    # centre of the leftmost lane: 2 m to the left edge, 10 m to the right one (3 lanes of 4 m)
    assert value(info, "d_left") == pytest.approx(2.0) and value(info, "d_right") == pytest.approx(10.0)
    assert np.all(features[2:8] == env.sensor_range)  # nobody around, no lane on the left
    assert observation.dtype == np.float32 and env.observation_space.contains(observation)
    assert observation[0] == pytest.approx(25.0 / 30.0) and observation[2] == pytest.approx(1.0)


@needs_highway
def test_gaps_are_bumper_to_bumper_per_lane_and_capped_at_the_sensor_range():
    env = fresh()
    _, info = env.place(lane=1, speed=20.0, others=[(1, 30.0, 20.0), (1, -12.0, 20.0), (0, 8.0, 20.0),
                                                    (2, -40.0, 20.0), (2, 150.0, 20.0), (0, 60.0, 20.0)])
    assert value(info, "lead_same") == pytest.approx(25.0) and value(info, "follow_same") == pytest.approx(7.0)
    assert value(info, "lead_left") == pytest.approx(3.0)  # the nearer of the two cars ahead on the left
    assert value(info, "follow_left") == env.sensor_range
    assert value(info, "follow_right") == pytest.approx(35.0)
    assert value(info, "lead_right") == env.sensor_range  # 150 m ahead: out of range


@needs_highway
def test_the_vectorised_neighbour_search_answers_like_highway_env():
    from highway_env.road.road import Road

    env = fresh(seed=3, vehicles=30)
    checked = 0
    for step in range(30):
        env.step(np.array([0.3 if step % 3 else -0.2, 0.0]))
        road = env.scene.road
        for vehicle in road.vehicles:
            for lane in range(env.lanes):
                index = ("0", "1", lane)
                ours, theirs = road.neighbour_vehicles(vehicle, index), Road.neighbour_vehicles(road, vehicle, index)
                assert ours[0] is theirs[0] and ours[1] is theirs[1]
                checked += 1
        if env.ego.crashed:
            break
    assert checked > 500


@needs_highway
def test_a_seed_replays_the_episode_exactly():
    runs = []
    for _ in range(2):
        env = fresh(seed=7)
        rng = np.random.default_rng(0)
        runs.append([info["features"] for *_, info in drive(env, None, 0)] +
                    [env.step(np.clip(rng.normal(0, 0.3, 2), -1, 1))[4]["features"] for _ in range(20)])
    assert all(np.array_equal(a, b) for a, b in zip(*runs))
    other = fresh(seed=8)
    assert not np.array_equal(other.features(), fresh(seed=7).features())


# --- ground truth ---------------------------------------------------------------------------------

@needs_highway
def test_driving_into_a_standing_car_is_a_collision_and_braking_in_time_is_not():
    env = fresh()
    env.place(lane=1, speed=25.0, others=[(1, 80.0, 0.0)])
    steps = drive(env, STRAIGHT, 60)
    reward, terminated, _, info = steps[-1]
    assert info["collision"] and not info["offroad"] and info["cost"] == 1.0 and terminated and reward == 0.0
    assert all(s[3]["cost"] == 0.0 for s in steps[:-1])
    gaps = [value(s[3], "lead_same") for s in steps]
    assert gaps[-1] <= 0.5 and all(a > b for a, b in zip(gaps, gaps[1:]))
    # braking at 5 m/s^2 from 25 m/s stops within 62.5 m, short of the car 80 m ahead
    env.reset(seed=0)
    env.place(lane=1, speed=25.0, others=[(1, 80.0, 0.0)])
    steps = drive(env, np.array([-1.0, 0.0]), 40)
    assert not any(s[3]["collision"] for s in steps)
    speeds = [value(s[3], "v_x") for s in steps]
    # stopped; highway-env clamps the speed at 0 one step late, so it dips to -1 m/s at most
    assert abs(speeds[-1]) < 1.0 and min(speeds) >= -1.0


@needs_highway
def test_steering_off_the_road_is_off_road_and_driving_straight_never_is():
    env = fresh()
    env.place(lane=0, speed=25.0, others=[])
    steps = drive(env, np.array([0.0, -1.0]), 40)  # steer left from the leftmost lane
    reward, terminated, _, info = steps[-1]
    assert info["offroad"] and not info["collision"] and info["cost"] == 1.0 and terminated and reward == 0.0
    assert value(info, "d_left") < 0 <= value(steps[-2][3], "d_left")  # off-road = centre beyond the edge
    assert value(info, "v_y") < 0
    env.reset(seed=0)
    env.place(lane=2, speed=25.0, others=[])
    steps = drive(env, STRAIGHT, 500)
    assert len(steps) == 150 and steps[-1][2] and not steps[-1][1]  # truncated after 30 s at 5 Hz
    assert all(s[3]["cost"] == 0.0 for s in steps)
    assert all(0.0 < s[0] <= 1.0 for s in steps)  # progress reward at 25 of 30 m/s


@needs_highway
def test_off_road_need_not_end_the_episode():
    env = fresh(offroad_terminal=False)
    env.place(lane=2, speed=25.0, others=[])
    steps = drive(env, np.array([0.0, 1.0]), 25)  # steer right, off the rightmost lane
    offroad = [s[3]["offroad"] for s in steps]
    assert len(steps) == 25 and any(offroad) and not any(s[1] for s in steps)
    first = offroad.index(True)
    assert all(offroad[first:]) and all(s[3]["cost"] == 1.0 for s in steps[first:])


@needs_highway
def test_bad_input_is_a_clear_error():
    from symlearn.envs.driving import DrivingEnv

    env = fresh()
    with pytest.raises(DataError, match="2 finite numbers"):
        env.step(np.array([np.nan, 0.0]))
    with pytest.raises(DataError, match="2 finite numbers"):
        env.step(np.zeros(3))
    with pytest.raises(DataError, match="lane 3 does not exist"):
        env.place(lane=3)
    with pytest.raises(DataError, match="multiple of the policy frequency"):
        DrivingEnv(frequency=5, simulation_frequency=7)
    with pytest.raises(DataError, match="does not render"):
        DrivingEnv(render_mode="human")


# --- demonstrator and a learned DNF ---------------------------------------------------------------

@pytest.fixture(scope="module")
def demos():
    if not optional.available("highway"):
        pytest.skip("highway-env not installed")
    from symlearn.envs.driving.expert import expert_demonstrations

    return expert_demonstrations(8, seed=0, noise=0.1, safe_only=False)


@needs_highway
def test_the_demonstrator_drives_whole_episodes_without_collisions(demos):
    assert len(demos) == 8 and demos.metadata["features"] == list(NAMES)
    for trajectory in demos:
        assert trajectory.states.shape == (151, 10) and trajectory.actions.shape == (150, 2)
        assert np.abs(trajectory.actions).max() <= 1.0
        assert not trajectory.info["collision"] and not trajectory.info["offroad"]
        assert not any(trajectory.labels)
    states = np.concatenate([t.states for t in demos])
    assert states[:, NAMES.index("lead_same")].min() > 5.0  # keeps its distance
    assert states[:, NAMES.index("d_left")].min() > 1.0 and states[:, NAMES.index("d_right")].min() > 1.0
    assert sum(t.info["lane_changes"] for t in demos) >= 1  # MOBIL overtakes


@needs_highway
def test_the_demonstrator_is_seeded():
    from symlearn.envs.driving.expert import expert_demonstrations

    first, second = (expert_demonstrations(1, seed=5, noise=0.1) for _ in range(2))
    assert np.array_equal(first[0].states, second[0].states) and np.array_equal(first[0].actions, second[0].actions)


@needs_highway
def test_a_dnf_learned_from_the_demonstrator_flags_leaving_the_road_before_it_happens(demos):
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    dnf = OneClassTreeConstraint(max_depth=1).fit(demos, list(NAMES)).dnf_
    env = fresh(seed=1)
    env.place(lane=0, speed=25.0, others=[])
    steps = drive(env, np.array([0.0, -1.0]), 40)
    states = np.array([s[3]["features"] for s in steps])
    flagged = dnf.evaluate(states, list(NAMES))
    assert steps[-1][3]["offroad"] and flagged[-1]
    assert flagged[-2]  # one step before the centre crossed the edge, the formula already objects
    # ... and a car standing 10 m ahead in the ego's lane is a near-collision state it flags too
    _, info = env.place(lane=1, speed=25.0, others=[(1, 15.0, 0.0)])
    assert dnf.evaluate(info["features"][None, :], list(NAMES))[0]
    # while a straight, unhurried drive along a lane centre with the road to itself is not
    _, info = env.place(lane=1, speed=24.0, others=[])
    assert not dnf.evaluate(info["features"][None, :], list(NAMES))[0]


# --- registry and CLI -----------------------------------------------------------------------------

@needs_highway
def test_the_registered_id_builds_the_environment():
    import gymnasium

    import symlearn.envs  # noqa: F401

    env = gymnasium.make("symlearn/driving-v0")
    observation, info = env.reset(seed=0)
    assert observation.shape == (10,) and info["cost"] == 0.0 and env.unwrapped.feature_names == NAMES


@needs_highway
def test_learn_dnf_and_train_on_it_from_the_command_line(capsys, tmp_path):
    rules = tmp_path / "driving.dnf"
    code, out, err = run(capsys, "learn", "dnf", "--env", "driving", "--n-demos", 2, "--max-depth", 1, "-o", rules,
                         "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == list(NAMES) and doc["samples"] == 302 and rules.exists()
    assert any(c.startswith("d_left <") for c in doc["conjunctions"])
    code, out, err = run(capsys, "train", "--env", "driving", "--cost", rules, "--steps", 512, "--eval-episodes", 1,
                         "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["steps"] >= 512 and 0 <= doc["violation_rate"] <= 1 and len(doc["multipliers"]) == 1
