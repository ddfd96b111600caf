"""Guards: canonicity, Boolean algebra laws, parsing and printing."""

import pickle

import numpy as np
import pytest
from automata_strategies import PROPS, all_labels, guards, labels
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.errors import ParseError
from symlearn.logic.guards import Guard

a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")


def truth_table(g, props=PROPS):
    return tuple(g.evaluate(label) for label in all_labels(props))


@settings(deadline=None)
@given(guards(), guards())
def test_equality_is_logical_equivalence(g, h):
    assert (g == h) == (truth_table(g) == truth_table(h))
    if g == h:
        assert hash(g) == hash(h)


@settings(deadline=None)
@given(guards(), guards(), guards())
def test_boolean_algebra_laws(g, h, k):
    assert g & (h | k) == (g & h) | (g & k)
    assert ~(g & h) == ~g | ~h
    assert ~~g == g
    assert g | ~g == Guard.true() and (g & ~g).is_false()
    assert (g & h) & k == g & (h & k)
    assert g | (g & h) == g


@settings(deadline=None)
@given(guards(), labels())
def test_operations_match_pointwise_semantics(g, label):
    h = Guard.var("a") | Guard.var("c")
    assert (g & h).evaluate(label) == (g.evaluate(label) and h.evaluate(label))
    assert (g | h).evaluate(label) == (g.evaluate(label) or h.evaluate(label))
    assert (~g).evaluate(label) == (not g.evaluate(label))
    assert (g ^ h).evaluate(label) == (g.evaluate(label) != h.evaluate(label))


@settings(deadline=None)
@given(guards())
def test_print_parse_round_trip_and_support(g):
    assert Guard.parse(str(g)) == g
    # the support is exactly the propositions the function depends on
    for p in PROPS:
        depends = any(g.evaluate(lab | {p}) != g.evaluate(lab - {p}) for lab in all_labels(PROPS))
        assert (p in g.propositions) == depends


@settings(deadline=None)
@given(guards())
def test_satisfying_label_is_minimal(g):
    label = g.satisfying_label()
    if g.is_false():
        assert label is None
        return
    assert g.evaluate(label)
    assert len(label) == min(len(lab) for lab in all_labels(PROPS) if g.evaluate(lab))


@settings(deadline=None)
@given(guards())
def test_count_matches_truth_table(g):
    assert g.count(PROPS) == sum(truth_table(g))


def test_sample_label_is_uniform_over_models():
    g = a | b
    rng = np.random.default_rng(0)
    counts = {}
    for _ in range(3000):
        lab = g.sample_label(["a", "b"], rng)
        assert g.evaluate(lab)
        counts[lab] = counts.get(lab, 0) + 1
    assert len(counts) == 3 and min(counts.values()) > 850


def test_readable_minimal_printing():
    assert str(Guard.true()) == "true" and str(Guard.false()) == "false"
    assert str((a & b) | (a & ~b)) == "a"
    assert str(Guard.parse("!(a | b) | a")) == "a | !b"
    assert str((a & ~b) | (~a & b)) == "(a & !b) | (!a & b)"
    assert str(Guard.cube({"b": False, "a": True})) == "a & !b"
    assert str(Guard.var("true stuff")) == '"true stuff"'
    assert str(Guard.var("false")) == '"false"'


def test_parse_accepts_all_spellings():
    assert Guard.parse("a && !b || c") == Guard.parse("(a & ~b) | c") == (a & ~b) | c
    assert Guard.parse("TRUE") == Guard.true() and Guard.parse("False") == Guard.false()
    assert Guard.parse('"x y" & trueish') == Guard.var("x y") & Guard.var("trueish")
    assert Guard.parse("!a & b | c") == ((~a) & b) | c  # ! > & > |


def test_large_support_does_not_enumerate():
    names = [f"p{i}" for i in range(40)]
    g = Guard.all_of(Guard.var(n) for n in names) | Guard.var("q")
    assert g.count(names + ["q"]) == 2 ** 40 + 1
    assert Guard.parse(str(g)) == g
    assert g.satisfying_label() == frozenset({"q"})


def test_quantifiers_restrict_rename():
    assert ((a & b) | c).restrict("c", False) == a & b
    assert (a & b).exists(["a"]) == b
    assert (a & ~b).rename({"a": "z", "b": "a"}) == Guard.var("z") & ~a


def test_immutable_and_picklable():
    g = a & ~b
    with pytest.raises(AttributeError):
        g._node = 0
    assert pickle.loads(pickle.dumps(g)) == g
    with pytest.raises(TypeError):
        bool(g)


@pytest.mark.parametrize("text, column, hint", [
    ("a &", 4, "true, false"),
    ("a and b", 3, "'&' instead of 'and'"),
    ("(a | b", 7, None),
    ("a $ b", 3, None),
    ("", 1, None),
    ("a b", 3, None),
    ('""', 1, None),
])
def test_parse_errors_name_the_column(text, column, hint):
    with pytest.raises(ParseError) as info:
        Guard.parse(text)
    assert info.value.column == column
    assert "guard" in info.value.message
    if hint:
        assert hint in info.value.hint


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="ab!&|()~ \"\\tfrue", max_size=12))
def test_fuzzing_parser_raises_only_parse_errors(text):
    try:
        g = Guard.parse(text)
    except ParseError:
        return
    assert Guard.parse(str(g)) == g


def test_deep_nesting_and_size_limit():
    from symlearn.errors import LimitExceededError

    assert Guard.parse("!" * 3001 + "a") == ~a
    assert Guard.parse("(" * 3000 + "a" + ")" * 3000) == a
    assert len(Guard.parse(" | ".join(f"p{i}" for i in range(200))).propositions) == 200
    # a chain over more propositions than Python's default recursion limit builds (the BDD's
    # operations make room for one frame per level: symlearn.logic.bdd) and prints back
    chain = Guard.parse(" & ".join(f"p{i}" for i in range(3000)))
    assert len(chain.propositions) == 3000 and chain.evaluate({f"p{i}" for i in range(3000)})
    assert not chain.evaluate({f"p{i}" for i in range(2999)}) and Guard.parse(str(chain)) == chain
    assert (~chain).evaluate(set()) and chain.implies(Guard.var("p2999"))


def test_large_support_prints_prime_implicants_in_natural_order():
    names = [f"p{i}" for i in range(12)]
    g = Guard.all_of(Guard.var(n) for n in names[:6]) | (Guard.var("p7") & ~Guard.var("p11")) | Guard.var("p9")
    assert str(g) == "p9 | (p7 & !p11) | (p0 & p1 & p2 & p3 & p4 & p5)"
    for cube in g.cubes():
        assert Guard.cube(cube).implies(g)
        for name in cube:  # prime: no literal can be dropped
            rest = {n: v for n, v in cube.items() if n != name}
            assert not Guard.cube(rest).implies(g)


# -- the shared table frees what no guard reaches ------------------------------------------------
def _garbage(tag: str, n: int = 300) -> None:
    """Build and drop guards over fresh proposition names (nodes nothing will reach)."""
    for i in range(n):
        _ = (Guard.var(f"{tag}{i}") & ~Guard.var(f"{tag}{i + 1}")) | Guard.var(f"{tag}{i + 2}")


def test_collect_frees_dead_guards_and_keeps_live_ones():
    from symlearn.logic import guards

    keep = (Guard.var("k1") & ~Guard.var("k2")) | Guard.var("k3")
    text, key, h = str(keep), keep.sort_key, hash(keep)
    _garbage("dead")
    before = guards.node_count()
    assert guards.collect() > 0 and guards.node_count() < before
    # a live guard keeps identity, meaning, printing and hash; equal guards rebuilt later are equal
    assert str(keep) == text and keep.sort_key == key and hash(keep) == hash(keep)
    assert keep.evaluate({"k1"}) and not keep.evaluate({"k1", "k2"})
    again = (Guard.var("k3") | Guard.var("k1")) & (Guard.var("k3") | ~Guard.var("k2"))
    assert again == keep and hash(again) == h and again is keep
    assert Guard.parse("a | !b") == a | ~b  # cached parses survive as live guards


def test_collection_runs_by_itself_and_bounds_the_table(monkeypatch):
    from symlearn.logic import guards

    guards.collect()
    monkeypatch.setattr(guards, "_COLLECT_FROM", 2000)
    monkeypatch.setattr(guards, "_collect_at", max(2000, len(guards._var)))
    live = [Guard.var(f"live{i}") & Guard.var(f"live{i + 1}") for i in range(100)]
    sizes = []
    for round_ in range(20):
        _garbage(f"r{round_}_")
        sizes.append(len(guards._var))
    assert max(sizes) < 3 * max(2000, sizes[0])  # freed ids are reused instead of growing
    assert all(g == Guard.var(f"live{i}") & Guard.var(f"live{i + 1}") for i, g in enumerate(live))


@settings(deadline=None, max_examples=60)
@given(guards(), guards())
def test_algebra_is_unchanged_by_collections(g, h):
    from symlearn.logic import guards as module

    expected = truth_table(g & ~h), truth_table(g | h)
    _garbage("hyp", 20)
    module.collect()
    assert (truth_table(g & ~h), truth_table(g | h)) == expected
    assert Guard.parse(str(g)) == g


def test_from_bdd_converts_nodes_of_another_manager():
    from symlearn.logic.bdd import BDD
    from symlearn.logic.guards import from_bdd

    m = BDD()
    x, y = m.var(0), m.var(1)
    both, either = m.apply_and(x, m.negate(y)), m.apply_or(x, y)
    assert from_bdd(m, [both, either, x], ["a", "b"]) == [a & ~b, a | b, a]
    with pytest.raises(ValueError, match="name order"):
        from_bdd(m, [both], ["b", "a"])


def test_from_bdd_gives_the_label_keys_a_fresh_walk_gives():
    """from_bdd records each converted guard's label_key (the order of a DFA state's edges)
    during its conversion; it must be the key of the guard's own minimal satisfying label, ties
    broken as satisfying_label breaks them, on random functions with many equal-cost labels."""
    import random

    from symlearn.logic.bdd import BDD, FALSE, TRUE
    from symlearn.logic.guards import _label_key_cache, from_bdd

    rng = random.Random(27)
    names = ["p0", "p1", "p2", "q", "r", "s"]
    for _ in range(200):
        m = BDD()
        nodes, disjunction = [FALSE, TRUE], FALSE
        for _ in range(rng.randrange(1, 5)):  # a growing disjunction of random cubes
            cube = TRUE
            for level in sorted(rng.sample(range(len(names)), rng.randrange(1, 4)), reverse=True):
                cube = m.node(level, FALSE, cube) if rng.random() < 0.5 else m.node(level, cube, FALSE)
            disjunction = m.apply_or(disjunction, cube)
            nodes += [cube, disjunction, m.negate(disjunction)]
        converted = from_bdd(m, nodes, names)
        for guard in converted:
            label = guard.satisfying_label()  # its own walk and cache, not the recorded key
            expected = (0, ()) if label is None else (1, len(label), tuple(sorted(label)))
            assert _label_key_cache[guard._node] == expected, (str(guard), expected)
            assert guard.label_key == expected


def test_guards_over_thousands_of_propositions_print():
    """The printer's diagram operations recurse once per proposition: a guard over 10,000
    (the edge guard of F(p0 & ... & p9999)) stopped as "too deep to print" before."""
    from symlearn.logic.ltlf import parse, translate

    dfa = translate(parse("F(" + " & ".join(f"p{i}" for i in range(10_000)) + ")"))
    texts = [str(g) for q in dfa.states for g, _ in dfa.successors(q)]
    assert "!p0 | !p1 | !p2" in texts[0] and texts[0].endswith("!p9999")
    assert "p9999" in max(texts, key=len)


def test_a_guard_over_many_propositions_prints_within_the_prime_cover_budget():
    """(a0 & !b) | ... | (a199 & !b) asked a prime cover at every node of its factored form
    (n^3 node visits: minutes); the printing now spends a bounded budget and stays exact."""
    import time

    names = [f"a{i}" for i in range(200)]
    guard = Guard.any_of(Guard.var(n) & ~Guard.var("b") for n in names)
    start = time.perf_counter()
    text = str(guard)
    assert time.perf_counter() - start < 20
    assert Guard.parse(text) == guard


def test_a_guard_whose_text_passes_the_limit_is_refused_before_printing():
    import time

    from symlearn.errors import LimitExceededError

    guard = Guard.cube({f"a_proposition_with_a_long_name_{i:05d}": True for i in range(6_000)})  # > 200,000 characters
    start = time.perf_counter()
    with pytest.raises(LimitExceededError, match="longer than 200,000 characters"):
        str(guard)
    assert time.perf_counter() - start < 5


def test_a_long_chain_prints_as_one_junction_in_linear_time():
    """A guard over thousands of propositions (a TLSF file's inputs) is a chain of BDD nodes; it
    prints as one conjunction or disjunction (guards._run), where one nesting per node made the
    text quadratic to build."""
    import time

    n = 900  # the Boolean operations recurse once per level: below Python's default depth
    names = [f"a{i:03d}" for i in range(n)]
    disjunction, conjunction = Guard.var(names[-1]), ~Guard.var(names[-1])
    for name in reversed(names[:-1]):  # built from the bottom: each step adds the node on top
        disjunction, conjunction = Guard.var(name) | disjunction, ~Guard.var(name) & conjunction
    started = time.perf_counter()
    texts = {"shared": str(disjunction & ~Guard.var("zz")), "cube": str(conjunction & Guard.var("zz")),
             "or": str(disjunction | Guard.var("zz"))}
    assert time.perf_counter() - started < 5.0
    assert texts["shared"].startswith("!zz & (a000 | a001 | a002 |") and texts["shared"].endswith("| a899)")
    assert texts["cube"].startswith("zz & !a000 & !a001") or texts["cube"].startswith("!a000 & !a001")
    assert texts["or"].count("|") == n
    small = Guard.var("a") | Guard.var("b")  # short guards print as before
    assert str(small) == "a | b"
    chain = Guard.var("x9")
    for i in range(8, -1, -1):
        chain = Guard.var(f"x{i}") | chain
    for guard in (chain & ~Guard.var("y"), ~chain | Guard.var("y"), chain & Guard.var("y") | ~Guard.var("z")):
        assert Guard.parse(str(guard)) == guard


def test_chains_deeper_than_the_recursion_limit_build_with_the_operators():
    """``g & Guard.var(n)`` in name order appends at the bottom of the diagram each time: past
    1,000 names the recursion is deeper than Python's default limit, which the operations make
    room for (and give back)."""
    import sys

    names = [f"q{i:04d}" for i in range(1100)]
    depth = sys.getrecursionlimit()
    chain, either = Guard.true(), Guard.false()
    for name in names:
        chain, either = chain & Guard.var(name), either | Guard.var(name)
    assert sys.getrecursionlimit() == depth
    assert len(chain.propositions) == 1100 and chain.implies(either) and not either.implies(chain)
    assert (~chain).evaluate(set(names[:-1])) and chain.restrict(names[-1], True).evaluate(set(names))
    assert chain.satisfying_label() == frozenset(names) and chain.count(names) == 1
    assert chain.rename({n: n.upper() for n in names}).propositions == frozenset(n.upper() for n in names)


def test_label_key_orders_disjoint_guards_as_sort_key_does():
    """A DFA state's edges are pairwise disjoint; label_key (no support walk) must give them the
    order sort_key gives, so automata are numbered the same either way."""
    import itertools
    import random

    from symlearn.logic.guards import Guard

    rng = random.Random(11)
    names = [f"p{i}" for i in range(5)]
    for _ in range(200):
        # a random partition of the labels over the names: each cell one guard (a DFA row)
        cells: dict[int, Guard] = {}
        for values in itertools.product((False, True), repeat=len(names)):
            minterm = Guard.true()
            for name, value in zip(names, values):
                minterm = minterm & (Guard.var(name) if value else ~Guard.var(name))
            cell = rng.randrange(4)
            cells[cell] = cells[cell] | minterm if cell in cells else minterm
        row = list(cells.values())
        rng.shuffle(row)
        assert sorted(row, key=lambda g: g.label_key) == sorted(row, key=lambda g: g.sort_key)
        for g in row:
            assert g.sort_key[:len(g.label_key)] == g.label_key
