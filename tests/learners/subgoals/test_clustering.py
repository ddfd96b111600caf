"""Sub-goals by DBSCAN on weighted collapsed frames: centres, initial clusters, NaN, bad input."""

import numpy as np
import pytest

from symlearn.envs.block_world import Demonstrator, place_task
from symlearn.errors import DataError
from symlearn.learners.subgoals.clustering import collapse, derive_eps, find_subgoals, otsu_split, travel_step
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


def test_dwelling_demonstrators_keep_the_eps_from_their_noise(place3):
    # the block world's blocks sit still for most frames and are carried in a few long steps: the
    # default is the one from the dwelling noise, as before the cap at half the travel step
    task, runs = place3
    _, records = find_subgoals(runs, feature_subsets(task.subsets(), task.feature_names()))
    for record, columns in zip(records, ([0, 1, 2], [3, 4, 5], [6, 7, 8])):
        projected = [r[:, columns] for r in runs]
        observed = [p[~np.isnan(p).any(axis=1)] for p in projected]
        stacked = np.concatenate(observed)
        steps = np.concatenate([np.linalg.norm(np.diff(p, axis=0), axis=1) for p in observed])
        noise_eps = max(0.02 * np.linalg.norm(stacked.max(axis=0) - stacked.min(axis=0)), 4 * np.quantile(steps, 0.25))
        assert record.eps_source == "dwelling noise" and record.eps == pytest.approx(noise_eps)
        assert derive_eps(projected).travel_step > 2 * record.eps


def test_travel_step_is_the_upper_mode_of_the_steps():
    rng = np.random.default_rng(0)
    dwell, walk = rng.rayleigh(0.03, 500), 0.3 + rng.normal(0, 0.02, 300)
    # the lower quartile of the walking steps
    assert travel_step(np.concatenate([dwell, walk])) == pytest.approx(np.quantile(walk, 0.25), abs=0.01)
    assert travel_step(np.array([0.0] * 40 + [1.0] * 10)) == 1.0  # exactly still frames: zero steps
    assert otsu_split(np.full(10, 0.2)) is None and otsu_split(np.zeros(10)) is None and travel_step(np.zeros(0)) is None


def _tours(n, speed, noise, rng):
    """Tours of three places (each in one of two orders) walking ``speed`` per step with ``noise``,
    dwelling 6-12 frames at each place."""
    places = np.array([(0.0, 0.0), (1.0, 0.0), (0.5, 0.8)])
    runs = []
    for k in range(n):
        pos, states = np.array([0.5, -0.6]), []
        for j in (0, 1, 2) if k % 3 else (1, 0, 2):
            while np.linalg.norm(places[j] - pos) > speed:
                pos = pos + speed * (places[j] - pos) / np.linalg.norm(places[j] - pos) + rng.normal(0, noise, 2)
                states.append(pos)
            states += [places[j] + rng.normal(0, noise, 2) for _ in range(int(rng.integers(6, 13)))]
        runs.append(np.array(states))
    return places, runs


@pytest.mark.parametrize("speed, noise", [(0.08, 0.012), (0.02, 0.006)])
def test_places_of_demonstrators_fast_or_slow_against_their_noise(speed, noise):
    # before: eps from the dwelling noise (4 x the lower-quartile step) was more than half a step,
    # and the passing frames chained the start and the places into one cluster: no sub-goal
    places, runs = _tours(30, speed, noise, np.random.default_rng(1))
    goals, (record,) = find_subgoals(runs, feature_subsets(None, ("x", "y")))
    assert len(goals) == 3 and record.eps_source == "half the travel step" and record.eps < speed / 2 + 0.01
    for goal in goals:
        assert min(np.linalg.norm(np.subtract(goal.centre, p)) for p in places) < 3 * noise


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


def walker_tours(n=30, seed=0, step=0.1, dwell=9, noise=0.01):
    """A deterministic walker's tours: from the same start, 2.2 from (0, 0) at 15 degrees below the
    x axis, walking in equal steps on straight lines to (0, 0), then (4, 0) and (2, 3), dwelling
    ``dwell`` frames at each; every tour's frames fall on the same points (up to ``noise``). The
    last frame before (0, 0) and the first after it lie 0.026 apart, two frames of every tour at
    one spot."""
    rng = np.random.default_rng(seed)
    angle = np.radians(15)
    start = 22 * step * np.array([np.cos(angle), -np.sin(angle)])
    stations = [np.array(p) for p in ((0.0, 0.0), (4.0, 0.0), (2.0, 3.0))]
    runs = []
    for _ in range(n):
        position, frames = start, [start]
        for target in stations:
            length = float(np.linalg.norm(target - position))
            frames += [position + (target - position) * j * step / length
                       for j in range(1, int(round(length / step, 6)) + 1)]
            frames += [target] * dwell
            position = target
        runs.append(np.array(frames) + rng.normal(0, noise, (len(frames), 2)))
    return runs, stations


def test_a_spot_every_tour_passes_through_is_no_sub_goal():
    # 30 tours each put two walking frames next to (0, 0) on the same line (arriving, leaving):
    # a dense cluster (60 frames >= min_samples 45) where nobody stays; dropped as pass-through
    runs, stations = walker_tours()
    goals, records = find_subgoals(runs, feature_subsets(None, ["x", "y"]))
    assert len(goals) == 3, [g.centre for g in goals]
    for goal, station in zip(sorted(goals, key=lambda g: g.centre), sorted(map(tuple, stations))):
        assert np.linalg.norm(np.subtract(goal.centre, station)) < 0.02
    assert records[0].dropped_passing >= 1
