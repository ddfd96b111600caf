"""LTLf formulas as immutable, hashable values with structural equality.

Every node is a frozen dataclass, so two formulas are ``==`` exactly when they have the same
syntax tree, and they can be used as dictionary keys or set members.  Semantic equivalence is a
different question, answered by :func:`symlearn.logic.ltlf.to_dfa.equivalent`.

>>> a, b = Prop("a"), Prop("b")
>>> Eventually(a & ~b) == Eventually(And(a, Not(b)))
True
>>> size(Until(a, Always(b)))
4

Binary operators keep their operands as written: ``a & b & c`` is ``And(And(a, b), c)``
(``&`` and ``|`` group to the left, temporal operators and ``->`` to the right); the printer
puts back exactly the parentheses needed to reproduce the same tree.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import ClassVar

__all__ = [
    "Formula", "Const", "Prop", "Unary", "Binary", "Not", "And", "Or", "Implies", "Iff",
    "Next", "WeakNext", "Eventually", "Always", "Until", "Release", "WeakUntil", "Then",
    "TRUE", "FALSE", "size", "operator_count", "temporal_depth", "propositions", "subformulas",
    "conjunction", "disjunction",
]


class Formula:
    """Base class of every LTLf node; supports ``&``, ``|``, ``~`` and ``>>`` (implies)."""

    __slots__ = ()

    # Equality and hashing are written out (not the dataclass ones) so that formulas nested
    # thousands deep compare without recursion; the hash is computed once, at construction.
    def __hash__(self) -> int:
        return self._hash  # type: ignore[attr-defined]

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        if not isinstance(other, Formula):
            return NotImplemented
        stack = [(self, other)]
        while stack:
            x, y = stack.pop()
            if x is y:
                continue
            if type(x) is not type(y) or x._hash != y._hash:  # type: ignore[attr-defined]
                return False
            kids_x, kids_y = x.children(), y.children()
            if not kids_x and x._leaf_key() != y._leaf_key():
                return False
            stack.extend(zip(kids_x, kids_y))
        return True

    def __ne__(self, other: object) -> bool:
        equal = self.__eq__(other)
        return equal if equal is NotImplemented else not equal

    def _leaf_key(self):
        return None

    def _set_hash(self) -> None:
        key = (type(self).__name__, self._leaf_key(), *(hash(c) for c in self.children()))
        object.__setattr__(self, "_hash", hash(key))

    def __and__(self, other: Formula) -> Formula:
        return And(self, _check(other))

    def __or__(self, other: Formula) -> Formula:
        return Or(self, _check(other))

    def __invert__(self) -> Formula:
        return Not(self)

    def __rshift__(self, other: Formula) -> Formula:
        return Implies(self, _check(other))

    def children(self) -> tuple[Formula, ...]:
        return ()

    def __str__(self) -> str:
        from symlearn.logic.ltlf.printer import to_string

        return to_string(self)

    def _repr_latex_(self) -> str:
        from symlearn.logic.ltlf.printer import to_latex

        return f"${to_latex(self)}$"


def _check(value: object) -> Formula:
    if not isinstance(value, Formula):
        raise TypeError(f"expected an LTLf formula, got {type(value).__name__}")
    return value


@dataclass(frozen=True, slots=True, repr=False, eq=False)
class Const(Formula):
    """``true`` or ``false``."""

    value: bool
    _hash: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._set_hash()

    def _leaf_key(self):
        return bool(self.value)

    def __repr__(self) -> str:
        return "TRUE" if self.value else "FALSE"


TRUE = Const(True)
FALSE = Const(False)


@dataclass(frozen=True, slots=True, eq=False)
class Prop(Formula):
    """An atomic proposition, true at a step when its name is in that step's label."""

    name: str
    _hash: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"a proposition name must be a non-empty string, not {self.name!r}")
        if "\n" in self.name or "\r" in self.name:  # could not be written back on one line
            raise ValueError(f"a proposition name cannot contain a line break: {self.name!r}")
        self._set_hash()

    def _leaf_key(self):
        return self.name


@dataclass(frozen=True, slots=True, eq=False)
class Unary(Formula):
    arg: Formula
    _hash: int = field(init=False, repr=False, compare=False)
    symbol: ClassVar[str] = "?"

    def __post_init__(self) -> None:
        _check(self.arg)
        self._set_hash()

    def children(self) -> tuple[Formula, ...]:
        return (self.arg,)


@dataclass(frozen=True, slots=True, eq=False)
class Binary(Formula):
    left: Formula
    right: Formula
    _hash: int = field(init=False, repr=False, compare=False)
    symbol: ClassVar[str] = "?"

    def __post_init__(self) -> None:
        _check(self.left)
        _check(self.right)
        self._set_hash()

    def children(self) -> tuple[Formula, ...]:
        return (self.left, self.right)


class Not(Unary):
    __slots__ = ()
    symbol = "!"


class Next(Unary):
    """Strong next: there is a next step and ``arg`` holds there."""

    __slots__ = ()
    symbol = "X"


class WeakNext(Unary):
    """Weak next: this is the last step, or ``arg`` holds at the next one."""

    __slots__ = ()
    symbol = "WX"


class Eventually(Unary):
    __slots__ = ()
    symbol = "F"


class Always(Unary):
    __slots__ = ()
    symbol = "G"


class And(Binary):
    __slots__ = ()
    symbol = "&"


class Or(Binary):
    __slots__ = ()
    symbol = "|"


class Implies(Binary):
    __slots__ = ()
    symbol = "->"


class Iff(Binary):
    __slots__ = ()
    symbol = "<->"


class Until(Binary):
    """``left U right``: ``right`` holds at some step from now on and ``left`` at every step before."""

    __slots__ = ()
    symbol = "U"


class Release(Binary):
    """``left R right``: ``right`` holds up to and including the first step where ``left`` holds (or to the end)."""

    __slots__ = ()
    symbol = "R"


class WeakUntil(Binary):
    """``left W right``: ``left U right`` or ``G left``."""

    __slots__ = ()
    symbol = "W"


class Then(Binary):
    """The task operator ``left T right`` = ``F(left & X F right)``: ``left``, later ``right``."""

    __slots__ = ()
    symbol = "T"


def subformulas(formula: Formula) -> Iterator[Formula]:
    """Every node once per occurrence, children before parents (post-order), without recursion."""
    stack: list[tuple[Formula, bool]] = [(formula, False)]
    while stack:
        node, expanded = stack.pop()
        if expanded:
            yield node
            continue
        stack.append((node, True))
        for child in reversed(node.children()):
            stack.append((child, False))


def size(formula: Formula) -> int:
    """Number of nodes of the syntax tree (propositions and constants count 1)."""
    return sum(1 for _ in subformulas(formula))


def operator_count(formula: Formula) -> int:
    """Number of operators (nodes that are not propositions or constants)."""
    return sum(1 for node in subformulas(formula) if not isinstance(node, (Prop, Const)))


_TEMPORAL = (Next, WeakNext, Eventually, Always, Until, Release, WeakUntil, Then)


def temporal_depth(formula: Formula) -> int:
    """Largest number of nested temporal operators."""
    depth: dict[int, int] = {}
    for node in subformulas(formula):
        inner = max((depth[id(c)] for c in node.children()), default=0)
        depth[id(node)] = inner + (1 if isinstance(node, _TEMPORAL) else 0)
    return depth[id(formula)]


def propositions(formula: Formula) -> frozenset[str]:
    """Names of the propositions that occur in ``formula``."""
    return frozenset(node.name for node in subformulas(formula) if isinstance(node, Prop))


def conjunction(*formulas: Formula) -> Formula:
    """``f1 & f2 & ...`` (``true`` for none)."""
    result: Formula | None = None
    for f in formulas:
        result = f if result is None else And(result, f)
    return TRUE if result is None else result


def disjunction(*formulas: Formula) -> Formula:
    """``f1 | f2 | ...`` (``false`` for none)."""
    result: Formula | None = None
    for f in formulas:
        result = f if result is None else Or(result, f)
    return FALSE if result is None else result
