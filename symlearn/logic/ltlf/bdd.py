"""A small reduced ordered BDD manager with integer variables, used by the LTLf -> DFA translation.

Variables are integers; a smaller integer is nearer the root. Nodes are hash-consed, so two
Boolean functions built in the same manager are equal exactly when their node ids are equal.
The translation needs this (rather than :class:`~symlearn.logic.guards.Guard`, whose variables
are proposition names) because it mixes letter propositions with formula obligations in one
diagram, propositions first, and a fresh manager per translation keeps the tables small.

>>> m = BDD()
>>> a, b = m.var(0), m.var(1)
>>> m.apply_or(m.apply_and(a, b), m.apply_and(a, m.negate(b))) == a
True
"""

from __future__ import annotations

from collections.abc import Callable

FALSE, TRUE = 0, 1
_TERMINAL_LEVEL = 1 << 60


class BDD:
    __slots__ = ("level", "low", "high", "_unique", "_and", "_or", "_not")

    def __init__(self) -> None:
        self.level: list[int] = [_TERMINAL_LEVEL, _TERMINAL_LEVEL]
        self.low: list[int] = [0, 1]
        self.high: list[int] = [0, 1]
        self._unique: dict[tuple[int, int, int], int] = {}
        self._and: dict[tuple[int, int], int] = {}
        self._or: dict[tuple[int, int], int] = {}
        self._not: dict[int, int] = {}

    def __len__(self) -> int:
        return len(self.level)

    def node(self, var: int, low: int, high: int) -> int:
        if low == high:
            return low
        key = (var, low, high)
        found = self._unique.get(key)
        if found is None:
            found = len(self.level)
            self.level.append(var)
            self.low.append(low)
            self.high.append(high)
            self._unique[key] = found
        return found

    def var(self, var: int) -> int:
        return self.node(var, FALSE, TRUE)

    def apply_and(self, u: int, v: int) -> int:
        return self._apply(u, v, FALSE, self._and)

    def apply_or(self, u: int, v: int) -> int:
        return self._apply(u, v, TRUE, self._or)

    def _apply(self, u: int, v: int, absorbing: int, cache: dict[tuple[int, int], int]) -> int:
        """``u & v`` (absorbing FALSE) or ``u | v`` (absorbing TRUE) by Shannon expansion."""
        if u == absorbing or v == absorbing:
            return absorbing
        if u <= TRUE:  # the neutral constant
            return v
        if v <= TRUE or u == v:
            return u
        key = (u, v) if u < v else (v, u)
        found = cache.get(key)
        if found is not None:
            return found
        lu, lv = self.level[u], self.level[v]
        top = lu if lu < lv else lv
        u0, u1 = (self.low[u], self.high[u]) if lu == top else (u, u)
        v0, v1 = (self.low[v], self.high[v]) if lv == top else (v, v)
        found = self.node(top, self._apply(u0, v0, absorbing, cache), self._apply(u1, v1, absorbing, cache))
        cache[key] = found
        return found

    def negate(self, u: int) -> int:
        if u <= TRUE:
            return 1 - u
        found = self._not.get(u)
        if found is None:
            found = self.node(self.level[u], self.negate(self.low[u]), self.negate(self.high[u]))
            self._not[u] = found
            self._not[found] = u
        return found

    def ite(self, f: int, g: int, h: int) -> int:
        if f == TRUE:
            return g
        if f == FALSE:
            return h
        if g == h:
            return g
        return self.apply_or(self.apply_and(f, g), self.apply_and(self.negate(f), h))

    def evaluate(self, u: int, value: Callable[[int], bool], cache: dict[int, bool] | None = None) -> bool:
        """Value of ``u`` when variable ``v`` has ``value(v)``; ``cache`` may be shared across calls."""
        while u > TRUE:
            u = self.high[u] if value(self.level[u]) else self.low[u]
        return u == TRUE

    def cubes(self, u: int) -> list[dict[int, bool]]:
        """Disjoint cubes (variable -> value) whose union is ``u``: the paths to ``TRUE``."""
        out: list[dict[int, bool]] = []
        stack: list[tuple[int, dict[int, bool]]] = [(u, {})]
        while stack:
            node, cube = stack.pop()
            if node == TRUE:
                out.append(cube)
            elif node != FALSE:
                var = self.level[node]
                stack.append((self.low[node], {**cube, var: False}))
                stack.append((self.high[node], {**cube, var: True}))
        return out
