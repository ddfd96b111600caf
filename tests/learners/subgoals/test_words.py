"""Algorithm 6.1: one symbol per frame, the first unreached sub-goal in set order, NaN unknown."""

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.grounding.subgoals import SubGoal, SubGoalSet
from symlearn.learners.subgoals.words import demonstration_word, demonstration_words, word_from_reached

NAN = np.nan


def reference_word(reached):
    """Algorithm 6.1 literally: for every frame, for every sub-goal in order."""
    word = []
    for row in reached:
        for g, hit in enumerate(row):
            if g not in word and hit:
                word.append(g)
                break
    return word


def test_event_driven_scan_equals_the_literal_algorithm():
    rng = np.random.default_rng(0)
    for _ in range(300):
        reached = rng.random((int(rng.integers(1, 12)), int(rng.integers(1, 6)))) < rng.uniform(0.05, 0.7)
        assert word_from_reached(reached) == reference_word(reached)


def test_one_symbol_per_frame_ties_to_the_earlier_subgoal():
    reached = np.array([[False, True, True], [False, True, True], [True, False, False]])
    assert word_from_reached(reached) == [1, 2, 0]  # frame 0 adds 1, frame 1 adds 2, frame 2 adds 0


def test_unobserved_features_never_reach_a_subgoal():
    goals = SubGoalSet([SubGoal("a", "s", (0, 1), (1.0, 1.0), 0.1), SubGoal("b", "s", (0, 1), (2.0, 2.0), 0.1)])
    frames = np.array([[1.0, NAN], [2.0, 2.0], [NAN, NAN], [1.0, 1.05]])
    assert demonstration_word(goals, frames) == ("b", "a")
    assert demonstration_words(goals, [frames[:1], frames[2:3]]) == [(), ()]


def test_frames_with_too_few_features_are_refused():
    goals = SubGoalSet([SubGoal("a", "s", (3,), (1.0,), 0.1)])
    with pytest.raises(DataError, match="reads feature column 3"):
        demonstration_word(goals, np.zeros((4, 2)))
