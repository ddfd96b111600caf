"""Examples that no hypothesis of the space can affect, and the verdict they force.

The general search (:mod:`~symlearn.logic.ilp.general`) excludes a negative by a cut specific to
one set of normal rules when the space has no integrity constraint, so a negative that nothing
can exclude makes it enumerate every subset of the normal rules (2^15 rounds for 15 rules) until
the time limit. This module proves such cases up front.

Let P be the predicates of the candidates' heads. When

* the space has no integrity constraint,
* no candidate uses a predicate of P under ``not`` or in a conditional literal,
* no predicate of P occurs in the background or in the example's context, and
* the example's inclusions and exclusions name no predicate of P,

then {atoms not in P} splits B ∪ C_e ∪ H (splitting set theorem): the bottom is B ∪ C_e, and
the top, the rules of H, is a positive program over P once the bottom is fixed, with exactly
one answer set. So the answer sets of B ∪ C_e ∪ H are those of B ∪ C_e, each extended by atoms of
P that the example does not look at: whether the example is accepted is the same for every H.
A hard negative that B ∪ C_e accepts, or a hard positive it rejects, then admits no hypothesis.
Predicates are compared by name only (any arity), which can only make the test refuse more.
"""

from __future__ import annotations

from collections.abc import Iterable

from symlearn.logic.asp.clingo_adapter import PredicateUses
from symlearn.logic.ilp.space import HypothesisSpace
from symlearn.logic.ilp.task import Example, ILPTask


def _name(atom: str) -> str:
    return atom.strip().lstrip("-").partition("(")[0].strip()


def head_predicates(space: HypothesisSpace) -> set[str] | None:
    """The names of the candidates' head predicates, or None when the space can change an example
    by other means (an integrity constraint, or a head predicate under ``not`` or in a condition)."""
    heads = set()
    for candidate in space.candidates:
        if candidate.head is None:
            return None
        heads.add(_name(candidate.head))
    for candidate in space.candidates:
        for literal in candidate.body:
            atoms = [literal.text, *literal.condition]
            if (literal.negated or literal.kind == "cond") and any(_name(a) in heads for a in atoms):
                return None
    return heads


def _mentions(example: Example, heads: set[str], background: set[str]) -> bool:
    if background & heads:
        return True
    if any(s.name in heads for s in (*example.inclusions, *example.exclusions)):
        return True
    return not example.context.is_empty() and bool(_names(PredicateUses(example.context).signatures) & heads)


def _names(signatures: Iterable[tuple[str, int, bool]]) -> set[str]:
    return {name for name, _arity, _defines in signatures}


def unaffected_examples(task: ILPTask, space: HypothesisSpace, examples: Iterable[Example]) -> list[Example]:
    """Those of ``examples`` that every hypothesis of ``space`` accepts or every one rejects."""
    heads = head_predicates(space)
    if not heads:
        return []
    background = _names(PredicateUses(task.background).signatures) if not task.background.is_empty() else set()
    return [e for e in examples if not _mentions(e, heads, background)]
