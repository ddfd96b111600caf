"""SafeNav: Safety-Gym's Point/Car x Goal/Push in numpy -- physics, lidar, cost, reward, speed, expert."""

import math
import time

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import symlearn.envs  # noqa: F401  (registers the gymnasium ids)
from symlearn.data import Demonstrations
from symlearn.envs.safenav import FEATURE_NAMES, SafeNavEnv
from symlearn.envs.safenav.layout import sample_layout
from symlearn.envs.safenav.lidar import bin_of, pseudo_lidar
from symlearn.envs.safenav_expert import expert_demonstrations
from symlearn.errors import DataError

VARIANTS = [(agent, task) for agent in ("point", "car") for task in ("goal", "push")]
FORWARD = {"point": np.array([1.0, 0.0], dtype=np.float32), "car": np.array([1.0, 1.0], dtype=np.float32)}
STILL = np.zeros(2, dtype=np.float32)


def fresh(agent="point", task="goal", **kwargs):
    env = SafeNavEnv(agent, task, **kwargs)
    env.reset(seed=0)
    return env


# --- gymnasium ------------------------------------------------------------------------------------

@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("agent, task", VARIANTS)
def test_the_env_checker_passes_on_the_registered_ids(agent, task):
    env = gymnasium.make(f"symlearn/safenav-{agent}-{task}-v0")
    check_env(env.unwrapped)
    observation, info = env.reset(seed=0)
    assert observation.shape == ((40,) if task == "goal" else (59,)) and observation.dtype == np.float32
    assert env.unwrapped.observation_names[:20] == FEATURE_NAMES


@pytest.mark.parametrize("agent, task", VARIANTS)
def test_a_seed_replays_the_episode_exactly(agent, task):
    runs = []
    for _ in range(2):
        env = SafeNavEnv(agent, task)
        first, _ = env.reset(seed=7)
        env.action_space.seed(7)
        steps = [env.step(env.action_space.sample()) for _ in range(200)]
        runs.append((first, env.hazards.copy(), steps))
    (a0, h0, s0), (a1, h1, s1) = runs
    assert np.array_equal(a0, a1) and np.array_equal(h0, h1)
    for (o0, r0, _, _, i0), (o1, r1, _, _, i1) in zip(s0, s1):
        assert np.array_equal(o0, o1) and r0 == r1 and np.array_equal(i0["features"], i1["features"])
    other = SafeNavEnv(agent, task)
    other.reset(seed=8)
    assert not np.array_equal(other.hazards, h0)


def test_the_layout_keeps_its_distances():
    rng = np.random.default_rng(0)
    for _ in range(50):
        layout = sample_layout(rng, box_radius=0.2)
        hazards = layout.hazards
        assert hazards.shape == (8, 2) and np.abs(hazards).max() <= 1.5
        gaps = np.hypot(*(hazards[:, None] - hazards[None]).transpose(2, 0, 1))
        assert gaps[~np.eye(8, dtype=bool)].min() >= 0.45  # no two hazards overlap
        assert np.hypot(*(hazards - layout.agent).T).min() >= 0.6  # the robot starts outside
        assert np.hypot(*(hazards - layout.goal).T).min() >= 0.55  # the goal circle is free
        assert np.hypot(*(hazards - layout.box).T).min() >= 0.45


def test_wrong_arguments_are_refused():
    with pytest.raises(DataError, match="unknown SafeNav agent"):
        SafeNavEnv("doggo")
    with pytest.raises(DataError, match="unknown SafeNav task"):
        SafeNavEnv("point", "button")
    with pytest.raises(DataError, match="only Push tasks have a box"):
        fresh().place(box=(0, 0))


# --- ground truth: cost ---------------------------------------------------------------------------

def test_the_cost_is_one_inside_a_hazard_and_zero_outside():
    env = fresh()
    centre = env.hazards[0]
    _, info = env.place(agent=centre)
    assert info["cost"] == 1.0
    assert env.step(STILL)[4]["cost"] == 1.0
    for distance, cost in ((0.19, 1.0), (0.2, 1.0), (0.21, 0.0), (0.6, 0.0)):
        _, info = env.place(agent=centre + [distance, 0.0], hazards=[centre])
        assert info["cost"] == cost, distance
        assert env.step(STILL)[4]["cost"] == cost, distance


@pytest.mark.parametrize("agent, task", VARIANTS)
def test_the_cost_is_exactly_a_lidar_reading_of_one(agent, task):
    # The ground truth is expressible over the features: inside a hazard <=> some bin reads 1.
    env = SafeNavEnv(agent, task)
    env.reset(seed=3)
    env.action_space.seed(3)
    seen = set()
    for hazard in env.hazards:  # drive through every hazard, with random wobbles
        start = hazard + [0.0, -0.6]
        if task == "push":
            env.place(box=hazard + [0.0, 0.6])  # out of the way
        env.place(agent=start, heading=math.pi / 2)
        for _ in range(60):
            action = FORWARD[agent] + 0.3 * env.action_space.sample()
            _, _, _, _, info = env.step(action)
            features = info["features"]
            assert features.shape == (20,) and features.dtype == np.float64 and np.isfinite(features).all()
            assert (features[4:] >= 1.0).any() == (info["cost"] == 1.0)
            assert (0.0 <= features[4:]).all() and (features[4:] <= 1.0).all()
            seen.add(info["cost"])
    assert seen == {0.0, 1.0}


# --- lidar ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("heading", [0.0, 1.0, -2.5])
@pytest.mark.parametrize("k", range(16))
def test_a_hazard_lights_the_bin_of_its_direction(heading, k):
    env = fresh()
    direction = heading + (k + 0.5) * 2 * math.pi / 16  # the middle of bin k, counter-clockwise from ahead
    hazard = np.array([math.cos(direction), math.sin(direction)])  # 1 m away
    _, info = env.place(agent=(0.0, 0.0), heading=heading, hazards=[hazard])
    lidar = info["features"][4:]
    assert int(np.argmax(lidar)) == k
    assert lidar[k] == pytest.approx(1 - 0.8 / 3)  # edge 0.8 m away, max_dist 3
    assert lidar[(k + 1) % 16] == pytest.approx(lidar[k] / 2) == pytest.approx(lidar[(k - 1) % 16])
    assert np.count_nonzero(lidar) == 3


def test_straight_ahead_is_bin_zero_and_left_is_bin_four():
    assert bin_of(0.0) == 0 and bin_of(0.01) == 0 and bin_of(-0.01) == 15
    assert bin_of(math.pi / 2 + 0.01) == 4 and bin_of(math.pi + 0.01) == 8
    env = fresh()
    _, info = env.place(agent=(0.0, 0.0), heading=math.pi / 2, hazards=[(0.0, 1.0)])  # ahead, facing +y
    lidar = info["features"][4:]
    assert lidar[0] == lidar.max() == lidar[15] > 0
    # Turning the robot turns the reading: the same hazard is now on its right (bins 11-12).
    _, info = env.place(heading=math.pi)
    assert info["features"][4:][12] == info["features"][4:].max()


def test_the_lidar_reads_closeness_and_ignores_far_hazards():
    here = pseudo_lidar(0.0, 0.0, 0.0, np.array([[1.0, 0.0], [0.0, 3.5]]), 0.2)
    assert here[0] == pytest.approx(1 - 0.8 / 3) and here[4] == 0.0
    inside = pseudo_lidar(0.05, 0.0, 0.0, np.array([[0.0, 0.0]]), 0.2)
    assert inside.max() == 1.0
    goal = pseudo_lidar(0.0, 0.0, 0.0, np.array([[0.0, -1.5]]))
    assert goal.argmax() in (11, 12) and goal.max() == pytest.approx(0.5)


# --- robots, reward, push -------------------------------------------------------------------------

@pytest.mark.parametrize("agent", ["point", "car"])
def test_driving_forward_moves_along_the_heading_at_about_one_metre_per_second(agent):
    env = fresh(agent)
    env.place(agent=(0.0, 0.0), heading=math.pi / 2, hazards=np.zeros((0, 2)))
    for _ in range(100):
        _, _, _, _, info = env.step(FORWARD[agent])
    assert abs(env.state.x) < 1e-9 and 1.4 < env.state.y < 2.0
    a_x, a_y, v_x, v_y = info["features"][:4]
    assert v_x == pytest.approx(1.0, abs=0.05) and abs(v_y) < 1e-9 and abs(a_x) < 0.5


def test_the_car_turns_in_place_with_opposite_wheels_and_the_point_turns_with_its_rotation():
    car = fresh("car")
    car.place(agent=(0.0, 0.0), heading=0.0, hazards=np.zeros((0, 2)))
    for _ in range(25):
        car.step(np.array([-1.0, 1.0], dtype=np.float32))
    assert math.hypot(car.state.x, car.state.y) < 1e-9 and car.state.heading > 0.5 and car.state.yaw_rate > 0
    point = fresh("point")
    point.place(agent=(0.0, 0.0), heading=0.0, hazards=np.zeros((0, 2)))
    for _ in range(25):
        point.step(np.array([0.0, -1.0], dtype=np.float32))
    assert point.state.heading == pytest.approx(2 * math.pi - 25 * 0.02 * 3.0)


def test_walls_stop_the_robot():
    env = fresh()
    env.place(agent=(1.7, 0.0), heading=0.0, hazards=np.zeros((0, 2)))
    for _ in range(50):
        _, _, _, _, info = env.step(FORWARD["point"])
    assert env.state.x == pytest.approx(1.9) and info["features"][2] == 0.0


@pytest.mark.parametrize("agent, task", VARIANTS)
def test_moving_toward_the_goal_pays_and_moving_away_costs(agent, task):
    env = fresh(agent, task)
    target = (1.0, 0.0) if task == "goal" else (0.6, 0.0)  # the box stands between robot and goal
    kwargs = {"box": (0.5, 0.0)} if task == "push" else {}
    env.place(agent=(-1.0, 0.0), heading=0.0, goal=(1.2, 0.0) if task == "push" else target,
              hazards=np.zeros((0, 2)), **kwargs)
    rewards = [env.step(FORWARD[agent])[1] for _ in range(40)]
    assert sum(rewards) > 0.5 and min(rewards) >= 0
    env.place(agent=(-1.0, 0.0), heading=math.pi, **kwargs)
    rewards = [env.step(FORWARD[agent])[1] for _ in range(40)]
    assert sum(rewards) < -0.3 and max(rewards) <= 0


def test_reaching_the_goal_pays_one_and_draws_a_new_goal():
    env = fresh()
    env.place(agent=(0.0, 0.0), heading=0.0, goal=(0.32, 0.0))
    _, reward, _, _, info = env.step(STILL)
    assert not info["goal_met"] and reward == 0.0
    for _ in range(20):
        _, reward, _, _, info = env.step(FORWARD["point"])
        if info["goal_met"]:
            break
    assert info["goal_met"] and info["goals_reached"] == 1 and 1.0 < reward < 1.1
    assert math.hypot(*(env.task.goal - [env.state.x, env.state.y])) >= 0.7


@pytest.mark.parametrize("agent", ["point", "car"])
def test_the_push_box_moves_when_pushed_and_only_then(agent):
    env = fresh(agent, "push")
    env.place(agent=(-0.5, 0.0), heading=0.0, box=(0.0, 0.0), goal=(1.4, 1.4), hazards=np.zeros((0, 2)))
    for _ in range(50):
        env.step(STILL)
    assert np.array_equal(env.task.box, [0.0, 0.0])
    for _ in range(100):
        env.step(FORWARD[agent])
    box = env.task.box
    assert box[0] > 0.5 and abs(box[1]) < 1e-6  # pushed straight ahead
    assert box[0] - env.state.x == pytest.approx(0.3, abs=0.02)  # the robot stays behind, in contact
    assert env.observation_names[40:42] == ("box_0", "box_1")


def test_pushing_the_box_into_the_goal_pays():
    env = fresh("point", "push")
    env.place(agent=(-0.5, 0.0), heading=0.0, box=(0.0, 0.0), goal=(0.8, 0.0), hazards=np.zeros((0, 2)))
    total, met = 0.0, False
    for _ in range(150):
        _, reward, _, _, info = env.step(FORWARD["point"])
        total += reward
        if info["goal_met"]:
            met = True
            break
    assert met and total > 1.5


# --- episodes, rendering, speed -------------------------------------------------------------------

@pytest.mark.parametrize("max_steps", [1000, 37])
def test_episodes_are_truncated_after_max_steps(max_steps):
    env = SafeNavEnv("car", "goal", max_steps=max_steps)
    env.reset(seed=0)
    for t in range(1, max_steps + 1):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        assert not terminated and truncated == (t == max_steps)


def test_gymnasium_make_passes_options():
    env = gymnasium.make("symlearn/safenav-point-push-v0", max_steps=12, render_mode="rgb_array")
    env.reset(seed=0)
    assert env.unwrapped.max_steps == 12 and env.unwrapped.task_name == "push"
    frame = env.render()
    assert frame.shape == (256, 256, 3) and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) >= 5  # floor, walls, hazards, goal, box, robot


@pytest.mark.parametrize("agent, task", VARIANTS)
def test_two_thousand_random_steps_take_less_than_two_seconds(agent, task):
    env = gymnasium.make(f"symlearn/safenav-{agent}-{task}-v0")  # with gymnasium's checking wrappers
    env.reset(seed=0)
    env.action_space.seed(0)
    start = time.perf_counter()
    for _ in range(2000):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
    assert time.perf_counter() - start < 2.0


# --- the scripted expert --------------------------------------------------------------------------

@pytest.mark.parametrize("agent, task", VARIANTS)
def test_the_expert_earns_reward_and_stays_out_of_the_hazards(agent, task):
    demos = expert_demonstrations(agent, task, n=2, seed=0, max_steps=400)
    assert isinstance(demos, Demonstrations) and len(demos) == 2
    assert demos.metadata["env"] == f"symlearn/safenav-{agent}-{task}-v0"
    for trajectory in demos:
        assert trajectory.states.shape == (401, 20) and trajectory.actions.shape == (400, 2)
        assert trajectory.info["cost"] == 0 and not any(trajectory.labels)
        assert (trajectory.states[:, 4:] < 1.0).all()
    assert sum(float(t.rewards.sum()) for t in demos) > (4.0 if task == "goal" else 1.0)
    assert sum(t.info["goals_reached"] for t in demos) >= (2 if task == "goal" else 0)


def test_expert_demonstrations_are_seeded():
    one = expert_demonstrations("point", "goal", n=1, seed=4, max_steps=50, noise=0.2)
    two = expert_demonstrations("point", "goal", n=1, seed=4, max_steps=50, noise=0.2)
    other = expert_demonstrations("point", "goal", n=1, seed=5, max_steps=50, noise=0.2)
    assert one == two and one != other
