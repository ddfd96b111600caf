"""Two-level minimisation of small Boolean functions: a minimum sum of products.

Guards over a few propositions print as their minimum cover (``a & !b | c``). This module finds
one for functions of up to :data:`MAX_VARIABLES` variables given by their minterms, in pure
Python on bit masks: Quine-McCluskey for the prime implicants, then the essential primes, then
a branch-and-bound search over the rest for the fewest cubes, ties broken by the fewest literals
(and then by a fixed order, so the result is deterministic). The search is bounded
(:data:`SEARCH_BUDGET` branch nodes); past it the best cover found so far is returned, still an
irredundant cover by primes. It replaces sympy's ``SOPform``, whose import alone took 0.35 s of
every ``symlearn ltl dfa`` that printed a guard.

A cube is ``(value, mask)``: variable ``i`` (bit ``n - 1 - i``, the first variable is the most
significant bit of a minterm) is free when its bit of ``mask`` is set, else fixed to its bit of
``value``.

>>> cover = minimum_cover([0b011, 0b111, 0b110], 3)  # !a&b&c | a&b&c | a&b&!c
>>> sorted(cube_literals(c, 3) for c in cover)
[[(0, True), (1, True)], [(1, True), (2, True)]]
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

__all__ = ["minimum_cover", "prime_implicants", "cube_literals", "MAX_VARIABLES", "SEARCH_BUDGET"]

MAX_VARIABLES = 8
SEARCH_BUDGET = 20_000

Cube = tuple[int, int]


def prime_implicants(minterms: Iterable[int], n: int) -> list[Cube]:
    """Every prime implicant of the function true exactly on ``minterms`` (Quine-McCluskey:
    cubes differing in one fixed variable merge; a cube that merges with none is prime)."""
    if n > MAX_VARIABLES:
        raise ValueError(f"two-level minimisation is for at most {MAX_VARIABLES} variables, not {n}")
    layer = {(m, 0) for m in minterms}
    primes: set[Cube] = set()
    while layer:
        merged: set[Cube] = set()
        used: set[Cube] = set()
        for value, mask in layer:
            for bit in range(n):
                flag = 1 << bit
                if mask & flag or value & flag:
                    continue  # merge each pair once, from the side with the bit clear
                partner = (value | flag, mask)
                if partner in layer:
                    merged.add((value, mask | flag))
                    used.add((value, mask))
                    used.add(partner)
        primes |= layer - used
        layer = merged
    return sorted(primes)


def _covers(cube: Cube, minterm: int) -> bool:
    value, mask = cube
    return (minterm & ~mask) == value


def _literals(cube: Cube, n: int) -> int:
    return n - bin(cube[1]).count("1")


def minimum_cover(minterms: Sequence[int], n: int) -> list[Cube]:
    """A cover of ``minterms`` by prime implicants with the fewest cubes, then the fewest
    literals (exact within :data:`SEARCH_BUDGET` search nodes). ``[]`` for no minterm;
    ``[(0, 2**n - 1)]`` (the empty cube: true) when every label is one."""
    minterms = sorted(set(minterms))
    if not minterms:
        return []
    if len(minterms) == 1 << n:
        return [(0, (1 << n) - 1)]
    primes = prime_implicants(minterms, n)
    covering = {m: [p for p in primes if _covers(p, m)] for m in minterms}
    chosen: list[Cube] = []
    uncovered = set(minterms)
    for m in minterms:  # essential primes: the only prime of some minterm
        if m in uncovered and len(covering[m]) == 1:
            prime = covering[m][0]
            chosen.append(prime)
            uncovered -= {x for x in uncovered if _covers(prime, x)}
    rest = _search(sorted(uncovered), covering, n)
    return sorted(chosen + rest)


def _search(uncovered: list[int], covering: dict[int, list[Cube]], n: int) -> list[Cube]:
    """The cheapest set of primes covering ``uncovered`` (cost: cubes, then literals)."""
    if not uncovered:
        return []
    best: list = [None, None]  # cost, cover
    nodes = [0]

    def cost(cover: list[Cube]) -> tuple[int, int]:
        return len(cover), sum(_literals(c, n) for c in cover)

    def greedy(left: set[int]) -> list[Cube]:
        cover = []
        while left:
            prime = max({p for m in left for p in covering[m]},
                        key=lambda p: (sum(_covers(p, m) for m in left), -_literals(p, n), p))
            cover.append(prime)
            left = {m for m in left if not _covers(prime, m)}
        return cover

    start = greedy(set(uncovered))
    best[0], best[1] = cost(start), start

    def branch(left: frozenset[int], cover: list[Cube]) -> None:
        nodes[0] += 1
        if nodes[0] > SEARCH_BUDGET:
            return
        if not left:
            found = cost(cover)
            if found < best[0]:
                best[0], best[1] = found, list(cover)
            return
        if len(cover) + 1 > best[0][0]:
            return  # one more cube is needed, and that already costs more cubes than the best
        # the minterm with the fewest primes: the smallest branching
        m = min(left, key=lambda x: (len(covering[x]), x))
        for prime in sorted(covering[m], key=lambda p: (-sum(_covers(p, x) for x in left), _literals(p, n), p)):
            cover.append(prime)
            branch(frozenset(x for x in left if not _covers(prime, x)), cover)
            cover.pop()

    branch(frozenset(uncovered), [])
    return best[1]


def cube_literals(cube: Cube, n: int) -> list[tuple[int, bool]]:
    """``(variable index, value)`` of the cube's fixed variables, in variable order."""
    value, mask = cube
    out = []
    for i in range(n):
        bit = 1 << (n - 1 - i)
        if not mask & bit:
            out.append((i, bool(value & bit)))
    return out
