"""Compositional translation (composition.py): the same minimal DFA as progression of the whole
formula, and the formulas it is for translate where progression ran out of time."""

import importlib
import random
import time

import pytest
from hypothesis import given, settings
from ltlf_strategies import formulas

from symlearn.errors import LimitExceededError
from symlearn.logic.ltlf import composition, parse, translate
from symlearn.logic.ltlf.composition import compose, is_composite
from symlearn.logic.ltlf.semantics import holds

to_dfa = importlib.import_module("symlearn.logic.ltlf.to_dfa")


@pytest.fixture
def always_compose(monkeypatch):
    """No progression trial of the whole: every composite formula is taken apart."""
    monkeypatch.setattr(composition, "TRIAL_STATES", 0)


@settings(max_examples=200, deadline=None)
@given(formulas(props=("a", "b", "c", "d"), max_leaves=10))
def test_composition_gives_the_dfa_progression_gives(f):
    composition.TRIAL_STATES, trial = 0, composition.TRIAL_STATES
    try:
        composed = compose(f, to_dfa._progression, 20_000)
    finally:
        composition.TRIAL_STATES = trial
    assert composed == to_dfa._progression(f, 20_000)  # equal languages, equal numbering


@pytest.mark.parametrize("text", [
    "a & G(a -> X b) & F !b",  # a state condition joined to the temporal part
    "(G F a -> G F b) & (G F c -> G F d) & G !(b & d)",
    "(F a | G b) <-> (a U b)",
    "!(F a & G(a -> b)) | (b W c)",
    "(a -> X b) & (b -> X c) & (c -> X a) & F(a & b)",
    "((G a) & (F b)) | ((G b) & (F a)) | (a & !b)",
    # a part whose DFA has one state (no word, every word) meets the other part without a product
    "(F a & G !a) <-> (a U b)",
    "(F a | G !a) & (a U b) & X c",
    "(F a & G !a) | (b W a)",
    "(F a | G !a) <-> (b U a)",
    "((F a & G !a) | (F c | G !c)) & (G(a -> X b) | F c)",
    # an assumption joins the products of the guarantee's parts it shares propositions with
    "(G F a & G(a -> X b)) -> (G(b -> X c) & F(c & a) & G(c -> !b))",
    "(G a) -> (G(b -> X c) & F(c & b) & G(a -> X a) & F(a & X !a))",
    "(F a & G(b -> X !a)) -> ((G(a -> X b) & (b U c)) | G(c -> X d))",
    "((a U b) -> (G(a -> X b) & F(b & c))) & ((G F c) -> (G(c -> X d) & F(d & !c)))",
])
def test_composed_skeletons(text, always_compose):
    f = parse(text)
    assert is_composite(f)
    assert translate(f) == to_dfa._progression(f, 20_000)


def test_independent_parts_stay_one_progression():
    assert not is_composite(parse(" & ".join(f"F p{i}" for i in range(14))))
    assert not is_composite(parse("G a -> F b"))
    assert is_composite(parse("G a -> F a"))


def _fairness_pairs(n: int) -> str:
    """Random/Lydia-like: G F x -> G F y for n pairs, outputs pairwise exclusive in threes."""
    parts = []
    for i in range(0, n, 2):
        parts += [f"(G F x{i} -> G F y{i})", f"(G F x{i + 1} -> G F y{i + 1})", f"G !(y{i} & y{i + 1})"]
    # chain the groups through shared outputs, so no conjunct is independent of the rest
    parts += [f"G !(y{i + 1} & y{i + 2})" for i in range(0, n - 2, 2)]
    return " & ".join(parts)


def test_shared_fairness_conjunctions_translate_quickly():
    """12 pairs, a 3-state DFA: progression of the whole stops at its 5,000,000-node limit after
    ~7 s (10 pairs: 6 s; a Random/Lydia file of SYNTCOMP's tlsf-fin like it timed out at 30 s);
    part by part it takes 0.15 s."""
    f = parse(_fairness_pairs(12))
    start = time.perf_counter()
    dfa = translate(f)
    assert time.perf_counter() - start < 10  # generous for noisy CI machines; ~0.1 s here
    assert dfa.n_states <= 4
    rng = random.Random(27)
    names = sorted(dfa.alphabet)
    for _ in range(300):  # against the semantics, non-empty traces up to 6 letters
        trace = [frozenset(p for p in names if rng.random() < 0.15) for _ in range(rng.randint(1, 6))]
        assert dfa.accepts(trace) == holds(f, trace)


def test_products_respect_the_state_limit(always_compose):
    f = parse("(F a & F b & F c & F d & F e) & (G(a -> X b)) & (F(e & c))")
    with pytest.raises(LimitExceededError, match="needs more than 8 states"):
        translate(f, max_states=8)


@pytest.mark.parametrize("text, parts", [
    ("X G (a & b & (c -> X d))", 3),  # strong next, then always: X G a & X G b & X G (c -> X d)
    ("WX G (a & X b)", 2),
    ("F X (a | X b | c)", 3),  # eventually over a disjunction
    ("G (a | b)", 1),  # G does not distribute over |
    ("F (a & b)", 1),  # F does not distribute over &
])
def test_temporal_chains_over_a_junction_are_distributed(text, parts, always_compose):
    f = parse(text)
    spread = composition._Composer(None, 0).distributed(f)
    assert (spread is f) if parts == 1 else len(composition._operands(spread)) == parts
    if parts > 1:
        assert translate(f) == to_dfa._progression(f, 20_000)
    rng = random.Random(5)
    for _ in range(200):
        trace = [frozenset(p for p in "abcd" if rng.random() < 0.5) for _ in range(rng.randint(1, 5))]
        assert holds(spread, trace) == holds(f, trace)


def _double_counter(bits: int) -> str:
    """The shape of SYNTCOMP's Two-player-Game/Double-Counter specifications: initial values, and
    under an environment assumption a strong-next G over the carry and bit rules of two counters
    plus a strong-next F of their equality."""
    init = [f"(X[!] ce{i} -> i{i}) && (i{i} -> X ce{i}) && !cs{i}" for i in range(bits)] + ["!incs"]
    rules = ["(X[!] ke0 -> ince)", "(ince -> X ke0)", "(ks0 <-> incs)"]
    for i in range(1, bits):
        for side in ("e", "s"):
            rules += [f"(X[!] k{side}{i} -> (c{side}{i - 1} && X[!] k{side}{i - 1}))",
                      f"((c{side}{i - 1} && X k{side}{i - 1}) -> X k{side}{i})"]
    for i in range(bits):
        for side in ("e", "s"):
            rules += [f"((X[!] c{side}{i} -> !(c{side}{i} <-> X[!] k{side}{i})) && "
                      f"(!(c{side}{i} <-> X k{side}{i}) -> X c{side}{i}))"]
    equal = " && ".join(f"(ce{i} <-> cs{i})" for i in range(bits))
    return (f"({' && '.join(init)}) && (G (ince -> !X[!] ince) -> "
            f"(X[!] G ({' && '.join(rules)}) && X[!] F ({equal})))")


def test_a_double_counter_is_composed_rule_by_rule(always_compose):
    """Its rules are one ``X[!] G (...)`` leaf until the chain is distributed, and its start
    conditions must not pull the composite rules back into one progression: SYNTCOMP's 5-bit
    counter (4,101 states, MONA 3.4 s) stopped at the 5,000,000-node limit after 14 s before."""
    from symlearn.logic.ltlf.tlsf import parse_tlsf

    import re

    text = _double_counter(2)
    names = sorted(set(re.findall(r"[a-z]+[0-9]*", text)) - {"G", "F", "X"})
    f = parse_tlsf(f"INFO {{ TITLE: \"c\" DESCRIPTION: \"c\" SEMANTICS: Finite,Moore TARGET: Moore }}\n"
                   f"MAIN {{ INPUTS {{ {'; '.join(names)}; }} GUARANTEES {{ {text}; }} }}").formula
    assert is_composite(f)
    composer = composition._Composer(to_dfa._progression, 20_000)
    rules = next(p for p in composition._operands(f)
                 if isinstance(p, composition.Implies) and isinstance(p.left, composition.Always))
    assert composer.composite(rules.right)  # X[!] G (...) & X[!] F (...): the rules are parts
    dfa = translate(f)
    assert dfa == to_dfa._progression(f, 20_000)
    rng = random.Random(3)
    names = sorted(dfa.alphabet)
    for _ in range(300):
        trace = [frozenset(p for p in names if rng.random() < 0.5) for _ in range(rng.randint(1, 6))]
        assert dfa.accepts(trace) == holds(f, trace)


def _take_away(heaps: int) -> str:
    """The shape of SYNTCOMP's Nim games: a start position (state conditions only) and, under an
    assumption on the turns, ``G (...)`` rules that read that position from the first letter on
    (a one-hot heap ``h0..hn`` that the player on turn lowers by one, the other keeps) and a goal."""
    mutex = [f"(h{i} -> !h{j})" for i in range(heaps + 1) for j in range(i)]
    moves = [f"((t && h{i}) -> X[!] h{i - 1})" for i in range(1, heaps + 1)]
    keeps = [f"((!t && h{i}) -> X[!] h{i})" for i in range(heaps + 1)]
    return (f"h{heaps} && t && (G (t -> X[!] !t) -> "
            f"(G ({' && '.join(mutex + moves + keeps)}) && F h0))")


def _tlsf_formula(text: str):
    from symlearn.logic.ltlf.tlsf import parse_tlsf

    import re

    names = sorted(set(re.findall(r"[a-z]+[0-9]*", text)) - {"G", "F", "X"})
    return parse_tlsf(f"INFO {{ TITLE: \"c\" DESCRIPTION: \"c\" SEMANTICS: Finite,Moore TARGET: Moore }}\n"
                      f"MAIN {{ INPUTS {{ {'; '.join(names)}; }} GUARANTEES {{ {text}; }} }}").formula


def test_first_letter_propositions():
    """What a formula may read at the first letter: nothing under X/WX, nor T's right side."""
    composer = composition._Composer(None, 0)
    f = parse("X a & G(b -> X c) & (d T e) & F(f U X[!] g) & !(WX h | i)")
    assert composer.first_letter_propositions(f) == {"b", "d", "f", "i"}
    assert composer.propositions(f) == set("abcdefghi")


@pytest.mark.parametrize("text, joined", [
    (_double_counter(2), False),  # its rules and goal read the system counter from the 2nd letter on
    (_take_away(3), True),  # its rules read the start position at the first letter
])
def test_start_conditions_join_parts_that_read_them_at_the_first_letter(text, joined, always_compose):
    """A state condition joins a temporal part (one progression of both) only where the part
    reads one of its propositions at the first letter: elsewhere the join cannot restrict the
    part's obligations, and SYNTCOMP's double counters took the joined progression 3x slower than
    composed. Either way the same minimal DFA as progression of the whole formula."""
    f = _tlsf_formula(text)
    composer = composition._Composer(to_dfa._progression, 20_000)
    parts = composition._operands(f)
    rules = next(p for p in parts if isinstance(p, composition.Implies))
    attached = composer.attach_state_conditions(parts)
    assert (rules not in attached) == joined  # joined: replaced by rules & conditions
    assert (len(attached) < len(parts)) == joined
    assert translate(f) == to_dfa._progression(f, 20_000)


@pytest.mark.parametrize("text, parts", [
    ("!a & X[!] G (a -> b)", 1),  # one progression: composing it would only add a product
    ("!a & X[!] G ((a -> b) & (b -> X c))", 2),  # composite (distributed), and reads a from the 2nd letter
    ("!a & G ((a -> b) & (b -> X c))", 1),  # composite, but reads a at the first letter
])
def test_only_composite_parts_are_kept_from_conditions_they_cannot_restrict(text, parts):
    composer = composition._Composer(to_dfa._progression, 20_000)
    assert len(composer.attach_state_conditions(composition._operands(parse(text)))) == parts


def test_start_conditions_that_fall_back_join_the_conjunction_they_are_in(always_compose, monkeypatch):
    """A part joined to its start conditions whose progression runs out (here: no nodes at all)
    is composed, and its skeleton's and conditions' DFAs join the surrounding conjunction's
    products one by one: the same minimal DFA as progression of the whole formula."""
    monkeypatch.setattr(composition, "JOINED_NODES", 1)
    monkeypatch.setattr(composition, "JOINED_FIRST_NODES", 1)
    f = _tlsf_formula(_take_away(3))
    spread = []
    original = composition._Composer.unjoined_conjuncts

    def spy(self, *args):
        out = original(self, *args)
        spread.append(len(out))
        return out

    monkeypatch.setattr(composition._Composer, "unjoined_conjuncts", spy)
    assert translate(f) == to_dfa._progression(f, 20_000)
    assert spread and max(spread) > 1  # the fallback was taken, and gave its DFAs apart


def test_the_propositions_of_a_long_conjunction_take_linear_memory():
    """A left-deep c1 & ... & cn kept a proposition set per inner node: n(n+1)/2 names (100,000
    TLSF assumptions filled 4 GB before the translation started)."""
    import tracemalloc

    from symlearn.logic.ltlf.ast import And, Prop

    n = 20_000
    formula = Prop("p0")
    for i in range(1, n):
        formula = And(formula, Prop(f"p{i}"))
    composer = composition._Composer(None, 1000)
    tracemalloc.start()
    names = composer.propositions(formula)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert len(names) == n
    assert peak < 40 * 2**20, f"{peak / 2**20:.0f} MiB for the propositions of {n} conjuncts"
