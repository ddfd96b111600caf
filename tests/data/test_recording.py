import gymnasium as gym
import numpy as np
import pytest

from symlearn.data import record
from symlearn.errors import SymlearnError


def test_record_is_seeded_and_complete():
    env = gym.make("FrozenLake-v1", is_slippery=True)
    demos = record(env, "random", 5, seed=3, labeler=lambda s: ["goal"] if s == 15 else [])
    again = record(gym.make("FrozenLake-v1", is_slippery=True), "random", 5, seed=3,
                   labeler=lambda s: ["goal"] if s == 15 else [])
    assert demos == again
    assert len(demos) == 5 and demos.state_kind == "discrete" and demos.action_kind == "discrete"
    for t in demos:
        assert len(t) == t.n_actions + 1
        assert t.info["terminated"] or t.info["truncated"]
        assert len(t.labels) == len(t)
    assert demos.metadata["env"] == "FrozenLake-v1" and demos.metadata["seed"] == 3


def test_each_episode_replays_from_its_own_seed():
    env = gym.make("FrozenLake-v1", is_slippery=True)
    policy = lambda s: 2  # noqa: E731
    demos = record(env, policy, 4, seed=11)
    third = demos[2]
    obs, _ = env.reset(seed=third.info["seed"])
    replay = [obs]
    for action in third.actions:
        obs, *_ = env.step(int(action))
        replay.append(obs)
    assert replay == third.states.tolist()


def test_vector_observations_and_max_steps():
    env = gym.make("CartPole-v1")
    demos = record(env, lambda obs: int(obs[2] > 0), 2, seed=0, max_steps=7)
    assert demos.state_kind == "vector" and demos[0].state_shape == (4,)
    assert all(t.n_actions <= 7 for t in demos)
    assert demos[0].states.dtype == np.float32


def test_bad_arguments():
    env = gym.make("FrozenLake-v1")
    with pytest.raises(SymlearnError, match="n_episodes must be at least 1"):
        record(env, "random", 0)
    with pytest.raises(SymlearnError, match="unknown policy 'greedy'"):
        record(env, "greedy", 1)
    with pytest.raises(SymlearnError, match="is not an environment"):
        record(object(), "random", 1)
