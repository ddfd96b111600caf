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


class _InfoEnv(gym.Env):
    """Counts steps; ``info["phase"]`` says whether the count is even or odd."""

    observation_space = gym.spaces.Discrete(10)
    action_space = gym.spaces.Discrete(1)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return 0, {"phase": "even"}

    def step(self, action):
        self.t += 1
        return self.t, 0.0, self.t >= 3, False, {"phase": "odd" if self.t % 2 else "even"}


def test_labeler_sees_info_and_the_labels_are_stored():
    demos = record(_InfoEnv(), lambda obs: 0, 1, seed=0, labeler=lambda obs, info: [info["phase"]])
    assert [sorted(step) for step in demos[0].labels] == [["even"], ["odd"], ["even"], ["odd"]]
    three = record(_InfoEnv(), lambda obs: 0, 1, seed=0, labeler=lambda obs, info, env: ["t"] if env.t else [])
    assert [sorted(step) for step in three[0].labels] == [[], ["t"], ["t"], ["t"]]


def test_labeler_returning_a_string_is_refused():
    with pytest.raises(SymlearnError, match="the labeler returned str 'even'"):
        record(_InfoEnv(), lambda obs: 0, 1, seed=0, labeler=lambda obs, info: info["phase"])


def test_what_is_stored_of_an_observation():
    demos = record(_InfoEnv(), lambda obs: 0, 1, seed=0, observation=lambda obs: obs * 10)
    assert demos[0].states.tolist() == [0, 10, 20, 30]


def test_a_dict_observation_holding_an_image_names_the_way_out():
    class Viewing(_InfoEnv):
        observation_space = gym.spaces.Dict({"image": gym.spaces.Box(0, 255, (2, 2), np.uint8)})

        def reset(self, seed=None, options=None):
            super().reset(seed=seed)
            return {"image": np.zeros((2, 2), np.uint8), "mission": "go"}, {}

        def step(self, action):
            _, r, end, cut, info = super().step(action)
            return {"image": np.full((2, 2), self.t, np.uint8), "mission": "go"}, r, end, cut, info

    with pytest.raises(SymlearnError, match=r"observation=lambda o: o\[KEY\]\); keys: image, mission"):
        record(Viewing(), lambda obs: 0, 1, seed=0)
    kept = record(Viewing(), lambda obs: 0, 1, seed=0, observation=lambda obs: obs["image"])
    assert kept.state_kind == "image" and kept[0].states[-1].tolist() == [[3, 3], [3, 3]]


class _Rover(_InfoEnv):
    """Dict(mode=Discrete, pos=Box(2), arm=Dict(joint=Box(1))): vectors and a nested part."""

    def _obs(self):
        return {"pos": np.array([0.5 * self.t, -0.25], np.float32), "mode": self.t % 2,
                "arm": {"joint": np.array([0.1 * self.t])}}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        return self._obs(), {}

    def step(self, action):
        _, r, end, cut, info = super().step(action)
        return self._obs(), r, end, cut, info


def test_a_dict_observation_of_vectors_becomes_named_columns():
    from symlearn.data.flat_observations import observation_features

    demos = record(_Rover(), lambda obs: 0, 1, seed=0)
    # the names of Minari's and imitation's readers: sorted keys, nested parts joined by ".",
    # a vector's entries (also a one-element vector's) as name[i]
    assert demos.metadata["feature_names"] == ["arm.joint[0]", "mode", "pos[0]", "pos[1]"]
    assert demos.state_kind == "vector"
    assert demos[0].states[2].tolist() == pytest.approx([0.2, 0.0, 1.0, -0.25])
    # the same names and values that train --cost reads from info["features"]
    live = _Rover()
    observation, _ = live.reset(seed=0)
    assert observation_features(observation) == dict(zip(demos.metadata["feature_names"],
                                                         demos[0].states[0].tolist()))


def test_a_flat_dict_of_numbers_stays_a_symbolic_state():
    class Cells(_InfoEnv):
        def reset(self, seed=None, options=None):
            super().reset(seed=seed)
            return {"cell": np.int64(0), "key": np.array(1)}, {}

        def step(self, action):
            _, r, end, cut, info = super().step(action)
            return {"cell": np.int64(self.t), "key": np.array(1)}, r, end, cut, info

    demos = record(Cells(), lambda obs: 0, 1, seed=0)
    assert "feature_names" not in demos.metadata
    assert demos[0].states[1] == {"cell": 1, "key": 1}
