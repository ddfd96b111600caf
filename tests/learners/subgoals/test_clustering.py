"""Sub-goals by DBSCAN on weighted collapsed frames: centres, initial clusters, NaN, bad input."""

import numpy as np
import pytest

from symlearn.envs.block_world import Demonstrator, place_task
from symlearn.errors import DataError
from symlearn.learners.subgoals.clustering import collapse, find_subgoals
from symlearn.learners.subgoals.subsets import feature_subsets


@pytest.fixture(scope="module")
def place3():
    task = place_task(3)
    runs, _ = Demonstrator(task, seed=3, drop=0.1).demonstrations(60)
    return task, runs


def test_collapse_keeps_weights_and_exact_sums():
    rng = np.random.default_rng(0)
    points = np.vstack([rng.normal(0, 0.001, (500, 2)), rng.normal(1, 0.001, (300, 2))])
    initial = np.zeros(800, dtype=bool)
    initial[0] = True
    c = collapse(points, initial, 0.01)
    assert c.weights.sum() == 800 and len(c.weights) < 20
    assert np.allclose(c.sums.sum(axis=0), points.sum(axis=0))
    assert c.initial.sum() == 1 and c.initial[np.argmin(np.linalg.norm(c.points, axis=1))]


def test_block_world_subgoals_are_the_targets_within_a_centimetre(place3):
    task, runs = place3
    goals, records = find_subgoals(runs, feature_subsets(task.subsets(), task.feature_names()))
    truth = task.truth_subgoals()
    mapping = goals.match(truth, tolerance=0.01)
    assert len(goals) == len(truth) == len(mapping)  # one sub-goal per target, none extra
    for record in records:  # the tray position of every block was a cluster, dropped as initial
        assert record.dropped_initial == 1 and record.points < record.frames / 3  # dwelling frames collapsed


def test_nan_frames_are_unknown_not_errors(place3):
    task, runs = place3
    blinded = [r.copy() for r in runs]
    for r in blinded:
        r[::2, :3] = np.nan  # the red block is seen in every other frame only
    goals, _ = find_subgoals(blinded, feature_subsets(task.subsets(), task.feature_names()))
    assert len(goals.match(task.truth_subgoals(), 0.01)) == 3


def test_hdbscan_option_finds_the_same_subgoals(place3):
    task, runs = place3
    goals, _ = find_subgoals(runs, feature_subsets(task.subsets(), task.feature_names()), method="hdbscan")
    assert len(goals.match(task.truth_subgoals(), 0.01)) == 3


def test_all_nan_is_a_clear_error(place3):
    task, runs = place3
    with pytest.raises(DataError, match="every frame is unobserved"):
        find_subgoals([np.full_like(r, np.nan) for r in runs], feature_subsets(task.subsets(), task.feature_names()))


def test_no_cluster_names_the_parameters_to_change(place3):
    task, runs = place3
    with pytest.raises(DataError) as info:
        find_subgoals(runs, feature_subsets(task.subsets(), task.feature_names()), min_samples=10**9)
    assert "no sub-goal found" in str(info.value) and "--min-samples" in info.value.hint


@pytest.mark.parametrize("subsets, message", [
    ("red=0,1,9", "column 9 is out of range; the states have 9 features"),
    ("red=0,1;red=2", "given twice"),
    ("red", "expected name=c,c"),
    ({"red": ["nope"]}, "no feature named 'nope'"),
    ({"1x": [0]}, "must be an identifier"),
    ({"red": []}, "names no feature"),
])
def test_bad_subsets_are_refused(subsets, message):
    with pytest.raises(DataError, match=message):
        feature_subsets(subsets, place_task(3).feature_names())


@pytest.mark.parametrize("kw, message", [({"eps": -1.0}, "eps must be"), ({"min_samples": 0}, "min_samples"),
                                         ({"method": "kmeans"}, "unknown clustering method")])
def test_bad_parameters_are_refused(place3, kw, message):
    task, runs = place3
    with pytest.raises(DataError, match=message):
        find_subgoals(runs, feature_subsets(None, task.feature_names()), **kw)


def test_values_whose_distances_overflow_are_refused_not_an_internal_error(tmp_path, capsys):
    # a column near 1e300 made the data-derived eps infinite and DBSCAN raise (an internal error)
    import json

    from tests.support.cli_runner import run

    path = tmp_path / "d.jsonl"
    header = {"symlearn": "demonstrations", "format_version": 1, "state_kind": "vector"}
    lines = [json.dumps(header)] + [json.dumps({"states": [[0.0, 1e300], [0.5, 1.0], [1.0, 2.0]]})] * 3
    path.write_text("\n".join(lines) + "\n")
    code, _, err = run(capsys, "learn", "pdfa", "--demos", path)
    assert code == 2 and f"{path}: the frames hold values up to 1e+300" in err and "internal error" not in err, err
