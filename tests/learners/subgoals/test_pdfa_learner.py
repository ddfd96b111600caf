"""The learner's inputs: Demonstrations (vector and feature-dict states), arrays, FeatureMaps; its outputs."""

import json

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError
from symlearn.grounding.features import FeatureMap
from symlearn.learners.subgoals import SubgoalPDFALearner


def line_demo(order, rng):
    path = [0.0] * 5 + sum(([float(g)] * 10 for g in order), [])
    return np.column_stack([np.array(path) + rng.normal(0, 0.01, len(path)), rng.normal(5, 0.01, len(path))])


@pytest.fixture(scope="module")
def runs():
    rng = np.random.default_rng(0)
    return [line_demo([1, 2], rng) for _ in range(6)] + [line_demo([2, 1], rng) for _ in range(2)]


def test_arrays_demonstrations_and_feature_dicts_give_the_same_automaton(runs):
    a = SubgoalPDFALearner(subsets="pos=0", eps=0.1).fit(runs, ["x", "y"])
    b = SubgoalPDFALearner(subsets="pos=x", eps=0.1).fit(Demonstrations([Trajectory(states=r) for r in runs]),
                                                        FeatureMap(["x", "y"]))
    dicts = Demonstrations([Trajectory(states=[{"x": float(s[0]), "y": float(s[1])} for s in r]) for r in runs])
    c = SubgoalPDFALearner(subsets={"pos": ["x"]}, eps=0.1).fit(dicts)
    assert a.pdfa_ == b.pdfa_ == c.pdfa_ and a.plan_ == ["pos_0", "pos_1"]
    assert a.words_.count(("pos_0", "pos_1")) == 6 and a.result_.metrics["distinct_words"] == 2
    array = SubgoalPDFALearner(subsets="pos=0", eps=0.1).fit(np.stack([r[:25] for r in runs]))
    assert array.subgoals_.propositions == ("pos_0", "pos_1")


def test_saved_document_is_an_automaton_with_subgoals(runs, tmp_path):
    learner = SubgoalPDFALearner(subsets="pos=0", eps=0.1).fit(runs, ["x", "y"])
    document = json.loads(learner.save(tmp_path / "plan.json").read_text())
    assert document["kind"] == "pdfa" and document["plan"] == ["pos_0", "pos_1"]
    assert document["words"][0] == {"word": ["pos_0", "pos_1"], "count": 6}
    assert abs(document["subgoals"]["pos_0"]["centre"][0] - 1.0) < 0.02
    assert set(learner.result_.timings) >= {"clustering", "words", "automaton", "total"}


@pytest.mark.parametrize("kw, message", [({"probabilities": "bayes"}, "unknown probabilities"),
                                         ({"method": "optics"}, "unknown clustering method")])
def test_bad_parameters(runs, kw, message):
    with pytest.raises(DataError, match=message):
        SubgoalPDFALearner(**kw).fit(runs)


@pytest.mark.parametrize("data, message", [
    ([np.zeros((3, 2)), np.zeros((3, 3))], "demonstration 1 has 3 features"),
    ([np.array([[0.0, np.inf]])], "infinite"),
    ([np.zeros((0, 2))], "has no frames"),
    ([], "no demonstrations"),
    ("frames", "cannot read demonstrations"),
])
def test_bad_demonstrations(data, message):
    with pytest.raises(DataError, match=message):
        SubgoalPDFALearner().fit(data)


def _walking_tours(n, rng):
    """A cook walks (0.3 per step) between three stations and dwells 6-10 frames at each, in
    mostly one order: eps from the dwell noise spans more than one walking step."""
    stations = [np.array(p) for p in [(0.0, 0.0), (5.0, 0.0), (2.5, 4.0)]]
    tours = []
    for k in range(n):
        order = [0, 1, 2] if k % 10 < 7 else [1, 0, 2]
        pos, states = np.array([2.5, -2.0]), []
        for i in order:
            while np.linalg.norm(stations[i] - pos) > 0.3:
                pos = pos + 0.3 * (stations[i] - pos) / np.linalg.norm(stations[i] - pos) + rng.normal(0, 0.05, 2)
                states.append(pos)
            states += [stations[i] + rng.normal(0, 0.05, 2) for _ in range(int(rng.integers(6, 11)))]
        tours.append(np.array(states))
    return tours


def test_places_joined_by_walking_frames_are_said_so():
    # an eps above half a walking step (the default before it was capped at half the travel step:
    # 0.45 here) chains the stations: "no sub-goal found" with the hint to lower eps, and with a
    # feature more, a sub-goal 3 wide with a warning
    tours = _walking_tours(60, np.random.default_rng(0))
    with pytest.raises(DataError, match="every cluster held a demonstration's first frame") as info:
        SubgoalPDFALearner(subsets="cook=0,1", eps=0.45).fit(tours, ["x", "y"])
    assert "lower eps (--eps) or raise min_samples" in info.value.hint
    hand = [np.column_stack([t, (np.arange(len(t)) > 20).astype(float)]) for t in tours]
    with pytest.warns(UserWarning, match=r"sub-goal all_0 has radius .* of the extent of its frames"):
        SubgoalPDFALearner(eps=0.45).fit(hand, ["x", "y", "hand"])
    found = SubgoalPDFALearner(subsets="cook=0,1", eps=0.2).fit(tours, ["x", "y"])
    assert len(found.subgoals_) == 3 and not found.warnings_


def test_walking_tours_at_the_defaults_find_the_stations_and_the_plan():
    # before: eps 0.45 from the dwelling noise (4 x the lower-quartile step) exceeded half a
    # walking step; "no sub-goal found", and with the hand a sub-goal 3 wide
    tours = _walking_tours(60, np.random.default_rng(0))
    learner = SubgoalPDFALearner(subsets="cook=0,1").fit(tours, ["x", "y"])
    stations = [(0.0, 0.0), (5.0, 0.0), (2.5, 4.0)]
    assert len(learner.subgoals_) == 3 and not learner.warnings_
    nearest = {g.name: int(np.argmin([np.linalg.norm(np.subtract(g.centre, s)) for s in stations]))
               for g in learner.subgoals_}
    assert all(np.linalg.norm(np.subtract(g.centre, stations[nearest[g.name]])) < 0.1 for g in learner.subgoals_)
    assert [nearest[s] for s in learner.plan_] == [0, 1, 2]  # 70 % of the tours
    (record,) = learner.history_
    assert record.eps_source == "half the travel step" and record.eps < 0.16
    hand = [np.column_stack([t, (np.arange(len(t)) > 20).astype(float)]) for t in tours]
    assert not SubgoalPDFALearner().fit(hand, ["x", "y", "hand"]).warnings_
