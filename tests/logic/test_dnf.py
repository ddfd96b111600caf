"""DNF constraints (symlearn.logic.dnf): text/JSON/unicode round trips, exact evaluation,
simplification and box algebra checked against an exhaustive cell oracle, and bad input."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.errors import DataError, LimitExceededError, ParseError
from symlearn.logic import dnf as dnf_module
from symlearn.logic.dnf import DNF, FALSE, TRUE, Atom, Conjunction, Interval, from_json, load, parse, to_sympy

NAMES = ("x", "y", "z")
GRID = (-1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 2.0)

# -- strategies ------------------------------------------------------------------------------

any_name = st.one_of(
    st.sampled_from(["x", "x0", "_a1", "true", "false", "inf", "nan", "Speed_2"]),
    st.text(st.characters(blacklist_characters="\n\r", blacklist_categories=("Cs",)), min_size=1, max_size=8),
)
any_value = st.floats(allow_nan=False, allow_infinity=False)
ops = st.sampled_from(["<", "<=", ">", ">="])


def dnfs(names=st.sampled_from(NAMES), values=st.sampled_from(GRID), max_conjunctions=5, max_atoms=4):
    atom = st.builds(Atom, names, ops, values)
    conjunction = st.lists(atom, max_size=max_atoms).map(lambda a: Conjunction(tuple(a)))
    return st.lists(conjunction, max_size=max_conjunctions).map(lambda c: DNF(tuple(c)))


any_dnf = dnfs(any_name, any_value)
grid_dnf = dnfs()
# mostly grid values (so boxes share faces and corners), sometimes any float
mixed_dnf = dnfs(values=st.one_of(st.sampled_from(GRID), st.floats(-3, 3, allow_nan=False)))


def naive(formula: DNF, X: np.ndarray, names) -> np.ndarray:
    """Per point, per conjunction, per atom: plain Python comparisons."""
    out = np.zeros((len(X), len(formula)), dtype=bool)
    for i, row in enumerate(X):
        point = dict(zip(names, row.tolist()))
        for j, c in enumerate(formula):
            out[i, j] = all(a.holds(point[a.feature]) for a in c)
    return out


def cell_points(*formulas: DNF, names=NAMES) -> np.ndarray:
    """One point in every cell of the grid all thresholds make: each threshold, a value between
    each two neighbours and one beyond each end, per feature. Two formulas agree on these
    points iff they are the same set (every cell is uniformly in or out)."""
    per_feature = []
    for name in names:
        t = sorted({a.value for f in formulas for c in f for a in c if a.feature == name})
        if not t:
            per_feature.append([0.0])
            continue
        values = [t[0] - 1.0, t[-1] + 1.0] + t + [(a + b) / 2 for a, b in zip(t, t[1:])]
        per_feature.append(sorted(set(values)))
    return np.array(list(itertools.product(*per_feature)), dtype=float).reshape(-1, len(names))


# -- text format -----------------------------------------------------------------------------

@settings(max_examples=300)
@given(any_dnf)
def test_text_round_trip_is_exact(f):
    assert parse(str(f)) == f
    assert parse(f.to_string(one_line=True)) == f
    assert parse(f.to_string("unicode")) == f
    assert parse(f.to_string("unicode", one_line=True)) == f


@given(any_value)
def test_numbers_round_trip_bit_for_bit(v):
    atom = parse(f"x < {dnf_module.format_number(v)}").conjunctions[0].atoms[0]
    assert atom.value == v and math.copysign(1, atom.value) == math.copysign(1, v + 0.0)


def test_text_format_details():
    f = parse('  # comment only\n\nx0 > 0.1 & x0 < 0.7 & x1 > 0.3   # a box\n"door open" >= -2e-05 && y ≤ 3\n')
    assert str(f) == 'x0 > 0.1 & x0 < 0.7 & x1 > 0.3\n"door open" >= -2e-05 & y <= 3'
    assert f.features == ("door open", "x0", "x1", "y")
    assert parse("a < 1 | b > 2 ∨ c >= 3") == DNF.of([("a", "<", 1)], [("b", ">", 2)], [("c", ">=", 3)])
    assert parse("") == FALSE and parse("# nothing\n") == FALSE and str(FALSE) == "false"
    assert parse("false") == FALSE and parse("false\nx < 1") == DNF.of([("x", "<", 1)])
    assert parse("true") == TRUE and str(TRUE) == "true" and parse("⊤") == TRUE
    assert str(DNF.of([("true", "<", 1)])) == '"true" < 1'
    assert str(DNF.of([('a"b\\c', ">", 1e300)])) == '"a\\"b\\\\c" > 1e+300'
    assert str(Atom("x", "<", 3.0)) == "x < 3" and str(Atom("x", "<", -0.0)) == "x < 0"
    assert parse("x<1&y>=2\r\nz>3") == DNF.of([("x", "<", 1), ("y", ">=", 2)], [("z", ">", 3)])
    assert parse("inf > 1").features == ("inf",)  # a feature may be called inf


def test_equality_and_inequality_are_boxes():
    """'==' is a degenerate box, '!=' splits its conjunction in two: the formula stays a DNF of bounds."""
    assert parse("cell == 12") == DNF.of([("cell", ">=", 12), ("cell", "<=", 12)])
    assert parse("a > 0 & cell != 3 | b < 1") == DNF.of([("a", ">", 0), ("cell", "<", 3)],
                                                        [("a", ">", 0), ("cell", ">", 3)], [("b", "<", 1)])
    points = np.array([[1.0, 2.0], [0.0, 2.0], [0.5, -1.0], [1.0, -1.0]])
    assert parse("x \u2260 1 & y < 0\ny == 2 & x != 0").evaluate(points, ["x", "y"]).tolist() == [
        True, False, True, False]
    with pytest.raises(ParseError, match="11 '!=' atoms"):
        parse(" & ".join(f"x{i} != 0" for i in range(11)), source="rules.dnf")


@pytest.mark.parametrize("text, line, column, words", [
    ("x > 0.1 & \n", 1, 11, "expected a feature name"),
    ("x > 1\ny >< 2", 2, 4, "expected a number"),
    ("x > 1\ny > 2 z > 1", 2, 7, "unexpected 'z'"),
    ("x = 1", 1, 3, "(== for equality)"),
    ("x => 1", 1, 3, "unexpected"),
    ("x ! 1", 1, 3, "== !="),
    ("x > 1 and y < 2", 1, 7, "write '&'"),
    ("x >", 1, 4, "unexpected end of input"),
    ("x < nan", 1, 5, "finite"),
    ("x < -inf", 1, 5, "finite"),
    ("y > 1\nx < 1e999", 2, 5, "too large"),
    ("x < 1 & & y > 2", 1, 9, "unexpected '&'"),
    ("(x < 1)", 1, 1, "unexpected"),
])
def test_syntax_errors_name_line_and_column(text, line, column, words):
    with pytest.raises(ParseError) as info:
        parse(text, source="rules.dnf")
    exc = info.value
    assert (exc.file, exc.line, exc.column) == ("rules.dnf", line, column), str(exc)
    assert words in str(exc)
    assert "\n" not in str(exc)


def test_values_are_checked():
    for bad in [("x", "==", 1), ("x", "<", math.nan), ("x", "<", math.inf), ("x", "<", "1"), ("", "<", 1),
                ("x", "<", True), ("a\nb", "<", 1)]:
        with pytest.raises(DataError):
            Atom(*bad)
    assert Atom("x", "≤", 1).op == "<=" and Atom("x", "<", np.float32(0.5)).value == 0.5
    with pytest.raises(DataError):
        Conjunction(("x < 1",))
    assert DNF([[Atom("x", "<", 1)]]) == DNF.of([("x", "<", 1)])
    assert hash(parse("x < 1")) == hash(DNF.of([("x", "<", 1.0)]))


# -- JSON, files, LaTeX, sympy -----------------------------------------------------------------

@settings(max_examples=200)
@given(any_dnf)
def test_json_round_trip(f):
    assert from_json(f.to_json()) == f
    assert DNF.from_json(json.loads(f.to_json())) == f


def test_json_format_and_errors():
    f = parse("x > 0.1 & y <= 2\ntrue")
    assert json.loads(f.to_json()) == {"symlearn": "dnf", "format_version": 1,
                                       "conjunctions": [[["x", ">", 0.1], ["y", "<=", 2.0]], []]}
    cases = [("[1, 2]", "not a symlearn dnf"), ('{"symlearn": "dnf", "format_version": 2}', "format_version"),
             ('{"symlearn": "dnf", "format_version": 1, "conjunctions": [[["x", "<", NaN]]]}', "conjunctions[0][0]"),
             ('{"symlearn": "dnf", "format_version": 1, "conjunctions": [[["x", "=", 1]]]}', "unknown comparison"),
             ('{"symlearn": "dnf", "format_version": 1, "conjunctions": [["x < 1"]]}', "[feature, op, value]"),
             ('{"symlearn": "dnf", "format_version": 1, "conjunctions": {}}', "list"),
             ('{"symlearn": "dnf",', "invalid JSON")]
    for text, words in cases:
        with pytest.raises((DataError, ParseError)) as info:
            from_json(text, source="f.json")
        assert words in str(info.value) and info.value.file == "f.json"


def test_save_and_load(tmp_path):
    f = parse("x0 > 0.1 & x0 < 0.7\nv > 1.46")
    path = f.save(tmp_path / "rules.dnf", header="learned by test\nthreshold 0.001")
    text = path.read_text()
    assert text.startswith("# learned by test\n# threshold 0.001\n") and text.endswith("v > 1.46\n")
    assert load(path) == f and DNF.load(path) == f
    assert load(f.save(tmp_path / "rules.json")) == f
    assert FALSE.save(tmp_path / "empty.dnf").read_text() == "false\n" and load(tmp_path / "empty.dnf") == FALSE
    (tmp_path / "bad.dnf").write_text("x > 1\ny >\n")
    with pytest.raises(ParseError) as info:
        load(tmp_path / "bad.dnf")
    assert info.value.location == f"{tmp_path / 'bad.dnf'}:2:4"
    with pytest.raises(DataError):
        load(tmp_path / "missing.dnf")


def test_latex_and_unicode():
    f = parse('x0 > 0.1 & x0 <= 1e-07 & v_x >= 2\nspeed < 3\n"a b_c" < 1')
    assert f.to_string("latex") == (r"\left(x_{0} > 0.1 \land x_{0} \leq 1 \times 10^{-7} \land v_{x} \geq 2\right) "
                                    r"\lor \mathit{speed} < 3 \lor \text{a b\_c} < 1")
    assert f.to_latex() == f.to_string("latex")
    assert f.to_string("unicode").splitlines()[0] == "x0 > 0.1 ∧ x0 ≤ 1e-07 ∧ v_x ≥ 2"
    assert TRUE.to_string("latex") == r"\top" and FALSE.to_string("latex") == r"\bot"
    assert TRUE.to_string("unicode") == "⊤" and FALSE.to_string("unicode") == "⊥"
    with pytest.raises(DataError):
        f.to_string("html")


@settings(max_examples=100)
@given(any_dnf)
def test_latex_is_balanced(f):
    text = f.to_string("latex")
    depth = 0
    for i, ch in enumerate(text):
        if ch in "{}" and i and text[i - 1] == "\\":
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        assert depth >= 0
    assert depth == 0 and "\n" not in text
    assert text.count(r"\lor") == max(len(f) - 1, 0)


def test_sympy():
    sympy = pytest.importorskip("sympy")
    f = parse("x > 0.1 & y <= 2\nz < -3")
    expr = to_sympy(f)
    x, y, z = (sympy.Symbol(n, real=True) for n in "xyz")
    assert expr == sympy.Or(sympy.And(x > sympy.Float(0.1), y <= 2), z < -3)
    assert f.to_sympy(rational=True) == sympy.Or(sympy.And(x > sympy.Rational(1, 10), y <= 2), z < -3)
    assert to_sympy(TRUE) == sympy.true and to_sympy(FALSE) == sympy.false
    # the Float keeps the double exactly: 0.1 < 0.1 + ulp is decided correctly
    tight = to_sympy(DNF.of([("x", ">", 0.1)]))
    assert bool(tight.subs(x, sympy.Float(math.nextafter(0.1, 1)))) and not bool(tight.subs(x, sympy.Float(0.1)))


@settings(max_examples=40, deadline=None)
@given(mixed_dnf, st.lists(st.sampled_from(GRID + (0.3, -2.0, 1.5)), min_size=3, max_size=3))
def test_sympy_agrees_with_evaluation(f, point):
    sympy = pytest.importorskip("sympy")
    expr = to_sympy(f)
    substituted = expr.subs({sympy.Symbol(n, real=True): sympy.Float(v) for n, v in zip(NAMES, point)})
    assert bool(substituted) == f.holds(dict(zip(NAMES, point)))


def test_dnf_loads_nothing_heavy():
    import subprocess
    import sys

    # the box algebra loads nothing heavy; evaluation loads numba (its kernels), and numba's own
    # import checks scipy's version when scipy is installed: nothing else
    code = ("import sys, symlearn.logic.dnf as d\n"
            "f = d.parse('x < 1 & y > 0')\n"
            "f.simplify().equivalent(f); f.volume({'x': (0, 1), 'y': (0, 1)})\n"
            "heavy = ('sympy', 'scipy', 'torch', 'gymnasium', 'sklearn', 'pandas', 'numba', 'symlearn.grounding')\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy or m.startswith('symlearn.grounding')))\n"
            "f.evaluate([[0.0, 1.0]], ['x', 'y'])\n"
            "heavy = ('sympy', 'torch', 'gymnasium', 'sklearn', 'pandas', 'symlearn.grounding')\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy or m.startswith('symlearn.grounding')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.split() == ["[]", "[]"], (done.stdout, done.stderr)


# -- evaluation ------------------------------------------------------------------------------

@settings(max_examples=150, deadline=None)
@given(mixed_dnf, st.integers(0, 2**32 - 1))
def test_evaluation_matches_a_per_point_loop(f, seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(0, 60))
    X = np.where(rng.random((n, 3)) < 0.5, rng.choice(GRID, (n, 3)), rng.normal(0, 2, (n, 3)))
    if n:
        X[rng.integers(n), rng.integers(3)] = rng.choice([np.inf, -np.inf])
    want = naive(f, X, NAMES)
    got = f.evaluate(X, NAMES, per_conjunction=True)
    assert got.shape == (n, len(f)) and got.dtype == bool
    assert np.array_equal(got, want)
    assert np.array_equal(f.evaluate(X, NAMES), want.any(axis=1))
    assert all(f.holds(dict(zip(NAMES, row))) == w for row, w in zip(X.tolist(), want.any(axis=1)))


def test_evaluation_inputs():
    f = parse("x > 0.5 & y <= 1\nz < 0")
    X = np.array([[1.0, 1.0, 5.0], [0.0, 0.0, -1.0], [1.0, 2.0, 0.0]])
    want = [True, True, False]
    assert f.evaluate(X, ["x", "y", "z"]).tolist() == want

    class FeatureMapLike:
        names = ("z", "y", "x", "unused")

    perm = np.column_stack([X[:, 2], X[:, 1], X[:, 0], np.full(3, np.nan)])   # NaN in an unused column is fine
    assert f.evaluate(perm, FeatureMapLike()).tolist() == want
    assert f.evaluate(X, "x,y,z").tolist() == want
    assert f.evaluate({"x": X[:, 0], "y": X[:, 1], "z": X[:, 2], "w": np.zeros(3)}).tolist() == want
    assert f.evaluate(X.astype(np.float32), NAMES).tolist() == want
    assert f.evaluate(np.array([[1, 1, 5], [0, 0, -1]]), NAMES).tolist() == [True, True]
    assert f.evaluate(np.asfortranarray(X), NAMES).tolist() == want
    assert f.evaluate(X[::-1], NAMES).tolist() == want[::-1]
    assert f.evaluate([1.0, 1.0, 5.0], NAMES).tolist() == [True]           # one point
    assert f.evaluate(np.empty((0, 3)), NAMES).shape == (0,)
    assert f.evaluate(np.empty((0, 3)), NAMES, per_conjunction=True).shape == (0, 2)
    assert TRUE.evaluate(X, NAMES).tolist() == [True] * 3 and FALSE.evaluate(X, NAMES).tolist() == [False] * 3
    assert FALSE.evaluate(X, NAMES, per_conjunction=True).shape == (3, 0)
    assert parse("true\nx > 5").evaluate(X, NAMES, per_conjunction=True).tolist() == [[True, False]] * 3
    assert parse("x > 2 & x < 1").evaluate(X, NAMES).tolist() == [False] * 3


def test_evaluation_errors():
    f = parse("x > 0.5 & speed <= 1\nz < 0")
    with pytest.raises(DataError, match="unknown features speed, z") as info:
        f.evaluate(np.zeros((2, 2)), ["x", "y"])
    assert "the points have: x, y" in str(info.value)
    with pytest.raises(DataError, match="unknown feature z"):
        f.evaluate({"x": np.zeros(2), "speed": np.zeros(2)})
    X = np.zeros((5, 3))
    X[3, 1] = np.nan
    with pytest.raises(DataError, match="feature speed is NaN in point 3"):
        f.evaluate(X, ["x", "speed", "z"])
    with pytest.raises(DataError, match="shape"):
        f.evaluate(np.zeros((2, 4)), ["x", "speed", "z"])
    with pytest.raises(DataError, match="repeat"):
        f.evaluate(np.zeros((2, 3)), ["x", "x", "z"])
    with pytest.raises(DataError, match="numbers"):
        f.evaluate(np.array([["a", "b", "c"]]), ["x", "speed", "z"])
    with pytest.raises(DataError, match="name the columns"):
        f.evaluate(np.zeros((2, 3)))
    with pytest.raises(DataError, match="1-D"):
        f.evaluate({"x": np.zeros(2), "speed": np.zeros(3), "z": np.zeros(2)})


def test_both_lookup_modes_and_chunks_agree_with_the_loop():
    rng = np.random.default_rng(7)
    spread = [0.0, 1e-300, 2e-300, 3e-300, 5e-300, 1e-10, 1.0, 1e300]     # no grid keeps buckets small
    conjunctions = []
    for _ in range(150):                                                   # > 128 bits: a void container
        atoms = [Atom("x", str(rng.choice(["<", "<=", ">", ">="])), float(rng.choice(spread))),
                 Atom("y", str(rng.choice(["<", "<=", ">", ">="])), float(rng.normal()))]
        conjunctions.append(Conjunction(tuple(atoms)))
    f = DNF(tuple(conjunctions))
    X = np.column_stack([rng.choice(spread + [-1.0, 5e-301, 2.0, np.inf], 300), rng.normal(size=300)])
    X[:5, 1] = [c.atoms[1].value for c in conjunctions[:5]]               # exactly on thresholds
    want = naive(f, X, ["x", "y"])
    from symlearn.logic.dnf_eval import compile_plan, points

    for mode in ("masks", "boxes"):                                       # both combination forms
        plan = compile_plan(f, mode=mode)
        assert plan.m == 150 and plan.masks.shape[1] == 3                # > 128 bits: three words
        Xp, cols = points(plan, X, ["x", "y"])
        assert np.array_equal(plan.run(Xp, cols, True, chunk=7), want)   # many chunks, a short last one
        assert np.array_equal(plan.run(Xp, cols, False, chunk=7), want.any(axis=1))
    assert np.array_equal(f.evaluate(X, ["x", "y"], per_conjunction=True), want)
    assert np.array_equal(f.evaluate(X, ["x", "y"]), want.any(axis=1))
    X[250, 0] = np.nan
    with pytest.raises(DataError, match="feature x is NaN in point 250"):
        f.evaluate(X, ["x", "y"])


@pytest.mark.parametrize("m", [1, 8, 9, 16, 17, 32, 33, 64, 65, 128, 129])
def test_every_bitmask_width(m):
    rng = np.random.default_rng(m)
    f = DNF(tuple(Conjunction((Atom("x", ">", float(lo)), Atom("x", "<", float(lo) + 0.3)))
                  for lo in rng.random(m)))
    X = rng.random((200, 1)) * 1.4 - 0.1
    assert np.array_equal(f.evaluate(X, ["x"], per_conjunction=True), naive(f, X, ["x"]))


# -- box algebra -----------------------------------------------------------------------------

def test_intervals():
    a = Interval(0, 1, True, False)
    assert 0 in a and 1 not in a and 0.5 in a and not a.is_empty
    assert Interval(1, 1, True, True).length == 0 and not Interval(1, 1, True, True).is_empty
    assert Interval(1, 1, True, False).is_empty and Interval(2, 1).is_empty
    assert a.union(Interval(1, 2, True, True)) == Interval(0, 2, True, True)
    assert a.union(Interval(1, 2)) is None and a.union(Interval(3, 4)) is None
    assert a.minus(Interval(0.25, 0.5, True, True)) == [Interval(0, 0.25, True, False), Interval(0.5, 1, False, False)]
    assert Interval(-math.inf, 1, True, True) == Interval(-math.inf, 1, False, True)
    assert a.contains(Interval(0, 0.5, True, True)) and not a.contains(Interval(0, 1, True, True))
    assert Interval().is_full and Interval().atoms("x") == []


def test_simplify_examples():
    assert str(parse("x > 0 & x > 1 & x <= 5 & y < 2 & x < 7").simplify()) == "x > 1 & x <= 5 & y < 2"
    assert parse("x > 2 & x < 1\ny > 0").simplify() == parse("y > 0")
    assert parse("x > 1 & x < 1").simplify() == FALSE
    assert parse("x >= 1 & x <= 1").simplify() == parse("x >= 1 & x <= 1")
    assert parse("x > 0 & x < 1 & y > 0\nx > 0.2 & x < 0.5 & y > 1").simplify() == parse("x > 0 & x < 1 & y > 0")
    assert parse("x > 0 & x < 1\nx >= 1 & x < 2\nx >= 2").simplify() == parse("x > 0")
    assert parse("x < 1\nx >= 1").simplify() == TRUE
    assert parse("x < 1\nx > 1").simplify() == parse("x < 1\nx > 1")      # the point 1 stays out
    assert parse("x < 1 & y < 1\nx < 1 & y >= 1").simplify() == parse("x < 1")
    assert parse("x < 1\nx < 1").simplify() == parse("x < 1")
    assert parse("true\nx < 1").simplify() == TRUE and FALSE.simplify() == FALSE
    assert Conjunction((Atom("y", "<", 3), Atom("x", ">", 0), Atom("y", "<", 2))).simplify() == \
        Conjunction((Atom("y", "<", 2), Atom("x", ">", 0)))


@settings(max_examples=200, deadline=None)
@given(mixed_dnf, st.integers(0, 2**32 - 1))
def test_simplify_preserves_the_set(f, seed):
    s = f.simplify()
    assert len(s) <= len(f)
    assert all(len(c.atoms) <= 2 * len(c.features) for c in s)
    corners = cell_points(f)
    assert np.array_equal(s.evaluate(corners, NAMES), f.evaluate(corners, NAMES))
    X = np.random.default_rng(seed).normal(0, 1.5, (100, 3))
    assert np.array_equal(s.evaluate(X, NAMES), f.evaluate(X, NAMES))
    assert parse(str(s)) == s and s.simplify().equivalent(s)


@settings(max_examples=200, deadline=None)
@given(grid_dnf, grid_dnf)
def test_set_algebra_against_the_cell_oracle(f, g):
    points = cell_points(f, g)
    a, b = f.evaluate(points, NAMES), g.evaluate(points, NAMES)
    assert f.implies(g) == bool(np.all(~a | b))
    assert g.contains(f) == f.implies(g)
    assert f.equivalent(g) == bool(np.array_equal(a, b))
    assert np.array_equal((f & g).evaluate(points, NAMES), a & b)
    assert np.array_equal((f | g).evaluate(points, NAMES), a | b)
    assert np.array_equal((f - g).evaluate(points, NAMES), a & ~b)
    assert np.array_equal((~f).evaluate(points, NAMES), ~a)
    assert f.is_empty() == (not a.any()) and f.is_valid() == bool(a.all())


def _cell_volume(f: DNF, bounds: dict) -> float:
    """The volume by the cell grid: each cell is uniformly in or out, test its midpoint."""
    edges = []
    for name in NAMES:
        lo, hi = bounds[name]
        t = sorted({lo, hi} | {a.value for c in f for a in c if a.feature == name and lo < a.value < hi})
        edges.append(list(zip(t, t[1:])))
    total = 0.0
    for cell in itertools.product(*edges):
        mid = np.array([[(a + b) / 2 for a, b in cell]])
        if f.evaluate(mid, NAMES)[0]:
            total += math.prod(b - a for a, b in cell)
    return total


@settings(max_examples=100, deadline=None)
@given(mixed_dnf)
def test_volume_against_the_cell_grid(f):
    bounds = {"x": (-0.75, 1.5), "y": (0.0, 2.0), "z": (-1.0, 1.0)}
    assert f.volume(bounds) == pytest.approx(_cell_volume(f, bounds), rel=1e-9, abs=1e-12)
    assert f.simplify().volume(bounds) == pytest.approx(f.volume(bounds), rel=1e-9, abs=1e-12)


def test_volume_examples_and_errors():
    bounds = {"x": (0, 1), "y": (0, 2)}
    assert parse("x < 0.5").volume(bounds) == 1.0
    assert parse("x < 0.5\nx < 0.5 & y > 1\nx > 0.75 & y < 1").volume(bounds) == 1.25
    assert TRUE.volume(bounds) == 2.0 and FALSE.volume(bounds) == 0.0
    assert parse("x >= 0.5 & x <= 0.5").volume(bounds) == 0.0
    with pytest.raises(DataError, match="no bounds for feature z"):
        parse("z < 1").volume(bounds)
    with pytest.raises(DataError, match="finite"):
        parse("x < 1").volume({"x": (0, math.inf)})


def test_containment_examples_and_limit():
    box = parse("x > 0 & x < 1 & y > 0 & y < 1")
    halves = parse("x > 0 & x <= 0.5 & y > 0 & y < 1\nx >= 0.5 & x < 1 & y > 0 & y < 1")
    assert box.equivalent(halves) and halves.implies(box) and box.implies(halves)
    assert not box.implies(parse("x > 0 & x < 0.5 & y > 0 & y < 1\nx > 0.5 & x < 1 & y > 0 & y < 1"))
    assert FALSE.implies(box) and box.implies(TRUE) and not TRUE.implies(box)
    cells = DNF(tuple(Conjunction((Atom("x", ">=", i), Atom("x", "<", i + 1), Atom("y", ">=", j),
                                   Atom("y", "<", j + 1))) for i in range(10) for j in range(10)))
    square = parse("x >= 0 & x < 10 & y >= 0 & y < 10")
    assert square.implies(cells) and cells.simplify() == square
    with pytest.raises(LimitExceededError):
        square.implies(cells, limit=10)


def test_interval_holds_whole_number():
    from symlearn.logic.dnf import Interval

    assert not Interval(1, 2).holds_whole_number and Interval(1, 2, lo_closed=True).holds_whole_number
    assert not Interval(1.2, 1.9, True, True).holds_whole_number and Interval(hi=0.5).holds_whole_number
    assert Interval().holds_whole_number and not Interval(2, 1, True, True).holds_whole_number
