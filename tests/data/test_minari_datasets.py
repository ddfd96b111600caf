"""Minari datasets written by Minari's own DataCollector read back as what was collected."""

from __future__ import annotations

import json
import shutil

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

from symlearn.data import load, record
from symlearn.data.files import detect
from symlearn.errors import DataError, LimitExceededError, MissingDependencyError

minari = pytest.importorskip("minari")
pytest.importorskip("jax")  # Minari's DataCollector needs it (minari[create])
h5py = pytest.importorskip("h5py")
# Minari asks for a description and an evaluation environment; these throwaway datasets need neither
pytestmark = pytest.mark.filterwarnings("ignore::UserWarning:minari")


class DictRoom(gym.Env):
    """A point in a square with a goal; Dict observations with a nested Dict and a Discrete flag."""

    def __init__(self):
        box = spaces.Box(-1.0, 1.0, (2,), dtype=np.float64)
        self.observation_space = spaces.Dict({"pos": box, "goal": spaces.Dict({"xy": box}),
                                              "near": spaces.Discrete(2)})
        self.action_space = spaces.Box(-0.2, 0.2, (2,), dtype=np.float64)

    def _obs(self):
        near = int(np.linalg.norm(self.pos - self.goal) < 0.3)
        return {"pos": self.pos.copy(), "goal": {"xy": self.goal.copy()}, "near": near}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = self.np_random.uniform(-1, 1, 2)
        self.goal = self.np_random.uniform(-1, 1, 2)
        self.t = 0
        return self._obs(), {"cost": 0.0}

    def step(self, action):
        self.pos = np.clip(self.pos + action, -1, 1)
        self.t += 1
        done = bool(np.linalg.norm(self.pos - self.goal) < 0.1)
        return self._obs(), -1.0, done, self.t >= 12, {"cost": float(abs(self.pos[0]) > 0.9)}


def _collect(env, tmp_path, monkeypatch, name, n=4, seed=3):
    """Record ``n`` episodes with symlearn's record() driving Minari's DataCollector."""
    from minari import DataCollector

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    collector = DataCollector(env, record_infos=True)
    demos = record(collector, "random", n, seed=seed)
    collector.create_dataset(dataset_id=f"{name}/test-v0", algorithm_name="random", author="t",
                             author_email="t@example.org", code_permalink="none")
    collector.close()
    return demos, tmp_path / "minari" / name / "test-v0"


@pytest.fixture
def cartpole(tmp_path, monkeypatch):
    return _collect(gym.make("CartPole-v1", max_episode_steps=30), tmp_path, monkeypatch, "cartpole")


def test_collected_episodes_read_back_equal(cartpole):
    collected, folder = cartpole
    demos = load(folder)
    assert detect(folder) == "minari"
    assert len(demos) == 4
    assert list(demos) == list(collected)  # states (float32), actions, rewards, seeds, ends: all equal
    assert demos[0].states.dtype == np.float32 and demos.action_kind == "discrete"
    assert demos.metadata["env"] == "CartPole-v1" and demos.metadata["dataset_id"] == "cartpole/test-v0"
    assert demos.metadata["source_format"] == "minari"
    # the data folder and the HDF5 file name the same dataset
    assert list(load(folder / "data")) == list(collected)
    assert list(load(folder / "data" / "main_data.hdf5")) == list(collected)


def test_dict_observations_are_flattened_in_gymnasium_order(tmp_path, monkeypatch):
    from minari import DataCollector

    # record() keeps states symlearn can hold, and a Dict of vectors is not one: step by hand
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    collector = DataCollector(gym.wrappers.TimeLimit(DictRoom(), 12), record_infos=True)
    collector.action_space.seed(0)
    episodes = []
    for seed in (1, 2, 3):
        observation, _ = collector.reset(seed=seed)
        observations, done = [observation], False
        while not done:
            observation, _, terminated, truncated, _ = collector.step(collector.action_space.sample())
            observations.append(observation)
            done = terminated or truncated
        episodes.append(observations)
    collector.create_dataset(dataset_id="room/test-v0", author="t", author_email="t@example.org",
                             code_permalink="none", algorithm_name="random")
    demos = load(tmp_path / "minari" / "room" / "test-v0")
    assert demos.metadata["feature_names"] == ["goal.xy[0]", "goal.xy[1]", "near", "pos[0]", "pos[1]"]
    assert demos.metadata["minari_infos"] == ["cost"]
    assert [t.info["seed"] for t in demos] == [1, 2, 3]
    goal_space = DictRoom().observation_space["goal"]
    for ours, observations in zip(demos, episodes):
        assert len(ours) == len(observations)
        for state, observation in zip(ours.states, observations):
            # Box leaves in gymnasium.spaces.flatten's order, the Discrete leaf as one integer column
            expected = np.concatenate([spaces.flatten(goal_space, observation["goal"]), [observation["near"]],
                                       observation["pos"]])
            np.testing.assert_array_equal(state, expected)


def test_cli_info_and_convert_from_a_minari_folder(cartpole, tmp_path, run_cli):
    collected, folder = cartpole
    done = run_cli("data", "info", folder, "--json")
    assert done.returncode == 0, done.stderr
    doc = json.loads(done.stdout)
    assert doc["format"] == "minari" and doc["summary"]["n_trajectories"] == 4
    for target in ("d.hdf5", "d.jsonl"):
        done = run_cli("data", "convert", folder, tmp_path / target)
        assert done.returncode == 0, done.stderr
        assert list(load(tmp_path / target)) == list(collected)


def _copy(folder, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    return copy, copy / "data" / "main_data.hdf5"


def test_broken_episodes_name_the_file_and_dataset(cartpole, tmp_path):
    _, folder = cartpole
    copy, data = _copy(folder, tmp_path)
    with h5py.File(data, "r+") as handle:
        observations = handle["episode_1/observations"][()]
        del handle["episode_1/observations"]
        handle["episode_1/observations"] = observations[:-2]
    with pytest.raises(DataError, match=r"main_data.hdf5: '/episode_1/observations' has \d+ rows, expected"):
        load(copy)
    with h5py.File(data, "r+") as handle:
        del handle["episode_1/observations"]
        handle["episode_1/observations"] = h5py.ExternalLink("elsewhere.h5", "/x")
    with pytest.raises(DataError, match="link to another file"):
        load(copy)
    with h5py.File(data, "r+") as handle:
        del handle["episode_1/observations"]
        handle.create_dataset("episode_1/observations", data=["a"] * len(observations),
                              dtype=h5py.string_dtype())
    with pytest.raises(DataError, match="dtype"):
        load(copy)


def test_declared_sizes_are_checked_before_reading(cartpole, tmp_path, monkeypatch):
    _, folder = cartpole
    copy, data = _copy(folder, tmp_path)
    with h5py.File(data, "r+") as handle:
        # 2**34 float64 rows declared, none written: a tiny file that would need 128 GB to read
        handle.create_dataset("episode_0/observations_big", shape=(2**34,), dtype="f8", chunks=(2**16,))
        del handle["episode_0/observations"]
        handle["episode_0/observations"] = handle["episode_0/observations_big"]
    with pytest.raises(LimitExceededError, match="SYMLEARN_MAX_ARRAY_MB"):
        load(copy)
    monkeypatch.setenv("SYMLEARN_MAX_ARRAY_MB", "0.0001")
    with pytest.raises(LimitExceededError, match="file size"):
        load(folder)


def test_folders_that_are_no_minari_dataset(tmp_path, cartpole):
    with pytest.raises(DataError, match="not a Minari dataset"):
        load(tmp_path)
    _, folder = cartpole
    copy, data = _copy(folder, tmp_path)
    meta = json.loads((copy / "data" / "metadata.json").read_text())
    (copy / "data" / "metadata.json").write_text(json.dumps({**meta, "data_format": "arrow"}))
    with pytest.raises(DataError, match="data_format 'arrow'"):
        load(copy)
    data.unlink()
    with pytest.raises(DataError, match="no main_data.hdf5"):
        load(copy)
    (tmp_path / "fake.hdf5").write_bytes(b"not hdf5 at all")
    with pytest.raises(DataError, match="fake.hdf5: not a readable HDF5 file"):
        load(tmp_path / "fake.hdf5")


def test_without_h5py_the_error_says_how_to_install(cartpole, monkeypatch):
    _, folder = cartpole
    monkeypatch.setitem(__import__("sys").modules, "h5py", None)
    with pytest.raises(MissingDependencyError, match="h5py") as caught:
        load(folder)
    assert "symlearn[formats]" in caught.value.hint


class Frames(gym.Env):
    """Image observations; Minari stores those of 32 x 32 pixels and more JPEG-encoded by default."""

    action_space = spaces.Discrete(2)

    def __init__(self, side):
        self.observation_space = spaces.Box(0, 255, (side, side, 3), dtype=np.uint8)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return self.observation_space.sample(), {}

    def step(self, action):
        return self.observation_space.sample(), 0.0, False, True, {}


@pytest.mark.parametrize("side", [8, 32])
def test_small_images_are_read_and_jpeg_encoded_ones_refused_clearly(tmp_path, monkeypatch, side):
    from minari import DataCollector

    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path / "minari"))
    collector = DataCollector(Frames(side))
    for seed in (0, 1):
        collector.reset(seed=seed)
        collector.step(0)
    collector.create_dataset(dataset_id="frames/test-v0", author="t", author_email="t@example.org",
                             code_permalink="none", algorithm_name="random")
    folder = tmp_path / "minari" / "frames" / "test-v0"
    if side < 32:
        demos = load(folder)
        assert demos.state_kind == "image" and demos[0].states.shape == (2, side, side, 3)
    else:
        with pytest.raises(DataError, match=r"JPEG-encoded .* the space says \(32, 32, 3\)"):
            load(folder)
