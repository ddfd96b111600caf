"""Hypothesis strategies for LTLf formulas and traces (tests of symlearn.logic.ltlf)."""

from __future__ import annotations

from hypothesis import strategies as st

from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Eventually, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil,
)

PROPS = ("a", "b", "c")
_UNARY = (Not, Next, WeakNext, Eventually, Always)
_BINARY = (And, Or, Implies, Iff, Until, Release, WeakUntil, Then)


def formulas(props=PROPS, max_leaves: int = 10, names=None):
    """Random formulas over ``props`` (``names`` adds extra, possibly quoted, proposition names)."""
    leaves = [st.sampled_from(props).map(Prop), st.sampled_from([TRUE, FALSE])]
    if names is not None:
        leaves.append(names.map(Prop))
    atoms = st.one_of(*leaves)

    def extend(children):
        return st.one_of(
            st.tuples(st.sampled_from(_UNARY), children).map(lambda p: p[0](p[1])),
            st.tuples(st.sampled_from(_BINARY), children, children).map(lambda p: p[0](p[1], p[2])),
        )

    return st.recursive(atoms, extend, max_leaves=max_leaves)


def traces(props=PROPS, min_size: int = 1, max_size: int = 6):
    return st.lists(st.frozensets(st.sampled_from(props)), min_size=min_size, max_size=max_size)
