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


def _random_ordered_diagram(rng, n_states: int, n_vars: int, n_nodes: int):
    """A reduced, ordered diagram of about ``n_nodes`` nodes over ``n_vars`` propositions (children
    test later propositions or are leaves), roots mostly internal, random acceptance."""
    diagram = td.TransitionDiagram([f"p{i}" for i in range(n_vars)])
    by_var: list[list[int]] = [[] for _ in range(n_vars)]

    def child(var: int) -> int:
        later = rng.randrange(var + 1, n_vars + 1)
        if later == n_vars or not by_var[later] or rng.random() < 0.2:
            return ~rng.randrange(n_states)
        return rng.choice(by_var[later])

    for _ in range(n_nodes * 3):
        if len(diagram) >= n_nodes:
            break
        var = rng.randrange(n_vars)
        before = len(diagram)
        u = diagram.node(var, child(var), child(var))
        if len(diagram) > before:
            by_var[var].append(u)
    roots = [rng.randrange(len(diagram)) if len(diagram) and rng.random() < 0.9 else ~rng.randrange(n_states)
             for _ in range(n_states)]
    # few distinct leaf blocks make many equivalent states: the rounds have merging to do
    accepting = [rng.random() < 0.3 for _ in range(n_states)]
    return diagram, roots, accepting


def _python_rounds(diagram, roots, accepting, max_rounds):
    return td._moore_rounds_python(diagram, roots, td._initial_blocks(accepting, len(roots)), max_rounds)[:2]


def _numpy_rounds(diagram, roots, accepting, max_rounds):
    levels = td._variable_levels(diagram, len(roots))
    assert levels is not None  # ordered
    return td._moore_rounds_numpy(roots, td._initial_blocks(accepting, len(roots)), max_rounds, levels, len(diagram))


def _as_partition(block):
    classes: dict[int, set[int]] = {}
    for q, b in enumerate(block):
        classes.setdefault(b, set()).add(q)
    return {frozenset(c) for c in classes.values()}


@pytest.mark.parametrize("n_nodes, n_vars", [(30, 3), (300, 8), (2_500, 6), (6_000, 12)])
def test_numpy_moore_rounds_give_the_python_rounds_partition(n_nodes, n_vars):
    """The numpy rounds against the Python loop, below and above the size where _moore_rounds
    switches (VECTOR_MOORE_NODES), converged and cut off after 0..3 rounds: the same classes,
    even numbered alike, and the same converged flag."""
    import random

    rng = random.Random(n_nodes)
    for _ in range(6 if n_nodes < 1_000 else 2):
        diagram, roots, accepting = _random_ordered_diagram(rng, max(2, n_nodes // rng.choice((3, 10, 40))),
                                                            n_vars, n_nodes)
        for max_rounds in (None, 0, 1, 2, 3):
            expected = _python_rounds(diagram, roots, accepting, max_rounds)
            got = _numpy_rounds(diagram, roots, accepting, max_rounds)
            assert _as_partition(got[0]) == _as_partition(expected[0])
            assert got == expected


def _chain(n: int):
    """A counter-like chain: state i goes to i + 1 on p0 & p1, else back to 0; the last accepts."""
    diagram = td.TransitionDiagram(["p0", "p1"])
    roots = [diagram.node(0, ~0, diagram.node(1, ~0, ~min(i + 1, n - 1))) for i in range(n)]
    return diagram, roots, [i == n - 1 for i in range(n)]


def test_numpy_moore_rounds_on_a_chain_that_needs_one_round_per_state():
    """Every state of a chain is its own class, found one round at a time, so max_rounds cuts
    the rounds short (converged False) and coarsest_blocks' Hopcroft finish starts from the
    numpy rounds' partition."""
    short = _chain(300)  # to convergence: one round per state, quadratic in the Python loop
    assert _numpy_rounds(*short, None) == _python_rounds(*short, None)
    assert _numpy_rounds(*short, None)[1]
    diagram, roots, accepting = _chain(3_000)  # above VECTOR_MOORE_NODES
    for max_rounds in (1, 5, 24):
        expected = _python_rounds(diagram, roots, accepting, max_rounds)
        assert _numpy_rounds(diagram, roots, accepting, max_rounds) == expected and not expected[1]
        assert len(set(expected[0])) == max_rounds + 2  # accepting, rejecting, one more a round
    assert len(set(td.coarsest_blocks(diagram, roots, accepting))) == 3_000


def test_moore_rounds_switch_to_numpy_only_on_large_ordered_diagrams(monkeypatch):
    import random

    import numpy  # noqa: F401  (loaded: _moore_rounds goes to numpy at once)

    calls = []
    real = td._moore_rounds_numpy
    monkeypatch.setattr(td, "_moore_rounds_numpy", lambda *args: calls.append(args) or real(*args))
    rng = random.Random(5)
    small = _random_ordered_diagram(rng, 30, 4, 200)
    large = _random_ordered_diagram(rng, 500, 6, 3_000)
    assert td._moore_rounds(*small, None) == _python_rounds(*small, None) and not calls
    assert td._moore_rounds(*large, None) == _python_rounds(*large, None) and len(calls) == 1
    # not ordered (a child tests an earlier proposition): the levels do not exist, Python rounds
    unordered = td.TransitionDiagram(["a", "b"])
    inner = unordered.node(0, ~0, ~1)
    unordered.node(1, inner, ~1)
    assert td._variable_levels(unordered, 2) is None


def test_moore_rounds_start_in_python_while_numpy_is_not_imported(monkeypatch):
    """Without numpy loaded, the first rounds (up to NUMPY_IMPORT_WORK node visits) are Python
    rounds and numpy takes over from the partition they reached: same result, same cut-off."""
    monkeypatch.setattr(td, "_numpy_loaded", lambda: False)
    chain = _chain(3_000)
    monkeypatch.setattr(td, "NUMPY_IMPORT_WORK", 5 * len(chain[0]))  # 5 Python rounds, then numpy
    calls = []
    real = td._moore_rounds_numpy
    monkeypatch.setattr(td, "_moore_rounds_numpy", lambda *args: calls.append(args[2]) or real(*args))
    for max_rounds in (3, 5, 24):
        assert td._moore_rounds(*chain, max_rounds) == _python_rounds(*chain, max_rounds)
    assert calls == [19]  # 3 and 5 rounds end in Python; 24 = 5 in Python + 19 in numpy
    import random

    diagram, roots, accepting = _random_ordered_diagram(random.Random(8), 600, 8, 4_000)
    monkeypatch.setattr(td, "NUMPY_IMPORT_WORK", 1)  # one Python round
    assert td._moore_rounds(diagram, roots, accepting, None) == _python_rounds(diagram, roots, accepting, None)


def test_numpy_quotient_builds_the_python_quotient(monkeypatch):
    """quotient's numpy passes (merged diagram, kept nodes) give the same DFA, node for node and
    in the same typed arrays, as its Python loops: for the coarsest partition, for nothing merged,
    and for everything merged into one block (no node left)."""
    import random

    def fields(result):
        diagram, roots, accepting, initial, order = result
        return ([list(f) for f in (diagram.var, diagram.low, diagram.high)],
                [type(f) for f in (diagram.var, diagram.low, diagram.high)], roots, accepting, initial, order)

    import numpy  # noqa: F401  (loaded: quotient uses it)

    rng = random.Random(11)
    for n_nodes, n_vars in ((2_500, 6), (5_000, 10)):
        diagram, roots, accepting = _random_ordered_diagram(rng, n_nodes // 10, n_vars, n_nodes)
        assert td._levels_worth_numpy(diagram, len(roots)) is not None
        partitions = [td.coarsest_blocks(diagram, roots, accepting), list(range(len(roots))), [0] * len(roots)]
        for block in partitions:
            with_numpy = fields(td.quotient(diagram, roots, block, accepting, 0))
            with monkeypatch.context() as patched:
                patched.setattr(td, "_numpy_loaded", lambda: False)
                assert fields(td.quotient(diagram, roots, block, accepting, 0)) == with_numpy
