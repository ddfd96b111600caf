"""Hypothesis strategies for guards, labels, words and small random DFAs (automata tests)."""

from __future__ import annotations

from hypothesis import strategies as st

from symlearn.logic.automata.dfa import DFA
from symlearn.logic.guards import Guard

PROPS = ("a", "b", "c")


def labels(props=PROPS):
    return st.frozensets(st.sampled_from(props))


def words(props=PROPS, max_size=6):
    return st.lists(labels(props), max_size=max_size)


@st.composite
def guards(draw, props=PROPS, depth=3):
    """Random guard expressions built with the Guard algebra."""
    if depth == 0 or draw(st.booleans()):
        choice = draw(st.sampled_from(list(props) + ["true", "false"]))
        return Guard.true() if choice == "true" else Guard.false() if choice == "false" else Guard.var(choice)
    op = draw(st.sampled_from(["and", "or", "not"]))
    left = draw(guards(props, depth - 1))
    if op == "not":
        return ~left
    right = draw(guards(props, depth - 1))
    return left & right if op == "and" else left | right


def all_labels(props):
    return [frozenset(p for i, p in enumerate(props) if bits >> i & 1) for bits in range(2 ** len(props))]


@st.composite
def dfas(draw, props=PROPS[:2], max_states=4, partial=True):
    """A random deterministic DFA: each state splits the label space into disjoint guard cells."""
    n = draw(st.integers(1, max_states))
    transitions = {}
    for q in range(n):
        # a random partition of the labels, each cell's guard is the disjunction of its labels
        cells: dict[int, Guard] = {}
        for label in all_labels(props):
            target = draw(st.integers(-1 if partial else 0, n - 1))
            if target >= 0:
                cells[target] = cells.get(target, Guard.false()) | Guard.label(label, props)
        transitions[q] = [(g, t) for t, g in cells.items()]
    accepting = draw(st.sets(st.integers(0, n - 1)))
    initial = draw(st.integers(0, n - 1))
    return DFA(props, n, initial, accepting, transitions)


def a_then_b_avoid_c() -> DFA:
    """F(a & X F b) & G !c written by hand; partial (a c-labelled step has no edge)."""
    a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")
    return DFA({"a", "b", "c"}, 3, 0, [2], {
        0: [(~a & ~c, 0), (a & ~c, 1)],
        1: [(~b & ~c, 1), (b & ~c, 2)],
        2: [(~c, 2)],
    })
