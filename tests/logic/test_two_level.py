"""Two-level minimisation (two_level.py): exact covers by primes, minimum where checked exhaustively,
never worse than sympy's SOPform, which it replaced."""

import itertools
import random

import pytest

from symlearn.logic.two_level import cube_literals, minimum_cover, prime_implicants


def _covers(cube, m):
    value, mask = cube
    return (m & ~mask) == value


def _cost(cover, n):
    return len(cover), sum(len(cube_literals(c, n)) for c in cover)


def _random_function(rng, n):
    return sorted(m for m in range(2 ** n) if rng.random() < rng.choice([0.2, 0.5, 0.8]))


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 6, 7, 8])
def test_covers_are_exact_and_made_of_primes(n):
    rng = random.Random(n)
    for _ in range(40 if n <= 6 else 10):  # the prime check walks all 2^n points per prime
        minterms = _random_function(rng, n)
        primes = set(prime_implicants(minterms, n))
        cover = minimum_cover(minterms, n)
        assert {m for m in range(2 ** n) if any(_covers(c, m) for c in cover)} == set(minterms)
        if 0 < len(minterms) < 2 ** n:
            assert set(cover) <= primes
        for p in primes:  # prime: widening any fixed variable leaves the function
            assert all(_covers(p, m) <= (m in minterms) for m in range(2 ** n))


def test_minimum_against_every_subset_of_primes():
    rng = random.Random(4)
    for _ in range(150):
        n = rng.randint(2, 4)
        minterms = _random_function(rng, n)
        if not 0 < len(minterms) < 2 ** n:
            continue
        primes = prime_implicants(minterms, n)
        best = min(_cost(list(s), n) for k in range(1, len(primes) + 1) for s in itertools.combinations(primes, k)
                   if all(any(_covers(p, m) for p in s) for m in minterms))
        assert _cost(minimum_cover(minterms, n), n) == best


def test_never_worse_than_sympy():
    from sympy import Symbol
    from sympy.logic import SOPform
    from sympy.logic.boolalg import And, Or

    rng = random.Random(8)
    for _ in range(60):
        n = rng.randint(3, 6)
        minterms = _random_function(rng, n)
        if not 0 < len(minterms) < 2 ** n:
            continue
        symbols = [Symbol(f"v{i}") for i in range(n)]
        expr = SOPform(symbols, [[(m >> (n - 1 - i)) & 1 for i in range(n)] for m in minterms])
        terms = expr.args if isinstance(expr, Or) else (expr,)
        theirs = (len(terms), sum(len(t.args) if isinstance(t, And) else 1 for t in terms))
        assert _cost(minimum_cover(minterms, n), n) <= theirs


def test_constants():
    assert minimum_cover([], 3) == []
    assert minimum_cover(range(8), 3) == [(0, 7)]
