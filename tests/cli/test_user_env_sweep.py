"""Third-party environments at default settings, as a new user brings them (``module:EnvId`` from
the module's folder): every command either works as docs/GUIDE.md says or refuses in one line."""

from __future__ import annotations

import json

import pytest
from cli_runner import run
from odd_cost_envs import MATRIX_ACTION, ODD_COST


def _module(tmp_path, monkeypatch, name, source):
    (tmp_path / f"{name}.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))


@pytest.fixture
def odd_cost(capsys, tmp_path, monkeypatch):
    """The OddCost module and an agent trained on it (the policy does not depend on the cost's form)."""
    _module(tmp_path, monkeypatch, "odd_cost", ODD_COST)
    code, _, err = run(capsys, "train", "--env", "odd_cost:OddCost-v0", "--env-kwargs", '{"kind": "none"}',
                       "--steps", 512, "--eval-episodes", 1, "-o", "agent.safetensors")
    assert code == 0, err


@pytest.mark.parametrize("kind, cost", [("vector", True), ("list", True), ("none", False)])
def test_data_record_reads_info_cost_as_train_does(capsys, odd_cost, kind, cost):
    """``data record`` summed ``float(info["cost"])``: a vector or list of constraints (which
    ``train`` accepts) and ``None`` were internal ``TypeError``s."""
    code, out, err = run(capsys, "data", "record", "--env", "odd_cost:OddCost-v0", "--env-kwargs",
                         json.dumps({"kind": kind}), "--policy", "agent.safetensors", "--episodes", 2,
                         "--stochastic", "-o", "demos.npz", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert (doc["cost"] is not None) is cost
    if cost:
        assert doc["cost"] >= 0


def test_data_record_refuses_a_cost_that_is_no_number_in_one_line(capsys, odd_cost):
    code, out, err = run(capsys, "data", "record", "--env", "odd_cost:OddCost-v0", "--env-kwargs",
                         '{"kind": "complex"}', "--policy", "agent.safetensors", "-o", "demos.npz", "--json")
    assert code == 2, err
    assert "internal error" not in err and "info['cost'] must be a number" in err
    assert "(episode 0, step 0)" in err   # not "environment 0": there is one
    assert json.loads(out)["error"]["kind"] != "internal"


@pytest.mark.parametrize("kind, algo", [("box", "sb3-ppo"), ("multi", "ppo")])
def test_data_record_refuses_matrix_actions_before_recording(capsys, tmp_path, monkeypatch, kind, algo):
    """An agent ``train`` saved in a ``(2, 2)`` action space: ``data record`` ran every episode and
    then said "actions must be ... not images"; now it names the space before the first episode.
    A ``(2, 2)`` ``Box`` is recorded since the fifth sweep (each action as its flat vector of 4,
    what symlearn's PPO acts in: ``tests/cli/test_user_env_sweep_round5.py``); a ``(2, 2)``
    ``MultiDiscrete`` is still refused."""
    _module(tmp_path, monkeypatch, "matrix_action", MATRIX_ACTION)
    env = ("--env", "matrix_action:MatrixAction-v0", "--env-kwargs", json.dumps({"kind": kind}))
    code, _, err = run(capsys, "train", *env, "--algo", algo, "--steps", 256, "--eval-episodes", 1,
                       "-o", "agent.safetensors")
    assert code == 0, err
    code, _, err = run(capsys, "data", "record", *env, "--policy", "agent.safetensors", "-o", "demos.npz")
    if kind == "box":
        import numpy as np

        from symlearn.data import load

        assert code == 0, err
        assert np.asarray(load(tmp_path / "demos.npz")[0].actions).shape[1:] == (4,)
        return
    assert code == 2, err
    assert "images" not in err and "shape (2, 2)" in err and len(err.strip().splitlines()) == 1


def test_a_trajectory_of_matrix_actions_names_their_shape():
    import numpy as np

    from symlearn.data import Trajectory
    from symlearn.errors import DataError

    with pytest.raises(DataError, match=r"shape \(2, 2\)"):
        Trajectory(states=[[0.0], [1.0]], actions=np.zeros((1, 2, 2)))


@pytest.mark.parametrize("kind", ["text", "complex"])
def test_sb3_refuses_a_cost_that_is_no_number_in_one_line(capsys, tmp_path, monkeypatch, kind):
    """stable-baselines3's monitor summed ``np.sum(info["cost"])``: text was an internal TypeError
    (our PPO turned "1" into 1.0 silently); both now refuse as the one cost reader does."""
    _module(tmp_path, monkeypatch, "odd_cost", ODD_COST)
    code, _, err = run(capsys, "train", "--env", "odd_cost:OddCost-v0", "--env-kwargs", json.dumps({"kind": kind}),
                       "--algo", "sb3-ppo", "--steps", 256, "--eval-episodes", 1)
    assert code == 2 and "internal error" not in err, err
    assert "info['cost'] must be a number" in err and "(step 0 of an episode of environment copy 0)" in err
    code, _, err = run(capsys, "train", "--env", "odd_cost:OddCost-v0", "--env-kwargs", json.dumps({"kind": kind}),
                       "--algo", "ppo-lag", "--steps", 256, "--eval-episodes", 1)
    assert code == 2 and "info['cost'] must be a number" in err, err
    assert "(training step 0, environment copy 0)" in err


def test_learn_icrl_reads_info_cost_as_train_does(capsys, odd_cost):
    """Neural ICRL's sampler summed ``float(np.sum(info.get("cost", 0.0)))``: ``None`` was an
    internal TypeError; a text cost is the environment's error, not the demonstrations file's."""
    code, _, err = run(capsys, "data", "record", "--env", "odd_cost:OddCost-v0", "--policy", "agent.safetensors",
                       "--episodes", 3, "--stochastic", "-o", "demos.npz")
    assert code == 0, err
    learn = ("learn", "icrl", "--env", "odd_cost:OddCost-v0", "--demos", "demos.npz", "--steps", 1024,
             "--iterations", 1)
    code, _, err = run(capsys, *learn, "--env-kwargs", '{"kind": "none"}', "-o", "cost.safetensors")
    assert code == 0, err
    code, _, err = run(capsys, *learn, "--env-kwargs", '{"kind": "text"}', "-o", "cost.safetensors")
    assert code == 2 and "info['cost'] must be a number" in err, err
    assert "demos.npz:" not in err


def test_a_coloured_library_warning_is_one_plain_line():
    """gymnasium's environment checker colours its warnings: the escape codes reached the
    ``warning:`` line raw (``^[[33mWARN: ...^[[0m`` in a log file)."""
    import warnings

    from symlearn.cli.main import _one_line_warnings

    with _one_line_warnings(debug=False):
        line = warnings.formatwarning("\x1b[33mWARN: The obs returned by the `reset()` method\n is odd\x07\x1b[0m",
                                      UserWarning, "env.py", 3)
    assert line == "warning: WARN: The obs returned by the `reset()` method is odd\\x07\n"


def test_feature_names_given_as_one_string_are_one_name(capsys, tmp_path, monkeypatch):
    """``feature_names = "xy"`` (a string where a tuple belongs) was iterated into the names ``x``
    and ``y``: rules silently over two made-up names. It is one name, and two columns refuse it."""
    source = ODD_COST.replace('feature_names = ("x",)', 'feature_names = "xy"').replace(
        'spaces.Box(-1.0, 1.0, (1,), np.float32)', 'spaces.Box(-1.0, 1.0, (2,), np.float32)').replace(
        'np.array([self.x], np.float32)', 'np.array([self.x, 0.0], np.float32)').replace("OddCost-v0", "OneName-v0")
    _module(tmp_path, monkeypatch, "one_name", source)   # a module name of its own: odd_cost is imported
    from symlearn.data import Demonstrations, Trajectory

    Demonstrations([Trajectory(states=[[0.0, 0.0], [0.1, 0.0]], actions=[1])]).save(tmp_path / "demos.npz")
    code, _, err = run(capsys, "learn", "dnf", "--env", "one_name:OneName-v0", "--demos", "demos.npz")
    assert code == 2 and "1 feature names (xy) for 2 columns" in err, err
