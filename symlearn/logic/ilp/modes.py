"""Mode declarations: the shapes of literals a hypothesis may use.

A mode literal is a template whose placeholders ``var(type)`` and ``const(type)`` are filled in
when the hypothesis space is generated:

* :class:`ModeAtom` -- ``p(var(t), const(c))``, optionally negated (``not p(...)``);
* :class:`ModeComparison` -- ``var(t) < var(t)``, ``var(n2) = var(n) + var(n)``;
* :class:`ModeConditional` -- ``not onRoad(var(dir)) : dir(var(dir))`` (``#modec``). Variables that
  occur only inside a conditional literal are local to it, as in clingo.

>>> ModeAtom("on", (Placeholder("var", "disk"), Placeholder("var", "disk"))).placeholders()
[Placeholder(kind='var', type='disk'), Placeholder(kind='var', type='disk')]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union


@dataclass(frozen=True)
class Placeholder:
    kind: str  # "var" or "const"
    type: str


@dataclass(frozen=True)
class ModeFunction:
    """A fixed function term that may contain placeholders, e.g. ``cell(var(x), var(y))``."""

    name: str
    args: tuple[ModeTerm, ...] = ()


@dataclass(frozen=True)
class Literal_:
    """A fixed constant (number, string or symbolic constant) written into the template."""

    text: str


ModeTerm = Union[Placeholder, ModeFunction, Literal_]


def term_placeholders(term: ModeTerm) -> list[Placeholder]:
    if isinstance(term, Placeholder):
        return [term]
    if isinstance(term, ModeFunction):
        return [p for a in term.args for p in term_placeholders(a)]
    return []


@dataclass(frozen=True)
class ModeAtom:
    name: str
    args: tuple[ModeTerm, ...] = ()
    negated: bool = False

    def placeholders(self) -> list[Placeholder]:
        return [p for a in self.args for p in term_placeholders(a)]

    @property
    def signature(self) -> tuple[str, int]:
        return self.name, len(self.args)


@dataclass(frozen=True)
class ModeComparison:
    op: str
    left: ModeTerm
    right: ModeTerm
    arith_op: str | None = None  # ``left op right arith_op right2``
    right2: ModeTerm | None = None

    def placeholders(self) -> list[Placeholder]:
        terms = [self.left, self.right] + ([self.right2] if self.right2 is not None else [])
        return [p for t in terms for p in term_placeholders(t)]


@dataclass(frozen=True)
class ModeConditional:
    literal: ModeAtom
    condition: tuple[ModeAtom, ...]

    def placeholders(self) -> list[Placeholder]:
        return self.literal.placeholders() + [p for c in self.condition for p in c.placeholders()]


ModeLiteral = Union[ModeAtom, ModeComparison, ModeConditional]


@dataclass(frozen=True)
class ModeDeclaration:
    """``#modeh``/``#modeb``/``#modec`` with its recall (max uses per rule; None = unbounded)."""

    kind: str  # "h", "b" or "c"
    literal: ModeLiteral
    recall: int | None = None
    positive: bool = False  # ILASP's (positive) flag: only positive literals from this mode
    line: int | None = None
    column: int | None = None

    def __str__(self) -> str:
        return f"#mode{self.kind}({'' if self.recall is None else f'{self.recall}, '}{render_mode(self.literal)})"


def render_term(term: ModeTerm) -> str:
    if isinstance(term, Placeholder):
        return f"{term.kind}({term.type})"
    if isinstance(term, ModeFunction):
        return term.name + (f"({','.join(render_term(a) for a in term.args)})" if term.args else "")
    return term.text


def render_mode(literal: ModeLiteral) -> str:
    if isinstance(literal, ModeAtom):
        body = literal.name + (f"({','.join(render_term(a) for a in literal.args)})" if literal.args else "")
        return ("not " if literal.negated else "") + body
    if isinstance(literal, ModeComparison):
        right = render_term(literal.right)
        if literal.arith_op:
            right += f" {literal.arith_op} {render_term(literal.right2)}"
        return f"{render_term(literal.left)} {literal.op} {right}"
    return render_mode(literal.literal) + " : " + ", ".join(render_mode(c) for c in literal.condition)
