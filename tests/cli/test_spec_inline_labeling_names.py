"""learn spec --labeling '{"p": "x > 1"}' (the object given as it is) takes the feature names from
the environment's feature_names, as a labeling .json file does (docs/FORMATS.md, "Labelings of
your own environment", form 2); before, only a file did, and the object was refused."""

import json

from tests.support.cli_runner import run

CORRIDOR = '''
import gymnasium as gym
from gymnasium import spaces


class Corridor(gym.Env):
    feature_names = ("x",)

    def __init__(self):
        self.observation_space = spaces.Discrete(6)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.pos = 0
        return self.pos, {}

    def step(self, action):
        self.pos = max(0, min(5, self.pos + (1 if action == 1 else -1)))
        return self.pos, float(self.pos == 5), self.pos == 5, False, {}


gym.register(id="NamedCorridor-v0", entry_point=Corridor, max_episode_steps=30)
'''


def test_inline_feature_labeling_reads_the_environments_names(capsys, tmp_path, monkeypatch):
    (tmp_path / "corridor_lab.py").write_text(CORRIDOR)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    header = {"symlearn": "demonstrations", "format_version": 1, "state_kind": "discrete", "action_kind": "discrete"}
    lines = [json.dumps(header)] + [json.dumps({"states": list(range(6)), "actions": [1] * 5})] * 6
    (tmp_path / "demos.jsonl").write_text("\n".join(lines) + "\n")
    code, out, err = run(capsys, "--json", "learn", "spec", "--env", "corridor_lab:NamedCorridor-v0", "--demos",
                         "demos.jsonl", "--labeling", '{"key": "x >= 2 & x <= 2", "door": "x >= 5"}',
                         "--q-steps", 2000, "--max-iterations", 1)
    assert code == 0, err
    assert set(json.loads(out)["propositions"]) == {"key", "door"}
