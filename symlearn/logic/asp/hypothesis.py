"""A learned (or hand-written) set of ASP rules and what it says about states and actions.

:class:`Hypothesis` keeps each rule in two forms: the text the user reads and edits (clingo syntax)
and its clingo AST. It knows the background program it was learned against, so it can answer the
questions the constraint-inference loop asks:

* :meth:`eliminates` -- does adding the rules remove every answer set of background + context?
* :meth:`allowed` -- may ``action`` be taken in a state given as facts?
* :meth:`forbidden_interpretations` -- over a finite domain program, the answer sets of B that
  are not answer sets of B ∪ H (the state-action pairs the rules forbid).

>>> h = Hypothesis([":- go(X), blocked(X)."], background="dir(n;s).")
>>> h.allowed("blocked(n).", "go(n)"), h.allowed("blocked(n).", "go(s)")
(False, True)
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import ParseError, SymlearnError
from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Part, Program, as_program, check_nesting, find_include

ASTType = cl.clingo.ast.ASTType


def rule_length(statement: cl.clingo.ast.AST) -> int:
    """ILASP-style length: head atoms (none for a constraint) plus body literals.

    A conditional body literal ``l : c1, ..., ck`` counts 1 + k.
    """
    if statement.ast_type != ASTType.Rule:
        raise SymlearnError(f"not a rule: {statement}")
    simple = cl.simple_rule_length(str(statement))  # most rules: from the printed text, no AST walk
    if simple is not None:
        return simple
    head = statement.head
    n_head = 0
    if head.ast_type == ASTType.Literal:
        atom = head.atom
        n_head = 0 if atom.ast_type == ASTType.BooleanConstant else 1
    elif head.ast_type in (ASTType.Disjunction, ASTType.Aggregate):
        n_head = len(head.elements)
    else:
        n_head = 1
    n_body = 0
    for element in statement.body:
        if element.ast_type == ASTType.ConditionalLiteral:
            n_body += 1 + len(element.condition)
        else:
            n_body += 1
    return n_head + n_body


def _normalise(text: str) -> str:
    return " ".join(text.split())


@dataclass
class Hypothesis:
    """Rules (clingo text), their cost, the background they refer to and where they came from."""

    rules: list[str]
    background: Program | str | None = None
    cost: int | None = None
    provenance: dict[str, Any] = field(default_factory=dict)
    # where each rule was read: (file, line, column), so clingo's errors (an unsafe variable)
    # name the user's file; None for rules built in code
    origins: list[tuple[str, int, int]] | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        self.rules = [_normalise(r) for r in self.rules]
        self.rules = [r if r.endswith(".") else r + "." for r in self.rules]
        self.background = as_program(self.background)
        self._asts = cl.parse_rules("\n".join(self.rules), source="<hypothesis>") if self.rules else []
        if len(self._asts) != len(self.rules):
            raise ParseError(f"expected {len(self.rules)} rules, clingo read {len(self._asts)}",
                             hint="give one rule per list entry")
        if self.cost is None:
            self.cost = sum(rule_length(s) for s in self._asts)

    # -- forms -----------------------------------------------------------------------------
    @property
    def asts(self) -> list[cl.clingo.ast.AST]:
        return list(self._asts)

    @property
    def lengths(self) -> list[int]:
        return [rule_length(s) for s in self._asts]

    @property
    def is_constraints_only(self) -> bool:
        return all(s.head.ast_type == ASTType.Literal and s.head.atom.ast_type == ASTType.BooleanConstant
                   for s in self._asts)

    def program(self) -> Program:
        """The rules as a program, one line per rule, located in their file when read from one."""
        if self.origins is None or len(self.origins) != len(self.rules):
            return Program.from_text("\n".join(self.rules), source="<hypothesis>")
        return Program(tuple(Part(rule, source, line, column)
                             for rule, (source, line, column) in zip(self.rules, self.origins)))

    def __getstate__(self) -> dict[str, Any]:
        # clingo AST objects point into this process: rebuild them from the text after unpickling
        state = dict(self.__dict__)
        state.pop("_asts", None)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._asts = cl.parse_rules("\n".join(self.rules), source="<hypothesis>") if self.rules else []

    def __len__(self) -> int:
        return len(self.rules)

    def __str__(self) -> str:
        return "\n".join(self.rules) if self.rules else "% (empty hypothesis)"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Hypothesis) and sorted(self.rules) == sorted(other.rules)

    # -- questions -------------------------------------------------------------------------
    def _with(self, context: Program | str | None) -> tuple[Program, Program]:
        base = self.background + as_program(context)
        return base, base + self.program()

    def eliminates(self, context: Program | str, *, timeout: float | None = None) -> bool:
        """True when background + context has an answer set and background + context + rules has none."""
        base, full = self._with(context)
        return cl.is_satisfiable(base, timeout=timeout) and not cl.is_satisfiable(full, timeout=timeout)

    def allowed(self, state_facts: Program | str, action: str, *, timeout: float | None = None) -> bool:
        """May ``action`` (an atom such as ``go(north)``) be taken in the state ``state_facts``?"""
        action = action.strip().rstrip(".")
        _base, full = self._with(as_program(state_facts) + f"{action}.")
        return cl.is_satisfiable(full, timeout=timeout)

    def forbidden_interpretations(self, domain: Program | str, *, show: Iterable[tuple[str, int]] | None = None,
                                  max_models: int = 0, timeout: float | None = None) -> list[frozenset[str]]:
        """Answer sets of background + ``domain`` that are not answer sets once the rules are added.

        ``domain`` generates the finite set of interpretations (e.g. a choice over states and
        actions). ``show`` limits each returned interpretation to the given predicates. For rules
        that are all integrity constraints this is one enumeration (the models where some rule
        body holds); otherwise both answer-set collections are enumerated and compared.
        """
        base, full = self._with(domain)
        keep = None if show is None else set(show)

        def view(model: Sequence[cl.Symbol]) -> frozenset[str]:
            return frozenset(str(s) for s in model
                             if keep is None or (s.name, len(s.arguments)) in keep)

        if self.is_constraints_only:
            fired = []
            for i, statement in enumerate(self._asts):
                body = "; ".join(str(b) for b in statement.body)
                fired.append(f"__violates({i}) :- {body}." if body else f"__violates({i}).")
            probe = base + Program.from_text("\n".join(fired) + "\n:- not __violates(_).\n", source="<hypothesis>")
            outcome = cl.solve(probe, max_models=max_models, timeout=timeout)
            self._check_complete(outcome, timeout, max_models)
            return sorted({view([s for s in m if s.name != "__violates"]) for m in outcome.models}, key=sorted)
        before = cl.solve(base, max_models=max_models, timeout=timeout)
        after = cl.solve(full, max_models=0, timeout=timeout)
        self._check_complete(before, timeout, max_models)
        self._check_complete(after, timeout, 0)
        kept = {frozenset(map(str, m)) for m in after.models}
        return sorted({view(m) for m in before.models if frozenset(map(str, m)) not in kept}, key=sorted)

    @staticmethod
    def _check_complete(outcome: cl.SolveOutcome, timeout: float | None, max_models: int) -> None:
        if not outcome.complete and not (max_models and len(outcome.models) >= max_models):
            raise cl.LimitExceededError(f"enumeration did not finish within {timeout} s",
                                        hint="raise the timeout or pass max_models")

    # -- files -----------------------------------------------------------------------------
    def lp_text(self, header: str | None = None, recheck: str | None = None) -> str:
        """The rules as editable ``.lp`` text with a comment header (what :meth:`to_lp` writes);
        ``recheck`` is the command the header recommends after an edit (default: ``symlearn ilp
        check`` with the task the rules were learned from, when known)."""
        if recheck is None:
            recheck = self._recheck("THIS.lp")
        lines = [f"% {line}" if line else "%" for line in (header or "learned by symlearn").splitlines()]
        lines.append(f"% cost (total rule length): {self.cost}")
        lines.append(f"% edit the rules below; re-check with: {recheck}")
        lines.append("")
        lines.extend(self.rules)
        return "\n".join(lines) + "\n"

    def to_lp(self, path: str | os.PathLike[str], header: str | None = None, recheck: str | None = None) -> Path:
        """Write the rules as an editable ``.lp`` file with a comment header whose last line is
        the command that re-checks them (naming the task they were learned from, when known)."""
        return write_text(path, self.lp_text(header, recheck if recheck is not None else self._recheck(path)))

    def _recheck(self, path: str | os.PathLike[str]) -> str:
        import shlex

        task = self.provenance.get("task")
        task = task if isinstance(task, str) and task and not task.startswith("<") else "TASK.las"
        return f"symlearn ilp check {shlex.quote(task)} {shlex.quote(str(path))}"

    @classmethod
    def from_lp(cls, path: str | os.PathLike[str], background: Program | str | None = None) -> Hypothesis:
        """Read rules back from an ``.lp`` file (comments ignored); errors point at the file."""
        program = Program.from_file(path, expand=False)
        return cls.from_text(program.text, source=str(path), background=background)

    @classmethod
    def from_text(cls, text: str, source: str = "<hypothesis>",
                  background: Program | str | None = None) -> Hypothesis:
        check_nesting(text, source)
        include = find_include(text)
        if include is not None:
            raise ParseError("#include is not allowed in a hypothesis", file=source, line=include[0],
                             column=include[1], hint="put the rules themselves in the file")
        statements = cl.parse_rules(text, source=source)
        lines = text.splitlines()
        rules = []
        origins = []
        for statement in statements:
            loc = statement.location.begin
            if statement.ast_type.name in cl.UNSUPPORTED_STATEMENTS:
                raise cl.unsupported_feature(statement, Program.from_text(text, source=source))
            if statement.ast_type != ASTType.Rule:
                raise ParseError(f"only rules are allowed in a hypothesis, found: {statement}",
                                 file=source, line=loc.line, column=loc.column,
                                 hint="a rule file holds rules such as ':- p(X), q(X).'; delete this line (a "
                                      "directive such as #show or #const belongs in the background)")
            rules.append(_slice(lines, statement.location))
            origins.append((source, loc.line, loc.column))
        return cls(rules, background=background, provenance={"source": source}, origins=origins)


def _slice(lines: list[str], location: Any) -> str:
    begin, end = location.begin, location.end
    if begin.line == end.line:
        return lines[begin.line - 1][begin.column - 1:end.column - 1]
    chunk = [lines[begin.line - 1][begin.column - 1:]]
    chunk.extend(lines[begin.line:end.line - 1])
    chunk.append(lines[end.line - 1][:end.column - 1])
    text = " ".join(line.split("%", 1)[0] if "%" in line else line for line in chunk)
    return text
