"""A fifth sweep of users' environments at the CLI's defaults (docs/BENCHMARKS.md, issue 25,
"Fifth sweep of users' environments"): kinds no earlier sweep wrote -- ``module:ClassName`` for a
module that registers nothing, ``Box`` actions of a scalar or matrix shape, ``feature_names`` that
repeat or miscount. The environments are in ``tests/support/sweep5_envs.py``; one test per failure,
each with the smallest step counts that show it."""

from __future__ import annotations

import json

import numpy as np
from cli_runner import run


def _one_line(code, err):
    lines = [line for line in err.strip().splitlines() if line.strip()]
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def test_module_colon_class_builds_the_class_the_module_defines(capsys, tmp_path, monkeypatch):
    """``--env sweep5_envs:Walker`` for a module that defines the class and registers nothing: "module
    'sweep5_envs' did not register the gymnasium id 'Walker'" (hint: call gymnasium.register). The
    class is now registered (once, as ``sweep5_envs/Walker``) and built; a function of that name is
    refused in one line saying how to register it."""
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "data", "record", "--env", "sweep5_envs:Walker", "--policy", "random",
                         "--episodes", 2, "-o", "w.npz")
    assert code == 0, err
    assert "sweep5_envs:Walker: 2 episodes" in out and (tmp_path / "w.npz").exists()
    code, out, err = run(capsys, "--json", "train", "--env", "sweep5_envs:Walker", "--algo", "ppo-lag",
                         "--steps", 64, "--eval-episodes", 1)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["env"] == "sweep5_envs:Walker" and doc["cost"] is not None, doc   # info["cost"] read
    line = _one_line(*run(capsys, "train", "--env", "sweep5_envs:not_an_env", "--steps", 64)[::2])
    assert "is a function but no gymnasium.Env class" in line and "gymnasium.register(" in line, line
    line = _one_line(*run(capsys, "train", "--env", "sweep5_envs:Nowhere", "--steps", 64)[::2])
    assert "defines no gymnasium.Env class of that name" in line and "gymnasium.Env classes: " in line, line
    assert "Walker" in line and "sweep5_envs/Walker" not in line, line   # the class, not our id for it


def test_box_actions_of_a_matrix_or_scalar_shape_train_and_record(capsys, tmp_path, monkeypatch):
    """A ``Box(-1, 1, (1, 2))`` action space: ``train`` said "PPO needs a 1-D Box action space, got
    shape (1, 2)", ``data record`` refused the space; a ``Box(())`` one: "got shape ()". PPO now acts
    in the flat vector of the entries (reshaped for the environment, which refuses any other shape),
    and demonstrations store that flat vector, which ``learn icrl`` reads back."""
    monkeypatch.chdir(tmp_path)
    for env in ("sweep5_envs:sweep5/MatrixPush-v0", "sweep5_envs:sweep5/ScalarPush-v0"):
        code, out, err = run(capsys, "--json", "train", "--env", env, "--algo", "ppo-lag", "--steps", 64,
                             "--eval-episodes", 1, "-o", "agent.safetensors")
        assert code == 0, err
        assert json.loads(out)["cost"] is not None
        code, _, err = run(capsys, "data", "record", "--env", env, "--policy", "agent.safetensors",
                           "--episodes", 1, "-o", "agent.npz")
        assert code == 0, err
    from symlearn.data import load

    # random episodes store the flat vector too (a scalar's is a vector of one: learn icrl said
    # "demonstration actions have shape (20,), the space's is (1,)" for scalars stored as they came)
    for env, width in (("sweep5_envs:sweep5/MatrixPush-v0", 2), ("sweep5_envs:sweep5/ScalarPush-v0", 1)):
        code, _, err = run(capsys, "data", "record", "--env", env, "--policy", "random", "--episodes", 2,
                           "-o", "random.npz")
        assert code == 0, err
        actions = np.asarray(load(tmp_path / "random.npz")[0].actions)
        assert actions.shape == (20, width), actions.shape     # one flat push per step
        code, _, err = run(capsys, "learn", "icrl", "--env", env, "--demos", "random.npz", "--steps", 128,
                           "--iterations", 1, "-o", "cost.safetensors")
        assert code == 0, err


def test_feature_names_that_repeat_or_miscount_are_named_as_the_environments(capsys, tmp_path, monkeypatch):
    """``feature_names = ("x", "x")``: ``learn dnf --env E --demos d.npz`` said "d.npz: feature names
    repeat: x, x", blaming the demonstrations for the environment's attribute. Three names for two
    columns said "3 feature names ... (hint: give one name per column with --features a,b,...)"
    without naming where the names came from. Both now name ``feature_names``."""
    monkeypatch.chdir(tmp_path)
    for env in ("sweep5_envs:sweep5/TwinNames-v0", "sweep5_envs:sweep5/ThreeNames-v0"):
        code, _, err = run(capsys, "data", "record", "--env", env, "--policy", "random", "--episodes", 2,
                           "-o", "d.npz")
        assert code == 0, err
        line = _one_line(*run(capsys, "learn", "dnf", "--env", env, "--demos", "d.npz", "-o", "r.dnf")[::2])
        assert "feature_names" in line and "d.npz" not in line, line
    assert "feature_names repeat x: x, x" in _one_line(*run(
        capsys, "learn", "dnf", "--env", "sweep5_envs:sweep5/TwinNames-v0", "--demos", "d.npz", "-o", "r.dnf")[::2])
    line = _one_line(*run(capsys, "learn", "dnf", "--env", "sweep5_envs:sweep5/ThreeNames-v0", "--demos",
                          "d.npz", "-o", "r.dnf")[::2])
    assert "feature_names gives 3 feature names (x, y, z) for 2 columns" in line, line
    # --features overrides the attribute, as documented
    code, _, err = run(capsys, "learn", "dnf", "--env", "sweep5_envs:sweep5/TwinNames-v0", "--demos", "d.npz",
                       "--features", "a,b", "-o", "r.dnf")
    assert code == 0, err


def test_a_reward_that_is_no_number_on_a_later_step_is_one_line(capsys, tmp_path, monkeypatch):
    """``step`` returning the reward ``None`` on its third step (the check when the environment is
    built looks at one step): ``data record`` and ``train`` stopped with "internal error: TypeError:
    float() argument must be ... not 'NoneType'" (PPO: "must be real number"). Now one line naming
    the environment, the step and the value, from every command that steps it."""
    monkeypatch.chdir(tmp_path)
    env = "sweep5_envs:sweep5/ForgetsReward-v0"
    for args in (("data", "record", "--env", env, "--policy", "random", "--episodes", 1, "-o", "d.npz"),
                 ("train", "--env", env, "--steps", 64, "--eval-episodes", 1)):
        line = _one_line(*run(capsys, *args)[::2])
        assert "step 3 of an episode returned the reward None" in line and "internal" not in line, line
    # a reward of a 0-d array, a one-entry list or numpy's bool is one number: still accepted
    from gymnasium import Env, spaces

    from symlearn.recipes.step_checks import CheckedRewards

    class Rewards(Env):
        observation_space, action_space = spaces.Discrete(1), spaces.Discrete(1)
        values = [np.array(1.5), [2.0], np.bool_(True), np.float32(0.5)]

        def reset(self, *, seed=None, options=None):
            return 0, {}

        def step(self, action):
            return 0, self.values.pop(0), False, False, {}

    checked = CheckedRewards(Rewards(), "rewards")
    checked.reset()
    assert [checked.step(0)[1] for _ in range(4)] == [1.5, 2.0, 1.0, 0.5]


def test_an_observation_of_another_size_than_its_space_is_named_when_built(capsys, tmp_path, monkeypatch):
    """A ``Box((2,))`` space with observations of 3 numbers: gymnasium only warns, ``data record``
    stored them, and ``train --algo ppo-lag`` stopped with "internal error: ValueError: could not
    broadcast input array from shape (6,2) into shape (4,2)". Now every command says it when the
    environment is first built."""
    monkeypatch.chdir(tmp_path)
    env = "sweep5_envs:sweep5/ThreeNumbers-v0"
    for args in (("train", "--env", env, "--algo", "ppo-lag", "--steps", 64),
                 ("data", "record", "--env", env, "--policy", "random", "--episodes", 1, "-o", "d.npz")):
        line = _one_line(*run(capsys, *args)[::2])
        assert "reset() returned an observation of shape (3,), but its observation_space is Box(" in line, line
    assert not (tmp_path / "d.npz").exists()


def test_a_feature_names_property_that_raises_is_the_users_error(capsys, tmp_path, monkeypatch):
    """``feature_names`` a property raising ``RuntimeError``: ``learn dnf --env`` and ``learn icrl``
    said "internal error: RuntimeError: names not ready" (please report it). Now one line with the
    property's file and line."""
    monkeypatch.chdir(tmp_path)
    env = "sweep5_envs:sweep5/LateNames-v0"
    code, _, err = run(capsys, "data", "record", "--env", env, "--policy", "random", "--episodes", 1, "-o", "d.npz")
    assert code == 0, err
    line = _one_line(*run(capsys, "learn", "dnf", "--env", env, "--demos", "d.npz", "-o", "r.dnf")[::2])
    assert "sweep5_envs.py:" in line and "LateNames.feature_names raised RuntimeError: names not ready" in line, line


def test_a_nan_observation_while_recording_says_which_episode_and_what_to_do(capsys, tmp_path, monkeypatch):
    """An observation holding NaN on a later step: ``data record`` said "states hold a non-finite value
    (nan) at step 4" (no episode, no hint; ``train`` names both). Now the episode's seed and the
    remedy, in one line."""
    monkeypatch.chdir(tmp_path)
    line = _one_line(*run(capsys, "data", "record", "--env", "sweep5_envs:sweep5/Blinded-v0", "--policy", "random",
                          "--episodes", 2, "-o", "d.npz")[::2])
    assert "the environment observed nan at step 4 of the episode of seed" in line, line
    assert "must observe finite numbers" in line and not (tmp_path / "d.npz").exists(), line
