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
trip holds), which Spot and LTLf2DFA cannot read; :func:`for_dialect` rewrites a formula into
the operators a tool reads (``a T b`` = ``F(a & X F b)`` for both, and for LTLf2DFA, which has
no weak until, ``a W b`` = ``(a U b) | G a``; Spot reads ``W``), as ``symlearn ltl parse --to``
does.

>>> to_string(for_dialect(parse("a T b"), "spot"), "spot")
'F(a & X[!] F b)'
>>> to_string(for_dialect(parse("a W b"), "ltlf2dfa"), "ltlf2dfa")
'a U b | G a'
"""

from __future__ import annotations

import re

from symlearn.logic.ltlf.ast import (
    Always, And, Binary, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then,
    Until, WeakNext, WeakUntil,
)
from symlearn.logic.ltlf.parser import check_dialect

__all__ = ["to_string", "to_latex", "for_dialect"]

#: operators each dialect's own tool cannot read, which :func:`for_dialect` expands
FOREIGN = {"ours": (), "spot": (Then,), "ltlf2dfa": (Then, WeakUntil)}


def for_dialect(formula: Formula, dialect: str) -> Formula:
    """An equivalent formula using only operators ``dialect``'s tool reads (see :data:`FOREIGN`):
    ``a T b`` -> ``F(a & X F b)``, ``a W b`` -> ``(a U b) | G a``. Iterative, so deep formulas work."""
    check_dialect(dialect)
    foreign = FOREIGN[dialect]
    if not foreign:
        return formula
    done: dict[int, Formula] = {}
    stack: list[tuple[Formula, bool]] = [(formula, False)]
    while stack:
        node, expanded = stack.pop()
        if id(node) in done:
            continue
        kids = node.children()
        if kids and not expanded:
            stack.append((node, True))
            stack.extend((kid, False) for kid in kids)
            continue
        new_kids = [done[id(kid)] for kid in kids]
        if isinstance(node, Then) and Then in foreign:
            a, b = new_kids
            result: Formula = Eventually(And(a, Next(Eventually(b))))
        elif isinstance(node, WeakUntil) and WeakUntil in foreign:
            a, b = new_kids
            result = Or(Until(a, b), Always(a))
        elif kids and any(new is not old for new, old in zip(new_kids, kids)):
            result = type(node)(*new_kids)
        else:
            result = node
        done[id(node)] = result
    return done[id(formula)]

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
    # Emit pieces left to right from an explicit stack: linear time and memory, no recursion
    # (a table of each sub-formula's text would hold O(n^2) characters for 100,000 nested `!`).
    pieces: list[str] = []
    stack: list[Formula | str] = [formula]
    while stack:
        node = stack.pop()
        if isinstance(node, str):
            pieces.append(node)
        elif isinstance(node, Const):
            pieces.append(symbols[node.value])
        elif isinstance(node, Prop):
            pieces.append(_prop_text(node.name, style))
        elif isinstance(node, Binary):
            p = _precedence(node, dialect)
            lp, rp = _precedence(node.left, dialect), _precedence(node.right, dialect)
            right_grouping = isinstance(node, _RIGHT_GROUPING)
            explicit = right_grouping and dialect == "ltlf2dfa"  # no chains for LTLf2DFA
            wrap_left = lp < p or (lp == p and right_grouping)
            wrap_right = rp < p or (rp == p and (explicit or not right_grouping))
            right = [lparen, node.right, rparen] if wrap_right else [node.right]
            left = [lparen, node.left, rparen] if wrap_left else [node.left]
            stack.extend(reversed([*left, f" {symbols[type(node)]} ", *right]))
        else:
            op = next_symbol if isinstance(node, Next) else weak_next if isinstance(node, WeakNext) else symbols[type(node)]
            if _precedence(node.arg, dialect) < _UNARY:
                stack.extend((rparen, node.arg, lparen, op))
            elif isinstance(node, Not) and style != "latex":
                stack.extend((node.arg, op))
            else:
                stack.extend((node.arg, f"{op} "))
    return "".join(pieces)


def to_latex(formula: Formula) -> str:
    """LaTeX math (without ``$``), as notebooks show it."""
    return to_string(formula, style="latex")
