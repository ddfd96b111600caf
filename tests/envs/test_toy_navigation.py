"""The thesis' toy navigation task (section 4.3.1): safe set, cost, reward, expert demonstrations."""

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import symlearn.envs  # noqa: F401  (registers the gymnasium ids)
from symlearn.data import Demonstrations
from symlearn.envs.toy_navigation import (
    GOAL, SAFE_RECTANGLES, START, UNSAFE_DNF, ToyNavigationEnv, expert_demonstrations, is_safe,
)
from symlearn.errors import DataError

GRID = np.linspace(0.0, 1.0, 101)


@pytest.mark.filterwarnings("error")
def test_the_env_checker_passes():
    env = gymnasium.make("symlearn/toy-navigation-v0")
    check_env(env.unwrapped)
    observation, info = env.reset(seed=0)
    assert np.allclose(observation, START) and info["cost"] == 0.0 and info["features"].tolist() == [0.1, 0.1]


@pytest.mark.parametrize("point, safe", [
    ((0.1, 0.1), True), ((0.4, 0.2), True), ((0.7, 0.3), True), ((0.8, 0.5), True), ((0.9, 0.9), True),
    ((0.5, 0.5), False), ((0.4, 0.31), False), ((0.05, 0.2), False), ((0.95, 0.5), False),
    ((0.8, 0.95), False), ((0.3, 0.05), False), ((0.69, 0.8), False),
])
def test_the_safe_set_is_the_thesis_l_shape(point, safe):
    assert is_safe(*point) == safe
    env = ToyNavigationEnv()
    env.reset(seed=0)
    env.position = np.array(point, dtype=np.float64)
    _, _, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    assert info["cost"] == (0.0 if safe else 1.0)
    assert info["features"].tolist() == list(point)


def test_the_unsafe_dnf_text_is_the_complement_of_the_safe_set():
    dnf = pytest.importorskip("symlearn.logic.dnf")
    formula = dnf.parse(UNSAFE_DNF)
    xs, ys = np.meshgrid(GRID, GRID)
    X = np.stack([xs.ravel(), ys.ravel()], axis=1)
    unsafe = np.asarray(formula.evaluate(X, ["x", "y"])).astype(bool)
    assert (unsafe == ~np.array([is_safe(x, y) for x, y in X])).all()


def test_the_diagonal_is_unsafe_and_rewards_progress():
    env = ToyNavigationEnv()
    env.reset(seed=0)
    costs, rewards = [], []
    terminated = False
    while not terminated:
        _, reward, terminated, truncated, info = env.step(np.array([1.0, 1.0], dtype=np.float32))
        costs.append(info["cost"])
        rewards.append(reward)
        assert not truncated
    assert terminated and max(costs) == 1.0 and all(r > 0 for r in rewards)
    # progress, plus the goal bonus on the last step
    assert sum(rewards) == pytest.approx(np.hypot(0.8, 0.8) - env.distance() + env.goal_reward)
    assert env.goal_reward == 1.0 and rewards[-1] > 1.0 > max(rewards[:-1])
    assert np.hypot(*(env.position - GOAL)) <= env.goal_radius
    env.reset()
    _, reward, _, _, _ = env.step(np.array([-1.0, 0.0], dtype=np.float32))
    assert reward < 0 and env.position.tolist() == [0.05, 0.1]


def test_actions_are_clipped_and_the_square_bounds_the_agent():
    env = ToyNavigationEnv(max_steps=5)
    env.reset(seed=0)
    env.step(np.array([100.0, -100.0]))
    assert env.position == pytest.approx([0.15, 0.05])
    for t in range(2, 6):
        _, _, terminated, truncated, _ = env.step(np.array([0.0, -1.0], dtype=np.float32))
        assert not terminated and truncated == (t == 5)
    assert env.position == pytest.approx([0.15, 0.0])


def test_bad_arguments_are_refused():
    with pytest.raises(DataError):
        ToyNavigationEnv(speed=0.0)
    with pytest.raises(DataError, match="goal_reward"):
        ToyNavigationEnv(goal_reward=float("nan"))
    with pytest.raises(DataError):
        expert_demonstrations(0)
    with pytest.raises(DataError):
        expert_demonstrations(3, noise=-1)


def test_render_draws_the_safe_set():
    env = ToyNavigationEnv(render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (128, 128, 3) and frame.dtype == np.uint8


# --- the expert -----------------------------------------------------------------------------------

@pytest.mark.parametrize("noise", [0.0, 0.1, 0.5])
def test_expert_demonstrations_never_enter_the_unsafe_set_and_reach_the_goal(noise):
    demos = expert_demonstrations(30, seed=1, noise=noise)
    assert isinstance(demos, Demonstrations) and len(demos) == 30 and demos.state_kind == "vector"
    for trajectory in demos:
        states = trajectory.states
        assert states.shape[1] == 2 and states[0].tolist() == list(START)
        assert all(is_safe(x, y) for x, y in states)
        assert trajectory.info["reached_goal"] and np.hypot(*(states[-1] - GOAL)) <= 0.05
        assert len(trajectory.actions) == len(states) - 1 and trajectory.rewards.sum() > 0.7
    # The route is the L, not the diagonal: the demonstrations fill both rectangles.
    everything = np.concatenate([t.states for t in demos])
    x0, x1, y0, y1 = SAFE_RECTANGLES[0]
    assert ((everything[:, 0] < 0.5) & (everything[:, 1] <= y1)).any()
    assert ((everything[:, 0] >= 0.7) & (everything[:, 1] > 0.6)).any()


def test_expert_demonstrations_vary_with_noise_and_are_seeded():
    one = expert_demonstrations(5, seed=3, noise=0.1)
    assert one == expert_demonstrations(5, seed=3, noise=0.1) and one != expert_demonstrations(5, seed=4, noise=0.1)
    assert len({t.states.tobytes() for t in one}) == 5
    clean = expert_demonstrations(2, seed=3, noise=0.0)
    assert np.array_equal(clean[0].states, clean[1].states)
