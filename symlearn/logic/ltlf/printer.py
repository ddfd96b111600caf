"""Print LTLf formulas: ASCII in each dialect (read back exactly by the parser), Unicode, LaTeX.

>>> from symlearn.logic.ltlf.parser import parse
>>> f = parse("G(a -> X b) & (c U d U e)")
>>> to_string(f)
'G(a -> X b) & c U d U e'
>>> to_string(f, dialect="spot")
'G(a -> X[!] b) & c U d U e'
>>> to_string(f, style="unicode")
'G(a → X b) ∧ c U d U e'

The printer adds exactly the parentheses needed to rebuild the same tree under the dialect's
precedence, so ``parse(to_string(f, dialect=d), dialect=d) == f`` for every formula and
dialect. Propositions that are not plain lowercase names are printed double-quoted.
The task operator ``T`` is symlearn's own: it is printed as ``T`` in every dialect (so the round
trip holds), which Spot and LTLf2DFA cannot read; :func:`symlearn.logic.ltlf.mona.to_ltlf2dfa_text`
expands it (``a T b`` = ``F(a & X F b)``) for LTLf2DFA.
"""

from __future__ import annotations

import re

from symlearn.logic.ltlf.ast import (
    Always, And, Binary, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then,
    Until, WeakNext, WeakUntil, subformulas,
)
from symlearn.logic.ltlf.parser import check_dialect

__all__ = ["to_string", "to_latex"]

_ATOM, _UNARY, _TEMPORAL, _AND, _OR, _IMPLIES, _IFF = 100, 90, 80, 70, 60, 50, 40
_RIGHT_GROUPING = (Until, Release, WeakUntil, Then, Implies, Iff)
_PLAIN_NAME = re.compile(r"[a-z_][a-z0-9_]*\Z")
_KEYWORDS = {"true", "false"}

_SYMBOLS = {
    "ascii": {Not: "!", And: "&", Or: "|", Implies: "->", Iff: "<->", Eventually: "F", Always: "G",
              WeakNext: "WX", Until: "U", Release: "R", WeakUntil: "W", Then: "T", True: "true", False: "false"},
    "unicode": {Not: "\u00ac", And: "\u2227", Or: "\u2228", Implies: "\u2192", Iff: "\u2194", Eventually: "F",
                Always: "G", WeakNext: "N", Until: "U", Release: "R", WeakUntil: "W", Then: "T",
                True: "\u22a4", False: "\u22a5"},
    "latex": {Not: r"\lnot", And: r"\land", Or: r"\lor", Implies: r"\rightarrow", Iff: r"\leftrightarrow",
              Eventually: r"\mathsf{F}", Always: r"\mathsf{G}", WeakNext: r"\mathsf{N}", Next: r"\mathsf{X}",
              Until: r"\mathbin{\mathsf{U}}", Release: r"\mathbin{\mathsf{R}}", WeakUntil: r"\mathbin{\mathsf{W}}",
              Then: r"\mathbin{\mathsf{T}}", True: r"\top", False: r"\bot"},
}


def _precedence(node: Formula, dialect: str) -> int:
    if isinstance(node, (Prop, Const)):
        return _ATOM
    if isinstance(node, (Not, Next, WeakNext, Eventually, Always)):
        return _UNARY
    if isinstance(node, Release) and dialect == "ltlf2dfa":
        return _TEMPORAL + 5
    if isinstance(node, (Until, Release, WeakUntil, Then)):
        return _TEMPORAL
    if isinstance(node, And):
        return _AND
    if isinstance(node, Or):
        return _OR
    if isinstance(node, Implies):
        return _IMPLIES
    return _IMPLIES if dialect == "spot" else _IFF  # Iff


def _prop_text(name: str, style: str) -> str:
    if _PLAIN_NAME.match(name) and name not in _KEYWORDS:
        return name.replace("_", r"\_") if style == "latex" else name
    if style == "latex":
        return r"\text{``" + re.sub(r"([\\{}_^#&$%~])", r"\\\1", name) + "''}"
    return '"' + name.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_string(formula: Formula, dialect: str = "ours", style: str = "ascii") -> str:
    """The formula as text; ``style`` is ``"ascii"``, ``"unicode"`` or ``"latex"``."""
    check_dialect(dialect)
    if style not in _SYMBOLS:
        raise ValueError(f"unknown style {style!r}; use ascii, unicode or latex")
    symbols = _SYMBOLS[style]
    if style == "latex":
        next_symbol, weak_next = symbols[Next], symbols[WeakNext]
    elif dialect == "spot":
        next_symbol, weak_next = "X[!]", "X"
    else:
        next_symbol, weak_next = "X", symbols[WeakNext]
    lparen, rparen = (r"\left(", r"\right)") if style == "latex" else ("(", ")")
    text: dict[int, str] = {}  # id(node) -> text, filled children first (no recursion)
    for node in subformulas(formula):
        if isinstance(node, Const):
            out = symbols[node.value]
        elif isinstance(node, Prop):
            out = _prop_text(node.name, style)
        elif isinstance(node, Binary):
            p = _precedence(node, dialect)
            left, right = text[id(node.left)], text[id(node.right)]
            lp, rp = _precedence(node.left, dialect), _precedence(node.right, dialect)
            right_grouping = isinstance(node, _RIGHT_GROUPING)
            explicit = right_grouping and dialect == "ltlf2dfa"  # no chains for LTLf2DFA
            if lp < p or (lp == p and right_grouping):
                left = f"{lparen}{left}{rparen}"
            if rp < p or (rp == p and (explicit or not right_grouping)):
                right = f"{lparen}{right}{rparen}"
            out = f"{left} {symbols[type(node)]} {right}"
        else:
            op = next_symbol if isinstance(node, Next) else weak_next if isinstance(node, WeakNext) else symbols[type(node)]
            arg = text[id(node.arg)]
            if _precedence(node.arg, dialect) < _UNARY:
                out = f"{op}{lparen}{arg}{rparen}"
            elif isinstance(node, Not) and style != "latex":
                out = f"{op}{arg}"
            else:
                out = f"{op} {arg}"
        text[id(node)] = out
    return text[id(formula)]


def to_latex(formula: Formula) -> str:
    """LaTeX math (without ``$``), as notebooks show it."""
    return to_string(formula, style="latex")
