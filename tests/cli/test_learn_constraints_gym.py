"""``learn constraints --env`` on a discrete gymnasium environment that exposes its model: a
gymnasium id (CliffWalking) or a user's ``module:EnvId`` with gymnasium's toy-text model."""

from __future__ import annotations

import json
import sys

import gymnasium
import numpy as np
import pytest
from cli_runner import run

from symlearn.data import record

#: a 3 x 3 floor: start in the middle of the left column, goal in the middle of the right one,
#: and a hot plate in the centre that the shortest route crosses; the user's expert goes round
#: it over the top row. ``constraint_mask()``: entering the centre is forbidden.
HOT_PLATE = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces

MOVES = [(-1, 0), (0, 1), (1, 0), (0, -1)]  # up, right, down, left


class HotPlate(gym.Env):
    def __init__(self, size=3):
        self.size = size
        n = size * size
        self.observation_space, self.action_space = spaces.Discrete(n), spaces.Discrete(4)
        self.start, self.goal, self.plate = self._id(size // 2, 0), self._id(size // 2, size - 1), self._id(size // 2, size // 2)
        self.initial_state_distrib = np.eye(n)[self.start]
        self.P = {s: {a: [(1.0, self._next(s, a), float(self._next(s, a) == self.goal) - 0.01,
                           self._next(s, a) == self.goal)] for a in range(4)} for s in range(n)}

    def _id(self, r, c):
        return r * self.size + c

    def _next(self, s, a):
        r, c = divmod(s, self.size)
        dr, dc = MOVES[a]
        r, c = min(max(r + dr, 0), self.size - 1), min(max(c + dc, 0), self.size - 1)
        return self._id(r, c)

    def constraint_mask(self):
        mask = np.zeros((self.size * self.size, 4), dtype=bool)
        for s in range(self.size * self.size):
            for a in range(4):
                mask[s, a] = self._next(s, a) == self.plate and s != self.plate
        return mask

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.s = self.start
        return self.s, {}

    def step(self, action):
        (_, self.s, reward, done), = self.P[self.s][int(action)]
        return self.s, reward, done, False, {}


gym.register("HotPlate-v0", entry_point=HotPlate, max_episode_steps=50)
'''


def round_the_plate(s: int) -> int:
    """Up from the start, right along the top row, down to the goal (3 x 3)."""
    r, c = divmod(int(s), 3)
    return 0 if (r, c) == (1, 0) else 1 if r == 0 and c < 2 else 2


def cliff_expert(s: int) -> int:
    """CliffWalking's careful route: up to the top row, along it, down to the goal."""
    r, c = divmod(int(s), 12)
    return 1 if r == 0 and c < 11 else 2 if c == 11 else 0


@pytest.fixture()
def user_folder(tmp_path, monkeypatch):
    (tmp_path / "hot_plate.py").write_text(HOT_PLATE)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import hot_plate  # noqa: F401 -- registers HotPlate-v0

    record(gymnasium.make("HotPlate-v0"), round_the_plate, 10, seed=0).save(tmp_path / "demos.jsonl")
    yield tmp_path
    sys.modules.pop("hot_plate", None)
    gymnasium.registry.pop("HotPlate-v0", None)


def demonstrated(path) -> set[tuple[int, int]]:
    lines = [json.loads(line) for line in open(path)][1:]
    return {(s, a) for t in lines for s, a in zip(t["states"], t["actions"])}


@pytest.mark.parametrize("method", ["ml", "mce-icrl"])
def test_a_users_module_with_a_toy_text_model_is_scored_against_its_constraint_mask(capsys, user_folder, method):
    code, out, err = run(capsys, "learn", "constraints", "--env", "hot_plate:HotPlate-v0", "--demos", "demos.jsonl",
                         "--method", method, "--json", "-o", "plate.json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["env"] == "hot_plate:HotPlate-v0" and doc["constraints"] > 0
    assert 0.0 <= doc["fnr"] < 1.0 and 0.0 <= doc["fpr"] <= 1.0  # scored against constraint_mask()
    forbidden = {(int(s), int(a)) for s, a in json.loads((user_folder / "plate.json").read_text())["forbidden"]}
    assert not forbidden & demonstrated(user_folder / "demos.jsonl")  # nothing the expert did on purpose
    # onto the plate from the start (the shortest route) and from the top row the expert walks;
    # from the bottom row, where nothing is demonstrated and the nominal planner rarely goes, it
    # may stay unlearned
    assert {(3, 1), (1, 2)} <= forbidden


def test_a_model_without_initial_state_distrib_starts_where_reset_does(capsys, tmp_path, monkeypatch):
    """``P`` is what the docs ask for; a world that does not also keep toy-text's
    ``initial_state_distrib`` has its start distribution read off its resets."""
    source = HOT_PLATE.replace("        self.initial_state_distrib = np.eye(n)[self.start]\n", "")
    source = source.replace("HotPlate-v0", "BarePlate-v0")
    assert "initial_state_distrib" not in source
    (tmp_path / "bare_plate.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import bare_plate  # noqa: F401 -- registers BarePlate-v0

    try:
        record(gymnasium.make("BarePlate-v0"), round_the_plate, 10, seed=0).save(tmp_path / "demos.jsonl")
        code, out, err = run(capsys, "learn", "constraints", "--env", "bare_plate:BarePlate-v0", "--demos",
                             "demos.jsonl", "--json", "-o", "plate.json")
        assert code == 0, err
        forbidden = {(int(s), int(a)) for s, a in json.loads((tmp_path / "plate.json").read_text())["forbidden"]}
        assert {(3, 1), (1, 2)} <= forbidden
    finally:
        sys.modules.pop("bare_plate", None)
        gymnasium.registry.pop("BarePlate-v0", None)


def test_a_gymnasium_id_with_a_model_learns_where_the_expert_never_went(capsys, tmp_path):
    record(gymnasium.make("CliffWalking-v1"), cliff_expert, 5, seed=0).save(tmp_path / "cliff.jsonl")
    code, out, err = run(capsys, "learn", "constraints", "--env", "CliffWalking-v1", "--demos", tmp_path / "cliff.jsonl",
                         "--method", "ml", "--json", "-o", tmp_path / "cliff.json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["constraints"] > 0 and doc["fpr"] is None  # no constraint_mask(): nothing to score against
    forbidden = {(int(s), int(a)) for s, a in json.loads((tmp_path / "cliff.json").read_text())["forbidden"]}
    assert forbidden and not forbidden & demonstrated(tmp_path / "cliff.jsonl")


@pytest.mark.parametrize("argv, message", [
    (["--env", "CartPole-v1", "--demos", "x.jsonl"], "CartPole-v1: CartPoleEnv does not expose its transition model"),
    (["--env", "gridworld", "--env-kwargs", '{"size": 3}'], "gridworld is a bundled environment; --env-kwargs is for"),
    (["--env", "NoSuchWorld-v3", "--demos", "x.jsonl"], "a discrete gymnasium environment with its model"),
    (["--env", "CliffWalkin-v1", "--demos", "x.jsonl"], "did you mean 'CliffWalking-v1'?"),
    (["--env", "hanio", "--demos", "x.jsonl"], "did you mean 'hanoi'?"),
    (["--env", "NoSuchWorld-v3", "--env-kwargs", '{"a": 1}', "--demos", "x.jsonl"],
     "unknown environment 'NoSuchWorld-v3'"),  # not "a bundled environment": it is none
    (["--env", "FrozenLake-v1", "--env-kwargs", '{"is_slipery": false}', "--demos", "x.jsonl"], "did you mean 'is_slippery'"),
    (["--env", "CliffWalking-v1", "--method", "logic", "--demos", "x.jsonl"], "has no ASP facts"),
    (["--env", "CliffWalking-v1"], "has no bundled expert: give your demonstrations with --demos"),
    (["--domain", "folder", "--env-kwargs", "{}"], "--env-kwargs goes with --env, not --domain"),
])
def test_refusals_are_one_line(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.jsonl").write_text("")
    code, out, err = run(capsys, "learn", "constraints", *argv)
    assert code == 2 and message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
