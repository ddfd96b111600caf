"""Readable DNF artefacts (issue #25 section 3): short thresholds that change no point's side,
closed slivers, and the warning when most of the bounding box is unsafe."""

from __future__ import annotations

import json
import sys
import warnings
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from cli_runner import run

sys.path.insert(0, str(Path(__file__).parent))  # the toy and the formula checks of test_one_class_tree

from test_one_class_tree import boundary_grid, check_formula, toy_demonstrations  # noqa: E402

from symlearn.data import Demonstrations, Trajectory  # noqa: E402
from symlearn.learners.trees import OneClassTreeConstraint  # noqa: E402
from symlearn.learners.trees.readable_bounds import fewest_digits  # noqa: E402
from symlearn.logic.dnf import parse  # noqa: E402


def quiet_fit(X, **params):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return OneClassTreeConstraint(**params).fit(X)


def digits(value: float) -> int:
    return len(Decimal(repr(value)).normalize().as_tuple().digits)


def two_blobs(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.vstack([rng.uniform([0.0, 0.0], [0.3, 1.0], (400, 2)), rng.uniform([0.6, 0.2], [1.0, 0.5], (400, 2))])


@pytest.mark.parametrize("value, low, high, low_open, high_open, expected", [
    (0.84631234, 0.8455, 0.84631234, True, False, 0.846),
    (0.123456, 0.123456, 0.1299, False, True, 0.124),  # 0.13 is out: 3 digits, the nearest of them
    (12345.678, 12000.0, 12345.678, True, False, 12300.0),  # 12000 is out (open end)
    (-0.0371, -0.04, -0.0371, True, False, -0.038),
    (0.004, -0.01, 0.004, True, False, 0.0),
    (1.0, 0.5, 1.0, True, False, 1.0),
])
def test_fewest_digits(value, low, high, low_open, high_open, expected):
    assert fewest_digits(value, low, high, low_open=low_open, high_open=high_open) == expected


def test_rounded_sides_keep_every_point_on_its_side_and_in_its_leaf():
    X = two_blobs()
    exact, readable = quiet_fit(X, readable=False), quiet_fit(X)
    assert readable.slivers_closed_ == 0  # a wide gap: only the rounding differs
    assert np.array_equal(exact.tree_.apply(X), readable.tree_.apply(X))
    pairs = list(zip(exact.tree_.root.walk(), readable.tree_.root.walk()))
    assert len(pairs) == exact.tree_.n_nodes == readable.tree_.n_nodes
    for a, b in pairs:
        for d in range(2):
            assert b.box.lower[d] <= a.box.lower[d] and b.box.upper[d] >= a.box.upper[d]
            assert np.array_equal(X[:, d] < a.box.lower[d], X[:, d] < b.box.lower[d])
            assert np.array_equal(X[:, d] > a.box.upper[d], X[:, d] > b.box.upper[d])
    # the formula is exact for what it prints: the stored values are the printed ones
    assert parse(str(readable.dnf_)) == readable.dnf_
    assert max(digits(a.value) for c in readable.dnf_ for a in c.atoms) <= 4
    assert max(digits(a.value) for c in exact.dnf_ for a in c.atoms) >= 15
    check_formula(readable, boundary_grid(readable))
    assert not readable.predict(X).any()


def test_a_sliver_between_neighbouring_boxes_is_closed():
    """The thesis toy: the split between the bottom bar and the right column leaves a gap of
    about 0.001 between the last and first points (the issue's `x > 0.8463 & x < 0.8471`)."""
    demos = toy_demonstrations(seed=0)
    exact, readable = quiet_fit(demos, readable=False), quiet_fit(demos)
    gaps = [c for c in exact.dnf_ if len(c.atoms) == 2 and {a.op for a in c.atoms} == {">", "<"}
            and c.atoms[0].feature == c.atoms[1].feature]
    assert gaps and all(abs(g.atoms[1].value - g.atoms[0].value) < 0.01 for g in gaps)
    assert readable.slivers_closed_ == len(gaps) and len(readable.dnf_) == len(exact.dnf_) - len(gaps)
    inside_gap = np.array([[(gaps[0].atoms[0].value + gaps[0].atoms[1].value) / 2, 0.2]])
    assert exact.predict(inside_gap).all() and not readable.predict(inside_gap).any()
    check_formula(readable, boundary_grid(readable))
    text = readable.artefact_text()
    assert "1 gap(s) between neighbouring safe boxes" in text and text.startswith("# unsafe set learned by a one-class tree")
    assert text.splitlines()[1].startswith("# thresholds: ")
    states = np.concatenate([t.states for t in demos])
    assert not readable.predict(states).any()


def thin_l(n: int = 300) -> np.ndarray:
    """An expert along two thin arms of the unit square (along the bottom, up the left side)."""
    t = np.linspace(0, 1, n)
    rng = np.random.default_rng(0)
    return np.vstack([np.column_stack([t, 0.05 * rng.random(n)]), np.column_stack([0.05 * rng.random(n), t])])


def test_a_thin_expert_path_warns_that_most_of_the_box_is_unsafe():
    arms = thin_l()
    with pytest.warns(UserWarning, match=r"marks \d+% of the demonstrations' bounding box unsafe"):
        learner = OneClassTreeConstraint().fit(arms)
    assert learner.unsafe_share_ > 0.5 and learner.warnings_
    assert learner.result_.metrics["unsafe_share"] == learner.unsafe_share_
    assert "# warning: the formula marks" in learner.artefact_text()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        silent = OneClassTreeConstraint(warn_unsafe_share=None).fit(arms)
        filled = OneClassTreeConstraint().fit(np.random.default_rng(1).uniform(0, 1, (500, 2)))
    assert not silent.warnings_ and not filled.warnings_ and filled.unsafe_share_ < 0.5


def test_cli_reports_warnings_and_notes(capsys, tmp_path):
    path = tmp_path / "demos.npz"
    Demonstrations([Trajectory(states=thin_l())]).save(path)
    out_file = tmp_path / "rules.dnf"
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["warnings"] and "bounding box unsafe" in doc["warnings"][0] and doc["unsafe_share"] > 0.5
    assert doc["notes"] and "UserWarning" not in err
    text = out_file.read_text()
    assert "# warning: the formula marks" in text and "# thresholds: " in text
    assert str(parse(text)) == doc["formula"]
    code, out, err = run(capsys, "learn", "dnf", "--demos", path)
    assert code == 0 and "warning: the formula marks" in out


def heating_runs(seed: int = 0, episodes: int = 20, outside: bool = False) -> Demonstrations:
    """A room heated from 15-20 degrees towards 26 at up to 1.5 degrees a step, then held there:
    most points crowd at the set point (a fine bandwidth), the way up is sparse, and every gap on
    it is crossed by a step. ``outside``: a second feature, the outside temperature, drawn once
    per episode (constant within it)."""
    rng = np.random.default_rng(seed)
    runs = []
    for _ in range(episodes):
        temp, out = rng.uniform(15, 20), rng.uniform(0, 10)
        states = [[temp, out] if outside else [temp]]
        for _ in range(60):
            temp += 1.5 * float(np.clip((26.0 - temp) / 1.5, -1, 1)) - 0.05 * (temp - out) + rng.normal(0, 0.1)
            states.append([temp, out] if outside else [temp])
        runs.append(Trajectory(states=states, actions=[0] * 60))
    return Demonstrations(runs)


def inner_gaps(dnf) -> list:
    """The conjunctions ``x > a & x < b`` on one feature: gaps between neighbouring boxes."""
    return [c for c in dnf if len(c.atoms) == 2 and {a.op for a in c.atoms} == {">", "<"}
            and c.atoms[0].feature == c.atoms[1].feature]


def test_a_gap_that_a_demonstrated_step_crosses_is_closed():
    demos = heating_runs()
    points = np.concatenate([np.asarray(t.states) for t in demos])
    as_points, as_demos = quiet_fit(points), quiet_fit(demos)
    # on the points alone the gaps on the way up are wider than the bandwidth and stay
    assert inner_gaps(as_points.dnf_) and as_points.slivers_crossed_ == 0
    assert any(abs(g.atoms[1].value - g.atoms[0].value) > 0.05 for g in inner_gaps(as_points.dnf_))
    # the demonstrations' steps cross them: closed, counted and said in the header
    assert not inner_gaps(as_demos.dnf_) and as_demos.slivers_crossed_ >= len(inner_gaps(as_points.dnf_))
    assert len(as_demos.dnf_) == len(as_points.dnf_) - as_demos.slivers_crossed_  # one rule less per gap
    assert "crossed by a demonstrated step were closed (made safe)" in as_demos.artefact_text()
    midpoint = [[(g.atoms[0].value + g.atoms[1].value) / 2] for g in inner_gaps(as_points.dnf_)]
    assert as_points.predict(midpoint).all() and not as_demos.predict(midpoint).any()
    assert not as_demos.predict(points).any() and parse(str(as_demos.dnf_)) == as_demos.dnf_
    check_formula(as_demos, np.linspace(10, 30, 4001)[:, None])


def test_a_gap_between_demonstrations_that_no_step_crosses_stays():
    rng = np.random.default_rng(0)
    runs = [Trajectory(states=list(rng.uniform(lo, lo + 1, (200, 1))), actions=[0] * 199) for lo in (0.0, 2.0)]
    learner = quiet_fit(Demonstrations(runs))
    assert learner.slivers_crossed_ == 0 and learner.predict([[1.5]]).all()
    assert "or crossed by a demonstrated step" in learner.artefact_text()  # "no gap was ... or crossed"


def test_a_feature_constant_within_every_demonstration_is_named_in_a_warning():
    demos = heating_runs(outside=True)
    with pytest.warns(UserWarning, match="feature x1 is constant within every demonstration"):
        learner = OneClassTreeConstraint().fit(demos)
    message = next(w for w in learner.warnings_ if "x1 is constant" in w)
    assert "--inputs x0" in message and "# warning: feature x1" in learner.artefact_text()
    points = np.concatenate([np.asarray(t.states) for t in demos])
    assert not any("constant within" in w for w in quiet_fit(points).warnings_)  # no episodes: no claim
    assert not any("constant within" in w for w in quiet_fit(demos, inputs=["x0"]).warnings_)
