"""The numeric view of observations that are not one Box or Discrete (MiniGrid's Dict with text)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

from symlearn.errors import DataError
from symlearn.recipes.spaces import NumericObservations, numeric_observations


class _Mixed(gym.Env):
    observation_space = spaces.Dict({"pos": spaces.Box(-1.0, 1.0, (2,)), "mode": spaces.Discrete(3),
                                     "note": spaces.Text(8), "grid": spaces.MultiBinary(2)})
    action_space = spaces.Discrete(2)

    def _obs(self):
        return {"pos": np.array([0.25, -0.5]), "mode": 2, "note": "hello", "grid": np.array([1, 0], dtype=np.int8)}

    def reset(self, seed=None, options=None):
        return self._obs(), {}

    def step(self, action):
        return self._obs(), 0.0, True, False, {}


def test_numeric_parts_are_kept_and_text_dropped():
    env = numeric_observations(_Mixed())
    assert isinstance(env, NumericObservations) and env.dropped == ["note"]
    assert env.observation_space.shape == (2 + 3 + 2,)
    observation, _ = env.reset()
    # Dict keys in sorted order (grid, mode, pos): one-hot Discrete, MultiBinary as it is
    assert observation.tolist() == [1.0, 0.0, 0.0, 0.0, 1.0, 0.25, -0.5]
    assert env.observation_space.contains(observation)


def test_box_and_discrete_environments_are_left_alone():
    env = gym.make("CartPole-v1")
    assert numeric_observations(env) is env


def test_nothing_numeric_is_one_clear_error():
    class Words(_Mixed):
        observation_space = spaces.Dict({"note": spaces.Text(8)})

    with pytest.raises(DataError, match="has no numeric part"):
        numeric_observations(Words())


def test_minigrid_observations_become_one_vector():
    pytest.importorskip("minigrid")
    env = numeric_observations(gym.make("MiniGrid-Empty-5x5-v0"))
    observation, _ = env.reset(seed=0)
    assert env.dropped == ["mission"] and observation.shape == (4 + 7 * 7 * 3,)
    assert env.observation_space.contains(env.step(2)[0])


def test_train_reaches_a_third_party_dict_environment(capsys):
    """A pip-installed package's environment with a Dict observation trains from the CLI."""
    pytest.importorskip("minigrid")
    import json

    from cli_runner import run

    code, out, err = run(capsys, "train", "--env", "minigrid:MiniGrid-Empty-5x5-v0", "--steps", 256, "--n-envs", 1,
                         "--n-steps", 128, "--eval-episodes", 1, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["algo"] == "ppo" and doc["cost"] is None and doc["violation_rate"] is None


class _Arm(gym.Env):
    """A Dict with a vector part and an image: features by name, the image left out of them."""
    observation_space = spaces.Dict({"pos": spaces.Box(-1.0, 1.0, (2,)), "mode": spaces.Discrete(3),
                                     "camera": spaces.Box(0, 255, (2, 2), np.uint8)})
    action_space = spaces.Discrete(2)

    def _obs(self):
        return {"pos": np.array([0.25, -0.5], np.float32), "mode": 2, "camera": np.zeros((2, 2), np.uint8)}

    def reset(self, seed=None, options=None):
        return self._obs(), {}

    def step(self, action):
        return self._obs(), 0.0, True, False, {}


def test_dict_observations_are_reported_by_the_recorded_names():
    env = numeric_observations(_Arm())
    observation, info = env.reset()
    assert observation.shape == (3 + 2 + 4,)   # the policy's view: one-hot mode, pos, the pixels
    assert info["features"] == {"mode": 2.0, "pos[0]": 0.25, "pos[1]": -0.5}
    *_, info = env.step(0)
    assert set(info["features"]) == {"mode", "pos[0]", "pos[1]"}


def test_a_tuple_of_numbers_is_named_as_learn_dnf_names_a_vector():
    class Cards(_Arm):
        observation_space = spaces.Tuple((spaces.Discrete(32), spaces.Discrete(11), spaces.Discrete(2)))

        def _obs(self):
            return (14, 10, 0)

    _, info = numeric_observations(Cards()).reset()
    # not the one-hot columns (32 + 11 + 2) that a formula over x0 would otherwise misread
    assert info["features"] == {"x0": 14.0, "x1": 10.0, "x2": 0.0}


def test_named_columns_rebuild_the_policy_view():
    """What record() stores of an observation (named columns) maps back onto the flattened view,
    for every kind of numeric part, and the view's entries are named."""
    from symlearn.data.flat_observations import observation_features

    class Every(_Arm):
        observation_space = spaces.Dict({"pos": spaces.Box(-1.0, 1.0, (2,)), "m": spaces.Discrete(3, start=1),
                                         "md": spaces.MultiDiscrete([2, 3]), "b": spaces.MultiBinary(2),
                                         "arm": spaces.Dict({"joint": spaces.Box(-1.0, 1.0, (1,))})})

        def _obs(self):
            return {"pos": np.array([0.1, 0.2], np.float32), "m": 2, "md": np.array([1, 2]),
                    "b": np.array([1, 0], np.int8), "arm": {"joint": np.array([0.5], np.float32)}}

    env = numeric_observations(Every())
    observation = Every()._obs()
    assert np.array_equal(env.from_columns(observation_features(observation)), env.observation(observation))
    assert env.column_names == ("arm.joint[0]", "b[0]", "b[1]", "m=1", "m=2", "m=3", "md[0]=0", "md[0]=1",
                                "md[1]=0", "md[1]=1", "md[1]=2", "pos[0]", "pos[1]")
    with pytest.raises(DataError, match="no column 'pos\\[1\\]'"):
        env.from_columns({k: v for k, v in observation_features(observation).items() if k != "pos[1]"})
