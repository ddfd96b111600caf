"""Specification learning in MiniGrid with a labeling-function file and no tabular model
(issue 23): the Python API and ``symlearn learn spec`` on DoorKey and on a two-tile room."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("minigrid")

import gymnasium as gym  # noqa: E402
from cli_runner import run  # noqa: E402
from minigrid_tasks import DOORKEY_ACTIONS, PlannedPolicy, doorkey_solved, room_demonstrator  # noqa: E402

from symlearn.data import Demonstrations, record  # noqa: E402
from symlearn.errors import DataError  # noqa: E402
from symlearn.grounding.labeling_function import load_labeling_function  # noqa: E402
from symlearn.learners.temporal.spec_from_demos import SpecLearner  # noqa: E402
from symlearn.logic.ltlf import holds, parse  # noqa: E402
from symlearn.logic.ltlf.ast import subformulas  # noqa: E402

SUPPORT = Path(__file__).resolve().parents[1] / "support"
DOORKEY_LABELS = f"{SUPPORT / 'minigrid_doorkey_labels.py'}:label"
ROOM_LABELS = f"{SUPPORT / 'minigrid_room_labels.py'}:label"
Q_STEPS = 10_000  # enough for both worlds (measured: every nominal rollout then completes the task)


def _words(demos: Demonstrations):
    return [[frozenset(step) for step in t.labels] for t in demos]


@pytest.fixture(scope="module")
def doorkey(tmp_path_factory):
    """Demonstrations (labelled while recorded) and aimless episodes of DoorKey-5x5."""
    labeling = load_labeling_function(DOORKEY_LABELS)
    env = gym.make("MiniGrid-DoorKey-5x5-v0")
    image = lambda observation: observation["image"]  # noqa: E731 - what a trajectory can store
    demos = record(env, PlannedPolicy(env, [doorkey_solved], DOORKEY_ACTIONS), 10, seed=0, labeler=labeling,
                   observation=image)
    aimless = record(env, "random", 30, seed=1, labeler=labeling, observation=image)
    path = tmp_path_factory.mktemp("doorkey") / "demos.npz"
    demos.save(path)
    return demos, aimless, path


def _check_doorkey_formula(formula, demos, aimless):
    formula = parse(formula) if isinstance(formula, str) else formula
    assert all(holds(formula, w) for w in _words(demos))
    aimless_words = _words(aimless)
    missed = [w for w in aimless_words if not any("at_goal" in step for step in w)]
    assert missed and not any(holds(formula, w) for w in missed)  # it demands reaching the goal
    assert np.mean([holds(formula, w) for w in aimless_words]) < 0.5


def test_doorkey_python_api(doorkey):
    demos, aimless, _ = doorkey
    labeling = load_labeling_function(DOORKEY_LABELS)
    learner = SpecLearner(labeling=labeling, q_steps=Q_STEPS, random_state=0).fit(
        demos, gym.make("MiniGrid-DoorKey-5x5-v0"))
    assert learner.world_ is not None and learner.world_.route == "tabular" and learner.model_ is None
    _check_doorkey_formula(learner.formula_, demos, aimless)
    assert learner.success_rate("F at_goal") >= 0.9
    assert all({"formula", "why"} <= set(r) for r in learner.rejected_)


def test_doorkey_cli(doorkey, capsys, tmp_path):
    demos, aimless, path = doorkey
    out_file = tmp_path / "doorkey.ltl"
    code, out, err = run(capsys, "learn", "spec", "--env", "minigrid:MiniGrid-DoorKey-5x5-v0", "--demos", path,
                         "--labeling", DOORKEY_LABELS, "--q-steps", Q_STEPS, "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["env"] == "minigrid:MiniGrid-DoorKey-5x5-v0" and doc["policy_update"] == "tabular"
    assert doc["success_rate"] is None and set(doc["propositions"]) == {"has_key", "door_open", "at_goal"}
    _check_doorkey_formula(doc["formula"], demos, aimless)
    assert out_file.read_text().strip() == doc["formula"]
    assert not (tmp_path / "doorkey.labeling.json").exists()  # a Python function is not saved as JSON


def test_room_preferred_order_cli(capsys, tmp_path):
    """Both tiles may be visited in either order; the demonstrator always takes ``a`` first."""
    labeling = load_labeling_function(ROOM_LABELS)
    env = gym.make("TwoTileRoom-v0")
    path = tmp_path / "room.npz"
    record(env, room_demonstrator(env), 10, seed=0, labeler=labeling).save(path)
    code, out, err = run(capsys, "learn", "spec", "--env", "minigrid_tasks:TwoTileRoom-v0", "--demos", path,
                         "--labeling", ROOM_LABELS, "--q-steps", Q_STEPS, "--json")
    assert code == 0, err
    formula = parse(json.loads(out)["formula"])
    assert parse("a T b") in list(subformulas(formula))
    assert not holds(formula, [frozenset(), frozenset({"b"}), frozenset({"a"})])  # the other order fails


def test_unlabelled_demonstrations_are_replayed_for_a_labeling_reading_info():
    """The room's labeling reads ``info``, which a file does not keep: the learner replays the
    recorded actions from each episode's seed to label them, as they were labelled live."""
    from symlearn.data import Trajectory
    from symlearn.learners.temporal.spec_env_world import EnvWorld

    env = gym.make("TwoTileRoom-v0")
    labeling = load_labeling_function(ROOM_LABELS)
    live = record(env, room_demonstrator(env), 3, seed=0, labeler=labeling)
    bare = Demonstrations([Trajectory(t.states, t.actions, t.rewards, None, t.info) for t in live])
    world = EnvWorld(env, labeling)
    assert [world.word(t) for t in world.expert_traces(bare)] == _words(live)
    assert any("a" in step for step in _words(live)[0])
    # states that the recorded actions do not reach: refused, not labelled wrongly
    first = live[0]
    wrong = Demonstrations([Trajectory(first.states[::-1], first.actions, None, None, first.info)])
    with pytest.raises(DataError, match=r"demonstration 0: replaying its actions from seed \d+ reaches another"):
        world.expert_traces(wrong)
