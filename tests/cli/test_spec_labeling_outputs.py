"""What ``learn spec -o SPEC.ltl`` writes and prints for the labelings of a user's environment:
a ``{proposition: condition}`` labeling (given as it is, read from the observation or from
``info["features"]``) is written as ``SPEC.labeling.json`` and printed with its conditions; a
Python function cannot be saved, so no labeling file is written, the output says so in one line
(and in the JSON), and its propositions are printed as ``(labels.py:function)``."""

from __future__ import annotations

import json

import pytest
from cli_runner import run

from symlearn.data import Demonstrations, Trajectory
from symlearn.grounding import load_labeling

CORRIDOR = '''
import gymnasium as gym
from gymnasium import spaces


class Corridor(gym.Env):
    feature_names = ("x",)

    def __init__(self, in_info=False):
        self.in_info = in_info
        self.observation_space = spaces.Discrete(6)
        self.action_space = spaces.Discrete(2)

    def _info(self):
        return {"features": [float(self.pos)]} if self.in_info else {}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = 0
        return self.pos, self._info()

    def step(self, action):
        self.pos = max(0, min(5, self.pos + (1 if action == 1 else -1)))
        return self.pos, float(self.pos == 5), self.pos == 5, False, self._info()


gym.register(id="OutputsCorridor-v0", entry_point=Corridor, max_episode_steps=30)
'''

INLINE = '{"key": "x >= 2 & x <= 2", "door": "x >= 5"}'


@pytest.fixture
def corridor(tmp_path, monkeypatch):
    (tmp_path / "outputs_lab.py").write_text(CORRIDOR)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    # labelled as recorded: the labeling of info["features"] needs no replay
    labels = [[], [], ["key"], [], [], ["door"]]
    Demonstrations([Trajectory(list(range(6)), [1] * 5, labels=labels)] * 6).save(tmp_path / "demos.jsonl")
    return tmp_path


def _spec(capsys, labeling, *extra):
    return run(capsys, "learn", "spec", "--env", "outputs_lab:OutputsCorridor-v0", "--demos", "demos.jsonl",
               "--labeling", labeling, "--q-steps", 500, "--max-iterations", 1, "-o", "out.ltl", *extra)


@pytest.mark.parametrize("kwargs", [(), ("--env-kwargs", '{"in_info": true}')], ids=["observation", "info"])
def test_an_inline_feature_labeling_is_written_and_printed_with_its_conditions(capsys, corridor, kwargs):
    code, out, err = _spec(capsys, INLINE, *kwargs)
    assert code == 0, err
    assert "  key: x >= 2 & x <= 2\n" in out and "  door: x >= 5\n" in out, out
    path = corridor / "out.labeling.json"
    assert "wrote out.labeling.json" in out, out
    saved = load_labeling(path)   # the format of docs/FORMATS.md, "Labelings" (kind "features")
    assert json.loads(path.read_text())["kind"] == "features" and saved.propositions == ("key", "door")
    assert saved.condition("door").to_string(one_line=True) == "x >= 5"
    # given again in the same environment, it reads the same columns
    code, out, err = _spec(capsys, "out.labeling.json", *kwargs, "--json")
    assert code == 0, err
    assert json.loads(out)["propositions"] == {"key": "x >= 2 & x <= 2", "door": "x >= 5"}


def test_a_python_labeling_writes_no_file_and_says_so(capsys, corridor):
    (corridor / "labels.py").write_text("PROPOSITIONS = ['door', 'key']\nMEANINGS = {'key': 'the key cell'}\n"
                                        "def label(obs, info):\n    return ['door'] if obs >= 5 else []\n")
    code, out, err = _spec(capsys, "labels.py:label")
    assert code == 0, err
    assert "  door: (labels.py:label)\n" in out and "  key: the key cell\n" in out, out
    assert not (corridor / "out.labeling.json").exists()
    [line] = [line for line in out.splitlines() if "out.labeling.json" in line]
    assert line.startswith("no out.labeling.json written") and "Python function labels.py:label" in line
    code, out, err = _spec(capsys, "labels.py:label", "--json")
    doc = json.loads(out)
    assert "Python function labels.py:label" in doc["labeling_not_written"]
    assert not any(f.endswith(".labeling.json") for f in doc["files"])
    code, out, err = _spec(capsys, INLINE, "--json")
    assert json.loads(out)["labeling_not_written"] is None


def test_the_help_promises_no_labeling_file_for_a_function(capsys):
    with pytest.raises(SystemExit):
        run(capsys, "learn", "spec", "--help")
    text = " ".join(capsys.readouterr().out.split())
    assert "SPEC.labeling.json" in text and "not a FILE.py:function labeling, which cannot be saved" in text
