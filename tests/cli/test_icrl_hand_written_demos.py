"""learn icrl on demonstrations a user wrote by hand: named feature columns (JSONL objects) for an
environment whose observation entries have names, and text actions (refused in one line)."""

import json

import numpy as np

from tests.support.cli_runner import run


def _module(tmp_path, monkeypatch):
    from user_envs import PLAIN_ROBOT, POINT_ROBOT

    (tmp_path / "hand_lab.py").write_text(POINT_ROBOT.replace("PointRobot-v0", "HandRobot-v0")
                                          + PLAIN_ROBOT.replace("PlainRobot-v0", "HandPlain-v0"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))


def _jsonl(path, state, actions):
    header = {"symlearn": "demonstrations", "format_version": 1, "state_kind": "features" if state else "vector",
              "action_kind": "symbol" if isinstance(actions[0], str) else "vector"}
    positions = np.linspace(-0.8, 0.3, 12)
    lines = [json.dumps(header)]
    for e in range(3):
        states = [{"py": -0.5, "px": float(x)} if state else [float(x), -0.5] for x in positions]
        lines.append(json.dumps({"states": states, "actions": actions * (len(positions) - 1)}))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_named_feature_states_are_placed_by_the_observation_names(capsys, tmp_path, monkeypatch):
    # before: an internal TypeError (float() of a dict)
    _module(tmp_path, monkeypatch)
    _jsonl(tmp_path / "named.jsonl", True, [[0.1, 0.0]])
    _jsonl(tmp_path / "plain.jsonl", False, [[0.1, 0.0]])
    runs = []
    for name in ("named", "plain"):
        code, out, err = run(capsys, "--json", "learn", "icrl", "--env", "hand_lab:HandRobot-v0", "--demos",
                             f"{name}.jsonl", "--steps", 600, "--iterations", 1)
        assert code == 0, err
        runs.append(json.loads(out))
    # px, py placed as the observation's entries 0, 1: the same learning as the vector file
    assert runs[0]["history"][0]["expert_features"] == runs[1]["history"][0]["expert_features"]
    assert runs[0]["lambda"] == runs[1]["lambda"]


def test_named_feature_states_without_observation_names_are_refused(capsys, tmp_path, monkeypatch):
    _module(tmp_path, monkeypatch)
    _jsonl(tmp_path / "named.jsonl", True, [[0.1, 0.0]])
    code, _, err = run(capsys, "learn", "icrl", "--env", "hand_lab:HandPlain-v0", "--demos", "named.jsonl",
                       "--steps", 600, "--iterations", 1)
    assert code == 2 and "named features (px, py)" in err and "does not name its entries" in err, err


def test_text_actions_are_refused_in_one_line(capsys, tmp_path, monkeypatch):
    # before: an internal ValueError (could not convert string to float)
    _module(tmp_path, monkeypatch)
    _jsonl(tmp_path / "text.jsonl", False, ["right"])
    code, _, err = run(capsys, "learn", "icrl", "--env", "hand_lab:HandRobot-v0", "--demos", "text.jsonl",
                       "--steps", 600, "--iterations", 1)
    assert code == 2 and "demonstration actions must be numbers, got text (e.g. 'right')" in err, err
    assert "internal error" not in err


def test_observations_beyond_float32_are_said_to_be_so():
    import pytest

    from symlearn.errors import DataError
    from symlearn.rl.spaces import encode

    spec = {"kind": "box", "shape": [2]}
    with pytest.raises(DataError, match="beyond float32's range .* the first at row 1"):
        encode(np.array([[0.0, 1.0], [1e300, 0.0]]), spec, "demonstration observations")
    with pytest.raises(DataError, match="not finite \\(NaN or inf\\) in 1 row"):
        encode(np.array([[0.0, np.nan]]), spec, "demonstration observations")
