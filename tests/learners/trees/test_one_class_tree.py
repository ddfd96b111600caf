"""One-class decision trees and their DNF constraints (thesis, chapter 4)."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest
from sklearn.base import clone

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError, SymlearnError
from symlearn.grounding.features import FeatureMap
from symlearn.learners.base import NotFittedError
from symlearn.learners.trees import Box, OneClassTreeConstraint, binned_kde
from symlearn.logic.dnf import DNF, parse
from symlearn.rendering import dot_available, dot_to_svg_text, render_dot

# -- the thesis' toy (Fig. 4.1) --------------------------------------------------------------------

BOTTOM = Box((0.1, 0.1), (0.7, 0.3))
RIGHT = Box((0.7, 0.1), (0.9, 0.9))


def toy_demonstrations(n: int = 20, seed: int = 0, step: float = 0.01, noise: float = 0.005) -> Demonstrations:
    """Experts from the start (0.1, 0.1) to the goal (0.9, 0.9), right along the bottom bar,
    then up the right column, with a little noise, never leaving the safe set."""
    rng = np.random.default_rng(seed)
    trajectories = []
    for _ in range(n):
        y0, x_turn = rng.uniform(0.12, 0.28), rng.uniform(0.72, 0.88)
        points = [(0.1, 0.1)] + [(x, y0) for x in np.arange(0.1, x_turn, step)] \
            + [(x_turn, y) for y in np.arange(y0, 0.9, step)] + [(0.9, 0.9)]
        p = np.array(points) + rng.normal(0, noise, (len(points), 2))
        p = np.clip(p, 0.1, 0.9)
        up = p[:, 1] > 0.3
        p[up, 0] = np.clip(p[up, 0], 0.7, 0.9)
        trajectories.append(Trajectory(p, actions=np.zeros((len(p) - 1, 2))))
    return Demonstrations(trajectories)


def truly_unsafe(X: np.ndarray) -> np.ndarray:
    return ~(BOTTOM.contains(X) | RIGHT.contains(X))


def grid(lo: float, hi: float, n: int, k: int = 2) -> np.ndarray:
    axis = np.linspace(lo, hi, n)
    return np.array(list(itertools.product(axis, repeat=k)))


def boundary_grid(learner: OneClassTreeConstraint, eps: float = 1e-9) -> np.ndarray:
    """Every combination of every box coordinate, just inside and outside it, and midpoints:
    the points where a formula and the boxes could disagree."""
    axes = []
    for d in range(len(learner.feature_names_)):
        values = {learner.bounds_.lower[d] - 1.0, learner.bounds_.upper[d] + 1.0}
        for box in learner.safe_boxes_:
            for v in (box.lower[d], box.upper[d]):
                values |= {v, v - eps, v + eps}
        ordered = sorted(values)
        values |= {(a + b) / 2 for a, b in zip(ordered, ordered[1:])}
        axes.append(sorted(values))
    return np.array(list(itertools.product(*axes)))


def inside_any_leaf(learner: OneClassTreeConstraint, X: np.ndarray) -> np.ndarray:
    return np.any([box.contains(X) for box in learner.safe_boxes_], axis=0)


def check_formula(learner: OneClassTreeConstraint, X: np.ndarray) -> None:
    unsafe = learner.dnf_.evaluate(X, learner.feature_names_)
    assert np.array_equal(unsafe, ~inside_any_leaf(learner, X))
    assert np.array_equal(unsafe, learner.predict(X))


def test_thesis_toy_finds_the_two_rectangles():
    learner = OneClassTreeConstraint().fit(toy_demonstrations(), FeatureMap(["phi0", "phi1"]))
    assert learner.feature_names_ == ("phi0", "phi1")
    assert learner.tree_.n_leaves == 2 and learner.tree_.root.feature == 0  # split on phi0, as Fig. 4.2
    bottom, right = learner.safe_boxes_
    assert np.allclose(bottom.lower + bottom.upper, BOTTOM.lower + BOTTOM.upper, atol=0.05)
    assert np.allclose(right.lower + right.upper, RIGHT.lower + RIGHT.upper, atol=0.05)
    assert learner.bounds_ == Box((0.1, 0.1), (0.9, 0.9))
    # the formula classifies a dense grid like the true unsafe set, except near the borders
    X = grid(0.0, 1.0, 201)
    learned = learner.dnf_.evaluate(X, ["phi0", "phi1"])
    near = np.zeros(len(X), dtype=bool)
    for box in (BOTTOM, RIGHT):
        for d in range(2):
            for side in (box.lower[d], box.upper[d]):
                near |= np.abs(X[:, d] - side) <= 0.05
    assert np.array_equal(learned[~near], truly_unsafe(X)[~near])
    assert (learned == truly_unsafe(X)).mean() > 0.95  # the experts kept below y = 0.28
    check_formula(learner, X)
    check_formula(learner, boundary_grid(learner))
    # the thesis' shape of the formula: the bounds, then the bottom bar's "above it" clause
    text = str(learner.dnf_)
    assert text.splitlines()[:4] == ["phi0 < 0.1", "phi0 > 0.9", "phi1 < 0.1", "phi1 > 0.9"]
    assert any(line.startswith(("phi0 >= 0.1 & phi0 <= 0.", "phi0 >= 0.1 & phi0 < 0.")) and "& phi1 > 0." in line
               for line in text.splitlines())


@pytest.mark.parametrize("seed", range(1, 10))
def test_thesis_toy_is_stable_across_samples(seed):
    learner = OneClassTreeConstraint().fit(toy_demonstrations(seed=seed))
    X = grid(0.0, 1.0, 101)
    assert (learner.predict(X) == truly_unsafe(X)).mean() > 0.95
    assert learner.tree_.n_leaves <= 3


def test_demonstrated_points_are_safe_and_formula_round_trips(tmp_path):
    demos = toy_demonstrations(seed=3)
    learner = OneClassTreeConstraint(min_samples_leaf=1, max_depth=4).fit(demos)
    states = np.concatenate([t.states for t in demos])
    assert not learner.predict(states).any()
    assert parse(str(learner.dnf_)) == learner.dnf_
    path = learner.save(tmp_path / "unsafe.dnf")
    assert parse(path.read_text()) == learner.dnf_
    header, formula = learner.result_.text.split("\nx0 < 0.1\n", 1)
    assert "x0 < 0.1\n" + formula == str(learner.dnf_) and learner.result_.artefact is learner.dnf_
    assert all(line.startswith("# ") for line in header.splitlines())
    assert learner.result_.metrics["n_leaves"] == len(learner.safe_boxes_)
    assert learner.result_.metrics["n_conjunctions"] == len(learner.dnf_)
    for record in learner.result_.history:
        assert set(record.as_dict()) >= {"depth", "feature", "gain", "intervals"}


def clusters(n: int, k: int, seed: int = 0, n_clusters: int = 4, spread: float = 0.3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    centers = rng.uniform(0, 10, (n_clusters, k))
    return centers[rng.integers(0, n_clusters, n)] + rng.normal(0, spread, (n, k))


@pytest.mark.parametrize("seed", range(3))
def test_formula_is_the_complement_of_the_leaf_boxes(seed):
    X = clusters(600, 3, seed=seed)
    X[:, 2] = np.round(X[:, 2] / 3)  # a discrete feature: flat boxes, touching values
    learner = OneClassTreeConstraint(min_samples_leaf=3).fit(X)
    assert learner.tree_.n_leaves > 1
    check_formula(learner, boundary_grid(learner))
    lo, hi = np.min(X, axis=0) - 1, np.max(X, axis=0) + 1
    rng = np.random.default_rng(seed)
    check_formula(learner, rng.uniform(lo, hi, (20000, 3)))
    assert not learner.predict(X).any()
    # leaves are disjoint and apply() finds the one holding each point
    leaf = learner.tree_.apply(X)
    assert (leaf >= 0).all()
    assert np.array_equal(inside_any_leaf(learner, X), leaf >= 0)
    for i, box in enumerate(learner.safe_boxes_):
        assert box.contains(X[leaf == i]).all()
    counts = np.sum([box.contains(X) for box in learner.safe_boxes_], axis=0)
    assert (counts == 1).all()


@pytest.mark.parametrize("seed", range(3))
def test_a_conjunction_keeps_the_tightest_bound_per_feature_and_direction(seed):
    # a side tightened below an ancestor's split used to print both bounds (x1 < -0.39 & x1 < -0.64);
    # seed 1 made one such conjunction
    X = clusters(600, 3, seed=seed)
    X[:, 2] = np.round(X[:, 2] / 3)
    learner = OneClassTreeConstraint(min_samples_leaf=3).fit(X)
    for conjunction in learner.dnf_:
        sides = [(a.feature, a.is_upper) for a in conjunction]
        assert len(sides) == len(set(sides)), str(conjunction)
    check_formula(learner, boundary_grid(learner))  # the same set of points as the leaf boxes' complement
    assert parse(str(learner.dnf_)) == learner.dnf_
    assert learner.result_.metrics["n_atoms"] == sum(len(c) for c in learner.dnf_)


def test_clusters_in_many_dimensions_give_one_box_each():
    X = clusters(20000, 8, n_clusters=3, spread=0.5)
    learner = OneClassTreeConstraint().fit(X)
    assert learner.tree_.n_leaves == 3
    gaussian = np.random.default_rng(1).normal(size=(20000, 8))  # one blob: nothing to cut
    assert OneClassTreeConstraint().fit(gaussian).tree_.n_leaves == 1


# -- edge cases ---------------------------------------------------------------------------------------

def test_constant_features():
    rng = np.random.default_rng(0)
    X = np.column_stack([rng.uniform(0, 1, 200), np.full(200, 3.0), np.concatenate([np.zeros(100), np.ones(100) * 5])])
    learner = OneClassTreeConstraint().fit(X, ["u", "c", "d"])
    assert "c < 3\nc > 3" in str(learner.dnf_)
    assert learner.tree_.n_leaves == 2 and learner.tree_.root.feature == 2
    assert learner.predict([[0.5, 3.0, 0.0], [0.5, 3.1, 0.0], [0.5, 3.0, 2.5]]).tolist() == [False, True, True]
    check_formula(learner, boundary_grid(learner))
    everything_constant = OneClassTreeConstraint().fit(np.tile([1.0, -2.0], (50, 1)))
    assert everything_constant.tree_.n_leaves == 1
    assert everything_constant.predict([[1.0, -2.0], [1.0, -1.0]]).tolist() == [False, True]


def test_duplicate_points():
    X = np.repeat([[0.0, 0.0], [1.0, 1.0], [4.0, 0.0]], 50, axis=0)
    learner = OneClassTreeConstraint().fit(X)
    assert sorted(b.lower for b in learner.safe_boxes_) == [(0.0, 0.0), (1.0, 1.0), (4.0, 0.0)]
    assert all(b.lower == b.upper for b in learner.safe_boxes_)
    assert learner.predict([[1.0, 1.0], [1.0, 0.0], [0.5, 0.5]]).tolist() == [False, True, True]
    check_formula(learner, boundary_grid(learner))


def test_one_point():
    learner = OneClassTreeConstraint().fit(np.array([[0.5, -1.0]]))
    assert learner.tree_.n_leaves == 1 and learner.safe_boxes_ == (Box((0.5, -1.0), (0.5, -1.0)),)
    assert str(learner.dnf_) == "x0 < 0.5\nx0 > 0.5\nx1 < -1\nx1 > -1"
    assert learner.predict([0.5, -1.0]).tolist() == [False]
    assert learner.predict([[0.5, -1.0], [0.5, -0.9]]).tolist() == [False, True]


def test_one_dimensional_data():
    rng = np.random.default_rng(0)
    values = np.concatenate([rng.normal(0, 0.1, 300), rng.normal(5, 0.1, 300)])
    learner = OneClassTreeConstraint().fit(values, ["speed"])  # a 1-D array: one feature
    assert learner.feature_names_ == ("speed",)
    assert learner.tree_.n_leaves == 2
    (low, high) = learner.safe_boxes_
    assert low.upper[0] < 1 and high.lower[0] > 4
    assert learner.predict([[0.0], [2.5], [5.0]]).tolist() == [False, True, False]
    assert learner.predict(np.array([0.0, 2.5])).tolist() == [False, True]  # N values of the one feature
    check_formula(learner, np.linspace(-1, 6, 7001)[:, None])


def test_fifty_features():
    X = clusters(3000, 50, n_clusters=2)
    learner = OneClassTreeConstraint().fit(X)
    assert len(learner.feature_names_) == 50 and learner.feature_names_[-1] == "x49"
    assert learner.tree_.n_leaves == 2
    assert not learner.predict(X).any()
    rng = np.random.default_rng(0)
    check_formula(learner, rng.uniform(X.min(axis=0), X.max(axis=0), (2000, 50)))
    check_formula(learner, np.vstack([X[:50], X[:50] + 0.5]))


def test_hundred_thousand_points_by_twenty_features_fit_quickly():
    rng = np.random.default_rng(0)
    X = clusters(100_000, 20, n_clusters=5, spread=0.5)
    X[:, 3] = rng.integers(0, 4, len(X))
    X[:, 7] = rng.uniform(0, 1, len(X))
    started = time.perf_counter()
    learner = OneClassTreeConstraint().fit(X)
    seconds = time.perf_counter() - started
    assert seconds < 10, seconds
    assert learner.tree_.n_leaves == 20  # 5 clusters x 4 values of the discrete feature
    assert not learner.predict(X).any()


# -- inputs -----------------------------------------------------------------------------------------------

def test_feature_dict_states_and_feature_maps():
    states = [{"speed": 0.1 * i, "gap": 10.0 - i} for i in range(10)]
    demos = Demonstrations([Trajectory(states)])
    learner = OneClassTreeConstraint().fit(demos)
    assert learner.feature_names_ == ("speed", "gap")
    assert learner.bounds_ == Box((0.0, 1.0), (0.9, 10.0))
    by_map = OneClassTreeConstraint().fit(demos, FeatureMap(["gap", "speed"]))
    assert by_map.feature_names_ == ("gap", "speed") and by_map.bounds_ == Box((1.0, 0.0), (10.0, 0.9))
    # discrete states through a table, and a function of vector states
    table = FeatureMap(["x", "y"], table=np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 3.0]]))
    ids = OneClassTreeConstraint().fit(Demonstrations([Trajectory([0, 1, 1, 2])]), table)
    assert ids.bounds_ == Box((0.0, 0.0), (3.0, 3.0)) and ids.n_samples_ == 4
    double = FeatureMap(["twice"], function=lambda s: [2 * s[0]])
    fitted = OneClassTreeConstraint().fit(np.array([[1.0], [2.0]]), double)
    assert fitted.bounds_ == Box((2.0,), (4.0,))


def test_bad_inputs_are_clear_errors():
    learner = OneClassTreeConstraint()
    with pytest.raises(DataError, match="not finite"):
        learner.fit(np.array([[0.0, 1.0], [np.nan, 2.0]]))
    with pytest.raises(DataError, match="feature x1 of point 1"):
        learner.fit(np.array([[0.0, 1.0], [0.0, np.inf]]))
    with pytest.raises(DataError, match="finite"):
        learner.fit(np.array([[0.0], [1.0]]), FeatureMap(["x"], function=lambda s: [float("nan")]))
    with pytest.raises(DataError, match="empty"):
        learner.fit(np.zeros((0, 3)))
    with pytest.raises(DataError, match="empty"):
        learner.fit([])
    with pytest.raises(DataError, match="2 feature names"):
        learner.fit(np.zeros((4, 3)), ["a", "b"])
    with pytest.raises(DataError, match="repeat"):
        learner.fit(np.zeros((4, 2)), ["a", "a"])
    with pytest.raises(DataError, match="symbol states"):
        learner.fit(Demonstrations([Trajectory(["a", "b"])]))
    with pytest.raises(DataError, match="text"):
        learner.fit(Demonstrations([Trajectory([{"x": 1.0, "mode": "fast"}])]))
    fitted = OneClassTreeConstraint().fit(np.zeros((3, 2)))
    with pytest.raises(DataError, match="shape"):
        fitted.predict(np.zeros((2, 3)))
    with pytest.raises(DataError, match="NaN"):
        fitted.predict([[np.nan, 0.0]])


@pytest.mark.parametrize("params, message", [
    ({"max_depth": 0}, "max_depth"), ({"max_depth": -3}, "max_depth"), ({"max_depth": 2.5}, "max_depth"),
    ({"min_samples_leaf": 0}, "min_samples_leaf"), ({"bandwidth": "wide"}, "bandwidth"),
    ({"bandwidth": 0.0}, "bandwidth"), ({"density_threshold": 1.0}, "density_threshold"),
    ({"min_gain": 1.0}, "min_gain"), ({"box_sigmas": 0}, "box_sigmas"), ({"grid_size": 4}, "grid_size"), ({"grid_size": 10**6}, "grid_size"),
])
def test_bad_hyper_parameters_are_clear_errors(params, message):
    with pytest.raises(SymlearnError, match=message):
        OneClassTreeConstraint(**params).fit(np.zeros((3, 2)))


# -- the learner contract, text and DOT -----------------------------------------------------------------

def test_contract():
    learner = OneClassTreeConstraint(max_depth=3, bandwidth=0.05, min_samples_leaf=2, random_state=7)
    params = learner.get_params()
    assert params["max_depth"] == 3 and params["bandwidth"] == 0.05 and params["random_state"] == 7
    twin = clone(learner)
    assert twin.get_params() == params
    for call in (lambda: learner.predict([[0.0, 0.0]]), learner.export_text, learner.to_dot,
                 lambda: learner.save("never.dnf"), lambda: learner.result_ if learner.check_fitted() else None):
        with pytest.raises(NotFittedError):
            call()
    assert learner.fit(toy_demonstrations(n=5)) is learner
    assert learner.get_params() == params
    assert "result_" not in vars(twin)
    # the fit does not depend on random_state
    other = OneClassTreeConstraint(max_depth=3, bandwidth=0.05, min_samples_leaf=2, random_state=8)
    assert other.fit(toy_demonstrations(n=5)).dnf_ == learner.dnf_


def test_export_text():
    learner = OneClassTreeConstraint().fit(toy_demonstrations(), ["x", "y"])
    text = learner.export_text(digits=2)
    lines = text.splitlines()
    assert lines[0].startswith("root: ") and "x in [0.1, 0.9], y in [0.1, 0.9]" in lines[0]
    assert lines[1].startswith("|--- x in [0.1, 0.7") and lines[1].endswith("leaf") and "y in [0.1, 0.2" in lines[1]
    assert lines[2].startswith("|--- x in [0.7") and lines[2].endswith("leaf")


def test_dot_output():
    learner = OneClassTreeConstraint().fit(toy_demonstrations(), ["x", "y"])
    dot = learner.to_dot(title="expert tree")
    assert dot.startswith("digraph one_class_tree {") and dot.count("->") == 2
    assert "safe box" in dot and "split on x" in dot and '<= x <=' in dot


@pytest.mark.skipif(not dot_available(), reason="graphviz dot not installed")
def test_dot_renders(tmp_path):
    X = clusters(2000, 4, n_clusters=3)
    learner = OneClassTreeConstraint().fit(X, ["a", "b", "c", "d"])
    svg = dot_to_svg_text(learner.to_dot())
    assert svg is not None and "<svg" in svg and "safe box" in svg
    assert render_dot(learner.to_dot(), tmp_path / "tree.svg").stat().st_size > 0
    assert "<svg" in learner._repr_svg_()


# -- the density estimate -----------------------------------------------------------------------------------

def test_binned_kde_matches_scipy_away_from_the_edges():
    from scipy.stats import gaussian_kde

    rng = np.random.default_rng(0)
    values = np.concatenate([rng.normal(0, 1, 4000), rng.normal(6, 0.5, 2000)])
    lo, hi, G = values.min(), values.max(), 512
    counts = np.bincount(np.minimum(((values - lo) / (hi - lo) * G).astype(int), G - 1), minlength=G)
    h = 0.3
    ours = binned_kde(counts[None].astype(float), h / (hi - lo) * G)[0]
    ours /= ours.sum() * (hi - lo) / G  # a density
    centers = lo + (np.arange(G) + 0.5) * (hi - lo) / G
    theirs = gaussian_kde(values, bw_method=h / values.std(ddof=1))(centers)
    interior = (centers > lo + 4 * h) & (centers < hi - 4 * h)
    assert np.max(np.abs(ours - theirs)[interior]) < 0.02 * theirs.max()
    # reflection: a uniform sample has a flat estimate up to the edges
    flat = binned_kde(np.ones((1, 100)), 10.0)[0]
    assert np.allclose(flat, 1.0)


def test_dnf_value_type():
    learner = OneClassTreeConstraint().fit(np.array([[0.0, 0.0], [1.0, 1.0]]))
    assert isinstance(learner.dnf_, DNF)
    assert learner.dnf_.features == ("x0", "x1")


def test_header_names_the_demonstrations_source():
    points = [[0.0, 0.0], [0.1, 0.2], [0.2, 0.1]]
    demos = Demonstrations([Trajectory(points)], metadata={"source": "3 steps of a\nhand-made\texpert"})
    made = OneClassTreeConstraint(max_depth=2).fit(demos, ["x", "y"]).artefact_text().splitlines()[0]
    # one line whatever the metadata holds, so the header stays a comment
    assert made.startswith("# unsafe set learned by a one-class tree (max depth 2) from 3 steps of a hand-made "
                           "expert (3 points); ")
    untold = OneClassTreeConstraint(max_depth=2).fit(points, ["x", "y"]).artefact_text().splitlines()[0]
    assert " from 3 points; " in untold


def test_values_near_the_float64_limit_do_not_overflow_the_bandwidth():
    import warnings as _warnings

    import numpy as _np

    from symlearn.learners.trees.one_class_tree import bandwidths

    X = _np.array([[0.5, 1.0], [1e300, 2.0], [0.7, 3.0]])
    with _warnings.catch_warnings():
        _warnings.simplefilter("error")
        h = bandwidths(X, "scott")
    assert _np.isfinite(h).all() and h[0] > 1e299
    assert bandwidths(X[:, 1:], "scott").tolist() == (1.06 * X[:, 1:].std(axis=0) * 3 ** -0.2).tolist()


def test_whole_numbers_drops_the_conjunctions_between_ids():
    # ids of a Discrete observation: 1, 2 visited, 3 avoided, 5 visited; slabs such as
    # x > 2 & x < 3 hold at no id and were printed as rules that forbid nothing
    from symlearn.learners.trees.one_class_tree import _holds_at_a_whole_number

    points = [[v] for v in [1.0] * 10 + [2.0] * 10 + [5.0] * 10 + [6.0] * 10]
    plain = OneClassTreeConstraint(max_depth=3, min_samples_leaf=2).fit(points, ["x"])
    ids = OneClassTreeConstraint(max_depth=3, min_samples_leaf=2, whole_numbers=True).fit(points, ["x"])
    assert all(_holds_at_a_whole_number(c) for c in ids.dnf_.conjunctions)
    assert not all(_holds_at_a_whole_number(c) for c in plain.dnf_.conjunctions)  # x > 1 & x < 2, ...
    assert len(ids.dnf_.conjunctions) < len(plain.dnf_.conjunctions)
    assert any("hold at no whole-number point" in note for note in ids.notes_)
    grid = [[float(v)] for v in range(-1, 9)]
    assert ids.dnf_.evaluate(grid, ["x"]).tolist() == plain.dnf_.evaluate(grid, ["x"]).tolist()
    assert ids.dnf_.evaluate([[3.0], [4.0]], ["x"]).tolist() == [True, True]


def test_whole_number_check_of_one_conjunction():
    from symlearn.learners.trees.one_class_tree import _holds_at_a_whole_number
    from symlearn.logic.dnf import DNF

    def holds(*atoms):
        return _holds_at_a_whole_number(DNF.of(atoms).conjunctions[0])

    assert not holds(("x", ">", 1), ("x", "<", 2))
    assert holds(("x", ">=", 1), ("x", "<", 2)) and holds(("x", ">", 1.5), ("x", "<=", 2))
    assert not holds(("x", ">", 1.2), ("x", "<", 1.9)) and holds(("x", "<", 0.5))
    assert holds(("x", ">", 1), ("x", "<", 3), ("y", ">=", -1), ("y", "<=", -1))
    with pytest.raises(SymlearnError):
        OneClassTreeConstraint(whole_numbers="yes").fit([[0.0], [1.0]], ["x"])
