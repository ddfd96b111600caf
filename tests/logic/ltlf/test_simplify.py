import pytest
from hypothesis import given, settings, strategies as st

from ltlf_strategies import formulas, traces
from symlearn.logic.ltlf import equivalent, holds, parse, simplify, size


@pytest.mark.parametrize("text, expected", [
    ("F F a", "F a"), ("G G a", "G a"), ("a & a", "a"), ("a | a", "a"), ("a & !a", "false"),
    ("a | !a", "true"), ("a & (a | b)", "a"), ("a | (a & b)", "a"), ("!!a", "a"), ("a & true", "a"),
    ("a | true", "true"), ("X false", "false"), ("WX true", "true"), ("F true", "true"), ("G false", "false"),
    ("a U false", "false"), ("true U b", "F b"), ("false U b", "b"), ("false R b", "G b"), ("a W false", "G a"),
    ("false -> a", "true"), ("a <-> a", "true"), ("F F (b & b & true)", "F b"),
])
def test_rules(text, expected):
    assert str(simplify(parse(text))) == expected


def test_propositional_minimisation_with_sympy():
    assert str(simplify(parse("(a & b) | (a & !b)"), propositional=True)) == "a"
    assert str(simplify(parse("G((a & b) | (a & !b)) & F(c | (c & d))"), propositional=True)) == "G a & F c"


@settings(max_examples=200, deadline=None)
@given(formulas(max_leaves=8), st.lists(traces(), min_size=1, max_size=6), st.booleans())
def test_simplify_preserves_meaning_and_never_grows(f, sample, propositional):
    g = simplify(f, propositional=propositional)
    assert size(g) <= size(f)
    assert [holds(g, t) for t in sample] == [holds(f, t) for t in sample]


@settings(max_examples=60, deadline=None)
@given(formulas(max_leaves=6))
def test_simplify_is_equivalent_by_automata(f):
    assert equivalent(simplify(f), f)
