"""The point-mass drone: RRT paths avoid the obstacles; sub-goals and orderings are learned from its
flights and the plan is flown again, around a location that is closed for a while."""

import numpy as np
import pytest

from symlearn.backends.subgoal_plan import execute
from symlearn.envs.drone import (
    HOME, LOCATIONS, DroneDemonstrator, DroneWorld, collides, preferred, rrt_path, segment_free, truth_pdfa,
    truth_subgoals,
)
from symlearn.learners.subgoals import SubgoalPDFALearner, pdfa_from_words
from symlearn.learners.subgoals.scoring import renamed


def test_rrt_paths_are_collision_free_and_end_at_the_goal():
    rng = np.random.default_rng(0)
    for goal in LOCATIONS:
        path = rrt_path(HOME, goal, rng)
        assert path is not None and np.allclose(path[-1], goal) and np.allclose(path[0], HOME)
        assert all(segment_free(a, b) for a, b in zip(path, path[1:]))
    assert not segment_free(np.array([3.0, 5.0, 1.0]), np.array([7.0, 5.0, 1.0]))  # through the tower
    assert rrt_path(HOME, (5.0, 5.0, 1.0), rng) is None  # inside the tower
    assert collides(np.array([-1.0, 1.0, 1.0]))


@pytest.fixture(scope="module")
def learned():
    runs, orders = DroneDemonstrator(seed=0).demonstrations(20)
    return SubgoalPDFALearner().fit(runs, ["x", "y", "z"]), orders


def test_three_locations_and_the_shown_orderings_are_learned(learned):
    learner, orders = learned
    mapping = learner.subgoals_.match(truth_subgoals(), 0.3)
    assert len(learner.subgoals_) == len(mapping) == 3
    names = ["A", "B", "C"]
    shown = pdfa_from_words([tuple(names[j] for j in o) for o in orders]).dfa
    assert renamed(learner.pdfa_, mapping).equivalent(shown)[0]
    if len({tuple(o) for o in orders}) == 6:
        assert renamed(learner.pdfa_, mapping).equivalent(truth_pdfa().dfa)[0]
    assert [mapping[s] for s in learner.plan_] == preferred() == ["A", "B", "C"]


def test_the_plan_is_flown_around_a_closed_location(learned):
    learner, _ = learned
    mapping = learner.subgoals_.match(truth_subgoals(), 0.3)
    for seed in range(5):
        world = DroneWorld(closed={"A": 1 + seed % 2}, seed=seed)
        report = execute(learner.pdfa_, world.controller(learner.subgoals_))
        assert report.success and mapping[report.achieved[0]] != "A" and report.replans
        assert sorted(mapping[s] for s in report.achieved) == ["A", "B", "C"]
