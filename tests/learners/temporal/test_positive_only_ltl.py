"""Roy et al.'s positive-only LTLf: consistent with the positives, and the most specific formula."""

import pytest

from symlearn.errors import DataError
from symlearn.learners.temporal.positive_only_ltl import learn_positive_only
from symlearn.logic.automata.operations import product
from symlearn.logic.ltlf import holds, parse, translate

TRACES = [[{"a"}, {"b"}], [{"a"}, {"a"}, {"b"}], [{"a"}, {"b"}, {"b"}]]


def test_the_result_holds_on_every_positive_and_is_more_specific_than_consistent_alternatives():
    result = learn_positive_only(TRACES, ["a", "b"], max_size=5)
    assert all(holds(result.formula, [frozenset(x) for x in t]) for t in TRACES)
    assert result.minimal_on_all_traces and result.universe == 2 + 4 + 8
    mine = translate(result.formula)
    for weaker in ("F b", "a", "true", "a & F b", "F a & F b"):
        other = translate(parse(weaker))
        assert all(holds(parse(weaker), [frozenset(x) for x in t]) for t in TRACES)
        assert product(mine, other, "minus").trim().accepting == frozenset()  # L(mine) is inside L(other)


def test_a_sampled_universe_says_so():
    long = [[{"a"}] * 9 + [{"b"}]]
    result = learn_positive_only(long, ["a", "b"], max_size=3, universe_limit=50)
    assert not result.minimal_on_all_traces and result.universe == 50
    assert holds(result.formula, [frozenset(x) for x in long[0]])


@pytest.mark.parametrize("traces, props, message", [
    ([], ["a"], "at least one trace"),
    ([[]], ["a"], "no empty trace"),
    ([[{"z"}]], ["a"], "'z' is not declared"),
])
def test_bad_input(traces, props, message):
    with pytest.raises(DataError, match=message):
        learn_positive_only(traces, props)


def test_the_learner_writes_the_formula(tmp_path):
    from symlearn.learners.temporal.positive_only_ltl import PositiveOnlyLtlLearner

    learner = PositiveOnlyLtlLearner(max_size=4).fit(TRACES[:2], ["a", "b"])
    assert str(learner.formula_) == "a & F b" and learner.result_.metrics["minimal_on_all_traces"]
    assert learner.save(tmp_path / "f.ltl").read_text().strip() == "a & F b"


def test_letters_the_positives_never_show_make_excluding_them_more_specific():
    # without "c" in the universe, "G !c" changes nothing there and the smaller formula wins;
    # with it, the most specific formula must rule "c" out
    traces = [[{"a"}, {"b"}], [{"b"}, {"a"}]]
    plain = learn_positive_only(traces, ["a", "b", "c"], max_size=4)
    wide = learn_positive_only(traces, ["a", "b", "c"], max_size=4, letters=[{"c"}, set()])
    assert "c" not in str(plain.formula)
    assert wide.letters == 4 and plain.letters == 2
    assert all(holds(wide.formula, [frozenset(x) for x in t]) for t in traces)
    assert not holds(wide.formula, [frozenset({"a"}), frozenset({"c"}), frozenset({"b"})])
    assert wide.stopped_by == "max_size"


def test_undeclared_letters_and_a_deadline():
    with pytest.raises(DataError, match="'z' is not declared"):
        learn_positive_only(TRACES, ["a", "b"], letters=[{"z"}])
    result = learn_positive_only(TRACES, ["a", "b"], max_size=12, timeout=0.0)
    assert result.stopped_by == "deadline" and result.complete_up_to < 12
    assert all(holds(result.formula, [frozenset(x) for x in t]) for t in TRACES)
