"""``learn spec`` in a user's environment: the labeling forms and their mistakes, one line each."""

from __future__ import annotations

import json

import pytest
from cli_runner import run

from symlearn.data import Demonstrations, Trajectory


@pytest.fixture
def lake_demos(tmp_path):
    path = tmp_path / "lake.jsonl"
    Demonstrations([Trajectory([0, 4, 8], [1, 1])]).save(path)  # unlabelled, no seed: stored states are labelled
    return path


def _labels_file(tmp_path, body: str, name: str = "labels.py"):
    path = tmp_path / name
    path.write_text(body)
    return path


def _one_line_error(code, out, err):
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("symlearn: error: "), err
    return lines[0]


@pytest.mark.parametrize("body, function, expected", [
    ("def label(obs, info):\n    return ['hole'] if 1 / (obs - 4) else []\n", "label",
     "{path}:2: labeling function label raised ZeroDivisionError: division by zero (demonstration 0, step 1)"),
    ("PROPOSITIONS = ['goal']\ndef label(obs, info):\n    return ['gaol'] if obs == 8 else []\n", "label",
     "{path}: labeling function label returned unknown proposition 'gaol' (demonstration 0, step 2) "
     "(hint: declared: goal"),
    ("def label(obs, info):\n    return [obs]\n", "label",
     "{path}: labeling function label returned int 0 (demonstration 0, step 0), which is not a proposition name"),
    ("def label(obs, info):\n    return 'goal'\n", "label",
     "{path}: labeling function label returned str 'goal' (demonstration 0, step 0)"),
    ("raise RuntimeError('no robot connected')\n", "label",
     "importing labeling module {path} raised RuntimeError: no robot connected"),
    ("def label(obs, info):\n    return []\n", "lable", "{path} defines no function 'lable' (hint: functions there: label)"),
    ("def label(obs, info)\n    return []\n", "label", "{path}:1:"),
])
def test_labeling_function_mistakes(capsys, tmp_path, lake_demos, body, function, expected):
    path = _labels_file(tmp_path, body)
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", f"{path}:{function}")
    line = _one_line_error(code, out, err)
    assert expected.format(path=path) in line


def test_labeling_module_missing(capsys, tmp_path, lake_demos):
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", f"{tmp_path / 'nowhere.py'}:label")
    assert "labeling module" in _one_line_error(code, out, err) and "does not exist" in err


def test_user_environment_needs_demonstrations(capsys):
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1")
    assert "FrozenLake-v1 has no expert: give your demonstrations with --demos FILE" in _one_line_error(code, out, err)


@pytest.fixture
def cart_demos(tmp_path):
    path = tmp_path / "cart.jsonl"
    Demonstrations([Trajectory([[0.0, 0.0, 0.0, 0.0], [0.1, 0.0, 0.0, 0.0]], [1])]).save(path)
    return path


@pytest.fixture
def feature_labels(tmp_path):
    path = tmp_path / "labels.json"
    path.write_text(json.dumps({"right": "x > 0.05"}))
    return path


@pytest.mark.parametrize("features, expected", [
    ("x,x,a,w", "--features names 'x' twice"),
    ("x,v", "2 feature names (x, v) for 4 columns of the observation of CartPole-v1"),
])
def test_feature_name_mistakes(capsys, cart_demos, feature_labels, features, expected):
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", feature_labels, "--features", features)
    assert expected in _one_line_error(code, out, err)


def test_feature_labeling_without_names_reads_x0_x1(capsys, cart_demos, feature_labels, tmp_path):
    """Nothing names CartPole's entries: they are x0 .. x3, as `learn dnf` and `train --cost` call
    them; a condition over another name is refused with the names there are."""
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", feature_labels)
    line = _one_line_error(code, out, err)
    assert "uses unknown feature 'x'" in line and "x0, x1, x2, x3" in line
    from symlearn.grounding.labeling_function import read_labeling

    with pytest.raises(Exception, match="needs the observation's feature names"):
        read_labeling('{"right": "x0 > 0.05"}')  # in Python, without names, it still says so
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", '{"right": "x0 > 0.05"}', "--max-iterations", "1", "--json",
                         "-o", tmp_path / "cart.ltl")
    assert code == 0, err
    labeling = json.loads((tmp_path / "cart.labeling.json").read_text())
    assert "x0" in json.dumps(labeling)


def test_feature_labeling_unknown_feature(capsys, cart_demos, tmp_path):
    path = tmp_path / "labels.json"
    path.write_text(json.dumps({"right": "q > 0.05"}))
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", path, "--features", "x,v,a,w")
    assert "proposition 'right' uses unknown feature 'q'" in _one_line_error(code, out, err)


def test_an_environment_that_raises(capsys, tmp_path, monkeypatch, lake_demos):
    (tmp_path / "broken_env.py").write_text(
        "import gymnasium as gym\n"
        "class Broken(gym.Env):\n"
        "    observation_space = gym.spaces.Discrete(3)\n"
        "    action_space = gym.spaces.Discrete(2)\n"
        "    def reset(self, seed=None, options=None):\n"
        "        return 0, {}\n"
        "    def step(self, action):\n"
        "        raise RuntimeError('motor driver offline')\n"
        "gym.register('Broken-v0', entry_point=Broken)\n")
    labels = _labels_file(tmp_path, "def label(obs, info):\n    return []\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, out, err = run(capsys, "learn", "spec", "--env", "broken_env:Broken-v0", "--demos", lake_demos,
                         "--labeling", f"{labels}:label")
    line = _one_line_error(code, out, err)
    assert "broken_env.py:8: random rollouts: the environment raised RuntimeError: motor driver offline" in line


def test_ppo_update_needs_array_observations(capsys, tmp_path, lake_demos):
    labels = _labels_file(tmp_path, "def label(obs, info):\n    return []\n")
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", f"{labels}:label", "--policy", "ppo")
    assert "a PPO policy update needs array observations (a Box), not Discrete(16)" in _one_line_error(code, out, err)


def test_demonstrations_of_another_environment_are_refused_when_replayed(capsys, tmp_path):
    """A labeling that reads ``info`` replays the demonstrations' actions; vector actions (recorded
    in a continuous environment) in FrozenLake are one line, not an internal error."""
    import numpy as np

    path = tmp_path / "robot.npz"
    Demonstrations([Trajectory(np.zeros((3, 2)), np.zeros((2, 2)), info={"seed": 1})]).save(path)
    labels = _labels_file(tmp_path, "def label(obs, info):\n    return ['goal'] if obs == 15 else []\n")
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", path,
                         "--labeling", f"{labels}:label")
    line = _one_line_error(code, out, err)
    assert "demonstration 0, step 0: an action of shape (2,) does not fit" in line and "Discrete(4)" in line


def test_feature_labeling_given_on_the_command_line(capsys, cart_demos):
    """README: ``--labeling '{"near_goal": "x > 0.8 & y > 0.8"}'`` -- the object itself, not only a file."""
    from symlearn.grounding.labeling_function import read_labeling

    labeling = read_labeling('{"right": "x > 0.05"}', feature_names=["x", "v", "a", "w"])
    assert list(labeling.propositions) == ["right"]
    assert set(labeling.label([0.1, 0.0, 0.0, 0.0])) == {"right"}
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", '{"right": "q > 0.05"}', "--features", "x,v,a,w")
    assert "--labeling: proposition 'right' uses unknown feature 'q'" in _one_line_error(code, out, err)
    code, out, err = run(capsys, "learn", "spec", "--env", "CartPole-v1", "--demos", cart_demos,
                         "--labeling", '{"right": "x > 0.05",}', "--features", "x,v,a,w")
    assert "--labeling:1:" in _one_line_error(code, out, err)


def test_learn_spec_with_ppo_in_a_dict_observation_and_a_labeling_over_its_named_parts(
        capsys, tmp_path, monkeypatch):
    """A goal-conditioned-style Dict of vectors: the PPO update sees it flattened, and a feature
    labeling names its numbers as record and learn dnf do (``"pos[0]"``, quoted as in DNF files)."""
    from dict_lift_env import rover_demonstrations

    demos = rover_demonstrations(tmp_path, monkeypatch, 2)
    env = ("--env", "vector_rover:VectorRover-v0", "--demos", demos, "--ppo-steps", 128, "--max-iterations", 1,
           "--horizon", 10)
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", *env,
                         "--labeling", '{"high": "\\"pos[1]\\" > 0.3"}')
    assert code == 0, err
    assert json.loads(out)["policy_update"] == "ppo"
    code, out, err = run(capsys, "learn", "spec", *env, "--labeling", '{"high": "\\"pos[9]\\" > 0.3"}')
    line = _one_line_error(code, out, err)
    assert "unknown feature 'pos[9]'" in line and "pos[0], pos[1]" in line


def test_a_discrete_observation_nothing_names_is_x0(capsys, lake_demos, tmp_path):
    """FrozenLake's observation is one number, the cell's index: like a scalar Box it is the
    column x0 (it used to get no name, so an inline labeling was refused asking for --features)."""
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", '{"goal": "x0 == 15", "hole": "x0 == 5"}', "--max-iterations", "1",
                         "-o", tmp_path / "lake.ltl")
    assert code == 0, err
    assert "x0" in (tmp_path / "lake.labeling.json").read_text()
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", '{"goal": "cell == 15"}')
    assert "uses unknown feature 'cell'" in _one_line_error(code, out, err) and "x0" in err
    # two names for its one column are refused, as for a Box of another width
    code, out, err = run(capsys, "learn", "spec", "--env", "FrozenLake-v1", "--demos", lake_demos,
                         "--labeling", '{"goal": "row == 3"}', "--features", "row,col")
    assert "2 feature names (row, col) for 1 columns of the observation" in _one_line_error(code, out, err)


def test_a_dnf_over_x0_trains_on_a_discrete_observation(capsys, tmp_path):
    rules = tmp_path / "lake.dnf"
    rules.write_text("x0 >= 5 & x0 <= 5\n")  # the hole at cell 5
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "FrozenLake-v1", "--cost", rules,
                         "--steps", 256, "--n-steps", 32, "--eval-episodes", 1)
    assert code == 0, err
    assert json.loads(out)["cost_kind"] == "dnf"
