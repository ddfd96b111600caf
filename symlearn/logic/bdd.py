"""The reduced ordered BDD engine of the symbolic core.

A :class:`BDD` manager stores Boolean functions as hash-consed nodes, so two functions built
in one manager are equal exactly when their node ids are equal. Variables are any totally
ordered keys; a smaller key is nearer the root. Node ``0`` is false and ``1`` is true.

Two kinds of manager use this one engine:

* :mod:`symlearn.logic.guards` keeps *one shared manager* whose variables are proposition
  names, so guards of different automata compare, combine and hash without conversion; it
  frees the nodes no live guard reaches (:meth:`BDD.collect`).
* the LTLf -> DFA translation builds a *fresh manager per formula* whose integer variables are
  the letter's propositions followed by formula obligations (an order per formula, which the
  name-ordered shared table cannot hold). Most of its nodes are obligations that never reach
  an edge guard: on the LTLf -> DFA benchmark families a finished translation's manager holds
  3.8x as many nodes as the guards it produces (9.6x on the 201 formulas of the public LTLf
  learning benchmark, 109x on random formulas; ``python benchmarks/bdd_engines.py``). So it
  lives for one translation only: its proposition layer is copied into the automaton's
  :class:`~symlearn.logic.automata.transition_diagram.TransitionDiagram`, and guards reach the
  shared manager only when edges are asked for (:func:`symlearn.logic.guards.from_bdd`).

>>> m = BDD()
>>> a, b = m.var(0), m.var(1)
>>> m.apply_or(m.apply_and(a, b), m.apply_and(a, m.negate(b))) == a
True
>>> m.collect([a]), len(m)
(4, 3)
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Hashable, Iterable

from symlearn.errors import LimitExceededError

__all__ = ["BDD", "FALSE", "TRUE"]

FALSE, TRUE = 0, 1
#: the deepest recursion an operation may be given (a level a frame: formulas and guards over up
#: to about a million propositions; Python 3.11 keeps these frames off the C stack)
MAX_RECURSION = 1 << 20


class BDD:
    """Nodes ``u >= 2`` test variable ``level[u]``: ``low[u]`` when it is false, ``high[u]`` when true.

    The three lists are only ever changed in place, so callers in hot loops may keep
    references to them. Terminals have level ``None``; no operation compares a terminal's
    level (each checks ``u <= TRUE`` first), so any ordered key type works.
    """

    __slots__ = ("level", "low", "high", "_unique", "_and", "_or", "_not", "_ite", "_support", "_free",
                 "max_nodes", "limit_hint", "_room")

    def __init__(self, max_nodes: int | None = None, limit_hint: str | None = None) -> None:
        #: building a node beyond this many raises LimitExceededError (None: no limit); about
        #: 250 bytes a node, so the limit bounds the table's memory before the machine runs out.
        self.max_nodes = max_nodes
        self.limit_hint = limit_hint
        self.level: list = [None, None]
        self.low: list[int] = [FALSE, TRUE]
        self.high: list[int] = [FALSE, TRUE]
        self._unique: dict[tuple, int] = {}
        self._and: dict[tuple[int, int], int] = {}
        self._or: dict[tuple[int, int], int] = {}
        self._not: dict[int, int] = {}
        self._ite: dict[tuple[int, int, int], int] = {}
        self._support: dict[int, frozenset] = {FALSE: frozenset(), TRUE: frozenset()}
        self._free: list[int] = []  # ids of collected nodes, reused before the lists grow
        self._room = 0  # the recursion limit the deepest operation so far needed (0: Python's own sufficed)

    def __len__(self) -> int:
        """Live nodes, terminals included."""
        return len(self.level) - len(self._free)

    # -- construction ---------------------------------------------------------------------------
    def node(self, var: Hashable, low: int, high: int) -> int:
        """The node testing ``var`` (which must precede the variables of ``low`` and ``high``)."""
        if low == high:
            return low
        key = (var, low, high)
        found = self._unique.get(key)
        return self._add(key) if found is None else found

    def _add(self, key: tuple) -> int:
        """A new node for ``key`` = ``(var, low, high)``, not in the table and with ``low != high``.
        Apart from :meth:`node` so the operations' recursions can look the table up inline and
        call only for a new node (a Python call per result node was about a fifth of a
        translation's time on the tlsf-fin sample, issue 27)."""
        var, low, high = key
        free = self._free
        if free:
            found = free.pop()
            self.level[found], self.low[found], self.high[found] = var, low, high
        else:
            level = self.level
            found = len(level)
            bound = self.max_nodes
            if bound is not None and found >= bound:
                raise LimitExceededError(f"the BDD needs more than {bound:,} nodes", hint=self.limit_hint)
            level.append(var)
            self.low.append(low)
            self.high.append(high)
        self._unique[key] = found
        return found

    def nodes_by_key(self, var: Hashable, low: dict, high: dict) -> dict:
        """``{k: node(var, low.get(k, FALSE), high.get(k, FALSE))}`` for the keys of ``low``, then
        those of ``high`` not in ``low`` (the order of ``{**low, **high}``): one step of splitting
        a diagram into a guard per target, whose children's guards are ``low`` and ``high``
        (``to_dfa._split``, ``transition_diagram.materialise``). The table is looked up inline:
        a call of :meth:`node` per guard node was a tenth of the translation of Patterns/GFand
        pb_09 (6,818 edges, issue 27)."""
        unique, add = self._unique, self._add
        found = {}
        for k, g0 in low.items():
            g1 = high.get(k, FALSE)
            if g0 == g1:
                found[k] = g0
            else:
                key = (var, g0, g1)
                g = unique.get(key)
                found[k] = add(key) if g is None else g
        for k, g1 in high.items():
            if k not in low:
                if g1 == FALSE:
                    found[k] = FALSE
                else:
                    key = (var, FALSE, g1)
                    g = unique.get(key)
                    found[k] = add(key) if g is None else g
        return found

    def var(self, var: Hashable) -> int:
        return self.node(var, FALSE, TRUE)

    # -- Boolean operations -----------------------------------------------------------------------
    # The operations recurse once per variable level along a path. The entry points catch a
    # RecursionError (free in Python 3.11 until raised) and repeat the call with room for a few
    # frames per level this manager holds (_deep): a chain over more variables than Python's
    # default limit of 1,000 then works as any other diagram. Caches only ever hold finished
    # results, so the first attempt leaves nothing half-done.
    def apply_and(self, u: int, v: int) -> int:
        if self._room:
            return self._deep(self._apply, u, v, FALSE, self._and)
        try:
            return self._apply(u, v, FALSE, self._and)
        except RecursionError:
            return self._deep(self._apply, u, v, FALSE, self._and)

    def apply_or(self, u: int, v: int) -> int:
        if self._room:
            return self._deep(self._apply, u, v, TRUE, self._or)
        try:
            return self._apply(u, v, TRUE, self._or)
        except RecursionError:
            return self._deep(self._apply, u, v, TRUE, self._or)

    def _deep(self, call: Callable, *args) -> int:
        """``call(*args)`` with a recursion limit doubled until it fits (the depth is at most the
        number of variable levels, which the manager does not count: that would cost every new
        node a lookup); Python's own limit is given back afterwards. The room found is kept, so
        later operations on a deep diagram start with it instead of failing first (an unwound
        RecursionError costs some 20 ms)."""
        depth = sys.getrecursionlimit()
        room = max(self._room, 2 * depth)
        try:
            while True:
                sys.setrecursionlimit(room)
                try:
                    found = call(*args)
                    self._room = room
                    return found
                except RecursionError:
                    if room >= MAX_RECURSION:
                        raise LimitExceededError(f"a BDD operation recursed deeper than {MAX_RECURSION:,} levels",
                                                 hint="use fewer propositions in one formula or guard") from None
                    room = min(2 * room, MAX_RECURSION)
        finally:
            sys.setrecursionlimit(depth)

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
        level = self.level
        lu, lv = level[u], level[v]
        if lu == lv:
            top, u0, u1, v0, v1 = lu, self.low[u], self.high[u], self.low[v], self.high[v]
        elif lu < lv:
            top, u0, u1, v0, v1 = lu, self.low[u], self.high[u], v, v
        else:
            top, u0, u1, v0, v1 = lv, u, u, self.low[v], self.high[v]
        lo = self._apply(u0, v0, absorbing, cache)
        hi = self._apply(u1, v1, absorbing, cache)
        if lo == hi:  # node(), inline: this is the hottest call of the translation
            found = lo
        else:
            triple = (top, lo, hi)
            found = self._unique.get(triple)
            if found is None:
                found = self._add(triple)
        cache[key] = found
        return found

    def negate(self, u: int) -> int:
        if self._room:
            return self._deep(self._negate, u)
        try:
            return self._negate(u)
        except RecursionError:
            return self._deep(self._negate, u)

    def _negate(self, u: int) -> int:
        if u <= TRUE:
            return 1 - u
        found = self._not.get(u)
        if found is None:
            found = self.node(self.level[u], self._negate(self.low[u]), self._negate(self.high[u]))
            self._not[u] = found
            self._not[found] = u
        return found

    def ite(self, f: int, g: int, h: int) -> int:
        """``(f & g) | (!f & h)``, in one pass over the three diagrams: the translation's
        substitution step calls it once per obligation node, and building it from two ands, a
        negation and an or walked the diagrams four times (measured: 2.3x more node visits on
        the Random/Syft families)."""
        if self._room:
            return self._deep(self._ite_rec, f, g, h)
        try:
            return self._ite_rec(f, g, h)
        except RecursionError:
            return self._deep(self._ite_rec, f, g, h)

    def _ite_rec(self, f: int, g: int, h: int) -> int:
        if f <= TRUE:
            return g if f == TRUE else h
        if g == h:
            return g
        if g <= TRUE and h <= TRUE:  # g, h are TRUE/FALSE or FALSE/TRUE: f itself or its negation
            return f if g == TRUE else self._negate(f)
        if g == f:  # f ? f : h  ==  f | h
            g = TRUE
        elif h == f:  # f ? g : f  ==  f & g
            h = FALSE
        key = (f, g, h)
        cache = self._ite
        found = cache.get(key)
        if found is not None:
            return found
        level, low, high = self.level, self.low, self.high
        top = level[f]
        if g > TRUE and level[g] < top:
            top = level[g]
        if h > TRUE and level[h] < top:
            top = level[h]
        if level[f] == top:
            f0, f1 = low[f], high[f]
        else:
            f0 = f1 = f
        if g > TRUE and level[g] == top:
            g0, g1 = low[g], high[g]
        else:
            g0 = g1 = g
        if h > TRUE and level[h] == top:
            h0, h1 = low[h], high[h]
        else:
            h0 = h1 = h
        lo = self._ite_rec(f0, g0, h0)
        hi = self._ite_rec(f1, g1, h1)
        if lo == hi:  # node(), inline (as in _apply)
            found = lo
        else:
            triple = (top, lo, hi)
            found = self._unique.get(triple)
            if found is None:
                found = self._add(triple)
        cache[key] = found
        return found

    def restrict(self, u: int, var: Hashable, value: bool) -> int:
        """The cofactor of ``u`` with ``var`` fixed to ``value``."""
        memo: dict[int, int] = {}

        def walk(w: int) -> int:
            if w <= TRUE:
                return w
            name = self.level[w]
            if name == var:
                return self.high[w] if value else self.low[w]
            if var < name:
                return w  # var cannot occur below a later variable
            found = memo.get(w)
            if found is None:
                found = memo[w] = self.node(name, walk(self.low[w]), walk(self.high[w]))
            return found

        try:
            return walk(u)
        except RecursionError:
            return self._deep(walk, u)

    def simplify(self, u: int, care: int) -> int:
        """A function equal to ``u`` wherever ``care`` holds, usually with fewer nodes (Coudert and
        Madre's *restrict*): ``apply_and(simplify(u, c), c) == apply_and(u, c)``. Where ``care``
        is false the result is arbitrary; ``simplify(u, FALSE)`` is ``FALSE``."""
        memo: dict[tuple[int, int], int] = {}
        level, low, high = self.level, self.low, self.high

        def walk(f: int, c: int) -> int:
            if c == FALSE:
                return FALSE
            if c == TRUE or f <= TRUE:
                return f
            if f == c:
                return TRUE
            key = (f, c)
            found = memo.get(key)
            if found is not None:
                return found
            lf, lc = level[f], level[c]
            if lc < lf:  # the care set tests a variable f does not: forget it
                found = walk(f, self.apply_or(low[c], high[c]))
            else:
                c0, c1 = (low[c], high[c]) if lc == lf else (c, c)
                if c1 == FALSE:
                    found = walk(low[f], c0)
                elif c0 == FALSE:
                    found = walk(high[f], c1)
                else:
                    found = self.node(lf, walk(low[f], c0), walk(high[f], c1))
            memo[key] = found
            return found

        try:
            return walk(u, care)
        except RecursionError:
            return self._deep(walk, u, care)

    # -- queries -----------------------------------------------------------------------------------
    def evaluate(self, u: int, value: Callable[[Hashable], bool]) -> bool:
        """Value of ``u`` when variable ``v`` has ``value(v)``."""
        while u > TRUE:
            u = self.high[u] if value(self.level[u]) else self.low[u]
        return u == TRUE

    def support(self, u: int) -> frozenset:
        """The variables ``u`` depends on."""
        found = self._support.get(u)
        if found is None:
            # one walk over the nodes below u, remembered for u only: a set per node would take
            # memory quadratic in a chain's length (a conjunction of n literals: n^2/2 entries),
            # and a recursion per node would exceed Python's depth on such a chain
            level, low, high = self.level, self.low, self.high
            seen, names, stack = set(), set(), [u]
            while stack:
                w = stack.pop()
                if w <= TRUE or w in seen:
                    continue
                seen.add(w)
                names.add(level[w])
                stack.append(low[w])
                stack.append(high[w])
            found = self._support[u] = frozenset(names)
        return found

    # -- memory ------------------------------------------------------------------------------------
    def collect(self, roots: Iterable[int]) -> int:
        """Free every node no root reaches; return how many were freed.

        Node ids of the reachable nodes do not change, so the caller's handles stay valid;
        every operation cache is emptied (its entries may name freed ids, which get reused).
        """
        level, low, high = self.level, self.low, self.high
        live = bytearray(len(level))
        live[FALSE] = live[TRUE] = 1
        stack = list(roots)
        while stack:
            u = stack.pop()
            if not live[u]:
                live[u] = 1
                stack.append(low[u])
                stack.append(high[u])
        kept = {key: u for key, u in self._unique.items() if live[u]}
        freed = [u for u in self._unique.values() if not live[u]]
        for u in freed:
            level[u], low[u], high[u] = None, FALSE, FALSE
        self._unique = kept
        self._free.extend(freed)
        self._and.clear()
        self._or.clear()
        self._not.clear()
        self._ite.clear()
        self._support = {FALSE: frozenset(), TRUE: frozenset()}
        return len(freed)
