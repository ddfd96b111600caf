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
support (Quine-McCluskey via sympy for up to 8 propositions, a greedy cover by prime implicants
computed on the BDD above that) and ``Guard.parse(str(g)) == g`` always holds.

The node table only grows; it holds one entry per distinct sub-function ever built, which
stays small for automaton guards.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator, Mapping
from typing import AbstractSet
from functools import lru_cache

from symlearn.errors import LimitExceededError, ParseError

__all__ = ["Guard", "GuardParseError"]

_FALSE, _TRUE = 0, 1
# _var[n], _low[n], _high[n] describe node n >= 2; terminals have var None.
_var: list[str | None] = [None, None]
_low: list[int] = [0, 1]
_high: list[int] = [0, 1]
_unique: dict[tuple[str, int, int], int] = {}
_and_cache: dict[tuple[int, int], int] = {}
_or_cache: dict[tuple[int, int], int] = {}
_not_cache: dict[int, int] = {}
_support_cache: dict[int, frozenset[str]] = {_FALSE: frozenset(), _TRUE: frozenset()}
_text_cache: dict[int, str] = {}
_label_cache: dict[int, frozenset[str]] = {}

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_KEYWORDS = {"true", "false"}
_SOP_LIMIT = 8  # beyond this many propositions, print BDD paths instead of a minimal cover


class GuardParseError(ParseError):
    """Guard text that does not follow ``grammars/guard.lark``."""


def _make(var: str, low: int, high: int) -> int:
    if low == high:
        return low
    key = (var, low, high)
    node = _unique.get(key)
    if node is None:
        node = len(_var)
        _var.append(var)
        _low.append(low)
        _high.append(high)
        _unique[key] = node
    return node


def _top(u: int, v: int) -> str:
    a, b = _var[u], _var[v]
    if a is None:
        return b  # type: ignore[return-value]
    if b is None or a <= b:
        return a
    return b


def _cofactors(u: int, var: str) -> tuple[int, int]:
    if _var[u] == var:
        return _low[u], _high[u]
    return u, u


def _apply(u: int, v: int, absorbing: int, cache: dict[tuple[int, int], int]) -> int:
    """``u & v`` (``absorbing`` false) or ``u | v`` (``absorbing`` true), Shannon expansion."""
    if u == absorbing or v == absorbing:
        return absorbing
    if u == 1 - absorbing:  # the neutral constant
        return v
    if v == 1 - absorbing or u == v:
        return u
    key = (u, v) if u < v else (v, u)
    hit = cache.get(key)
    if hit is not None:
        return hit
    var = _top(u, v)
    u0, u1 = _cofactors(u, var)
    v0, v1 = _cofactors(v, var)
    result = _make(var, _apply(u0, v0, absorbing, cache), _apply(u1, v1, absorbing, cache))
    cache[key] = result
    return result


def _and(u: int, v: int) -> int:
    return _apply(u, v, _FALSE, _and_cache)


def _or(u: int, v: int) -> int:
    return _apply(u, v, _TRUE, _or_cache)


def _not(u: int) -> int:
    if u <= _TRUE:
        return 1 - u
    hit = _not_cache.get(u)
    if hit is None:
        hit = _make(_var[u], _not(_low[u]), _not(_high[u]))  # type: ignore[arg-type]
        _not_cache[u] = hit
        _not_cache[hit] = u
    return hit


def _support(u: int) -> frozenset[str]:
    hit = _support_cache.get(u)
    if hit is None:
        hit = _support(_low[u]) | _support(_high[u]) | {_var[u]}  # type: ignore[operator]
        _support_cache[u] = hit
    return hit


def _restrict(u: int, var: str, value: bool) -> int:
    if u <= _TRUE:
        return u
    name = _var[u]
    if name == var:
        return _high[u] if value else _low[u]
    if name > var:  # type: ignore[operator]
        return u  # var cannot occur below a later variable
    return _make(name, _restrict(_low[u], var, value), _restrict(_high[u], var, value))  # type: ignore[arg-type]


class Guard:
    """An immutable propositional formula over proposition names; ``==`` is equivalence."""

    __slots__ = ("_node",)

    def __init__(self, node: int = _TRUE) -> None:  # prefer the named constructors
        object.__setattr__(self, "_node", node)

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
        return Guard(_make(name, _FALSE, _TRUE))

    @staticmethod
    def cube(literals: Mapping[str, bool]) -> Guard:
        """Conjunction of literals: ``{"a": True, "b": False}`` is ``a & !b``."""
        node = _TRUE
        for name in sorted(literals, reverse=True):  # build bottom-up: no apply needed
            node = _make(name, node, _FALSE) if not literals[name] else _make(name, _FALSE, node)
        return Guard(node)

    @staticmethod
    def label(label: AbstractSet[str], alphabet: Iterable[str]) -> Guard:
        """The guard matching exactly ``label`` among ``alphabet`` (one letter)."""
        return Guard.cube({p: p in label for p in alphabet})

    @staticmethod
    def any_of(guards: Iterable[Guard]) -> Guard:
        node = _FALSE
        for g in guards:
            node = _or(node, g._node)
        return Guard(node)

    @staticmethod
    def all_of(guards: Iterable[Guard]) -> Guard:
        node = _TRUE
        for g in guards:
            node = _and(node, g._node)
        return Guard(node)

    @staticmethod
    def parse(text: str) -> Guard:
        """Read guard text; raises :class:`GuardParseError` with the column of the problem."""
        return _parse_cached(text)

    # -- algebra ----------------------------------------------------------------------------
    def __and__(self, other: Guard) -> Guard:
        return Guard(_and(self._node, _as_guard(other)._node))

    def __or__(self, other: Guard) -> Guard:
        return Guard(_or(self._node, _as_guard(other)._node))

    def __invert__(self) -> Guard:
        return Guard(_not(self._node))

    def __sub__(self, other: Guard) -> Guard:
        """``g - h`` is ``g & ~h``."""
        return Guard(_and(self._node, _not(_as_guard(other)._node)))

    def __xor__(self, other: Guard) -> Guard:
        o = _as_guard(other)._node
        return Guard(_or(_and(self._node, _not(o)), _and(_not(self._node), o)))

    def implies(self, other: Guard) -> bool:
        """Whether every label satisfying ``self`` satisfies ``other``."""
        return _and(self._node, _not(other._node)) == _FALSE

    def intersects(self, other: Guard) -> bool:
        return _and(self._node, other._node) != _FALSE

    def restrict(self, name: str, value: bool) -> Guard:
        """The cofactor with proposition ``name`` fixed to ``value``."""
        return Guard(_restrict(self._node, name, value))

    def exists(self, names: Iterable[str]) -> Guard:
        """Existential quantification: true where some value of ``names`` makes ``self`` true."""
        node = self._node
        for name in names:
            node = _or(_restrict(node, name, False), _restrict(node, name, True))
        return Guard(node)

    def rename(self, mapping: Mapping[str, str]) -> Guard:
        """Substitute proposition names (the result is re-ordered canonically)."""
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

        return Guard(walk(self._node))

    # -- queries ----------------------------------------------------------------------------
    def evaluate(self, label: AbstractSet[str]) -> bool:
        """Truth value under the label (the set of propositions that are true)."""
        u = self._node
        while u > _TRUE:
            u = _high[u] if _var[u] in label else _low[u]
        return u == _TRUE

    __call__ = evaluate

    @property
    def propositions(self) -> frozenset[str]:
        """The support: propositions the guard actually depends on."""
        return _support(self._node)

    def is_true(self) -> bool:
        return self._node == _TRUE

    def is_false(self) -> bool:
        return self._node == _FALSE

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
        cost: dict[int, float] = {_FALSE: float("inf"), _TRUE: 0}

        def best(u: int) -> float:
            if u not in cost:
                cost[u] = min(best(_low[u]), 1 + best(_high[u]))
            return cost[u]

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

    def cubes(self) -> list[dict[str, bool]]:
        """A sum of products equal to the guard (minimal for small supports); ``[]`` is false."""
        return [dict(c) for c in _cover(self._node)]

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
            text = _format(_cover(self._node))
            _text_cache[self._node] = text
        return text

    @property
    def sort_key(self) -> tuple:
        """A canonical total-order key (equal for equal guards), cheap to compute."""
        label = self.satisfying_label()
        return (0, ()) if label is None else (1, len(label), tuple(sorted(label)), len(self.propositions))


_GUARD_TRUE = Guard(_TRUE)
_GUARD_FALSE = Guard(_FALSE)


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


@lru_cache(maxsize=4096)
def _cover(u: int) -> tuple[tuple[tuple[str, bool], ...], ...]:
    if u == _FALSE:
        return ()
    if u == _TRUE:
        return ((),)
    support = sorted(_support(u))
    if len(support) <= _SOP_LIMIT:
        cubes = _minimal_cover(u, support)
    else:
        cubes = _prime_cover(u)
    cubes = [tuple(sorted(c, key=lambda lit: _natural(lit[0]))) for c in cubes]
    return tuple(sorted(cubes, key=lambda c: (len(c), [(_natural(n), not v) for n, v in c])))


def _natural(name: str) -> tuple:
    """Sort key reading digit runs as numbers, so p2 prints before p10."""
    return tuple(int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name))


def _prime_cover(u: int) -> list[tuple[tuple[str, bool], ...]]:
    """An irredundant cover by prime implicants, found on the BDD (no truth table).

    Take a path to true of the still-uncovered part, drop every literal whose removal keeps
    the cube inside ``u`` (so the cube becomes a prime implicant), remove what it covers, and
    repeat. Not always minimum, but every cube is prime and each covers something new.
    """
    cubes, remaining = [], u
    while remaining != _FALSE:
        cube = dict(next(_paths(remaining)))
        for name in sorted(cube):
            value = cube.pop(name)
            if _and(Guard.cube(cube)._node, _not(u)) != _FALSE:
                cube[name] = value  # needed: without it the cube leaves u
        cubes.append(tuple(sorted(cube.items())))
        remaining = _and(remaining, _not(Guard.cube(cube)._node))
    return cubes


def _minimal_cover(u: int, support: list[str]) -> list[tuple[tuple[str, bool], ...]]:
    from sympy import Symbol
    from sympy.logic import SOPform
    from sympy.logic.boolalg import And, Not, Or

    minterms = []
    for bits in range(2 ** len(support)):
        values = [(bits >> (len(support) - 1 - i)) & 1 for i in range(len(support))]
        label = {name for name, bit in zip(support, values) if bit}
        if Guard(u).evaluate(label):
            minterms.append(values)
    symbols = [Symbol(f"v{i}") for i in range(len(support))]
    expr = SOPform(symbols, minterms)
    terms = expr.args if isinstance(expr, Or) else (expr,)
    cubes = []
    for term in terms:
        literals = term.args if isinstance(term, And) else (term,)
        cube = []
        for lit in literals:
            negated = isinstance(lit, Not)
            sym = lit.args[0] if negated else lit
            cube.append((support[int(sym.name[1:])], not negated))
        cubes.append(tuple(sorted(cube)))
    return cubes


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

    values: dict[int, Guard] = {}
    stack = [(tree, False)]
    while stack:
        node, expanded = stack.pop()
        kind = node.data
        kids = operands(node)
        if kind in ("not_", "and_", "or_") and not expanded:
            stack.append((node, True))
            stack.extend((kid, False) for kid in kids)
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
        elif kind == "and_":
            value = values.pop(id(kids[0])) & values.pop(id(kids[1]))
        elif kind == "or_":
            value = values.pop(id(kids[0])) | values.pop(id(kids[1]))
        else:  # pragma: no cover - the grammar has no other constructs
            raise GuardParseError(f"unknown guard construct {kind!r}")
        values[id(node)] = value
    return values[id(tree)]
