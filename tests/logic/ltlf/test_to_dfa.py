import time

import pytest
from hypothesis import given, settings

from ltlf_strategies import formulas
from symlearn.errors import LimitExceededError
from symlearn.logic.automata import DFA
from symlearn.logic.ltlf import equivalent, parse, to_dfa, translate
from symlearn.logic.ltlf.ast import Always, Eventually, Next, Not, Prop, conjunction


@pytest.mark.parametrize("text, states, edges", [
    ("true", 1, 1), ("false", 1, 1), ("a", 3, 4), ("F a", 2, 3), ("G a", 2, 3), ("a U b", 3, 5),
    ("X a", 4, 5), ("WX a", 4, 5), ("F a & F b", 4, 9), ("a T b", 3, 5), ("G(a -> X b)", 3, 6),
    ("G(!hole) & F goal", 3, 6), ("F a & G !a", 1, 1),
])
def test_known_minimal_sizes(text, states, edges):
    dfa = translate(parse(text))
    assert (dfa.n_states, dfa.n_edges) == (states, edges)


def test_result_is_a_complete_minimal_dfa_numbered_canonically():
    dfa = translate(parse("G(req -> F grant) & (a T b) & G !bad"))
    assert isinstance(dfa, DFA) and dfa.alphabet == {"a", "b", "bad", "grant", "req"}
    assert dfa.is_complete() and dfa.initial == 0
    assert dfa.minimize() == dfa  # minimize numbers states breadth-first too
    dead = set(dfa.states) - dfa.live_states()
    assert len(dead) == 1  # the rejecting sink
    assert to_dfa(parse("F a")).accepts([set(), {"a"}])


@settings(max_examples=150, deadline=None)
@given(formulas(max_leaves=8))
def test_translation_is_already_minimal(f):
    dfa = translate(f)
    assert dfa.minimize() == dfa  # minimal, and numbered canonically
    assert all(len({t for _, t in dfa.successors(q)}) == len(dfa.successors(q)) for q in dfa.states)  # one edge per target


def test_many_propositions_are_not_enumerated():
    # 2^24 letters; the symbolic construction only splits where the formula looks
    props = [Prop(f"p{i}") for i in range(24)]
    f = conjunction(Always(conjunction(*(Not(p) for p in props[:12]))), *(Eventually(p) for p in props[12:15]))
    start = time.perf_counter()
    dfa = translate(f)
    assert time.perf_counter() - start < 5
    assert dfa.n_states == 2 ** 3 + 1  # subsets of the three F's met, plus the sink
    assert dfa.n_edges < 200


def test_state_limit():
    counter = " & ".join(f"F p{i}" for i in range(12))
    with pytest.raises(LimitExceededError, match="more than 100 states") as info:
        translate(parse(counter), max_states=100)
    assert "max_states" in info.value.hint


def test_equivalence():
    assert equivalent(parse("a T b"), parse("F(a & X F b)"))
    assert equivalent(parse("a W b"), parse("a U b | G a"))
    assert equivalent(parse("!(a U b)"), parse("!a R !b"))
    assert equivalent(parse("G F a"), parse("F G a"))  # both: 'a' at the last step
    assert not equivalent(parse("X a"), parse("WX a"))


def test_deeply_nested_formulas_translate_or_stop_cleanly():
    from symlearn.logic.ltlf.ast import Next

    f = Prop("a")
    for _ in range(1500):
        f = Next(f)
    dfa = translate(f)
    assert dfa.n_states == 1503  # 1500 waiting steps + 'a' checked + accepting + sink
    assert dfa.accepts([set()] * 1500 + [{"a"}]) and not dfa.accepts([set()] * 1500)


@settings(max_examples=100, deadline=None)
@given(formulas(max_leaves=8))
def test_translation_edges_are_disjoint_and_complete_by_construction(f):
    # translate() skips the constructor's checks (they hold by construction); assert them here
    dfa = translate(f)
    assert dfa.is_complete()
    rebuilt = DFA(dfa.alphabet, dfa.n_states, dfa.initial, dfa.accepting, dfa.transitions)  # checks overlaps
    assert rebuilt == dfa


def test_large_minimal_dfas_stay_symbolic_and_agree_with_their_explicit_form():
    f = parse(" & ".join(f"F p{i}" for i in range(9)) + " & G(p0 -> X !p1)")
    dfa = translate(f)
    assert dfa.is_symbolic() and dfa.count_edges() > 10_000
    explicit = DFA(dfa.alphabet, dfa.n_states, dfa.initial, dfa.accepting, dfa.transitions)
    assert explicit == dfa and explicit.minimize() == dfa
    assert dfa.accepts([{f"p{i}" for i in range(9)}, set()]) and not dfa.accepts([{f"p{i}" for i in range(9)}])
    assert not dfa.accepts([{"p0"}, {"p1"}])


@settings(max_examples=120, deadline=None)
@given(formulas(max_leaves=9))
def test_diagram_minimisation_gives_the_same_dfa_as_the_explicit_one(f):
    # force the symbolic path (Moore on diagram signatures, quotient, canonical renumbering): its
    # minimal DFA, small enough to come out explicit, must be identical to the Hopcroft path's
    import sys

    module = sys.modules["symlearn.logic.ltlf.to_dfa"]  # the package's to_dfa attribute is the function
    expected = translate(f)
    saved = module.EXPLICIT_EDGES
    module.EXPLICIT_EDGES = -1
    try:
        assert translate(f) == expected
    finally:
        module.EXPLICIT_EDGES = saved


def test_explicit_edge_threshold_is_the_automata_side_one():
    import sys

    from symlearn.logic.automata import transition_diagram

    assert sys.modules["symlearn.logic.ltlf.to_dfa"].EXPLICIT_EDGES == transition_diagram.EXPLICIT_EDGES


def _eventuality_shapes():
    """Formulas rich in eventualities nested under ``&``, ``X``, ``U`` and ``T`` (the shapes of
    sub-goal sequences), with the weak operators beside them."""
    from hypothesis import strategies as st

    from symlearn.logic.ltlf.ast import And, Or, Then, Until, WeakNext

    atoms = st.sampled_from(["a", "b"]).map(Prop)

    def extend(children):
        return st.one_of(
            st.tuples(st.sampled_from((Next, WeakNext, Eventually, Always, Not)), children).map(lambda p: p[0](p[1])),
            st.tuples(st.sampled_from((And, And, Until, Then, Or)), children, children).map(lambda p: p[0](p[1], p[2])),
        )

    return st.recursive(atoms, extend, max_leaves=7)


def _agrees_with_the_semantics(f) -> None:
    import itertools

    from symlearn.logic.ltlf.semantics import holds

    dfa = translate(f)
    letters = [frozenset(), frozenset({"a"}), frozenset({"b"}), frozenset({"a", "b"})]
    for length in range(1, 5):
        for trace in itertools.product(letters, repeat=length):
            assert dfa.accepts(list(trace)) == holds(f, list(trace)), (str(f), trace)


@settings(max_examples=300, deadline=None)
@given(_eventuality_shapes())
def test_nested_eventualities_keep_the_language(f):
    _agrees_with_the_semantics(f)


@pytest.mark.parametrize("text", [
    # one eventuality forcing another through &, strong X, U's right side and nesting
    "F(a & X F b)", "F(a & X F(b & X F a))", "F(a U F b)", "F(F b & a)", "F(a & X(b & X F b))", "a T (b T a)",
    # weak next, always and a disjunction force nothing: a last a ends F(a & WX F b) without any b
    "F(a & WX F b)", "F(a & G F b)", "F(a | X F b)", "F(a & WX(b & X F a))", "F(G b & a) & F b",
])
def test_eventualities_forcing_others_or_not(text):
    _agrees_with_the_semantics(parse(text))


def test_translated_edges_are_in_guard_order():
    """The translation's rows reach DFA._trusted already sorted (ordered=True: not sorted a
    second time); each state's edges must still be in label_key/sort_key order, on the explicit
    route, the composed route (transition_diagram.finish) and a start state split for the empty word."""
    from symlearn.logic.ltlf.parser import parse

    for text in ["F a & F b & G !c", "G(a -> X b) & (F c | G d)", "!a", "(a U b) & (c R d) & F(e & X f)",
                 "G F a & G F b & G(c -> X !c)"]:
        dfa = translate(parse(text))
        assert not dfa.is_symbolic()
        for q in dfa.states:
            guards = [g for g, _ in dfa.successors(q)]
            assert guards == sorted(guards, key=lambda g: g.sort_key), (text, q)
