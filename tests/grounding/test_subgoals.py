"""Sub-goals as a labeling: reaching, NaN = not reached, JSON round trip, matching, bad input."""

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet


def test_reached_is_a_closed_ball_and_nan_is_never_reached():
    g = SubGoal("a", "s", (0, 2), (0.0, 0.0), 1.0)
    frames = np.array([[1.0, 9.0, 0.0], [0.8, 0.0, 0.61], [np.nan, 0.0, 0.0], [0.0, 0.0, np.nan]])
    assert g.reached(frames).tolist() == [True, False, False, False]
    assert g.observed(frames).tolist() == [True, True, False, False]


def test_json_round_trip_meanings_and_labels(tmp_path):
    goals = SubGoalSet([SubGoal("a", "s", (0,), (1.5,), 0.25), SubGoal("b", "t", (1,), (-2.0,), 0.5)],
                       feature_names=("x", "y"))
    path = goals.save(tmp_path / "g.json")
    assert SubGoalSet.load(path) == goals
    assert goals.meanings["a"] == "s within 0.25 of (x=1.5)"
    assert goals.label_word([[1.5, -2.0], [0.0, 0.0]]) == (frozenset({"a", "b"}), frozenset())


def test_match_pairs_nearest_centres_on_the_same_features_once():
    truth = SubGoalSet([SubGoal("t0", "s", (0,), (0.0,), 0.1), SubGoal("t1", "s", (0,), (1.0,), 0.1)])
    mine = SubGoalSet([SubGoal("m0", "s", (0,), (0.98,), 0.1), SubGoal("m1", "s", (0,), (0.95,), 0.1),
                       SubGoal("m2", "r", (1,), (0.0,), 0.1)])
    assert mine.match(truth, 0.1) == {"m0": "t1"}


@pytest.mark.parametrize("args, message", [
    (("1a", "s", (0,), (0.0,), 1.0), "identifier"),
    (("a", "s", (0, 1), (0.0,), 1.0), "1 centre values for 2 features"),
    (("a", "s", (0,), (np.nan,), 1.0), "finite"),
    (("a", "s", (0,), (0.0,), -1.0), "radius >= 0"),
    (("a", "s", (0, 0), (0.0, 0.0), 1.0), "distinct"),
])
def test_bad_subgoals_are_refused(args, message):
    with pytest.raises(DataError, match=message):
        SubGoal(*args)


def test_bad_documents_and_names():
    with pytest.raises(DataError, match="repeat"):
        SubGoalSet([SubGoal("a", "s", (0,), (0.0,), 1.0)] * 2)
    with pytest.raises(DataError, match="unknown sub-goal 'z'"):
        SubGoalSet([SubGoal("a", "s", (0,), (0.0,), 1.0)])["z"]
    with pytest.raises(DataError, match="malformed sub-goal set"):
        SubGoalSet.from_json('{"symlearn": "subgoals", "format_version": 1, "subgoals": [{"name": "a"}]}')
