"""The ROBDD engine shared by guards and the LTLf translation."""

from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.logic.bdd import BDD, FALSE, TRUE


def build(m: BDD, expr):
    """Build a nested tuple expression ('and'|'or'|'not', ...) or a variable key."""
    if not isinstance(expr, tuple):
        return m.var(expr)
    if expr[0] == "not":
        return m.negate(build(m, expr[1]))
    left, right = build(m, expr[1]), build(m, expr[2])
    return m.apply_and(left, right) if expr[0] == "and" else m.apply_or(left, right)


def value(expr, env):
    if not isinstance(expr, tuple):
        return env[expr]
    if expr[0] == "not":
        return not value(expr[1], env)
    return (value(expr[1], env) and value(expr[2], env)) if expr[0] == "and" else (
        value(expr[1], env) or value(expr[2], env))


VARS = ["p", "q", "r"]
exprs = st.recursive(st.sampled_from(VARS), lambda inner: st.one_of(
    st.tuples(st.just("not"), inner), st.tuples(st.sampled_from(["and", "or"]), inner, inner)), max_leaves=8)
ENVS = [dict(zip(VARS, (bits >> 2 & 1, bits >> 1 & 1, bits & 1))) for bits in range(8)]


@settings(deadline=None)
@given(exprs, exprs)
def test_canonical_with_any_ordered_keys(e, f):
    m = BDD()  # string variables, as the guard table uses
    u, v = build(m, e), build(m, f)
    same = all(value(e, env) == value(f, env) for env in ENVS)
    assert (u == v) == same
    assert all(m.evaluate(u, env.get) == bool(value(e, env)) for env in ENVS)


@settings(deadline=None)
@given(exprs)
def test_restrict_and_support(e):
    m = BDD()
    u = build(m, e)
    for var in VARS:
        for fixed in (False, True):
            r = m.restrict(u, var, fixed)
            assert all(m.evaluate(r, env.get) == bool(value(e, {**env, var: fixed})) for env in ENVS)
    depends = {v for v in VARS if any(value(e, {**env, v: 0}) != value(e, {**env, v: 1}) for env in ENVS)}
    assert m.support(u) == depends


@settings(deadline=None)
@given(exprs, exprs, exprs)
def test_ite_is_the_one_pass_form_of_and_or_not(e, f, g):
    # ite walks the three diagrams at once (the translation's substitution step): it must build
    # the very node that (e & f) | (!e & g) hash-conses to, whatever the terminal shortcuts took
    m = BDD()
    u, v, w = build(m, e), build(m, f), build(m, g)
    expected = m.apply_or(m.apply_and(u, v), m.apply_and(m.negate(u), w))
    assert m.ite(u, v, w) == expected
    for a, b, c in ((u, u, w), (u, v, u), (u, TRUE, FALSE), (u, FALSE, TRUE), (u, v, v), (u, TRUE, w), (u, v, FALSE)):
        assert m.ite(a, b, c) == m.apply_or(m.apply_and(a, b), m.apply_and(m.negate(a), c))
    m.collect([u, v, w, expected])  # the ite cache is emptied with the others (freed ids are reused)
    m.apply_and(m.negate(m.var("p")), m.var("r"))  # new nodes, possibly on freed ids
    assert m.ite(u, v, w) == expected


def test_collect_keeps_roots_and_reuses_freed_ids():
    m = BDD()
    x, y, z = m.var(0), m.var(1), m.var(2)
    keep = m.apply_or(m.apply_and(x, y), z)
    m.apply_and(m.negate(x), m.negate(z))  # garbage
    size = len(m.level)
    freed = m.collect([keep])
    assert freed > 0 and len(m) == size - freed
    assert [m.evaluate(keep, lambda v, bits=bits: bits >> v & 1) for bits in range(8)] == \
        [bool((b & 1 and b >> 1 & 1) or b >> 2 & 1) for b in range(8)]
    again = m.apply_or(m.apply_and(m.var(0), m.var(1)), m.var(2))
    assert again == keep  # hash-consing still finds the surviving nodes
    m.apply_and(m.negate(m.var(0)), m.var(1))
    assert len(m.level) == size  # new nodes took freed ids
    assert m.ite(TRUE, x, y) == x and m.ite(FALSE, x, y) == y


def test_operations_on_a_chain_deeper_than_the_recursion_limit():
    import sys

    import pytest

    from symlearn.errors import LimitExceededError

    m, f = BDD(), 1
    depth = sys.getrecursionlimit()
    for i in range(1500):   # conjoined in order: every step recurses down the whole chain
        f = m.apply_and(f, m.var(i))
    g = m.negate(f)
    assert sys.getrecursionlimit() == depth
    assert m.apply_or(f, g) == 1 and m.apply_and(f, g) == 0
    assert m.restrict(f, 1499, False) == 0 and m.restrict(f, 0, True) != f
    assert m.simplify(f, m.var(0)) != 0 and len(m.support(f)) == 1500
    assert m.ite(f, g, f) == 0 and m.ite(g, m.var(0), f) == m.apply_or(m.apply_and(g, m.var(0)), f)  # deep
    small = BDD(max_nodes=500)   # the node bound still stops an exploding diagram, deep or not
    with pytest.raises(LimitExceededError, match="more than 500 nodes"):
        h = 0
        for i in range(40):   # (a_i & b_i) | ... with every a before every b: exponential
            h = small.apply_or(h, small.apply_and(small.var(i), small.var(40 + i)))


def test_nodes_by_key_is_node_per_key_in_merged_order():
    """nodes_by_key looks the unique table up inline; it must give node(var, low[k], high[k])
    (FALSE where a side lacks k) for every key, keys in the order of {**low, **high}, build
    only the nodes node() would, and respect the node bound as node() does."""
    import random

    import pytest

    from symlearn.errors import LimitExceededError

    rng = random.Random(27)
    for _ in range(100):
        m = BDD()
        pool = [FALSE, TRUE] + [m.apply_or(m.var(rng.randrange(1, 5)), m.var(rng.randrange(1, 5))) for _ in range(6)]
        low = {k: rng.choice(pool) for k in rng.sample(range(8), rng.randrange(0, 5))}
        high = {k: rng.choice(pool) for k in rng.sample(range(8), rng.randrange(0, 5))}
        found = m.nodes_by_key(0, low, high)
        size = len(m)
        expected = {k: m.node(0, low.get(k, FALSE), high.get(k, FALSE)) for k in {**low, **high}}
        assert list(found.items()) == list(expected.items())
        assert len(m) == size  # node() found every node nodes_by_key built: none missing, none extra
    small = BDD(max_nodes=4)
    a = small.var(1)
    with pytest.raises(LimitExceededError, match="more than 4 nodes"):
        small.nodes_by_key(0, {"x": a, "y": FALSE}, {"y": a, "z": TRUE})
