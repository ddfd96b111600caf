"""Arguments of a rule file's atoms that can never match: the other silent mistake of an edited rule.

A rule atom of a defined predicate still never holds when one of its arguments is a value the
predicate never takes: ``:- add(R), in_flask(S), reaction(R, S, "explosive").`` where the
background says ``reaction("Na", "H2O", explosive)`` (a string for a constant), or
``:- fly(Est).`` (no ``fly(est)`` exists)... except that ``Est`` starts with a capital letter, so
it is a *variable*, which matches every value: the rule forbids every flight. clingo accepts both.
:func:`unmatched_arguments` compares each constant argument of a rule's body atoms with the
values the predicate takes at that position (from the answer sets the caller gives), and each
variable that occurs once in its rule with those values written in lowercase, and says which
value was probably meant.

>>> from symlearn.logic.asp.program import Program
>>> rules = Program.from_text(':- fly(East).\\n:- reaction(R, S, "explosive"), in(R), in(S).', source="r.lp")
>>> values = {("fly", 1): [{"east", "west"}], ("reaction", 3): [{'"Na"'}, {'"H2O"'}, {"explosive"}]}
>>> for u in unmatched_arguments(rules, values):
...     print(u.line, u.column, u.message())
1 8 variable East occurs nowhere else in its rule, so it matches every value of fly/1's argument 1; did you mean the constant east?
2 19 reaction/3 never has "explosive" as argument 3 (it has: explosive), so the atom is always false; did you mean explosive?
"""

from __future__ import annotations

import difflib
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import clingo.ast

from symlearn.logic.asp.clingo_adapter import parse_statements
from symlearn.logic.asp.program import Program

__all__ = ["UnmatchedArgument", "argument_values", "unmatched_arguments"]

Values = Mapping[tuple[str, int], Sequence[set[str]]]
_SHOWN = 5  # values listed in a message


@dataclass(frozen=True)
class UnmatchedArgument:
    """A rule atom's argument that no value of its predicate matches (``variable`` False), or a
    variable used once whose name is one of those values in lowercase (``variable`` True)."""

    predicate: str  # name/arity
    position: int  # 1-based
    written: str
    variable: bool
    known: tuple[str, ...]  # the values the predicate takes there (a few)
    suggestion: str | None
    file: str | None
    line: int
    column: int

    def message(self) -> str:
        if self.variable:
            return (f"variable {self.written} occurs nowhere else in its rule, so it matches every value of "
                    f"{self.predicate}'s argument {self.position}; did you mean the constant {self.suggestion}?")
        text = (f"{self.predicate} never has {self.written} as argument {self.position} (it has: "
                f"{', '.join(self.known)}), so the atom is always false")
        return text + (f"; did you mean {self.suggestion}?" if self.suggestion else "")

    def as_dict(self) -> dict:
        return {"predicate": self.predicate, "file": self.file, "line": self.line, "column": self.column,
                "did_you_mean": self.suggestion, "message": self.message()}


def argument_values(atoms: Iterable[clingo.Symbol]) -> dict[tuple[str, int], list[set[str]]]:
    """``{(name, arity): [values at position 1, ...]}`` of ground atoms, values as clingo prints them."""
    values: dict[tuple[str, int], list[set[str]]] = {}
    for atom in atoms:
        if atom.type != clingo.SymbolType.Function or not atom.name:
            continue
        slots = values.setdefault((atom.name, len(atom.arguments)), [set() for _ in atom.arguments])
        for slot, argument in zip(slots, atom.arguments):
            slot.add(str(argument))
    return values


def unmatched_arguments(rules: Program, values: Values) -> list[UnmatchedArgument]:
    """The body atoms' arguments of ``rules`` that ``values`` (:func:`argument_values` of every
    atom that can hold) says never match, in file order. Predicates without values are left to
    :func:`symlearn.logic.asp.predicates.undefined_predicates`."""
    found: list[UnmatchedArgument] = []

    def statement(node: clingo.ast.AST) -> None:
        if node.ast_type != clingo.ast.ASTType.Rule:
            return
        counts = Counter(v.name for v in _variables(node))
        for literal in node.body:
            if literal.ast_type != clingo.ast.ASTType.Literal or literal.atom.ast_type != clingo.ast.ASTType.SymbolicAtom:
                continue
            atom = literal.atom.symbol
            if atom.ast_type != clingo.ast.ASTType.Function or (atom.name, len(atom.arguments)) not in values:
                continue
            slots = values[(atom.name, len(atom.arguments))]
            for position, (argument, known) in enumerate(zip(atom.arguments, slots), start=1):
                problem = _check(argument, known, counts)
                if problem is not None:
                    written, variable, suggestion = problem
                    file, line, column = rules.locate(argument.location.begin.line, argument.location.begin.column)
                    shown = sorted(known, key=_order)
                    shown = shown[:_SHOWN] + (["..."] if len(shown) > _SHOWN else [])
                    found.append(UnmatchedArgument(f"{atom.name}/{len(atom.arguments)}", position, written, variable,
                                                   tuple(shown), suggestion, file, line, column))

    parse_statements(rules.text, statement, program=rules)
    return found


def _order(value: str) -> tuple:
    """Numbers first, in numeric order, then the other values as text."""
    try:
        return (0, int(value), "")
    except ValueError:
        return (1, 0, value)


def _check(argument: clingo.ast.AST, known: set[str], counts: Counter) -> tuple[str, bool, str | None] | None:
    kind = argument.ast_type
    if kind == clingo.ast.ASTType.Variable:
        # a variable used once matches anything; written like a value in capitals, it was meant as one
        if counts[argument.name] == 1 and argument.name != "_":
            for value in (argument.name.lower(), argument.name[:1].lower() + argument.name[1:]):
                if value in known:
                    return argument.name, True, value
        return None
    if not _ground(argument):
        return None
    written = str(argument)
    if written in known:
        return None
    # a string for a constant (or the reverse) first, then the closest spelling
    twin = written[1:-1] if written.startswith('"') else f'"{written}"'
    suggestion = twin if twin in known else next(iter(difflib.get_close_matches(written, sorted(known), n=1)), None)
    return written, False, suggestion


def _ground(term: clingo.ast.AST) -> bool:
    """A constant, number or string (maybe negated), or a function of those: what a value prints as."""
    kind = term.ast_type
    if kind == clingo.ast.ASTType.SymbolicTerm:
        return True
    if kind == clingo.ast.ASTType.UnaryOperation:
        return term.operator_type == clingo.ast.UnaryOperator.Minus and term.argument.ast_type == \
            clingo.ast.ASTType.SymbolicTerm and term.argument.symbol.type == clingo.SymbolType.Number
    if kind == clingo.ast.ASTType.Function:
        return not term.external and all(_ground(a) for a in term.arguments)
    return False


def _variables(node: clingo.ast.AST) -> Iterable[clingo.ast.AST]:
    """Every Variable node under ``node`` (head, body, conditions, comparisons)."""
    stack = [node]
    while stack:
        current = stack.pop()
        if current.ast_type == clingo.ast.ASTType.Variable:
            yield current
            continue
        for key in current.child_keys:
            child = getattr(current, key)
            if isinstance(child, clingo.ast.AST):
                stack.append(child)
            elif child is not None and not isinstance(child, (str, int)):
                stack.extend(c for c in child if isinstance(c, clingo.ast.AST))
