"""Finite-trace (LTLf) semantics, written directly from the definitions.

A trace is a non-empty sequence of labels; a label is the set of propositions true at that
step. ``holds(f, trace)`` evaluates ``f`` at step 0:

* ``X f`` (strong next): there is a next step and ``f`` holds there; ``WX f`` / ``N f`` (weak
  next): the current step is the last one or ``f`` holds at the next;
* ``F f``, ``G f``, ``f U g``, ``f R g``, ``f W g`` range over the current and later steps;
* ``a T b`` holds when ``a`` holds at some step and ``b`` at a strictly later one.

**Empty traces.** LTLf is defined on non-empty traces, so ``holds`` rejects an empty trace
with :class:`~symlearn.errors.DataError`. Automata and batch evaluation still have to decide
the empty word; there symlearn uses :func:`~symlearn.logic.ltlf.progression.holds_at_end`:
propositions are false, ``!`` is the complement, ``X``, ``F``, ``U`` and ``T`` are false and
``WX``, ``G``, ``R`` and ``W`` are true (so ``G a`` and ``!a`` accept the empty word, ``F a``
and ``a`` do not). The DFA of :func:`~symlearn.logic.ltlf.to_dfa.translate`, the vectorised
evaluator and MONA's automata (through LTLf2DFA) all follow this convention.

This module is the reference the faster evaluators are tested against: it stays a plain
dynamic program over (sub-formula, step).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import AbstractSet

from symlearn.errors import DataError
from symlearn.logic.ltlf.ast import (
    Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil, subformulas,
)

__all__ = ["holds", "as_trace"]

Trace = Sequence[AbstractSet[str]]


def as_trace(trace: Iterable[Iterable[str]]) -> list[frozenset[str]]:
    """A trace as a list of frozensets; a bare string label is refused (it would be split into letters)."""
    labels = []
    for step, label in enumerate(trace):
        if isinstance(label, str):
            raise DataError(f"step {step}: a label must be a set of proposition names, not the string {label!r}",
                            hint=f"write [{label!r}] for a step where only {label!r} is true")
        labels.append(frozenset(label))
    return labels


def holds(formula: Formula, trace: Iterable[Iterable[str]]) -> bool:
    """Whether ``formula`` holds on ``trace`` at its first step (LTLf semantics).

    >>> from symlearn.logic.ltlf.parser import parse
    >>> holds(parse("a T b"), [{"a"}, set(), {"b"}])
    True
    >>> holds(parse("X true"), [{"a"}])
    False
    """
    labels = as_trace(trace)
    n = len(labels)
    if n == 0:
        raise DataError("LTLf formulas are evaluated on non-empty traces; this trace is empty")
    value: dict[Formula, list[bool]] = {}
    for node in subformulas(formula):
        if node in value:
            continue
        value[node] = _values(node, labels, value)
    return value[formula][0]


def _values(node: Formula, labels: list[frozenset[str]], value: dict) -> list[bool]:
    n = len(labels)
    if isinstance(node, Const):
        return [node.value] * n
    if isinstance(node, Prop):
        return [node.name in label for label in labels]
    if isinstance(node, Not):
        return [not v for v in value[node.arg]]
    if isinstance(node, (Next, WeakNext)):
        arg = value[node.arg]
        end = isinstance(node, WeakNext)
        return [arg[i + 1] if i + 1 < n else end for i in range(n)]
    if isinstance(node, Eventually):
        arg = value[node.arg]
        return [any(arg[i:]) for i in range(n)]
    if isinstance(node, Always):
        arg = value[node.arg]
        return [all(arg[i:]) for i in range(n)]
    left, right = value[node.left], value[node.right]
    if isinstance(node, And):
        return [a and b for a, b in zip(left, right)]
    if isinstance(node, Or):
        return [a or b for a, b in zip(left, right)]
    if isinstance(node, Implies):
        return [(not a) or b for a, b in zip(left, right)]
    if isinstance(node, Iff):
        return [a == b for a, b in zip(left, right)]
    if isinstance(node, (Until, WeakUntil)):
        weak = isinstance(node, WeakUntil)
        out = []
        for i in range(n):
            j = next((k for k in range(i, n) if right[k]), None)
            if j is None:
                out.append(weak and all(left[i:]))
            else:
                out.append(all(left[i:j]))
        return out
    if isinstance(node, Release):
        # right holds up to and including the first step where left holds, or to the end
        out = []
        for i in range(n):
            j = next((k for k in range(i, n) if left[k]), n - 1)
            out.append(all(right[i : j + 1]))
        return out
    if isinstance(node, Then):
        return [any(left[j] and any(right[j + 1 :]) for j in range(i, n)) for i in range(n)]
    raise TypeError(f"not an LTLf formula node: {node!r}")
