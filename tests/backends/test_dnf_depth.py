"""The depth of a point in a DNF's unsafe set (backends/dnf_depth.py) and the cost shaped by it."""

import numpy as np
import pytest

from symlearn.backends import dnf_depth
from symlearn.backends.dnf_cost import FormulaCost
from symlearn.backends.dnf_depth import NO_EXIT_DEPTH, ViolationDepth
from symlearn.errors import DataError, SymlearnError
from symlearn.logic.dnf import parse


def _brute_force(dnf, names, spans, x, step=1e-3, reach=3.0):
    """Walk each axis both ways in small steps until the formula no longer holds."""
    if not dnf.evaluate(x[None], names)[0]:
        return 0.0
    best = np.inf
    for j in range(len(x)):
        for sign in (1, -1):
            t = np.arange(1, int(reach / step)) * step * sign
            line = np.repeat(x[None], len(t), axis=0)
            line[:, j] += t
            out = np.flatnonzero(~dnf.evaluate(line, names))
            if len(out):
                best = min(best, abs(t[out[0]]) / spans[j])
    return best if np.isfinite(best) else NO_EXIT_DEPTH


def test_depth_is_the_shortest_axis_exit_across_touching_boxes():
    rng = np.random.default_rng(0)
    for trial in range(12):
        lines = []
        for _ in range(rng.integers(1, 5)):
            atoms = []
            for name in ("x", "y"):
                if rng.random() < 0.8:
                    lo, hi = np.sort(rng.choice(np.arange(-1.0, 1.01, 0.25), 2, replace=False))
                    atoms += [f"{name} {rng.choice(['>', '>='])} {lo:g}", f"{name} {rng.choice(['<', '<='])} {hi:g}"]
            if atoms:
                lines.append(" & ".join(atoms))
        dnf = parse("\n".join(lines))
        depth = ViolationDepth(dnf, ["x", "y"])
        X = rng.uniform(-1.2, 1.2, (60, 2)).round(3)
        got = depth(X)
        want = np.array([_brute_force(dnf, ["x", "y"], depth.spans, x) for x in X])
        assert np.all(got[want == 0] == 0) and np.all(got[want > 0] > 0), trial
        # the walk's resolution (1e-3 in feature units) bounds the difference
        assert np.allclose(got, want, atol=2e-3 / depth.spans.min()), (trial, dnf, X[np.argmax(abs(got - want))])


def test_open_and_closed_ends_and_a_rule_with_no_exit():
    depth = ViolationDepth(parse("x < 0\nx >= 0 & x < 1 & y > 0.5"), ["x", "y"])
    # (0, 0.7): x < 0 does not hold at 0 (open), the second rule does; out through y = 0.5 (0.2 spans:
    # y has one threshold, so its span is 1) or x = 1 (1 span of x's thresholds 0..1)
    assert depth(np.array([[0.0, 0.7]]))[0] == pytest.approx(0.2)
    assert depth(np.array([[0.0, 0.5]]))[0] == 0.0       # y > 0.5 is open: safe
    # x < 0 bounds nothing but x: the only way out crosses the second rule too (y > 0.5)
    assert depth(np.array([[-0.5, 0.9]]))[0] == pytest.approx(1.5)
    everywhere = ViolationDepth(parse("x > -1\nx <= -1"), ["x"])
    assert everywhere(np.array([[0.0]]))[0] == NO_EXIT_DEPTH


def test_chunks_give_the_same_depths(monkeypatch):
    dnf = parse("x > 0.2 & x < 0.8 & y > 0.1\nx >= 0.8 & y < 0.5\ny > 0.9")
    X = np.random.default_rng(1).uniform(0, 1, (500, 2))
    whole = ViolationDepth(dnf, ["x", "y"])(X)
    monkeypatch.setattr(dnf_depth, "CHUNK_CELLS", 7)
    assert np.array_equal(ViolationDepth(dnf, ["x", "y"])(X), whole)


def test_shaped_cost_is_one_plus_weight_times_depth_and_zero_where_safe():
    dnf = parse("x > 0 & x < 1\nx >= 1 & x < 2")
    X = np.array([[-0.5], [0.1], [1.5], [3.0]])
    depth = ViolationDepth(dnf, ["x"])(X)
    costs, totals = FormulaCost(dnf, ["x"], depth_weight=3.0)(X)
    assert costs.tolist() == pytest.approx([0.0, 1 + 3 * depth[1], 1 + 3 * depth[2], 0.0])
    assert depth[1] == pytest.approx(0.05) and depth[2] == pytest.approx(0.25)   # x's span: 0..2
    per_rule, totals = FormulaCost(dnf, ["x"], per_rule=True, depth_weight=3.0)(X)
    assert per_rule.shape == (4, 2) and totals.tolist() == pytest.approx(costs.tolist())
    assert FormulaCost(dnf, ["x"])(X)[0].tolist() == [0.0, 1.0, 1.0, 0.0]     # the default: binary
    for bad in (-1.0, float("nan"), float("inf"), True):
        with pytest.raises(SymlearnError, match="depth_weight"):
            FormulaCost(dnf, ["x"], depth_weight=bad)
    with pytest.raises(DataError, match="'y'"):
        ViolationDepth(parse("y > 0"), ["x"])
