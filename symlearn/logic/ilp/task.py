"""An ILP learning task: background, examples and the language bias.

Semantics of examples follow ILASP's context-dependent partial interpretations: an example
``(inclusions, exclusions, context)`` is *accepted* by a program P when P ∪ context has an answer
set containing every inclusion and no exclusion. A positive example must be accepted by B ∪ H, a
negative one must not be.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from symlearn.logic.asp.clingo_adapter import Symbol
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.modes import ModeDeclaration

DEFAULT_MAXV = 3
DEFAULT_MAX_BODY = 3


@dataclass(frozen=True)
class Example:
    id: str
    positive: bool
    inclusions: tuple[Symbol, ...] = ()
    exclusions: tuple[Symbol, ...] = ()
    context: Program = field(default_factory=Program)
    penalty: int | None = None  # None: must be covered (ILASP's infinite penalty)
    line: int | None = None

    @classmethod
    def from_facts(cls, id: str, positive: bool, facts: Sequence[str], penalty: int | None = None) -> Example:
        """An example whose context is a list of ground facts (``("at(1,2).", "go(north).")``)."""
        return cls(id, positive, context=Program.from_text(" ".join(facts), source=f"<example {id}>"),
                   penalty=penalty)

    @property
    def kind(self) -> str:
        return "pos" if self.positive else "neg"

    @property
    def facts(self) -> tuple[str, ...]:
        """The context's statements, one normalised string each (``"at(1,2)."``)."""
        from symlearn.logic.asp.clingo_adapter import parse_rules

        return tuple(str(s) for s in parse_rules(self.context.text, source=f"<example {self.id}>"))

    def to_text(self) -> str:
        """The example in ILASP syntax: ``#pos(id@penalty, {incl}, {excl}, { context }).``"""
        ident = self.id if self.penalty is None else f"{self.id}@{self.penalty}"
        inclusions = ", ".join(map(str, self.inclusions))
        exclusions = ", ".join(map(str, self.exclusions))
        context = self.context.text.strip()
        return f"#{self.kind}({ident}, {{{inclusions}}}, {{{exclusions}}}, {{ {context} }})."

    def describe(self) -> str:
        return f"#{self.kind}({self.id}) at line {self.line}" if self.line else f"#{self.kind}({self.id})"


@dataclass
class ILPTask:
    background: Program
    examples: list[Example]
    modeh: list[ModeDeclaration] = field(default_factory=list)
    modeb: list[ModeDeclaration] = field(default_factory=list)
    modec: list[ModeDeclaration] = field(default_factory=list)
    constants: dict[str, list[Symbol]] = field(default_factory=dict)
    maxv: int | None = None
    max_penalty: int | None = None
    bias: list[str] = field(default_factory=list)  # #bias scoring programs (FastLAS style)
    max_body: int = DEFAULT_MAX_BODY
    source: str = "<task>"
    # "ilasp": a #modeb atom may also be used negated unless flagged (positive);
    # "fastlas": every mode literal is used exactly as written (write #modeb(not p) for negation)
    dialect: str = "ilasp"

    @property
    def positives(self) -> list[Example]:
        return [e for e in self.examples if e.positive]

    @property
    def negatives(self) -> list[Example]:
        return [e for e in self.examples if not e.positive]

    @property
    def n_variables(self) -> int:
        return DEFAULT_MAXV if self.maxv is None else self.maxv

    @property
    def constraints_only(self) -> bool:
        """Without ``#modeh`` the hypothesis space holds integrity constraints only."""
        return not self.modeh

    def with_background(self, extra: Sequence[Program]) -> ILPTask:
        background = self.background
        for program in extra:
            background = background + program
        copy = ILPTask(**{**self.__dict__})
        copy.background = background
        return copy

    def summary(self) -> dict:
        return {"source": self.source, "positives": len(self.positives), "negatives": len(self.negatives),
                "modeh": [str(m) for m in self.modeh], "modeb": [str(m) for m in self.modeb],
                "modec": [str(m) for m in self.modec], "maxv": self.n_variables,
                "max_body": self.max_body, "max_penalty": self.max_penalty, "dialect": self.dialect,
                "constants": {k: [str(v) for v in vs] for k, vs in self.constants.items()}}
