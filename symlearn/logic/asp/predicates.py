"""Predicates a rule file uses that no program defines: the misspelling an ASP solver stays silent on.

In ASP an atom of a predicate that nothing defines is simply false, so ``:- wal(V1), go(V1).``
(for ``wall``) is a valid rule that never fires: the edit silently forbids nothing.
:func:`undefined_predicates` compares the atoms a rule file's bodies use with every predicate the
other programs define (heads and facts of the background, the examples' contexts, the rules' own
heads, or a domain's state facts and actions) and suggests the closest defined name.

>>> from symlearn.logic.asp.program import Program
>>> rules = Program.from_text(":- wal(V1), go(V1).", source="edited.lp")
>>> [u.message() for u in undefined_predicates(rules, {("wall", 1), ("go", 1)})]
['predicate wal/1 is defined nowhere (no head, fact or context has it), so the atom is always false; did you mean wall/1?']
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program

Signature = tuple[str, int]


@dataclass(frozen=True)
class UndefinedPredicate:
    """A used predicate no program defines, where the rule file first uses it, and a suggestion."""

    name: str
    arity: int
    file: str | None
    line: int
    column: int
    suggestion: str | None  # "wall/1", or None

    def message(self) -> str:
        text = (f"predicate {self.name}/{self.arity} is defined nowhere (no head, fact or context has it), "
                "so the atom is always false")
        return text + (f"; did you mean {self.suggestion}?" if self.suggestion else "")

    def as_dict(self) -> dict:
        return {"predicate": f"{self.name}/{self.arity}", "file": self.file, "line": self.line,
                "column": self.column, "did_you_mean": self.suggestion, "message": self.message()}


def defined_signatures(programs: Iterable[Program]) -> set[Signature]:
    """``name/arity`` of every predicate the programs' heads and facts define."""
    found: set[Signature] = set()
    for program in programs:
        found |= {(name, arity) for name, arity, defines in cl.PredicateUses(program).signatures if defines}
    return found


def undefined_predicates(rules: Program, defined: set[Signature]) -> list[UndefinedPredicate]:
    """The predicates ``rules`` use (bodies, conditions) that neither ``defined`` nor the rules'
    own heads define, each once, in the order the file first uses them."""
    uses = cl.PredicateUses(rules)  # positions only of the atoms reported
    known = set(defined) | {(name, arity) for name, arity, defines in uses.signatures if defines}
    out: dict[Signature, UndefinedPredicate] = {}
    closest = Suggestions(known)
    for index, (name, arity, defines) in enumerate(uses.signatures):
        signature = (name, arity)
        if defines or signature in known or signature in out:
            continue
        use = uses.located(index)
        source, line, column = rules.locate(use.line, use.column)
        suggestion = closest(signature) if len(out) < MAX_SUGGESTIONS else None
        out[signature] = UndefinedPredicate(name, arity, source, line, column, suggestion)
    return list(out.values())


#: "did you mean" is looked up for the first this many undefined predicates of a file; each lookup
#: compares against every known name, so a generated file with thousands of them stays linear
MAX_SUGGESTIONS = 100


class Suggestions:
    """The closest known predicate to a misspelt one, with the known names indexed once."""

    def __init__(self, known: set[Signature]) -> None:
        self.arities: dict[str, list[int]] = {}
        for name, arity in known:
            self.arities.setdefault(name, []).append(arity)
        for arities in self.arities.values():
            arities.sort()
        self.by_arity: dict[int, list[str]] = {}
        for name, arity in sorted(known):
            self.by_arity.setdefault(arity, []).append(name)
        self.names = sorted(self.arities)

    def __call__(self, signature: Signature) -> str | None:
        name, arity = signature
        if name in self.arities:  # the right name with another number of arguments
            return f"{name}/{self.arities[name][0]}"
        close = difflib.get_close_matches(name, self.by_arity.get(arity) or self.names, n=1, cutoff=0.6)
        if not close:
            return None
        arities = self.arities[close[0]]
        return f"{close[0]}/{arity if arity in arities else arities[0]}"


__all__ = ["MAX_SUGGESTIONS", "Suggestions", "UndefinedPredicate", "defined_signatures", "undefined_predicates"]
