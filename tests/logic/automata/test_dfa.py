"""DFA construction, running, completion, minimisation, products, shortest words, equivalence."""

import pytest
from automata_strategies import dfas, words
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata import DFA
from symlearn.logic.guards import Guard

a, b = Guard.var("a"), Guard.var("b")
T = Guard.true()


def eventually(p):
    g = Guard.var(p)
    return DFA({p}, 2, 0, [1], {0: [(~g, 0), (g, 1)], 1: [(T, 1)]})


def a_then_b_redundant():
    """F(a & X F b) written with duplicate states (5 states, minimal has 3 + none dead)."""
    return DFA({"a", "b"}, 5, 0, [3, 4], {
        0: [(~a, 0), (a, 1)],
        1: [(~b, 2), (b, 3)],
        2: [(~b, 1), (b, 4)],
        3: [(T, 4)],
        4: [(T, 3)],
    })


def test_run_step_accepts():
    d = eventually("a")
    assert d.step(0, {"a"}) == 1 and d.step(0, set()) == 0
    assert d.run([set(), {"a"}, set()]) == [0, 0, 1, 1]
    assert d.accepts([{"a", "zzz"}]) and not d.accepts([]) and not d.accepts([{"b"}])


def test_partial_run_stops_and_rejects():
    d = DFA({"a"}, 2, 0, [1], {0: [(a, 1)], 1: [(a, 1)]})
    assert d.run([{"a"}, set(), {"a"}]) == [0, 1]
    assert not d.accepts([{"a"}, set()]) and d.accepts([{"a"}, {"a"}])
    assert not d.is_complete()
    full = d.complete()
    assert full.is_complete() and full.n_states == 3
    assert full.run([{"a"}, set(), {"a"}]) == [0, 1, 2, 2]
    assert full.complete() is full


def test_edges_to_same_target_are_merged_canonically():
    d1 = DFA({"a", "b"}, 2, 0, [1], {0: [(a & b, 1), (a & ~b, 1), (~a, 0)]})
    d2 = DFA({"a", "b"}, 2, 0, [1], {0: [("!a", 0), ("a", 1)]})
    assert d1 == d2 and hash(d1) == hash(d2)
    assert d1.n_edges == 2


@pytest.mark.parametrize("kwargs, message", [
    (dict(n_states=0), "at least one state"),
    (dict(initial=5), "initial state 5"),
    (dict(accepting=[3]), "accepting state 3"),
    (dict(transitions={0: [(a, 7)]}), "target"),
    (dict(transitions={9: [(a, 0)]}), "source"),
    (dict(transitions={0: [(Guard.var("zz"), 0)]}), "outside the alphabet"),
    (dict(transitions={0: [(a, 0), (a | b, 1)]}), "not deterministic"),
    (dict(transitions={0: [("a &", 0)]}), "unexpected end"),
    (dict(transitions={0: [(a,)]}), "not a (guard, target) pair"),
    (dict(state_names=["x"]), "1 state names for 2 states"),
    (dict(alphabet="ab"), "not the string"),
])
def test_bad_construction_raises_model_error(kwargs, message):
    args = dict(alphabet={"a", "b"}, n_states=2, initial=0, accepting=[1], transitions={0: [(a, 1)]})
    args.update(kwargs)
    with pytest.raises(Exception) as info:
        DFA(**args)
    assert message in str(info.value)
    assert isinstance(info.value, (ModelError,)) or "unexpected" in message


def test_nondeterminism_message_names_witness():
    with pytest.raises(ModelError, match=r"from state 0.*both match the label \{a\}"):
        DFA({"a", "b"}, 2, 0, [1], {0: [(a, 0), (a | b, 1)]})


def test_minimize_merges_equivalent_states():
    m = a_then_b_redundant().minimize()
    assert m.n_states == 3 and m.is_complete()
    assert m.equivalent(a_then_b_redundant()) == (True, None)
    assert m.initial == 0
    # canonical: already minimal input gives the same structure
    assert m.minimize() == m


def test_minimize_adds_sink_and_drops_unreachable():
    d = DFA({"a"}, 3, 0, [0], {0: [(a, 0)], 2: [(T, 0)]})
    m = d.minimize()
    assert m.n_states == 2 and m.accepting == {0}
    assert m.accepts([{"a"}]) and not m.accepts([set()])


def test_minimize_empty_and_universal_languages():
    empty = DFA({"a"}, 3, 0, [], {0: [(a, 1), (~a, 2)], 1: [(T, 2)], 2: [(T, 0)]}).minimize()
    assert empty.n_states == 1 and not empty.accepting and empty.is_empty()
    universal = DFA({"a"}, 2, 0, [0, 1], {0: [(a, 1), (~a, 0)], 1: [(T, 0)]}).minimize()
    assert universal.n_states == 1 and universal.is_universal()


def test_product_modes_and_limits():
    fa, fb = eventually("a"), eventually("b")
    both = fa & fb
    assert both.alphabet == {"a", "b"}
    assert both.accepts([{"a"}, {"b"}]) and not both.accepts([{"a"}])
    assert (fa | fb).accepts([{"b"}])
    assert (fa - fb).accepts([{"a"}]) and not (fa - fb).accepts([{"a", "b"}])
    assert fa.product(fb, "xor").accepts([{"a"}]) and not fa.product(fb, "xor").accepts([{"a", "b"}])
    with pytest.raises(ModelError, match="unknown product mode"):
        fa.product(fb, "nand")
    with pytest.raises(LimitExceededError, match="exceeds 2 states"):
        fa.product(fb, max_states=2)


def test_shortest_words():
    d = a_then_b_redundant()
    assert d.shortest_accepted() == [frozenset({"a"}), frozenset({"b"})]
    assert d.shortest_rejected() == []
    assert d.shortest_accepted(start=3) == []
    never = DFA({"a"}, 1, 0, [], {0: [(T, 0)]})
    assert never.shortest_accepted() is None and never.is_empty()
    assert DFA({"a"}, 1, 0, [0], {0: [(a, 0)]}).shortest_rejected() == [frozenset()]


def test_equivalence_counterexample_is_shortest():
    same, witness = eventually("a").equivalent(eventually("a").complement().complement())
    assert same and witness is None
    same, witness = eventually("a").equivalent(a_then_b_redundant())
    assert not same and witness == [frozenset({"a"})]


def test_complement_and_live_states():
    d = DFA({"a"}, 3, 0, [1], {0: [(a, 1), (~a, 2)], 1: [(T, 1)], 2: [(T, 2)]})
    assert d.live_states() == {0, 1}
    assert d.trim().n_states == 2
    c = d.complement()
    assert c.accepts([set()]) and not c.accepts([{"a"}]) and c.accepts([])


# -- properties ------------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(dfas(), st.lists(words(("a", "b")), max_size=15))
def test_minimize_preserves_language(d, ws):
    m = d.minimize()
    assert m.n_states <= d.complete().n_states
    for w in ws:
        assert m.accepts(w) == d.accepts(w)
    assert m.equivalent(d) == (True, None)
    assert m.minimize() == m


@settings(max_examples=60, deadline=None)
@given(dfas(), dfas(), st.lists(words(("a", "b")), max_size=10))
def test_product_and_complement_semantics(d1, d2, ws):
    for w in ws:
        x, y = d1.accepts(w), d2.accepts(w)
        assert (d1 & d2).accepts(w) == (x and y)
        assert (d1 | d2).accepts(w) == (x or y)
        assert (d1 - d2).accepts(w) == (x and not y)
        assert d1.complement().accepts(w) == (not x)


@settings(max_examples=60, deadline=None)
@given(dfas(), dfas())
def test_equivalence_agrees_with_canonical_minimal_form(d1, d2):
    same, witness = d1.equivalent(d2)
    assert same == d1.minimize().same_structure(d2.minimize())
    if not same:
        assert d1.accepts(witness) != d2.accepts(witness)


@settings(max_examples=60, deadline=None)
@given(dfas())
def test_shortest_words_are_correct(d):
    acc, rej = d.shortest_accepted(), d.shortest_rejected()
    if acc is None:
        assert d.minimize().accepting == frozenset()
    else:
        assert d.accepts(acc)
    if rej is not None:
        assert not d.accepts(rej)


@settings(max_examples=80, deadline=None)
@given(dfas(("a", "b", "c"), max_states=6))
def test_hopcroft_agrees_with_moore_and_is_minimal(d):
    from symlearn.logic.automata.operations import minimize_moore

    m = d.minimize()
    assert m.same_structure(minimize_moore(d))
    # no two states of the result accept the same language
    for i in m.states:
        for j in range(i + 1, m.n_states):
            left = DFA._trusted(m.alphabet, m.n_states, i, m.accepting, [m.successors(q) for q in m.states])
            right = DFA._trusted(m.alphabet, m.n_states, j, m.accepting, [m.successors(q) for q in m.states])
            assert not left.equivalent(right)[0]


def test_minimize_large_counter_is_fast():
    import time

    n = 400
    tr = {k: [(a, ((k % n + 1) % n) + n * (1 - k // n)), (~a, k)] for k in range(2 * n)}
    d = DFA({"a", "b"}, 2 * n, 0, [0, n], tr)
    start = time.perf_counter()
    m = d.minimize()
    assert m.n_states == n and time.perf_counter() - start < 2.0


def test_a_guard_outside_a_huge_alphabet_is_a_short_message():
    # the whole alphabet was listed: 200,000 names made a 2 MB error line (held-out pass)
    import pytest

    from symlearn.errors import ModelError
    from symlearn.logic.automata.dfa import DFA

    names = [f"p{i}" for i in range(5000)]
    with pytest.raises(ModelError) as caught:
        DFA(names, 1, 0, [0], {0: [("q", 0)]})
    assert "(5,000 in all)" in str(caught.value) and len(str(caught.value)) < 600
