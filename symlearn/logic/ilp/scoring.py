"""FastLAS-style ``#bias`` scoring programs: the cost of a rule computed by clingo.

Each rule is described by facts ``in_head(T)`` and ``in_body(T)`` (one per literal) and the task's
``#bias`` programs derive ``penalty(Weight, Id)`` atoms; the rule's cost is the sum of the weights
of the distinct ``penalty`` atoms. A bias program whose integrity constraint fires for a rule
removes that rule from the space.

Literal terms: an atom is written as itself with variables ``V1, V2, ...`` turned into ``var(1),
var(2), ...``; ``not a`` is ``naf(a)``; a comparison is ``cmp("V1 < V2")``; a conditional literal
is ``cond("l : c")``. All rules are scored together in one clingo call (the bias program is
copied once per rule with :func:`~symlearn.logic.asp.clingo_adapter.tag_program`).
"""

from __future__ import annotations

import re
from dataclasses import replace

from symlearn.errors import SymlearnError
from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.space import BodyLiteral, HypothesisSpace
from symlearn.logic.ilp.task import ILPTask

_VAR = re.compile(r"\bV(\d+)\b")


def literal_term(literal: BodyLiteral) -> str:
    if literal.kind == "atom":
        atom = _VAR.sub(r"var(\1)", literal.text)
        return f"naf({atom})" if literal.negated else atom
    kind = "cmp" if literal.kind == "cmp" else "cond"
    return f'{kind}("{literal.render()}")'


def apply_bias(task: ILPTask, space: HypothesisSpace) -> HypothesisSpace:
    """Replace each candidate's cost by its #bias penalty; drop rules the bias forbids."""
    bias = Program.from_text("\n".join(task.bias), source=f"{task.source} (#bias)")
    tagged = cl.tag_program(bias, "R__", ["rule__(R__)"], constraint_head="excluded__")
    facts = []
    for c in space.candidates:
        facts.append(f"rule__({c.index}).")
        if c.head is not None:
            head = _VAR.sub(r"var(\1)", c.head)
            facts.append(f"in_head({c.index},{head}).")
        for lit in c.body:
            facts.append(f"in_body({c.index},{literal_term(lit)}).")
    program = Program.from_text("\n".join(facts), source="<rule descriptions>") + Program.from_text(
        tagged, source=f"{task.source} (#bias)") + "#show penalty/3. #show excluded__/1."
    outcome = cl.solve(program, max_models=1, shown_only=True)
    if not outcome.models:
        raise SymlearnError("the #bias programs have no answer set", file=task.source,
                            hint="a #bias program must derive penalty(Weight, Id) atoms and be satisfiable")
    penalties: dict[int, int] = {}
    excluded: set[int] = set()
    for atom in outcome.models[0]:
        if atom.name == "excluded__":
            excluded.add(atom.arguments[0].number)
        elif atom.name == "penalty" and len(atom.arguments) == 3:
            weight = atom.arguments[1]
            if weight.type != cl.SymbolType.Number:
                raise SymlearnError(f"#bias penalty weight must be an integer, got {weight}", file=task.source)
            rid = atom.arguments[0].number
            penalties[rid] = penalties.get(rid, 0) + weight.number
    kept = []
    for c in space.candidates:
        if c.index in excluded:
            continue
        kept.append(replace(c, index=len(kept), cost=penalties.get(c.index, 0)))
    notes = list(space.notes)
    if excluded:
        notes.append(f"#bias excluded {len(excluded)} rules")
    return HypothesisSpace(kept, space.truncated, notes)
