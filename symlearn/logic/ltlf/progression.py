"""Formula progression: what the rest of a trace must satisfy after one step has been seen.

>>> from symlearn.logic.ltlf.parser import parse
>>> str(progress(parse("a U b"), {"a"}))
'a U b'
>>> str(progress(parse("G(a -> X b)"), {"a"}))
'b & G(a -> X b)'
>>> holds_at_end(parse("G a")), holds_at_end(parse("F a")), holds_at_end(parse("!a"))
(True, False, True)

``progress(f, label)`` assumes at least one more step follows (``X g`` and ``WX g`` both
become ``g``); when ``label`` is the last step use :func:`last_step` instead.
:func:`holds_at_end` is the verdict on an empty remainder, which is also how symlearn treats
the empty trace (see :mod:`symlearn.logic.ltlf.semantics`).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import AbstractSet

from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release,
    Then, Until, WeakNext, WeakUntil, subformulas,
)
from symlearn.logic.ltlf.simplify import mk_and, mk_iff, mk_not, mk_or

__all__ = ["progress", "last_step", "holds_at_end", "holds_by_progression"]


def holds_at_end(formula: Formula) -> bool:
    """The verdict on the empty remainder of a trace.

    Propositions are false, ``!`` is the complement, ``X``, ``F``, ``U`` and ``T`` are false,
    ``WX``, ``G``, ``R`` and ``W`` are true (this matches MONA's automata via LTLf2DFA).
    """
    value: dict[int, bool] = {}
    for node in subformulas(formula):
        if isinstance(node, Const):
            v = node.value
        elif isinstance(node, (Prop, Next, Eventually, Until, Then)):
            v = False
        elif isinstance(node, (WeakNext, Always, Release, WeakUntil)):
            v = True
        elif isinstance(node, Not):
            v = not value[id(node.arg)]
        else:
            a, b = value[id(node.left)], value[id(node.right)]
            v = (a and b) if isinstance(node, And) else (a or b) if isinstance(node, Or) else \
                ((not a) or b) if isinstance(node, Implies) else (a == b)
        value[id(node)] = v
    return value[id(formula)]


def progress(formula: Formula, label: AbstractSet[str]) -> Formula:
    """The obligation on the rest of the trace after a step labelled ``label`` (more steps follow)."""
    out: dict[int, Formula] = {}
    for node in subformulas(formula):
        out[id(node)] = _progress_node(node, label, out)
    return out[id(formula)]


def _progress_node(node: Formula, label: AbstractSet[str], out: dict[int, Formula]) -> Formula:
    if isinstance(node, Const):
        return node
    if isinstance(node, Prop):
        return TRUE if node.name in label else FALSE
    if isinstance(node, Not):
        return mk_not(out[id(node.arg)])
    if isinstance(node, (Next, WeakNext)):
        return node.arg
    if isinstance(node, Eventually):
        return mk_or(out[id(node.arg)], node)
    if isinstance(node, Always):
        return mk_and(out[id(node.arg)], node)
    left, right = out[id(node.left)], out[id(node.right)]
    if isinstance(node, And):
        return mk_and(left, right)
    if isinstance(node, Or):
        return mk_or(left, right)
    if isinstance(node, Implies):
        return mk_or(mk_not(left), right)
    if isinstance(node, Iff):
        return mk_iff(left, right)
    if isinstance(node, (Until, WeakUntil)):
        return mk_or(right, mk_and(left, node))
    if isinstance(node, Release):
        return mk_and(right, mk_or(left, node))
    if isinstance(node, Then):
        return mk_or(mk_and(left, Eventually(node.right)), node)
    raise TypeError(f"not an LTLf formula node: {node!r}")


def last_step(formula: Formula, label: AbstractSet[str]) -> bool:
    """The verdict when ``label`` is the last step of the trace."""
    from symlearn.logic.ltlf.semantics import holds

    return holds(formula, [label])


def holds_by_progression(formula: Formula, trace: Iterable[Iterable[str]]) -> bool:
    """``holds`` computed by progressing through the trace (an independent check of the semantics)."""
    labels = [frozenset(label) for label in trace]
    if not labels:
        return holds_at_end(formula)
    current = formula
    for label in labels[:-1]:
        current = progress(current, label)
        if isinstance(current, Const):
            return current.value
    return last_step(current, labels[-1])

