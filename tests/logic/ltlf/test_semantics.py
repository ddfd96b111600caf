import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from ltlf_strategies import formulas, traces
from symlearn.errors import DataError
from symlearn.logic.ltlf import holds, holds_at_end, parse, progress, translate
from symlearn.logic.ltlf.progression import holds_by_progression
from symlearn.logic.ltlf.vectorized import TraceBatch, evaluate, evaluate_many

A, B, E = {"a"}, {"b"}, set()


@pytest.mark.parametrize("text, trace, expected", [
    ("X a", [E, A], True), ("X a", [A], False), ("X true", [E], False),
    ("WX a", [A], True), ("WX false", [E], True), ("WX a", [E, B], False),
    ("F a", [E, E, A], True), ("F a", [E, B], False),
    ("G a", [A, A], True), ("G a", [A, E], False),
    ("a U b", [A, A, B], True), ("a U b", [A, A], False), ("a U b", [B], True), ("a U b", [A, E, B], False),
    ("a R b", [B, B], True), ("a R b", [B, {"a", "b"}, E], True), ("a R b", [B, E], False),
    ("a W b", [A, A], True), ("a W b", [A, E], False), ("a W b", [A, B], True),
    ("a T b", [A, B], True), ("a T b", [{"a", "b"}], False), ("a T b", [B, A], False), ("a T b", [A, E, E, B], True),
    ("G(a -> X b)", [A, B, E], True), ("G(a -> X b)", [E, A], False), ("G(a -> WX b)", [E, A], True),
    ("a <-> X b", [E, E], True), ("!a -> b", [E, B], False), ("!a -> b", [B], True),
])
def test_holds_follows_the_ltlf_definitions(text, trace, expected):
    f = parse(text)
    assert holds(f, trace) is expected
    assert evaluate_many(f, [trace])[0] == expected
    assert translate(f).accepts(trace) is expected
    assert holds_by_progression(f, trace) is expected


def test_empty_trace_convention():
    with pytest.raises(DataError, match="non-empty"):
        holds(parse("a"), [])
    for text, expected in [("G a", True), ("F a", False), ("!a", True), ("a", False), ("X a", False),
                           ("WX a", True), ("a R b", True), ("a U b", False), ("!(a U b)", True)]:
        f = parse(text)
        assert holds_at_end(f) is expected
        assert evaluate_many(f, [[]])[0] == expected
        assert translate(f).accepts([]) is expected


def test_bad_labels_are_refused():
    with pytest.raises(DataError, match="not the string"):
        holds(parse("a"), ["a"])
    with pytest.raises(DataError, match="not the string"):
        evaluate_many(parse("a"), [["a"]])


def test_progression():
    f = parse("G(a -> X b)")
    assert str(progress(f, {"a"})) == "b & G(a -> X b)"
    assert str(progress(parse("F a"), {"a"})) == "true"
    assert str(progress(parse("a U b"), set())) == "false"


def test_benchmark_column_layout():
    batch = TraceBatch.from_columns([{"a": [1, 0], "b": [0, 1]}, {"a": [0], "b": [0]}])
    assert evaluate(parse("a U b"), batch).tolist() == [True, False]
    with pytest.raises(DataError, match="has 1 values"):
        TraceBatch.from_columns([{"a": [1, 0], "b": [1]}])


@settings(max_examples=250, deadline=None)
@given(formulas(), st.lists(traces(), min_size=1, max_size=8))
def test_reference_vectorised_progression_and_dfa_agree(f, sample):
    expected = [holds(f, t) for t in sample]
    assert evaluate_many(f, sample).tolist() == expected
    assert [holds_by_progression(f, t) for t in sample] == expected
    dfa = translate(f)
    assert [dfa.accepts(t) for t in sample] == expected
    assert dfa.accepts([]) == holds_at_end(f) == bool(evaluate_many(f, [[]])[0])


def test_vectorised_handles_mixed_lengths_and_unknown_propositions():
    f = parse("G(zz -> F a)")
    sample = [[A], [E, A, E], [E] * 10]
    assert evaluate_many(f, sample).tolist() == [True, True, True]
    assert evaluate_many(parse("F zz"), sample).dtype == np.bool_
