"""A user's own gymnasium module, outside the repository, reached as ``--env module:EnvId``."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from cli_runner import run
from user_envs import PLAIN_ROBOT, POINT_ROBOT, write_module


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "symlearn", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The user's folder: their module and demonstrations recorded with their own expert."""
    root = tmp_path_factory.mktemp("user")
    write_module(root, "robot_lab", POINT_ROBOT)
    write_module(root, "plain_lab", PLAIN_ROBOT)
    code = (f"import sys; sys.path.insert(0, {str(root)!r}); sys.path.insert(0, {str(root.parent)!r})\n"
            "import robot_lab, gymnasium\n"
            "from symlearn.data import record\n"
            "from user_envs import careful_expert\n"
            f"record(gymnasium.make('PointRobot-v0'), careful_expert(), 12, seed=0).save({str(root / 'demos.npz')!r})\n")
    import user_envs

    (root.parent / "user_envs.py").write_text(open(user_envs.__file__).read())
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    return root


def test_learn_dnf_names_the_features_from_the_users_environment(folder):
    result = _cli("learn", "dnf", "--env", "robot_lab:PointRobot-v0", "--demos", "demos.npz", "--json",
                  "-o", "robot.dnf", cwd=folder)
    assert result.returncode == 0, result.stderr
    doc = json.loads(result.stdout)
    assert doc["features"] == ["px", "py"]
    # the expert stops short of the wall at 0.5: something right of its corridor is unsafe
    assert any("px >" in c for c in doc["conjunctions"])
    assert (folder / "robot.dnf").read_text().count("\n") >= 2


def test_without_demonstrations_the_message_says_to_give_them(folder):
    result = _cli("learn", "dnf", "--env", "robot_lab:PointRobot-v0", cwd=folder)
    assert result.returncode == 2 and "has no expert" in result.stderr and "--demos" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    result = _cli("learn", "icrl", "--env", "robot_lab:PointRobot-v0", cwd=folder)
    assert result.returncode == 2 and "has no expert: give your demonstrations with --demos" in result.stderr


@pytest.fixture
def inside(folder, monkeypatch):
    """In-process runs from the user's folder (the module imports from the current directory)."""
    monkeypatch.chdir(folder)
    return folder


def test_features_flag_names_the_columns_of_an_unnamed_environment(inside, capsys):
    code, out, err = run(capsys, "learn", "dnf", "--env", "plain_lab:PlainRobot-v0", "--demos", "demos.npz",
                         "--features", "a,b", "--json")
    assert code == 0, err
    assert json.loads(out)["features"] == ["a", "b"]
    code, _, err = run(capsys, "learn", "dnf", "--env", "plain_lab:PlainRobot-v0", "--demos", "demos.npz",
                       "--features", "a,a")
    assert code == 2 and "names 'a' twice" in err
    code, _, err = run(capsys, "learn", "dnf", "--env", "plain_lab:PlainRobot-v0", "--demos", "demos.npz",
                       "--features", "a,b,c")
    assert code == 2 and "3 feature names" in err


def test_learn_icrl_on_the_users_environment(inside, capsys):
    code, out, err = run(capsys, "learn", "icrl", "--env", "robot_lab:PointRobot-v0", "--env-kwargs",
                         '{"horizon": 20}', "--demos", "demos.npz", "--steps", 2000, "--iterations", 1,
                         "--cost-inputs", "px,py", "--json", "-o", "cost.safetensors")
    assert code == 0, err
    doc = json.loads(out)
    folder = inside
    assert doc["env"] == "robot_lab:PointRobot-v0" and doc["violation_rate"] is not None
    assert doc["recovery_auc"] is None  # no is_unsafe: nothing to score the recovery against
    assert (folder / "cost.safetensors").exists() and (folder / "cost.json").exists()


def test_an_environment_without_ground_truth_reports_none(inside, capsys):
    code, out, err = run(capsys, "learn", "icrl", "--env", "plain_lab:PlainRobot-v0", "--demos", "demos.npz",
                         "--steps", 1000, "--iterations", 1)
    assert code == 0, err
    assert "violation rate n/a" in out and "feasible reward n/a" in out


@pytest.mark.parametrize("args, message", [
    (("--env", "robot_lab:PointRobot-v7"), "did not register the gymnasium id 'PointRobot-v7'"),
    (("--env", "robot_lab:PointRobot-v0", "--env-kwargs", '{"wal": 1}'), "unknown --env-kwargs key 'wal'"),
    (("--env", "robot_lab:PointRobot-v0", "--env-kwargs", '{"wall": 1, "wall": 2}'), 'key "wall" appears twice'),
    (("--env", "no_lab:PointRobot-v0"), "no module named 'no_lab'"),
])
def test_bad_names_are_one_line_everywhere(inside, capsys, args, message):
    for command in (("learn", "dnf", "--demos", "demos.npz"), ("learn", "icrl", "--demos", "demos.npz"),
                    ("learn", "pdfa", "--demos", "demos.npz")):
        code, _, err = run(capsys, *command, *args)
        assert code == 2, err
        assert message in err and len(err.strip().splitlines()) == 1, err
