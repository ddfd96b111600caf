"""``symlearn data record``: demonstrations from a policy ``train -o`` saved, in the environment's own
observations and actions, read back by the learners."""

from __future__ import annotations

import json

import numpy as np
import pytest
from cli_runner import run
from dict_lift_env import VECTOR_ROVER
from space_envs import SWITCH_BOARD

from symlearn.data import load


def _module(tmp_path, monkeypatch, name, source):
    (tmp_path / f"{name}.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))


def test_a_trained_expert_records_demonstrations_the_learners_read(capsys, tmp_path, monkeypatch):
    """Train on the environment's own cost, record the expert, learn a formula from the file."""
    _module(tmp_path, monkeypatch, "vector_rover", VECTOR_ROVER)
    code, out, err = run(capsys, "train", "--env", "vector_rover:VectorRover-v0", "--algo", "ppo-lag",
                         "--steps", 4096, "--eval-episodes", 1, "-o", "expert.safetensors", "--json")
    assert code == 0, err
    code, out, err = run(capsys, "data", "record", "--env", "vector_rover:VectorRover-v0", "--policy",
                         "expert.safetensors", "--episodes", 5, "-o", "demos.npz", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["episodes"] == 5 and doc["cost"] is not None and doc["files"] == ["demos.npz"]
    demos = load(tmp_path / "demos.npz")
    # the environment's own Dict observation, flattened and named as record() does (moving stays one column)
    assert len(demos) == 5 and demos.metadata["policy"] == "expert.safetensors"
    names = demos.metadata["feature_names"]
    assert sorted(names) == ["moving", "pos[0]", "pos[1]", "vel[0]", "vel[1]"]
    assert doc["steps"] == sum(len(t.actions) for t in demos)
    assert doc["return"] == pytest.approx(np.mean([np.sum(t.rewards) for t in demos]))
    # greedy by default: the same seed records the same file again
    code, _, err = run(capsys, "data", "record", "--env", "vector_rover:VectorRover-v0", "--policy",
                       "expert.safetensors", "--episodes", 5, "-o", "again.npz")
    assert code == 0, err
    assert load(tmp_path / "again.npz") == demos
    code, out, err = run(capsys, "learn", "dnf", "--env", "vector_rover:VectorRover-v0", "--demos", "demos.npz",
                         "--json")
    assert code == 0, err
    assert json.loads(out)["features"] == names


def test_joint_actions_are_recorded_as_the_environments_own(capsys, tmp_path, monkeypatch):
    _module(tmp_path, monkeypatch, "switch_board", SWITCH_BOARD)
    code, _, err = run(capsys, "train", "--env", "switch_board:SwitchBoard-v0", "--steps", 1024,
                       "--eval-episodes", 1, "-o", "agent.safetensors")
    assert code == 0, err
    code, _, err = run(capsys, "data", "record", "--env", "switch_board:SwitchBoard-v0", "--policy",
                       "agent.safetensors", "--episodes", 2, "--stochastic", "-o", "demos.npz")
    assert code == 0, err
    actions = np.concatenate([np.asarray(t.actions) for t in load(tmp_path / "demos.npz")])
    assert actions.shape[1:] == (2,) and set(np.unique(actions)) <= {0, 1, 2}   # MultiDiscrete([3, 3])


def test_a_policy_from_elsewhere_and_bad_flags_are_one_line(capsys, tmp_path, monkeypatch):
    _module(tmp_path, monkeypatch, "switch_board", SWITCH_BOARD)
    code, _, err = run(capsys, "train", "--env", "CartPole-v1", "--steps", 512, "--eval-episodes", 1,
                       "-o", "cartpole.safetensors")
    assert code == 0, err
    cases = [
        (("--env", "switch_board:SwitchBoard-v0", "--policy", "cartpole.safetensors"), "was trained for observations"),
        (("--env", "CartPole-v1", "--policy", "missing.safetensors"), "no such model: neither missing.safetensors"),
        (("--env", "CartPole-v1", "--policy", "cartpole.safetensors", "--episodes", 0), "--episodes must be"),
        (("--env", "CartPole-v1", "--policy", "cartpole.safetensors", "--max-steps", 2.5), "--max-steps must be"),
        (("--env", "CartPole-v1", "--policy", "cartpole.safetensors", "-o", "demos.csv"), "cannot tell the format"),
        (("--env", "CartPle-v1", "--policy", "cartpole.safetensors"), "CartPole-v1"),
    ]
    for flags, needle in cases:
        if "-o" not in flags:
            flags = (*flags, "-o", "demos.npz")
        code, _, err = run(capsys, "data", "record", *flags)
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1 and needle in lines[0] and "Traceback" not in err, (flags, err)
    assert not (tmp_path / "demos.npz").exists()


CAMERA_CART = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class CameraCart(gym.Env):
    """A cart on a line of 5 cells that sees a 3 x 3 picture as well as its cell, as MiniGrid's Dict does."""

    def __init__(self):
        self.observation_space = spaces.Dict({"image": spaces.Box(0, 255, (3, 3, 1), np.uint8),
                                              "cell": spaces.Box(0.0, 4.0, (1,), np.float32)})
        self.action_space = spaces.Discrete(2)

    def _obs(self):
        image = np.zeros((3, 3, 1), np.uint8)
        image[self.cell % 3, :, 0] = 255
        return {"image": image, "cell": np.array([self.cell], np.float32)}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.cell, self.t = 0, 0
        return self._obs(), {}

    def step(self, action):
        self.cell = int(np.clip(self.cell + (1 if int(action) == 1 else -1), 0, 4))
        self.t += 1
        return self._obs(), float(self.cell == 4), self.cell == 4, self.t >= 20, {}


gym.register("CameraCart-v0", entry_point=CameraCart)
'''


def test_an_observation_holding_an_image_is_recorded_in_the_view_the_policy_reads(capsys, tmp_path, monkeypatch):
    """A Dict with an image (MiniGrid's) cannot be stored as it is: `data record` keeps the numeric
    view the policy acts on, says so, and `learn icrl` reads the file back."""
    _module(tmp_path, monkeypatch, "camera_cart", CAMERA_CART)
    code, _, err = run(capsys, "train", "--env", "camera_cart:CameraCart-v0", "--steps", 1024,
                       "--eval-episodes", 1, "-o", "agent.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "data", "record", "--env", "camera_cart:CameraCart-v0", "--policy",
                         "agent.safetensors", "--episodes", 3, "-o", "demos.npz", "--json")
    assert code == 0, err
    assert json.loads(out)["episodes"] == 3
    assert "stored the numeric view the policy reads (10 columns)" in err and "'image'" in err
    demos = load(tmp_path / "demos.npz")
    assert len(demos) == 3 and np.asarray(demos[0].states).shape[1] == 10
    assert demos.metadata["observation_view"] == "numeric" and len(demos.metadata["feature_names"]) == 10
    code, _, err = run(capsys, "learn", "icrl", "--env", "camera_cart:CameraCart-v0", "--demos", "demos.npz",
                       "--steps", 512, "--iterations", 1, "-o", "cost.safetensors")
    assert code == 0, err


def test_policy_random_samples_the_action_space(capsys, tmp_path, monkeypatch):
    """`--policy random` is record()'s "random" (it was read as a model file random.json); seeded."""
    _module(tmp_path, monkeypatch, "switch_board", SWITCH_BOARD)
    flags = ("data", "record", "--env", "switch_board:SwitchBoard-v0", "--policy", "random", "--episodes", 2)
    code, out, err = run(capsys, *flags, "-o", "random.npz", "--json")
    assert code == 0, err
    assert json.loads(out)["policy"] == "random"
    demos = load(tmp_path / "random.npz")
    assert len(demos) == 2 and demos.metadata["policy"] == "random"
    code, _, err = run(capsys, *flags, "-o", "again.npz")
    assert code == 0, err
    assert load(tmp_path / "again.npz") == demos


BOOST_ROVER = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Rover(gym.Env):
    """Observes (x, battery); its features add whether the step boosted, which no observation holds."""
    feature_names = ("x", "battery", "boost")

    def __init__(self):
        self.observation_space = spaces.Box(0.0, 1.0, (2,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.battery = 0.0, 1.0
        obs = np.array([self.x, self.battery], np.float32)
        return obs, {"features": np.array([self.x, self.battery, 0.0], np.float32), "cost": 0.0}

    def step(self, action):
        boost = int(action) == 1
        self.x = min(1.0, self.x + (0.1 if boost else 0.05))
        self.battery -= 0.1 if boost else 0.02
        obs = np.array([self.x, self.battery], np.float32)
        info = {"features": np.array([self.x, self.battery, float(boost)], np.float32),
                "cost": float(boost and self.battery < 0.5)}
        return obs, 0.0, self.x >= 1.0, False, info


gym.register("BoostRover-v0", entry_point=Rover, max_episode_steps=30)
'''


def test_states_features_records_what_a_formula_reads(capsys, tmp_path, monkeypatch):
    """Features that are not the observation (a flag of the action taken): `learn dnf` refuses the
    observations, names `--states features`, and learns from the file it writes (issue 24)."""
    _module(tmp_path, monkeypatch, "boost_rover_t", BOOST_ROVER)
    flags = ("data", "record", "--env", "boost_rover_t:BoostRover-v0", "--policy", "random", "--episodes", 4)
    code, _, err = run(capsys, *flags, "-o", "obs.npz")
    assert code == 0, err
    code, _, err = run(capsys, "learn", "dnf", "--env", "boost_rover_t:BoostRover-v0", "--demos", "obs.npz")
    assert code != 0 and "data record --states features" in err
    code, _, err = run(capsys, *flags, "--states", "features", "-o", "features.npz")
    assert code == 0, err
    demos = load(tmp_path / "features.npz")
    assert demos.metadata["feature_names"] == ["x", "battery", "boost"]
    first = demos[0]
    assert np.asarray(first.states).shape == (len(first.actions) + 1, 3)
    # the boost column is the action just taken (the reset's 0 first), not anything observed
    assert np.asarray(first.states)[1:, 2].tolist() == [float(a) for a in first.actions]
    code, out, err = run(capsys, "learn", "dnf", "--env", "boost_rover_t:BoostRover-v0", "--demos", "features.npz",
                         "--json")
    assert code == 0, err
    assert json.loads(out)["features"] == ["x", "battery", "boost"]
