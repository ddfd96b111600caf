"""Mode declarations of a domain's bias that can never help: the silent mistakes of a bias file.

A ``#modeb`` whose predicate nothing defines (``#modeb(1, stak(var(block), var(block)))`` for
``stack``) gives literals that are false in every pair's answer set, and a ``const(t)`` with no
``#constant(t, ...)`` gives no literal at all. Neither is an error to clingo or to the hypothesis
space, so without a word the learner reports "no rules" and the user looks for the fault in the
demonstrations. :func:`bias_warnings` names each such declaration with its file, line and column.

"Defined" means: a head or fact of the background (and of the bias file's own background part),
a fact of some state, or an action atom, exactly what a rule file is checked against
(:meth:`symlearn.grounding.Domain.undefined_predicates`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from symlearn.logic.asp.predicates import MAX_SUGGESTIONS, Suggestions
from symlearn.logic.ilp.modes import ModeAtom, ModeConditional, Placeholder, render_mode


@dataclass(frozen=True)
class BiasWarning:
    """One declaration of the bias file that can give no useful literal, and where it is."""

    file: str | None
    line: int | None
    column: int | None
    message: str

    def located(self) -> str:
        where = ":".join(str(x) for x in (self.file, self.line, self.column) if x is not None)
        return f"{where}: {self.message}" if where else self.message

    def as_dict(self) -> dict[str, Any]:
        return {"file": self.file, "line": self.line, "column": self.column, "message": self.message}


def _atoms(literal) -> list[ModeAtom]:
    if isinstance(literal, ModeAtom):
        return [literal]
    if isinstance(literal, ModeConditional):
        return [literal.literal, *literal.condition]
    return []  # a comparison names no predicate


def bias_warnings(domain) -> list[BiasWarning]:
    """The body declarations of ``domain``'s bias whose predicate nothing defines, and the
    ``const(t)`` placeholders without constants, in file order."""
    task = domain.bias
    defined = domain.defined_signatures
    source = domain.sources.get("bias")
    out: list[BiasWarning] = []
    closest = Suggestions(defined)   # indexed once: a generated bias may name thousands of predicates
    suggested = 0
    for mode in sorted([*task.modeb, *task.modec], key=lambda m: (m.line or 0, m.column or 0)):
        declaration = f"#mode{mode.kind}({render_mode(mode.literal)})"
        for atom in _atoms(mode.literal):
            if atom.signature in defined:
                out += _unmatched_constants(domain, atom, declaration, source, mode)
                continue
            name, arity = atom.signature
            suggestion = closest(atom.signature) if suggested < MAX_SUGGESTIONS else None
            suggested += 1
            out.append(BiasWarning(source, mode.line, mode.column,
                                   f"{declaration}: predicate {name}/{arity} is defined nowhere (no background "
                                   "head or fact, state fact or action atom has it), so the literal has the same "
                                   "value in every pair and no rule can use it"
                                   + (f"; did you mean {suggestion}?" if suggestion else "")))
        for slot in mode.literal.placeholders():
            if slot.kind == "const" and not task.constants.get(slot.type):
                out.append(BiasWarning(source, mode.line, mode.column,
                                       f"{declaration}: const({slot.type}) has no #constant({slot.type}, ...) "
                                       "declaration, so the mode gives no literal"))
    return out


def _unmatched_constants(domain, atom: ModeAtom, declaration: str, source, mode) -> list[BiasWarning]:
    """``#constant(player, bob)`` where the facts say ``"Bob"``: a ``const(t)`` argument value that
    the atom never has in any pair's answer set makes every literal with it false, silently (the
    learner then finds no rule and reports the pairs as unexplained)."""
    import difflib

    values = domain.argument_values.get(atom.signature)
    if not values:
        return []
    out = []
    for position, argument in enumerate(atom.args):
        if not (isinstance(argument, Placeholder) and argument.kind == "const"):
            continue
        have = values[position]
        for constant in domain.bias.constants.get(argument.type, []):
            written = str(constant)
            if written in have:
                continue
            plain = {v.strip('"').lower(): v for v in have}
            meant = plain.get(written.strip('"').lower()) or next(iter(difflib.get_close_matches(written, have, n=1)),
                                                                  None)
            shown = ", ".join(sorted(have)[:5]) + (", ..." if len(have) > 5 else "")
            out.append(BiasWarning(source, mode.line, mode.column,
                                   f"{declaration}: #constant({argument.type}, {written}): {atom.name}/"
                                   f"{len(atom.args)} never has {written} as argument {position + 1} in any pair "
                                   f"(it has: {shown}), so the literal with it is always false"
                                   + (f"; did you mean {meant}?" if meant else "")))
    return out


__all__ = ["BiasWarning", "bias_warnings"]
