"""Propositional guards on automaton edges, canonical by construction.

A :class:`Guard` is a Boolean function of proposition names, stored as a node of a reduced
ordered binary decision diagram (ROBDD) shared by every guard in the process. Variables are
ordered by name and nodes are hash-consed, so two guards are ``==`` exactly when they are
logically equivalent, comparison is O(1), and no operation enumerates the 2^|AP| labels of the
alphabet (only printing looks at the truth table, and only over the guard's own support).

>>> a, b = Guard.var("a"), Guard.var("b")
>>> (a & b) | (a & ~b) == a
True
>>> str(Guard.parse("!(a | b) | a"))
'a | !b'
>>> (a & ~b).evaluate({"a"}), (a & ~b).satisfying_label()
(True, frozenset({'a'}))

Text syntax (``grammars/guard.lark``): ``true``, ``false``, names ``[A-Za-z_][A-Za-z0-9_]*`` or
double-quoted strings, ``!``/``~``, ``&``/``&&``, ``|``/``||`` and parentheses; ``!`` binds
tightest, then ``&``, then ``|``. ``str(g)`` prints a minimal sum of products over the guard's
support (a single cube or clause directly, a minimum cover (symlearn.logic.two_level) for up to 8 propositions,
a greedy cover by prime implicants computed on the BDD above that) and
``Guard.parse(str(g)) == g`` always holds. A sum of products can be exponentially longer than
the BDD (``!((p0 & q0) | ... | (p11 & q11))`` needs 4096 cubes), so above 8 propositions a
cover needing more than 16 cubes is printed *factored* from the BDD instead: each node
``x ? H : L`` becomes ``x & H``, ``!x & L``, ``x | L``, ``!x | H``, ``L & (!x | H')`` (when H
implies L) or ``L | (x & H')`` (when L implies H), with ``H'`` simplified against the care set
(:meth:`BDD.simplify`), and ``(x & H) | (!x & L)`` otherwise; that guard prints as
``(!p0 | !q0) & ... & (!p11 | !q11)``. A printed form longer than 200,000 characters raises
:class:`LimitExceededError` (:meth:`Guard.summary` describes such a guard in one line).

Memory: the shared table keeps the nodes that live guards reach. Nodes of guards that no longer
exist are freed by :func:`collect`, which runs by itself once the table has doubled since the
last collection (from 2^17 nodes on), so a long run that builds and drops automata does not
grow without bound. The table is not thread-safe: build guards from one thread at a time.
"""

from __future__ import annotations

import re
import sys
import weakref
from collections.abc import Iterable, Iterator, Mapping, Sequence
from functools import lru_cache
from math import isqrt
from typing import AbstractSet

from symlearn.errors import LimitExceededError, ParseError
from symlearn.input_limits import limit as _limit
from symlearn.logic.bdd import BDD
from symlearn.logic.two_level import cube_literals, minimum_cover

__all__ = ["Guard", "GuardParseError", "from_bdd", "collect", "node_count"]

_FALSE, _TRUE = 0, 1
# Every guard lives in this one manager (variables: proposition names), so guards of different
# automata combine and compare without conversion. _var/_low/_high alias its node lists (changed
# only in place) for the hot loops below.
# The table is bounded (SYMLEARN_MAX_BDD_NODES, see symlearn.input_limits): a guard whose BDD
# explodes under the name order, e.g. (a0 & b0) | ... | (a40 & b40), stops with a clear error.
_MANAGER = BDD(max_nodes=_limit("SYMLEARN_MAX_BDD_NODES"),
               limit_hint="guards over many propositions can need exponentially many BDD nodes in name "
                          "order; raise SYMLEARN_MAX_BDD_NODES (0: no limit) or use fewer propositions")
_var, _low, _high = _MANAGER.level, _MANAGER.low, _MANAGER.high
_and = _MANAGER.apply_and
_or = _MANAGER.apply_or
_not = _MANAGER.negate
_make = _MANAGER.node
_support = _MANAGER.support
# node -> weak reference to the one Guard object holding it: the live guards are the roots from
# which collect() keeps nodes, and one object per node lets an operation whose result already
# has a guard return that object instead of allocating another.
_guards: dict[int, weakref.ref] = {}
_text_cache: dict[int, str] = {}
_label_cache: dict[int, frozenset[str]] = {}
_key_cache: dict[int, tuple] = {}
_label_key_cache: dict[int, tuple] = {}
_cost_cache: dict[int, float] = {_FALSE: float("inf"), _TRUE: 0}  # see Guard.satisfying_label

# Collect when the node lists pass this length, then when they pass twice the nodes left live
# (or their old length: freed ids are reused first). Either way at least half the lists' length
# in new nodes is built between two collections, so their cost (linear in the table) is
# amortised O(1) per node. benchmarks/bdd_engines.py measures table size and time with and
# without collection (docs/BENCHMARKS.md).
_COLLECT_FROM = 1 << 17
_collect_at = _COLLECT_FROM

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_KEYWORDS = {"true", "false"}
_SOP_LIMIT = 8  # beyond this many propositions, print BDD paths instead of a minimal cover
_CUBE_BUDGET = 16  # beyond 8 propositions, a cover needing more cubes is printed factored
_TEXT_LIMIT = 200_000  # characters; a guard whose printed form would be longer is refused
# node visits one printing may spend on prime covers (about a second): each is tried only when
# its bound (cubes x literals x nodes) fits in what is left, else that node prints factored. A
# guard over n propositions asked a prime cover at every node of its factored form, n^3 visits
# (100 propositions: 18 s, 200: minutes).
_PRIME_WORK = 1_000_000
_SOP_NODES = 256  # a diagram over at most 8 propositions has fewer nodes than this


class GuardParseError(ParseError):
    """Guard text that does not follow ``grammars/guard.lark``."""


def _deep(operation):
    """``operation`` (a Guard method with a recursion of its own over the diagram: renaming,
    counting, labels, cubes), given room to recurse once per proposition level when it needs it;
    the BDD's own operations do the same for themselves (:meth:`BDD.apply_and`). A guard over more
    propositions than Python's recursion limit (a chain of 1,000 names) would otherwise end in a
    RecursionError. Python 3.11 keeps such Python-to-Python recursion off the C stack, so the call
    is repeated with a limit of a few frames per variable the shared manager holds; the first
    attempt leaves nothing half-done (memo entries are written for finished results only)."""
    import functools

    @functools.wraps(operation)
    def run(*args, **kwargs):
        try:
            return operation(*args, **kwargs)
        except RecursionError:
            pass
        depth = sys.getrecursionlimit()
        levels = len({v for v in _var if v is not None})
        sys.setrecursionlimit(max(depth, 4 * levels + 1000))
        try:
            return operation(*args, **kwargs)
        except RecursionError:
            raise LimitExceededError(f"a guard operation over {levels:,} propositions recursed too deep",
                                     hint="use fewer propositions in one guard") from None
        finally:
            sys.setrecursionlimit(depth)

    return run


def _wrap(node: int) -> Guard:
    """The Guard of ``node`` (the existing object when one is alive)."""
    ref = _guards.get(node)
    if ref is not None:
        guard = ref()
        if guard is not None:
            return guard
    guard = object.__new__(Guard)
    object.__setattr__(guard, "_node", node)
    _guards[node] = weakref.ref(guard)
    return guard


def _maybe_collect() -> None:
    # Called only at the start of public operations, where every node in use is held by a Guard:
    # internal helpers keep raw node ids in local variables, which collect() cannot see.
    if len(_var) > _collect_at:
        collect()


def collect() -> int:
    """Free the guard nodes no live :class:`Guard` reaches; return how many were freed.

    Runs by itself whenever the table has doubled since the last collection; call it to
    release memory earlier. Live guards keep their identity, equality and hash.
    """
    global _collect_at
    dead = [node for node, ref in _guards.items() if ref() is None]
    for node in dead:
        del _guards[node]
    freed = _MANAGER.collect(_guards)
    _text_cache.clear()
    _label_cache.clear()
    _key_cache.clear()
    _label_key_cache.clear()
    _cost_cache.clear()
    _cost_cache.update({_FALSE: float("inf"), _TRUE: 0})  # freed ids are reused for other functions
    _cover.cache_clear()
    _collect_at = max(_COLLECT_FROM, 2 * len(_MANAGER), len(_var))
    return freed


def node_count() -> int:
    """Nodes in the shared guard table (terminals included)."""
    return len(_MANAGER)


def _cube_node(literals: Mapping[str, bool]) -> int:
    node = _TRUE
    for name in sorted(literals, reverse=True):  # build bottom-up: no apply needed
        node = _make(name, node, _FALSE) if not literals[name] else _make(name, _FALSE, node)
    return node


def _evaluate(u: int, label: AbstractSet[str]) -> bool:
    while u > _TRUE:
        u = _high[u] if _var[u] in label else _low[u]
    return u == _TRUE


def from_bdd(bdd: BDD, nodes: Sequence[int], names: Sequence[str]) -> list[Guard]:
    """The guards of ``nodes`` of another manager whose variable ``i`` is proposition ``names[i]``.

    ``names`` must be sorted (variable order = name order, as in the shared table), so each
    node maps to exactly one guard node; nodes shared between the inputs are converted once.
    """
    if list(names) != sorted(names):
        raise ValueError("from_bdd needs the variables in proposition-name order")
    _maybe_collect()
    memo = {_FALSE: _FALSE, _TRUE: _TRUE}
    level, low, high = bdd.level, bdd.low, bdd.high

    def convert(u: int) -> int:
        found = memo.get(u)
        if found is None:
            found = memo[u] = _make(names[level[u]], convert(low[u]), convert(high[u]))
        return found

    converted = [convert(u) for u in nodes]  # every node is built before any Guard exists
    # Callers sort a DFA state's edges by label_key, which walks each guard once more (in a fresh
    # process about a third of a 257-state translation: Patterns/GFand pb_09, 6,818 edges, issue
    # 27). The keys of the guards not seen before are found here instead, by the recurrence of
    # Guard.satisfying_label (fewest true propositions, the low child on ties) memoised per node
    # of ``bdd``: one step per node for all the guards together. Guards whose key is known
    # already (a translation repeated in one process) cost a lookup.
    keys = _label_key_cache
    missing = [(u, g) for u, g in zip(nodes, converted) if g not in keys]
    if missing:
        best: dict[int, tuple] = {_FALSE: (float("inf"), None), _TRUE: (0, ())}

        def fewest(u: int) -> tuple:
            found = best.get(u)
            if found is None:
                cost_lo, label_lo = fewest(low[u])
                cost_hi, label_hi = fewest(high[u])
                # names are in variable order, so prefixing keeps the label's tuple sorted
                found = best[u] = ((cost_lo, label_lo) if cost_lo <= 1 + cost_hi
                                   else (1 + cost_hi, (names[level[u]],) + label_hi))
            return found

        for u, g in missing:
            cost, label = fewest(u)
            keys[g] = (0, ()) if label is None else (1, cost, label)
    return [_wrap(u) for u in converted]


class Guard:
    """An immutable propositional formula over proposition names; ``==`` is equivalence."""

    __slots__ = ("_node", "__weakref__")

    def __new__(cls, node: int = _TRUE) -> Guard:  # prefer the named constructors
        return _wrap(node)

    def __setattr__(self, name, value):
        raise AttributeError("Guard is immutable")

    # -- construction -----------------------------------------------------------------------
    @staticmethod
    def true() -> Guard:
        return _GUARD_TRUE

    @staticmethod
    def false() -> Guard:
        return _GUARD_FALSE

    @staticmethod
    def var(name: str) -> Guard:
        """The guard true exactly when proposition ``name`` holds."""
        if not isinstance(name, str) or not name:
            raise ValueError(f"a proposition name must be a non-empty string, not {name!r}")
        _maybe_collect()
        return _wrap(_make(name, _FALSE, _TRUE))

    @staticmethod
    def cube(literals: Mapping[str, bool]) -> Guard:
        """Conjunction of literals: ``{"a": True, "b": False}`` is ``a & !b``."""
        _maybe_collect()
        return _wrap(_cube_node(literals))

    @staticmethod
    def label(label: AbstractSet[str], alphabet: Iterable[str]) -> Guard:
        """The guard matching exactly ``label`` among ``alphabet`` (one letter)."""
        return Guard.cube({p: p in label for p in alphabet})

    @staticmethod
    def any_of(guards: Iterable[Guard]) -> Guard:
        guards = [_as_guard(g) for g in guards]  # built first: they may create guards themselves
        _maybe_collect()
        node = _FALSE
        for g in guards:
            node = _or(node, g._node)
        return _wrap(node)

    @staticmethod
    def all_of(guards: Iterable[Guard]) -> Guard:
        guards = [_as_guard(g) for g in guards]
        _maybe_collect()
        node = _TRUE
        for g in guards:
            node = _and(node, g._node)
        return _wrap(node)

    @staticmethod
    def parse(text: str) -> Guard:
        """Read guard text; raises :class:`GuardParseError` with the column of the problem."""
        return _parse_cached(text)

    # -- algebra ----------------------------------------------------------------------------
    def __and__(self, other: Guard) -> Guard:
        _maybe_collect()
        return _wrap(_and(self._node, _as_guard(other)._node))

    def __or__(self, other: Guard) -> Guard:
        _maybe_collect()
        return _wrap(_or(self._node, _as_guard(other)._node))

    def __invert__(self) -> Guard:
        _maybe_collect()
        return _wrap(_not(self._node))

    def __sub__(self, other: Guard) -> Guard:
        """``g - h`` is ``g & ~h``."""
        _maybe_collect()
        return _wrap(_and(self._node, _not(_as_guard(other)._node)))

    def __xor__(self, other: Guard) -> Guard:
        _maybe_collect()
        o = _as_guard(other)._node
        return _wrap(_or(_and(self._node, _not(o)), _and(_not(self._node), o)))

    def implies(self, other: Guard) -> bool:
        """Whether every label satisfying ``self`` satisfies ``other``."""
        return _and(self._node, _not(other._node)) == _FALSE

    def intersects(self, other: Guard) -> bool:
        return _and(self._node, other._node) != _FALSE

    def restrict(self, name: str, value: bool) -> Guard:
        """The cofactor with proposition ``name`` fixed to ``value``."""
        _maybe_collect()
        return _wrap(_MANAGER.restrict(self._node, name, value))

    def exists(self, names: Iterable[str]) -> Guard:
        """Existential quantification: true where some value of ``names`` makes ``self`` true."""
        names = list(names)
        _maybe_collect()
        node = self._node
        for name in names:
            node = _or(_MANAGER.restrict(node, name, False), _MANAGER.restrict(node, name, True))
        return _wrap(node)

    @_deep
    def rename(self, mapping: Mapping[str, str]) -> Guard:
        """Substitute proposition names (the result is re-ordered canonically)."""
        _maybe_collect()
        memo: dict[int, int] = {}

        def walk(u: int) -> int:
            if u <= _TRUE:
                return u
            hit = memo.get(u)
            if hit is None:
                name = _var[u]
                v = _make(mapping.get(name, name), _FALSE, _TRUE)  # type: ignore[arg-type]
                lo, hi = walk(_low[u]), walk(_high[u])
                hit = _or(_and(_not(v), lo), _and(v, hi))
                memo[u] = hit
            return hit

        return _wrap(walk(self._node))

    # -- queries ----------------------------------------------------------------------------
    def evaluate(self, label: AbstractSet[str]) -> bool:
        """Truth value under the label (the set of propositions that are true)."""
        return _evaluate(self._node, label)

    __call__ = evaluate

    @property
    def propositions(self) -> frozenset[str]:
        """The support: propositions the guard actually depends on."""
        return _support(self._node)

    def is_true(self) -> bool:
        return self._node == _TRUE

    def is_false(self) -> bool:
        return self._node == _FALSE

    @_deep
    def satisfying_label(self) -> frozenset[str] | None:
        """A label satisfying the guard with as few true propositions as possible.

        Deterministic: among labels of minimal size, the BDD prefers false for the earlier
        proposition name. ``None`` for the false guard.
        """
        if self._node == _FALSE:
            return None
        cached = _label_cache.get(self._node)
        if cached is not None:
            return cached
        # fewest true propositions below each node: a property of the node alone, so shared by
        # every guard (sorting the edges of a large automaton asks for tens of thousands)
        cost = _cost_cache

        def best(u: int) -> float:
            found = cost.get(u)
            if found is None:
                found = cost[u] = min(best(_low[u]), 1 + best(_high[u]))
            return found

        best(self._node)
        label, u = set(), self._node
        while u > _TRUE:
            if cost[_low[u]] <= 1 + cost[_high[u]]:
                u = _low[u]
            else:
                label.add(_var[u])
                u = _high[u]
        result = frozenset(label)  # type: ignore[arg-type]
        _label_cache[self._node] = result
        return result

    @_deep
    def closest_label(self, label: AbstractSet[str]) -> frozenset[str] | None:
        """A satisfying label that differs from ``label`` in as few propositions as possible.

        Propositions outside the guard's support keep their value in ``label``. ``None`` for
        the false guard.
        """
        if self._node == _FALSE:
            return None
        cost: dict[int, float] = {_FALSE: float("inf"), _TRUE: 0}

        def best(u: int) -> float:
            if u not in cost:
                here = _var[u] in label
                cost[u] = min(best(_low[u]) + here, best(_high[u]) + (not here))
            return cost[u]

        best(self._node)
        result, u = set(label), self._node
        while u > _TRUE:
            here = _var[u] in label
            if cost[_low[u]] + here <= cost[_high[u]] + (not here):
                result.discard(_var[u])
                u = _low[u]
            else:
                result.add(_var[u])  # type: ignore[arg-type]
                u = _high[u]
        return frozenset(result)

    @_deep
    def count(self, alphabet: Iterable[str]) -> int:
        """How many labels over ``alphabet`` (a superset of the support) satisfy the guard."""
        names = sorted(set(alphabet))
        missing = self.propositions - set(names)
        if missing:
            raise ValueError(f"alphabet lacks {sorted(missing)}")
        position = {n: i for i, n in enumerate(names)}
        memo: dict[int, int] = {}

        def models(u: int) -> int:  # over the variables at positions >= level(u)
            if u <= _TRUE:
                return u
            if u not in memo:
                memo[u] = sum(models(c) * 2 ** (_level(c) - position[_var[u]] - 1)  # type: ignore[index]
                              for c in (_low[u], _high[u]))
            return memo[u]

        def _level(u: int) -> int:
            return len(names) if u <= _TRUE else position[_var[u]]  # type: ignore[index]

        return models(self._node) * 2 ** _level(self._node)

    @_deep
    def sample_label(self, alphabet: Iterable[str], rng) -> frozenset[str] | None:
        """A label over ``alphabet`` drawn uniformly among those satisfying the guard."""
        names = sorted(set(alphabet))
        if self._node == _FALSE:
            return None
        label: set[str] = set()
        g = self
        for name in names:
            hi, lo = g.restrict(name, True), g.restrict(name, False)
            rest = [n for n in names if n > name]
            n_hi, n_lo = hi.count(rest), lo.count(rest)
            if rng.random() * (n_hi + n_lo) < n_hi:
                label.add(name)
                g = hi
            else:
                g = lo
        return frozenset(label)

    @_deep
    def cubes(self) -> list[dict[str, bool]]:
        """A sum of products equal to the guard (minimal for small supports); ``[]`` is false.
        It may have exponentially many cubes (``str(g)`` then prints a factored form)."""
        return [dict(c) for c in _cover(self._node)]

    def summary(self) -> str:
        """One line describing the guard without printing it: its text when that is short,
        else the number of propositions and BDD nodes (for displays of huge guards)."""
        try:
            text = str(self)
        except LimitExceededError:
            text = None
        if text is not None and len(text) <= 200:
            return text
        nodes, stack, seen = 0, [self._node], set()
        while stack:
            u = stack.pop()
            if u > _TRUE and u not in seen:
                seen.add(u)
                nodes += 1
                stack += [_low[u], _high[u]]
        size = f"{len(text):,} characters" if text is not None else "too long to print"
        return f"<guard over {len(self.propositions)} propositions, {nodes} BDD nodes; {size}>"

    def to_text(self, *, unicode: bool = False) -> str:
        text = str(self)
        if unicode:
            text = text.replace("!", "¬").replace(" & ", " ∧ ").replace(" | ", " ∨ ")
            text = text.replace("true", "⊤").replace("false", "⊥") if self._node <= _TRUE else text
        return text

    # -- identity ---------------------------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        return isinstance(other, Guard) and other._node == self._node

    def __hash__(self) -> int:
        return hash(("Guard", self._node))

    def __bool__(self) -> bool:
        raise TypeError("a Guard has no truth value; use is_true()/is_false() or evaluate(label)")

    def __reduce__(self):
        return (Guard.parse, (str(self),))

    def __repr__(self) -> str:
        return f"Guard({str(self)!r})"

    def __str__(self) -> str:
        text = _text_cache.get(self._node)
        if text is None:
            # the diagram operations printing uses recurse once per proposition level: room for
            # a guard over 10,000 propositions (F(p1 & ... & p10000)), as translation has
            depth = sys.getrecursionlimit()
            sys.setrecursionlimit(max(depth, 4 * len(_support(self._node)) + 1000))
            try:
                text = _text(self._node)
            except RecursionError:
                raise LimitExceededError(
                    f"guard over {len(self.propositions)} propositions is too deep to print",
                    hint="guards over hundreds of propositions exceed the printer's recursion depth") from None
            finally:
                sys.setrecursionlimit(depth)
            _text_cache[self._node] = text
        return text

    @property
    def sort_key(self) -> tuple:
        """A canonical order key (equal for equal guards; distinct for disjoint ones), cheap to compute."""
        key = _key_cache.get(self._node)
        if key is None:
            key = self.label_key
            if key[0]:
                key = key + (len(self.propositions),)
            _key_cache[self._node] = key
        return key

    @property
    def label_key(self) -> tuple:
        """:attr:`sort_key` without its last element (the support's size): it orders *pairwise
        disjoint* guards (a DFA state's edges) exactly as ``sort_key`` does, since disjoint guards
        have distinct satisfying labels, and it needs no walk for the support (listing the edges
        of a 66-state DFA spent half its time there, Random/Syft 055)."""
        key = _label_key_cache.get(self._node)
        if key is None:
            label = self.satisfying_label()
            key = _label_key_cache[self._node] = (0, ()) if label is None else (1, len(label), tuple(sorted(label)))
        return key


_GUARD_TRUE = _wrap(_TRUE)
_GUARD_FALSE = _wrap(_FALSE)


def _as_guard(value) -> Guard:
    if isinstance(value, Guard):
        return value
    if isinstance(value, bool):
        return _GUARD_TRUE if value else _GUARD_FALSE
    raise TypeError(f"expected a Guard, got {type(value).__name__}")


# -- printing ---------------------------------------------------------------------------------
def _paths(u: int, prefix: tuple[tuple[str, bool], ...] = ()) -> Iterator[tuple[tuple[str, bool], ...]]:
    if u == _TRUE:
        yield prefix
    elif u > _TRUE:
        yield from _paths(_low[u], prefix + ((_var[u], False),))  # type: ignore[operator]
        yield from _paths(_high[u], prefix + ((_var[u], True),))  # type: ignore[operator]


def _single_path(u: int) -> list[tuple[str, bool]] | None:
    """The literals of ``u`` when it is one cube (every node has a false child), else None."""
    literals = []
    while u > _TRUE:
        if _low[u] == _FALSE:
            literals.append((_var[u], True))
            u = _high[u]
        elif _high[u] == _FALSE:
            literals.append((_var[u], False))
            u = _low[u]
        else:
            return None
    return literals if u == _TRUE else None


def _sorted_cover(cubes) -> tuple[tuple[tuple[str, bool], ...], ...]:
    cubes = [tuple(sorted(c, key=lambda lit: _natural(lit[0]))) for c in cubes]
    return tuple(sorted(cubes, key=lambda c: (len(c), [(_natural(n), not v) for n, v in c])))


@lru_cache(maxsize=4096)
def _cover(u: int, budget: int | None = None) -> tuple[tuple[tuple[str, bool], ...], ...] | None:
    """A sum of products equal to ``u`` (minimal up to 8 propositions); None when ``budget`` is
    given and a cover above 8 propositions needs more cubes than that."""
    if u == _FALSE:
        return ()
    if u == _TRUE:
        return ((),)
    cube = _single_path(u)
    if cube is not None:  # one cube: its own minimal cover
        return _sorted_cover([cube])
    clause = _single_path(_not(u))
    if clause is not None:  # a clause: one literal per cube
        return _sorted_cover([((name, not value),) for name, value in clause])
    support = sorted(_support(u))
    if len(support) <= _SOP_LIMIT:
        cubes = _minimal_cover(u, support)
    else:
        cubes = _prime_cover(u, budget)
        if cubes is None:
            return None
    return _sorted_cover(cubes)


def _text(u: int) -> str:
    """``str`` of the guard at node ``u``: a (minimal) sum of products, or factored when that is big."""
    support = _support(u)
    if sum(len(_name_text(name)) for name in support) + 3 * (len(support) - 1) > _TEXT_LIMIT:
        raise _too_long(u)  # every proposition is printed at least once: refused before any work
    work = [_PRIME_WORK]
    cover = _affordable_cover(u, work)
    if cover is not None:
        text = _format(cover)
    else:
        text = _factored(u, {}, work)[0]
    if len(text) > _TEXT_LIMIT:
        raise _too_long(u)
    return text


def _too_long(u: int) -> LimitExceededError:
    return LimitExceededError(
        f"guard over {len(_support(u))} propositions is longer than {_TEXT_LIMIT:,} characters when printed",
        hint="split the formula or use fewer propositions; Guard.summary() describes it")


_ATOM_TEXT, _AND_TEXT, _OR_TEXT = 0, 1, 2


def _join(op: int, parts: list[tuple]) -> tuple:
    """``parts`` joined by ``&`` (op _AND_TEXT) or ``|``: operands of the same operator are
    flattened and sorted (names in natural order), a disjunction inside a conjunction (or the
    reverse, for readability) is parenthesised. A part is ``(text, kind, operands)``."""
    operands: list[str] = []
    for text, kind, inner in parts:
        if kind == op:
            operands.extend(inner)
        else:
            operands.append(text if kind == _ATOM_TEXT else f"({text})")
    operands.sort(key=lambda t: (t.startswith("("), _natural(t.lstrip("(!"))))
    return (" & " if op == _AND_TEXT else " | ").join(operands), op, tuple(operands)


def _piece(text: str, kind: int) -> tuple:
    """A printed sum of products or cube as a part for :func:`_join`."""
    if kind == _ATOM_TEXT:
        return text, kind, (text,)
    operands = [t if t.startswith("(") or " " not in t else f"({t})"
                for t in (text.split(" & ") if kind == _AND_TEXT else text.split(" | "))]
    return text, kind, tuple(operands)


def _affordable_cover(u: int, work: list[int]) -> tuple | None:
    """``_cover(u, _CUBE_BUDGET)`` when its prime-cover bound (cubes x literals x nodes) fits in
    ``work[0]``, which it then spends; else None (print factored). A diagram of at most
    :data:`_SOP_NODES` nodes is always affordable: over at most :data:`_SOP_LIMIT` propositions
    it takes a truth table of at most 256 rows, over more its bound is checked. The node count
    is walked only up to the limit, so a node of a long chain costs a bounded walk, not one
    over the chain below it."""
    size = _size_at_most(u, max(_SOP_NODES, isqrt(work[0] // _CUBE_BUDGET)))
    if size is None:
        return None
    n = len(_support(u))
    if n > _SOP_LIMIT:
        cost = size * n * _CUBE_BUDGET
        if cost > work[0]:
            return None
        work[0] -= cost
    return _cover(u, _CUBE_BUDGET)


def _size_at_most(u: int, limit: int) -> int | None:
    """The number of nodes below ``u``, or None when it passes ``limit`` (the walk stops there)."""
    seen, stack = set(), [u]
    while stack:
        w = stack.pop()
        if w <= _TRUE or w in seen:
            continue
        seen.add(w)
        if len(seen) > limit:
            return None
        stack.append(_low[w])
        stack.append(_high[w])
    return len(seen)


def _factored(u: int, memo: dict[int, tuple[str, int]] | None = None, work: list[int] | None = None) -> tuple[str, int]:
    """A factored form of ``u`` read off the BDD (see the module docstring), with its top operator."""
    if memo is None:
        memo = {}
    if work is None:
        work = [_PRIME_WORK]
    found = memo.get(u)
    if found is not None:
        return found
    if u <= _TRUE:
        return _piece("true" if u == _TRUE else "false", _ATOM_TEXT)
    cover = _affordable_cover(u, work)
    sop = None
    if cover is not None:
        text = _format(cover)
        sop = _piece(text, _OR_TEXT if len(cover) > 1 else _AND_TEXT if " & " in text else _ATOM_TEXT)
    run = None if cover is not None else _run(u)
    if cover is not None and len(cover) <= 1:  # a cube prints best as itself
        result = sop
    elif run is not None:
        op, literals, rest, shared = run
        tail = [] if rest is None else [_factored(rest, memo, work)]
        result = _join(op, [_piece(text, _ATOM_TEXT) for text in literals] + tail)
        if shared is not None:  # the run shares one child: shared & (x0 | x1 ...) or shared | (!x0 & ...)
            result = _join(_AND_TEXT if op == _OR_TEXT else _OR_TEXT, [_factored(shared, memo, work), result])
    else:
        name, low, high = _var[u], _low[u], _high[u]
        pos, neg = _piece(_name_text(name), _ATOM_TEXT), _piece("!" + _name_text(name), _ATOM_TEXT)
        if low == _FALSE:
            result = _join(_AND_TEXT, [pos, _factored(high, memo, work)])
        elif high == _FALSE:
            result = _join(_AND_TEXT, [neg, _factored(low, memo, work)])
        elif high == _TRUE:
            result = _join(_OR_TEXT, [pos, _factored(low, memo, work)])
        elif low == _TRUE:
            result = _join(_OR_TEXT, [neg, _factored(high, memo, work)])
        elif _and(high, _not(low)) == _FALSE:  # high implies low: u = low & (!x | high')
            rest = _MANAGER.simplify(high, low)
            result = _join(_AND_TEXT, [_factored(low, memo, work), _join(_OR_TEXT, [neg, _factored(rest, memo, work)])])
        elif _and(low, _not(high)) == _FALSE:  # low implies high: u = low | (x & high')
            rest = _MANAGER.simplify(high, _not(low))
            result = _join(_OR_TEXT, [_factored(low, memo, work), _join(_AND_TEXT, [pos, _factored(rest, memo, work)])])
        else:
            result = _join(_OR_TEXT, [_join(_AND_TEXT, [pos, _factored(high, memo, work)]),
                                      _join(_AND_TEXT, [neg, _factored(low, memo, work)])])
        if sop is not None and len(sop[0]) <= len(result[0]):
            result = sop
    if len(result[0]) > _TEXT_LIMIT:
        raise _too_long(u)
    memo[u] = result
    return result


#: a run of at least this many nodes of one shape prints in one piece (:func:`_run`)
_RUN_MIN = 8


def _run(u: int) -> tuple[int, list[str], int | None, int | None] | None:
    """``(op, literals, rest, shared)`` when ``u`` heads a run of at least :data:`_RUN_MIN`
    nodes of one shape, so that the run prints as one conjunction or disjunction instead of one
    nesting per node -- the factored text of a long chain rebuilt at every level is quadratic in
    its length (a TLSF file with thousands of assumptions gives guards over thousands of inputs):

    * every node has a FALSE child: ``l0 & l1 & ... & rest`` (``op`` AND; the literal is the
      variable on the side that is not FALSE);
    * every node has a TRUE child: ``l0 | l1 | ... | rest`` (``op`` OR);
    * every node has the same node ``H`` as its high child, the low child continues, and the run
      ends in FALSE or TRUE: ``H & (x0 | x1 | ...)``, or ``H | (!x0 & !x1 & ...)``; likewise with
      ``H`` as every low child (``H & (!x0 | ...)``, ``H | (x0 & ...)``) -- ``shared`` is ``H``.

    ``rest`` is the node the run ends in (None when it ends in the run's neutral terminal). None
    when ``u`` heads no such run."""
    def terminal_run(w: int) -> tuple[int, list[str], int | None] | None:
        first = _low[w] == _FALSE or _high[w] == _FALSE
        op = _AND_TEXT if first else _OR_TEXT
        absorbing, neutral = (_FALSE, _TRUE) if op == _AND_TEXT else (_TRUE, _FALSE)
        literals = []
        while w > _TRUE and (_low[w] == absorbing or _high[w] == absorbing):
            name = _name_text(_var[w])
            # AND: the literal is the side that is not FALSE; OR: the side that is TRUE
            positive = (_low[w] == absorbing) if op == _AND_TEXT else (_high[w] == absorbing)
            literals.append(name if positive else "!" + name)
            w = _high[w] if _low[w] == absorbing else _low[w]
        if len(literals) < _RUN_MIN:
            return None
        return op, literals, (None if w == neutral else w)

    if _low[u] in (_FALSE, _TRUE) or _high[u] in (_FALSE, _TRUE):
        found = terminal_run(u)
        return None if found is None else (*found, None)
    for side in ("high", "low"):
        shared = _high[u] if side == "high" else _low[u]
        w, names = u, []
        while w > _TRUE and (_high[w] if side == "high" else _low[w]) == shared:
            names.append(_name_text(_var[w]))
            w = _low[w] if side == "high" else _high[w]
        if len(names) >= _RUN_MIN and w in (_FALSE, _TRUE):
            # ite(x, H, next): ends in FALSE -> H & (x0 | ...); in TRUE -> H | (!x0 & ...)
            positive = side == "high"
            if w == _FALSE:
                return _OR_TEXT, [n if positive else "!" + n for n in names], None, shared
            return _AND_TEXT, ["!" + n if positive else n for n in names], None, shared
    return None


@lru_cache(maxsize=65536)
def _natural(name: str) -> tuple:
    """Sort key reading digit runs as numbers, so p2 prints before p10."""
    return tuple(int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name))


def _cube_inside(cube: Mapping[str, bool], u: int) -> bool:
    """Whether every label the cube allows satisfies ``u``: no path to false agrees with the
    cube (a walk over ``u``'s nodes; nothing is built in the table). The printer calls it once
    per literal of every prime implicant it grows, so the loop keeps everything local."""
    var, low, high, get = _var, _low, _high, cube.get
    stack, seen = [u], set()
    pop, push, add = stack.pop, stack.append, seen.add
    while stack:
        w = pop()
        if w == _TRUE or w in seen:
            continue
        if w == _FALSE:
            return False
        add(w)
        value = get(var[w])
        if value is None:
            push(low[w])
            push(high[w])
        elif value:
            push(high[w])
        else:
            push(low[w])
    return True


def _prime_cover(u: int, budget: int | None = None) -> list[tuple[tuple[str, bool], ...]] | None:
    """An irredundant cover by prime implicants, found on the BDD (no truth table).

    Take a path to true of the still-uncovered part, drop every literal whose removal keeps
    the cube inside ``u`` (so the cube becomes a prime implicant), remove what it covers, and
    repeat. Not always minimum, but every cube is prime and each covers something new.
    """
    cubes, remaining = [], u
    while remaining != _FALSE:
        if budget is not None and len(cubes) >= budget:
            return None
        cube = dict(next(_paths(remaining)))
        for name in sorted(cube):
            value = cube.pop(name)
            if not _cube_inside(cube, u):
                cube[name] = value  # needed: without it the cube leaves u
        cubes.append(tuple(sorted(cube.items())))
        remaining = _and(remaining, _not(_cube_node(cube)))
    return cubes


def _minimal_cover(u: int, support: list[str]) -> list[tuple[tuple[str, bool], ...]]:
    """A minimum sum of products of ``u`` (``support``: its at most 8 variables), by
    :mod:`~symlearn.logic.two_level` on the truth table."""
    n = len(support)
    return [tuple(sorted((support[i], value) for i, value in cube_literals(cube, n)))
            for cube in minimum_cover(_minterms(u, support), n)]


def _minterms(u: int, support: list[str]) -> list[int]:
    """The labels over ``support`` satisfying ``u`` as bit masks (the first variable the most
    significant bit): its paths to true, each with its untested variables expanded -- one walk of
    the diagram instead of one evaluation per label."""
    n = len(support)
    position = {name: n - 1 - i for i, name in enumerate(support)}  # bit of each variable
    found: list[int] = []
    stack = [(u, 0, 0)]  # node, values set so far, variables tested so far
    while stack:
        w, value, tested = stack.pop()
        if w == _FALSE:
            continue
        if w == _TRUE:
            free = ((1 << n) - 1) & ~tested
            sub = free
            while True:  # every assignment of the untested variables
                found.append(value | sub)
                if not sub:
                    break
                sub = (sub - 1) & free
            continue
        bit = 1 << position[_var[w]]
        stack.append((_low[w], value, tested | bit))
        stack.append((_high[w], value | bit, tested | bit))
    return sorted(found)


def _name_text(name: str) -> str:
    if _IDENTIFIER.match(name) and name.lower() not in _KEYWORDS:
        return name
    return '"' + name.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _format(cubes: tuple[tuple[tuple[str, bool], ...], ...]) -> str:
    if not cubes:
        return "false"
    if cubes == ((),):
        return "true"
    terms = [" & ".join(_name_text(n) if v else "!" + _name_text(n) for n, v in cube) for cube in cubes]
    if len(terms) == 1:
        return terms[0]
    return " | ".join(f"({t})" if " & " in t else t for t in terms)


# -- parsing ----------------------------------------------------------------------------------
@lru_cache(maxsize=1)
def _parser():
    from lark import Lark

    from symlearn.resources import grammar_text

    return Lark(grammar_text("guard"), parser="lalr", maybe_placeholders=False)


_SPELLINGS = {"and": "&", "or": "|", "not": "!", "&&&": "&", "^": "xor is not supported; write (a & !b) | (!a & b)"}


@lru_cache(maxsize=65536)
def _parse_cached(text: str) -> Guard:
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    if not isinstance(text, str):
        raise GuardParseError(f"a guard must be text, not {type(text).__name__}")
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as exc:
        column = getattr(exc, "column", None)
        if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
            what, column = "unexpected end of guard", len(text) + 1
        elif isinstance(exc, UnexpectedToken):
            what = f"unexpected {exc.token.value!r}"
        elif isinstance(exc, UnexpectedCharacters):
            what = f"unexpected character {text[exc.pos_in_stream]!r}"
        else:  # pragma: no cover - lark has no other kinds today
            what = "syntax error"
        hint = "guards use true, false, names, ! & | and parentheses"
        if isinstance(exc, UnexpectedCharacters) and not text[exc.pos_in_stream].isascii():
            # a proposition such as "ü" or "café": plain names are ASCII identifiers, others are quoted
            name = re.match(r"[^\s!&|()\"]+", text[exc.pos_in_stream:])
            hint = (f"quote a name that is not a plain identifier: \"{name.group() if name else text[exc.pos_in_stream]}\" "
                    "(guards use true, false, names, ! & | and parentheses)")
        for word, spelling in _SPELLINGS.items():
            if re.search(rf"(?<![A-Za-z0-9_]){re.escape(word)}(?![A-Za-z0-9_])", text, re.I) and word.isalpha():
                hint = f"write {spelling!r} instead of {word!r}"
        raise GuardParseError(f"{what} in guard {text!r}", line=1, column=column, hint=hint) from None
    try:
        return _build(tree)
    except RecursionError:
        raise LimitExceededError(f"guard of {len(text)} characters is too large to build",
                                 hint="guards over hundreds of propositions exceed the BDD's recursion depth") from None


def _build(tree) -> Guard:
    """Evaluate a parse tree bottom-up with an explicit stack (long guards nest deeply)."""
    from lark import Token

    def operands(node) -> list:
        return [c for c in node.children if not isinstance(c, Token) or c.type in ("NAME", "QUOTED")]

    def same_kind_leaves(node) -> list:
        """The operands of the maximal run of ``node``'s operator below it (``a & b & c`` parses
        as ``(a & b) & c``)."""
        leaves, todo = [], [node]
        while todo:
            for kid in reversed(operands(todo.pop())):
                if not isinstance(kid, Token) and kid.data == node.data:
                    todo.append(kid)
                else:
                    leaves.append(kid)
        return leaves

    values: dict[int, Guard] = {}
    stack: list = [(tree, None)]
    while stack:
        node, expanded = stack.pop()
        kind = node.data
        if kind in ("and_", "or_"):
            if expanded is None:
                leaves = same_kind_leaves(node)
                stack.append((node, leaves))
                stack.extend((leaf, None) for leaf in leaves)
                continue
            # combined pairwise, not left to right: a chain of n names built in order appends
            # at the bottom of the diagram every time (n^2 node visits); balanced, n log n
            parts = [values.pop(id(leaf)) for leaf in expanded]
            while len(parts) > 1:
                pairs = [(parts[i] & parts[i + 1]) if kind == "and_" else (parts[i] | parts[i + 1])
                         for i in range(0, len(parts) - 1, 2)]
                parts = pairs + parts[len(pairs) * 2:]
            values[id(node)] = parts[0]
            continue
        kids = operands(node)
        if kind == "not_" and expanded is None:
            stack.append((node, True))
            stack.extend((kid, None) for kid in kids)
            continue
        if kind == "true":
            value = _GUARD_TRUE
        elif kind == "false":
            value = _GUARD_FALSE
        elif kind == "name":
            value = Guard.var(str(kids[0]))
        elif kind == "quoted":
            value = Guard.var(re.sub(r"\\(.)", r"\1", str(kids[0])[1:-1]))
        elif kind == "not_":
            value = ~values.pop(id(kids[0]))
        else:  # pragma: no cover - the grammar has no other constructs
            raise GuardParseError(f"unknown guard construct {kind!r}")
        values[id(node)] = value
    return values[id(tree)]
