"""A hand-written reader for well-formed LTLf formulas, so parsing needs no lark.

:func:`symlearn.logic.ltlf.parser.parse` tries this reader first and falls back to the lark
parser of ``grammars/ltlf.lark`` whenever it returns ``None``: on any syntax error (lark's
LALR parser then words the error: what was expected, the column, the hint), and when a formula
is nested deeper than Python's recursion allows. So the reader only has to agree with the
grammar on the formulas the grammar accepts; a test checks that it builds the same formula as
lark on those and gives up on the others. Why: importing lark and building the LALR tables
cost about a third of a ``symlearn ltl`` command's start-up.

It follows the grammar's levels (arrows, ``|``, ``&``, binary temporal, unary, atoms) and lark's
contextual lexer: after an operand only binary operators, ``)`` or the end are tokens (so
``a WX b`` is ``a W (X b)``), before an operand only unary operators and atoms; a lowercase
word is a proposition unless it is exactly ``true``/``false``. The dialects' groupings are
:func:`group_arrows` and :func:`group_temporal`, shared with the lark transformer.
"""

from __future__ import annotations

import re

from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil,
)

__all__ = ["read", "group_arrows", "group_temporal", "fold_left", "fold_right"]

UNARY = {
    "!": Not, "~": Not, "\u00ac": Not,
    "X[!]": Next, "\u25cb": Next, "N": WeakNext, "WX": WeakNext,
    "F": Eventually, "\u25c7": Eventually, "G": Always, "\u25a1": Always,
}
TEMPORAL = {"U": Until, "R": Release, "W": WeakUntil, "T": Then}
IFF_OPS = ("<->", "\u2194")

_WHITESPACE = " \t\r\n"  # the grammar's %ignore, exactly
_NAME = re.compile(r"[a-z_][a-z0-9_]*")
_QUOTED = re.compile(r'"(?:[^"\\\n]|\\.)+"')
# longest spellings first, as lark's lexer matches
_UNARY_SPELLINGS = ("X[!]", "WX", "!", "~", "\u00ac", "X", "N", "F", "G", "\u25c7", "\u25a1", "\u25cb")
_BINARY = (("<->", "arrow"), ("\u2194", "arrow"), ("->", "arrow"), ("\u2192", "arrow"), ("||", "or"),
           ("|", "or"), ("\u2228", "or"), ("&&", "and"), ("&", "and"), ("\u2227", "and"), ("U", "temporal"),
           ("R", "temporal"), ("W", "temporal"), ("T", "temporal"))
_CONSTANTS = {"true": TRUE, "false": FALSE, "1": TRUE, "\u22a4": TRUE, "0": FALSE, "\u22a5": FALSE}


class _GiveUp(Exception):
    """Not a formula this reader builds: the lark parser decides (and words the error)."""


def read(text: str, dialect: str) -> Formula | None:
    """The formula ``text`` denotes in ``dialect``, or ``None`` (then ask the lark parser)."""
    reader = _Reader(text, dialect)
    try:
        formula = reader.arrows()
        reader.skip()
        if reader.pos != len(text):
            return None
        return formula
    except (_GiveUp, RecursionError):
        return None


class _Reader:
    __slots__ = ("text", "pos", "bare_x", "flat_arrows", "release_tighter")

    def __init__(self, text: str, dialect: str) -> None:
        self.text, self.pos = text, 0
        self.bare_x = WeakNext if dialect == "spot" else Next
        self.flat_arrows = dialect == "spot"
        self.release_tighter = dialect == "ltlf2dfa"

    def skip(self) -> None:
        text, pos = self.text, self.pos
        while pos < len(text) and text[pos] in _WHITESPACE:
            pos += 1
        self.pos = pos

    def binary(self, level: str) -> str | None:
        """The binary operator of ``level`` at the cursor (consumed), if the next token is one."""
        self.skip()
        for spelling, kind in _BINARY:
            if self.text.startswith(spelling, self.pos):
                if kind != level:
                    return None  # another level's operator (or none): that level reads it
                self.pos += len(spelling)
                return spelling
        return None

    def arrows(self) -> Formula:
        items: list = [self.ors()]
        while (op := self.binary("arrow")) is not None:
            items += [op, self.ors()]
        return group_arrows(items, self.flat_arrows)

    def ors(self) -> Formula:
        items: list = [self.ands()]
        while (op := self.binary("or")) is not None:
            items += [op, self.ands()]
        return fold_left(items, Or)

    def ands(self) -> Formula:
        items: list = [self.temporals()]
        while (op := self.binary("and")) is not None:
            items += [op, self.temporals()]
        return fold_left(items, And)

    def temporals(self) -> Formula:
        items: list = [self.unary()]
        while (op := self.binary("temporal")) is not None:
            items += [op, self.unary()]
        return group_temporal(items, self.release_tighter)

    def unary(self) -> Formula:
        operators = []  # a run of unary operators, applied innermost first (no recursion per operator)
        text = self.text
        while True:
            self.skip()
            spelling = next((s for s in _UNARY_SPELLINGS if text.startswith(s, self.pos)), None)
            if spelling is None:
                break
            operators.append(self.bare_x if spelling == "X" else UNARY[spelling])
            self.pos += len(spelling)
        formula = self.atom()
        for op in reversed(operators):
            formula = op(formula)
        return formula

    def atom(self) -> Formula:
        text, pos = self.text, self.pos
        if pos >= len(text):
            raise _GiveUp
        char = text[pos]
        if char == "(":
            self.pos += 1
            inner = self.arrows()
            self.skip()
            if not text.startswith(")", self.pos):
                raise _GiveUp
            self.pos += 1
            return inner
        word = _NAME.match(text, pos)
        if word:
            self.pos = word.end()
            name = word.group(0)
            return _CONSTANTS[name] if name in ("true", "false") else Prop(name)
        if char in _CONSTANTS:
            self.pos += 1
            return _CONSTANTS[char]
        quoted = _QUOTED.match(text, pos)
        if quoted:
            self.pos = quoted.end()
            return Prop(re.sub(r"\\(.)", r"\1", quoted.group(0)[1:-1]))
        raise _GiveUp


# -- grouping (shared with the lark transformer) ------------------------------------------------
def fold_left(items: list, node) -> Formula:
    """``[x0, op, x1, op, x2]`` -> ``node(node(x0, x1), x2)``."""
    result = items[0]
    for i in range(2, len(items), 2):
        result = node(result, items[i])
    return result


def fold_right(items: list, node_for) -> Formula:
    """``[x0, op1, x1, op2, x2]`` -> ``node_for(op1)(x0, node_for(op2)(x1, x2))``."""
    result = items[-1]
    for i in range(len(items) - 3, -1, -2):
        result = node_for(str(items[i + 1]))(items[i], result)
    return result


def group_temporal(items: list, release_tighter: bool) -> Formula:
    """A chain of binary temporal operators: to the right; ``R`` first in LTLf2DFA's grammar."""
    if not release_tighter:
        return fold_right(items, lambda op: TEMPORAL[op])
    parts: list[list] = [[]]
    joins: list = []
    for i, item in enumerate(items):
        if i % 2 and str(item) != "R":
            joins.append(item)
            parts.append([])
        else:
            parts[-1].append(item)
    folded = [fold_right(part, lambda op: Release) for part in parts]
    chain = [folded[0]]
    for op, part in zip(joins, folded[1:]):
        chain += [op, part]
    return fold_right(chain, lambda op: TEMPORAL[op])


def group_arrows(items: list, flat: bool) -> Formula:
    """A chain of ``->``/``<->``: one right-grouping level (Spot) or ``<->`` looser than ``->``."""
    if flat:
        return fold_right(items, lambda op: Iff if op in IFF_OPS else Implies)
    parts: list[list] = [[]]
    for i, item in enumerate(items):
        if i % 2 and str(item) in IFF_OPS:
            parts.append([])
        else:
            parts[-1].append(item)
    groups = [fold_right(part, lambda op: Implies) for part in parts]
    result = groups[-1]
    for g in reversed(groups[:-1]):
        result = Iff(g, result)
    return result
