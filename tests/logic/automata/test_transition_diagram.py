"""Symbolic transitions (transition_diagram.py) and the DFA operations that work on them."""

import pytest

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata import transition_diagram as td
from symlearn.logic.automata.dfa import DFA
from symlearn.logic.guards import Guard
from symlearn.logic.ltlf import parse, translate


def conjunction_of_f(n: int) -> DFA:
    return translate(parse(" & ".join(f"F p{i}" for i in range(n))), max_states=100_000)


@pytest.fixture(scope="module")
def big():
    """F p0 & ... & F p8: 512 states, 3^9 = 19683 edges, so it comes out symbolic."""
    return conjunction_of_f(9)


def test_large_translation_is_symbolic_and_counts_states_without_edges(big):
    assert big.is_symbolic() and big.n_states == 2 ** 9
    assert big.diagram_nodes() < 3 ** 9 // 5  # about n 2^(n-1) nodes, not 3^n edges
    assert big.count_edges(1000) is None  # stops counting beyond the limit
    assert big.count_edges() == 3 ** 9
    assert big.is_complete() and big.initial == 0 and len(big.accepting) == 1


def test_running_a_symbolic_dfa(big):
    everything = {f"p{i}" for i in range(9)}
    assert big.accepts([everything])
    assert not big.accepts([everything - {"p3"}])
    assert big.accepts([everything - {"p3"}, {"p3"}])
    assert not big.accepts([])
    state = big.step(big.initial, {"p0"})
    assert state != big.initial and big.step(state, {"p0"}) == state


def test_symbolic_operations_agree_with_the_explicit_ones(big):
    explicit = DFA(big.alphabet, big.n_states, big.initial, big.accepting,
                   {q: list(big.successors(q)) for q in big.states})  # materialised, checked on construction
    assert not explicit.is_symbolic() and explicit == big and hash(explicit) == hash(big)
    assert big.equivalent(explicit) == (True, None)
    assert explicit.minimize() == big  # a large explicit DFA is minimised symbolically: same numbering
    assert big.minimize() == big
    complement = ~big
    assert complement.is_symbolic() and complement.accepts([]) and not complement.accepts([set(big.alphabet)])
    assert big.shortest_accepted() is not None and len(big.shortest_accepted()) == 1
    assert big.accepts(big.shortest_accepted())
    assert big.shortest_rejected() == []
    assert not big.is_empty() and not big.is_universal()
    assert (big & complement).is_empty()
    assert big.live_states() == frozenset(big.states)
    assert big.reachable_states() == frozenset(big.states)


def test_products_mix_symbolic_and_explicit_operands(big):
    no_p0 = translate(parse("G !p0"))
    assert not no_p0.is_symbolic()
    both = big & no_p0
    assert both.is_symbolic() and both.is_empty()
    either = (big | no_p0).minimize()
    everything = {f"p{i}" for i in range(9)}
    assert either.accepts([set()]) and either.accepts([everything]) and not either.accepts([{"p0"}])
    same, witness = big.equivalent(conjunction_of_f(8).with_alphabet(big.alphabet))
    assert not same and conjunction_of_f(8).accepts(witness) != big.accepts(witness)


def test_materialising_edges_has_a_limit_that_says_so():
    dfa = conjunction_of_f(8)  # 6561 edges: explicit by default
    assert not dfa.is_symbolic()
    diagram, roots = dfa.transition_diagram()
    symbolic = DFA._symbolic(dfa.alphabet, dfa.n_states, dfa.initial, dfa.accepting, diagram, roots)
    with pytest.raises(LimitExceededError, match="kept symbolic"):
        td.materialise(diagram, roots, limit=1000)
    assert symbolic == dfa  # equality materialises nothing: it compares canonical diagrams
    assert symbolic.successors(5) == dfa.successors(5)  # within the default limit, produced on demand


def test_explicit_to_diagram_round_trip_keeps_the_language():
    a, b = Guard.var("a"), Guard.var("b")
    dfa = DFA({"a", "b"}, 3, 0, [2], {0: [(a & ~b, 1), (b, 2)], 1: [(a, 2), (~a, 0)]})  # partial: gets a sink
    diagram, roots = dfa.transition_diagram()
    assert len(roots) == 4  # completed
    symbolic = DFA._symbolic(dfa.alphabet, 4, 0, [2], diagram, roots)
    assert symbolic.equivalent(dfa) == (True, None)
    assert symbolic.minimize() == dfa.minimize()


def test_minimisation_merges_equivalent_states_symbolically():
    a = Guard.var("a")
    # states 1 and 2 are equivalent copies; 3 is a sink
    dfa = DFA({"a"}, 4, 0, [1, 2], {0: [(a, 1), (~a, 2)], 1: [(a, 1), (~a, 2)], 2: [(a, 2), (~a, 1)],
                                     3: [(Guard.true(), 3)]})
    diagram, roots = dfa.transition_diagram()
    symbolic = DFA._symbolic(dfa.alphabet, 4, 0, [1, 2], diagram, roots)
    minimal = symbolic.minimize()
    assert minimal.n_states == 2 and minimal == dfa.minimize()


def test_user_guards_are_still_checked_for_determinism():
    a, b = Guard.var("a"), Guard.var("b")
    with pytest.raises(ModelError, match="not deterministic.*both match the label"):
        DFA({"a", "b"}, 3, 0, [], {0: [(a, 1), (~a & ~b, 0), (b, 2)]})
    cubes = []
    for m in range(64):
        g = Guard.true()
        for i in range(6):
            g = g & (Guard.var(f"x{i}") if m >> i & 1 else ~Guard.var(f"x{i}"))
        cubes.append(g)
    dfa = DFA({f"x{i}" for i in range(6)}, 64, 0, [0], {0: [(g, j) for j, g in enumerate(cubes)]})
    assert dfa.n_edges == 64


def test_symbolic_numbering_is_canonical():
    # the same language built two ways gets the same symbolic DFA
    big = conjunction_of_f(9)
    other = translate(parse(" & ".join(f"F p{i}" for i in reversed(range(9)))), max_states=100_000)
    assert other == big


def test_sink_states():
    dfa = translate(parse("G !bad & F goal"))
    assert len(dfa.sink_states()) == 1
    assert dfa.sink_states() == frozenset(dfa.states) - dfa.live_states()


def test_diagrams_over_many_propositions_need_no_deep_recursion():
    n = 900  # about as deep as Python's default recursion limit (1000 frames)
    dfa = translate(parse(" | ".join(f"p{i}" for i in range(n))))
    diagram, roots = dfa.transition_diagram()
    symbolic = DFA._symbolic(dfa.alphabet, dfa.n_states, dfa.initial, dfa.accepting, diagram, roots)
    assert symbolic.count_edges() == dfa.n_edges and symbolic == dfa
    assert symbolic.live_states() == dfa.live_states()
    assert (symbolic & symbolic).minimize() == dfa
    assert symbolic.accepts([{f"p{n - 1}"}]) and not symbolic.accepts([set()])


def test_edge_counts_by_bitsets_agree_with_successor_sets():
    """count_edges' bit sets (freed as they are used) against the frozensets per node, with and
    without a limit, on random diagrams sharing nodes between roots, and with a budget so small
    that the bit sets give up and the frozensets count."""
    import random

    rng = random.Random(27)
    for _ in range(300):
        n_states, n_vars = rng.randint(1, 40), rng.randint(1, 6)
        diagram = td.TransitionDiagram([f"p{i}" for i in range(n_vars)])
        nodes: list[int] = []
        for _ in range(rng.randint(0, 60)):
            var = rng.randrange(n_vars)
            # children test later propositions (or are leaves): reduced and ordered
            below = [u for u in nodes if diagram.var[u] > var] + [~rng.randrange(n_states) for _ in range(3)]
            u = diagram.node(var, rng.choice(below), rng.choice(below))
            if u >= 0 and u not in nodes:
                nodes.append(u)
        roots = [rng.choice(nodes + [~rng.randrange(n_states)]) for _ in range(n_states)]
        exact = sum(len(s) for s in td._successor_sets(diagram, roots, None))
        assert td.count_edges(diagram, roots) == exact
        assert td._count_by_bitsets(diagram, roots, None, 0) in (exact, td._TOO_WIDE)
        for limit in (0, exact - 1, exact, exact + 1):
            expected = None if exact > limit else exact
            assert td.count_edges(diagram, roots, limit) == expected
            assert td._count_by_bitsets(diagram, roots, limit, 10 ** 9) == expected


def test_counting_the_edges_of_a_wide_automaton_is_fast():
    """F p0 & ... & F p13: 3^14 edges over 16,384 states; the frozenset count took ~0.5 s to
    give up at a million edges, the bit sets count all of them in ~0.08 s."""
    import time

    wide = translate(parse(" & ".join(f"F p{i}" for i in range(14))), max_states=100_000)
    start = time.perf_counter()
    assert wide.count_edges() == 3 ** 14
    assert wide.count_edges(1_000_000) is None
    assert time.perf_counter() - start < 2.0  # generous for noisy CI machines
