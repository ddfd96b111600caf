import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError


@pytest.mark.parametrize(
    "states, kind, shape",
    [
        ([0, 3, 2], "discrete", ()),
        (np.array([0, 3], dtype=np.int32), "discrete", ()),
        ([[0.0, 1.0], [1.5, 2.0]], "vector", (2,)),
        (np.array([0.5, 1.5]), "vector", ()),
        (np.zeros((3, 4, 4, 3), dtype=np.uint8), "image", (4, 4, 3)),
        ([{"x": 1, "lane": "left"}, {"x": 2, "lane": "right"}], "features", ("lane", "x")),
        (["at(1,2)", "at(1,3)"], "symbol", ()),
    ],
)
def test_state_kinds_are_recognised(states, kind, shape):
    t = Trajectory(states)
    assert t.state_kind == kind
    assert t.state_shape == shape
    assert t.actions is None and t.labels is None


def test_actions_may_have_one_entry_fewer_than_states():
    t = Trajectory([0, 1, 2], actions=[1, 1], rewards=[0.0, 1.0])
    assert t.n_actions == 2
    assert list(t.state_action_pairs()) == [(0, 1), (1, 1)]
    assert t.total_reward() == 1.0


def test_trajectory_is_immutable():
    t = Trajectory([0, 1])
    with pytest.raises(AttributeError):
        t.states = [2]


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(states=[]), "at least one state"),
        (dict(states=[[0.0, 1.0], [1.0]]), "ragged"),
        (dict(states=[[0.0, np.nan]]), "non-finite"),
        (dict(states=np.array([[0.0], [np.inf]])), r"non-finite value \(inf\) at step 1"),
        (dict(states=[0, 1, 2], actions=[0]), "mismatched lengths: 1 actions for 3 states"),
        (dict(states=[0, 1], actions=[0, 1, 1]), "mismatched lengths"),
        (dict(states=[0, 1], actions=[0], rewards=[1.0, 2.0]), "2 rewards, expected one per action"),
        (dict(states=[0, 1], labels=[["a"]]), "1 labels for 2 states"),
        (dict(states=[0, 1], labels=["a", "b"]), "got the string 'a'"),
        (dict(states=[0], labels=[[""]]), "not a proposition name"),
        (dict(states=[0, 1], rewards=[0.0, float("nan")]), "rewards hold a non-finite value"),
        (dict(states=[{"x": 1}, {"y": 2}]), "different feature names at step 1"),
        (dict(states=[{"x": [1, 2]}]), "must be a number, boolean or string"),
        (dict(states=[{"x": float("inf")}]), "not finite"),
        (dict(states=[0, "a"]), "mixes value types"),
        (dict(states=["a\x00"]), "NUL"),
        (dict(states="abc"), "sequence of per-step values"),
        (dict(states=[0], info={"f": object()}), "JSON values only"),
        (dict(states=[0], info={"x": float("nan")}), "JSON values only"),
        (dict(states=[0, 1], actions=np.zeros((1, 2, 2))), r"1-D vector.*shape \(2, 2\)"),
    ],
)
def test_bad_trajectories_are_refused_clearly(kwargs, message):
    with pytest.raises(DataError, match=message):
        Trajectory(**kwargs)


def test_demonstrations_validate_consistency():
    with pytest.raises(DataError, match="empty"):
        Demonstrations([])
    with pytest.raises(DataError, match="trajectory 1 has symbol states"):
        Demonstrations([Trajectory([0]), Trajectory(["a"])])
    with pytest.raises(DataError, match="ragged states across trajectories"):
        Demonstrations([Trajectory([[0.0, 1.0]]), Trajectory([[0.0, 1.0, 2.0]])])
    with pytest.raises(DataError, match="has no actions"):
        Demonstrations([Trajectory([0, 1], [0]), Trajectory([0, 1])])
    with pytest.raises(DataError, match="actions of shape"):
        Demonstrations([Trajectory([0, 1], [0]), Trajectory([0, 1], ["go"])])
    with pytest.raises(DataError, match="not a Trajectory"):
        Demonstrations([[0, 1]])


def test_slicing_concatenation_and_conversions():
    a = Trajectory([0, 1, 2], [1, 1], [0.0, 1.0], [[], ["key"], ["goal"]])
    b = Trajectory([3, 4], [0, 0], [0.5, 0.5], [["key"], []])
    demos = Demonstrations([a, b], metadata={"env": "toy"})
    assert demos[0] == a and demos[-1] == b
    assert isinstance(demos[1:], Demonstrations) and len(demos[1:]) == 1
    assert list(demos[[1, 0]]) == [b, a]
    assert list(demos[np.array([False, True])]) == [b]
    joined = demos + demos[:1]
    assert len(joined) == 3 and joined.metadata == {"env": "toy"}
    assert demos.to_state_action_pairs() == [(0, 1), (1, 1), (3, 0), (4, 0)]
    states, actions = demos.to_arrays()
    assert states.tolist() == [0, 1, 3, 4] and actions.tolist() == [1, 1, 0, 0]
    assert demos.to_label_words()[0] == (frozenset(), frozenset({"key"}), frozenset({"goal"}))
    with pytest.raises(DataError, match="boolean mask"):
        demos[np.array([True])]


def test_summary_statistics():
    demos = Demonstrations([
        Trajectory([[0.0, 1.0], [1.0, 1.0], [2.0, 3.0]], [0, 1], [1.0, 2.0], [["a"], [], ["a", "b"]]),
        Trajectory([[0.0, 1.0]], [], [], [[]]),
    ])
    s = demos.summary()
    assert s["n_trajectories"] == 2 and s["n_steps"] == 4
    assert s["length"] == {"min": 1.0, "max": 3.0, "mean": 2.0, "std": 1.0}
    assert s["return"]["max"] == 3.0 and s["return"]["min"] == 0.0
    assert s["label_counts"] == {"a": 2, "b": 1}
    assert s["n_distinct_states"] == 3 and s["n_distinct_actions"] == 2
    assert s["state_min"] == [0.0, 1.0] and s["state_max"] == [2.0, 3.0]


def test_missing_parts_are_reported():
    demos = Demonstrations([Trajectory([0, 1])])
    with pytest.raises(DataError, match="no actions"):
        demos.to_state_action_pairs()
    with pytest.raises(DataError, match="no labels"):
        demos.to_label_words()
    with pytest.raises(DataError, match="no rewards"):
        demos[0].total_reward()
