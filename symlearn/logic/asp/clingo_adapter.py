"""The one place symlearn talks to clingo: grounding, solving, enumeration, optimisation.

Everything else in ``symlearn`` hands a :class:`~symlearn.logic.asp.program.Program` (text plus a
map back to its source files) to the functions here. Keeping every clingo call in this module means
timeouts, interrupts and error translation are handled once:

* clingo reports syntax errors and unsafe variables through its logger callback, with positions in
  the text it was given (``<block>:LINE:COL``). :func:`control_for` collects those messages and
  :func:`_raise_clingo_error` turns the first error into a :class:`~symlearn.errors.ParseError`
  located in *our* file via ``Program.locate``.
* every solve runs asynchronously and is cancelled when its time budget is spent; the caller is
  told whether the search was exhausted (``complete``) or cut short.

>>> from symlearn.logic.asp.program import Program
>>> [sorted(map(str, m)) for m in answer_sets(Program.from_text("{a}. b :- not a."))]
[['b'], ['a']]
"""

from __future__ import annotations

import bisect
import copyreg
import math
import re
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import clingo
import clingo.ast

from symlearn.errors import LimitExceededError, ParseError

from symlearn.logic.asp.program import Part, Program

Symbol = clingo.Symbol


def _symbol_from_text(text: str) -> Symbol:
    return clingo.parse_term(text)


def _reduce_symbol(symbol: Symbol):
    return _symbol_from_text, (str(symbol),)


# clingo's own pickling of a Symbol copies a pointer into this process's symbol table, which
# crashes another process (the worker of symlearn.worker); pickle the text instead
copyreg.pickle(clingo.Symbol, _reduce_symbol)

#: clingo statement kinds a learning task cannot hold, with the name users write
UNSUPPORTED_STATEMENTS = {
    "Minimize": "#minimize/#maximize", "Heuristic": "#heuristic", "ProjectAtom": "#project",
    "ProjectSignature": "#project", "External": "#external", "Edge": "#edge", "TheoryDefinition": "#theory",
    "Script": "#script", "Defined": "#defined",
}

# "<block>:3:5-9: error: syntax error, unexpected ..." ; also "<block>:3:5-4:2: ..." spans
_POSITION = re.compile(r"^<(?:block|string)>:(\d+):(\d+)(?:-\d+(?::\d+)?)?:\s*(error|warning|info|note):\s*(.*)$")


@dataclass
class SolveOutcome:
    """Models found by one solve call and whether the search space was exhausted."""

    models: list[list[Symbol]] = field(default_factory=list)
    costs: list[list[int]] = field(default_factory=list)
    complete: bool = True
    satisfiable: bool | None = None
    seconds: float = 0.0

    @property
    def optimal(self) -> bool:
        """For an optimisation: the last model is proven optimal."""
        return self.complete and bool(self.models)


class _Messages:
    def __init__(self) -> None:
        self.items: list[tuple[clingo.MessageCode, str]] = []

    def __call__(self, code: clingo.MessageCode, message: str) -> None:
        self.items.append((code, message))


def control_for(arguments: Sequence[str] = ()) -> tuple[clingo.Control, _Messages]:
    """A fresh ``clingo.Control`` whose messages are collected instead of printed."""
    messages = _Messages()
    ctl = clingo.Control(["--warn=none", *arguments], logger=messages)
    return ctl, messages


def _code_end(text: str, line: int, column: int) -> tuple[int, int] | None:
    """The position just after the last character of code before ``(line, column)`` of ``text``
    (``%`` comments and blanks skipped), when it lies on an earlier line and is no ``.``: where a
    rule without its terminating dot ends. None otherwise."""
    lines = text.split("\n")
    for at in range(min(line, len(lines)) - 1, -1, -1):
        code = lines[at][: column - 1] if at == line - 1 else lines[at]
        code = _strip_comment(code).rstrip()
        if code:
            if at == line - 1 or code.endswith("."):
                return None
            return at + 1, len(code) + 1
    return None


def _strip_comment(code: str) -> str:
    """``code`` without a trailing ``%`` comment (a ``%`` inside a string is kept)."""
    quoted = False
    for i, char in enumerate(code):
        if char == '"' and (i == 0 or code[i - 1] != "\\"):
            quoted = not quoted
        elif char == "%" and not quoted:
            return code[:i]
    return code


def _unsafe_variables(rest: list[str]) -> list[tuple[str, int, int]]:
    """``(variable, line, column)`` of clingo's "'X' is unsafe" notes."""
    found = []
    for note in rest:
        match = _POSITION.match(note.strip())
        name = re.search(r"'([^']+)' is unsafe", note)
        if match and name:
            found.append((name.group(1), int(match.group(1)), int(match.group(2))))
    return found


def _raise_clingo_error(program: Program, messages: _Messages, fallback: str) -> None:
    for _code, text in messages.items:
        first, *rest = text.strip().splitlines() or [""]
        match = _POSITION.match(first)
        if not match or match.group(3) != "error":
            continue
        line, column, message = int(match.group(1)), int(match.group(2)), match.group(4)
        if message.startswith("syntax error"):
            end = _code_end(program.text, line, column)
            if end is not None:  # clingo stumbles on the next rule; the mistake is where this one ends
                source, src_line, src_col = program.locate(*end)
                raise ParseError(f"syntax error: the rule ending here has no '.' (clingo: {message})",
                                 file=source, line=src_line, column=src_col,
                                 hint="end every rule with a '.'")
        unsafe = _unsafe_variables(rest) if message.startswith("unsafe variables") else []
        if unsafe:
            names = ", ".join(dict.fromkeys(v for v, _, _ in unsafe))
            source, src_line, src_col = program.locate(unsafe[0][1], unsafe[0][2])
            several = "s" if "," in names else ""
            raise ParseError(f"unsafe variable{several} {names}: a variable must occur in a positive body atom of "
                             "its rule (a comparison, a negated atom or the head alone does not bind it)",
                             file=source, line=src_line, column=src_col,
                             hint=f"add a positive atom that binds {names} to the body, or use a variable "
                                  "that one already binds")
        detail = " ".join(r.strip() for r in rest if r.strip() and not r.startswith(("<block>", "<string>")))
        notes = [r.split("note:", 1)[1].strip() for r in rest if "note:" in r]
        source, src_line, src_col = program.locate(line, column)
        full = message.rstrip(":")
        if notes:
            full = re.sub(r"\s+in$", "", full)  # "unsafe variables in:" is followed by the rule, dropped here
            full += " (" + "; ".join(notes) + ")"
        elif detail:
            full += ": " + detail
        raise ParseError(f"clingo: {full}", file=source, line=src_line, column=src_col,
                         hint=_syntax_hint(program.text, line, column, message))
    raise ParseError(f"clingo: {fallback}", file=program.first_source)


_DIRECTIVES = ("#modeb", "#modeh", "#modec", "#pos", "#neg", "#constant", "#maxv", "#max_penalty", "#bias",
               "#include", "#const", "#show", "#program")


def _syntax_hint(text: str, line: int, column: int, message: str) -> str:
    """What a clingo syntax error at ``line:column`` of ``text`` most likely means, in the user's
    terms: the mistakes people bring from other languages, which clingo words in its grammar's."""
    import difflib

    lines = text.splitlines()
    here = lines[line - 1] if 0 < line <= len(lines) else ""
    rest = here[max(column - 1, 0):]
    if rest.startswith("//") or here.lstrip().startswith("//"):
        return "comments in ASP start with '%' (a block comment is %* ... *%)"
    if re.search(r"\d\.\d", here[max(column - 4, 0):column + 3]):
        return ("ASP has no decimal numbers: write 0.5 as a scaled integer (5 in tenths) or a string (\"0.5\"); "
                "compare scaled integers in rules")
    # "Waiting(P)" or ":- Finish, ...": a name with a capital is a variable, and a variable can be
    # neither called nor a literal, so clingo stops at the "(" or "," after it; say so in the user's terms
    before = here[max(column - 201, 0):max(column - 1, 0)]  # a window: a search anchored at "$" is quadratic
    called = re.search(r"(?<![A-Za-z0-9_'])([A-Z_][A-Za-z0-9_']*)\s*$", before)
    literal = called and re.search(r"(:-|,|\bnot)\s*$", before[:called.start()]) and rest[:1] in (",", ".", ";")
    if called and (rest.startswith("(") or literal):
        return (f"{called.group(1)} starts with a capital letter or '_', which makes it a variable in ASP: "
                f"predicate names start with a lowercase letter (write {called.group(1)[:1].lower()}"
                f"{called.group(1)[1:]})")
    directive = re.match(r"#\w+", rest)
    if directive and "unexpected" in message:
        close = difflib.get_close_matches(directive.group(), _DIRECTIVES, n=1, cutoff=0.6)
        if close and close[0] != directive.group():
            return f"unknown directive {directive.group()}: did you mean {close[0]}?"
    return "check the ASP syntax at this position"


class _Stop(Exception):
    """Raised inside a clingo callback to stop it; the real exception is kept aside."""


#: comments and strings, where any character may stand, else one character clingo cannot take; an
#: unclosed %* runs to the end (clingo refuses it), so it is scanned once, not from every later %*
_CODE_CHARACTER = re.compile(r'%\*(?:.*?\*%|.*\Z)|%[^\n]*|"(?:[^"\\\n]|\\.)*"|[^\x01-\x7f]', re.S)
_SPELLINGS = {"\u2212": "-", "\u2013": "-", "\u2264": "<=", "\u2265": ">=", "\u2260": "!=", "\u00ac": "not",
              "\u2018": "'", "\u2019": "'", "\u201c": '"', "\u201d": '"', "\u00a0": "a plain space"}


def check_characters(program: Program, text: str | None = None) -> None:
    """Refuse, at its place in the user's file, a character clingo must never see: a NUL (clingo
    reads text up to it and silently drops the rest) and, outside strings and comments, any
    non-ASCII character (ASP names, numbers and operators are ASCII; clingo's error message
    would cut the character's UTF-8 bytes apart, and decoding that message aborts the process).
    A plain ``isascii`` test first: almost every program passes it at C speed."""
    text = program.text if text is None else text
    if text.isascii() and "\x00" not in text:
        return
    for found in _CODE_CHARACTER.finditer(text):
        char = found.group()
        if len(char) != 1 and "\x00" not in char:
            continue
        offset = found.start() + (char.find("\x00") if len(char) != 1 else 0)
        char = text[offset]
        line = text.count("\n", 0, offset) + 1
        column = offset - (text.rfind("\n", 0, offset) + 1) + 1
        source, src_line, src_col = program.locate(line, column)
        if char == "\x00":
            raise ParseError("a NUL character (byte 0) in the program: clingo would ignore everything after it",
                             file=source, line=src_line, column=src_col, hint="remove the NUL byte")
        spelling = _SPELLINGS.get(char)
        hint = f"write {spelling!r}" if spelling and len(spelling) <= 3 else (
            f"write {spelling}" if spelling else "non-ASCII text belongs in a quoted string or a % comment")
        raise ParseError(f"unexpected character {char!r} (U+{ord(char):04X}): ASP names, numbers and operators "
                         "are ASCII", file=source, line=src_line, column=src_col, hint=hint)


def parse_statements(text: str, callback: Callable[[clingo.ast.AST], None], *,
                     program: Program | None = None, messages: _Messages | None = None) -> None:
    """``clingo.ast.parse_string`` that lets exceptions of ``callback`` through unchanged.

    clingo re-raises a callback's exception as ``type(exc)(exc)``, which turns our errors into
    exceptions whose message is an exception object (``__str__ returned non-string``); here the
    callback's exception is kept and re-raised once clingo has stopped. Syntax errors become
    :class:`ParseError` located through ``program`` (default: ``text`` itself)."""
    failure: list[BaseException] = []
    messages = _Messages() if messages is None else messages
    check_characters(program if program is not None else Program.from_text(text), text)

    def guarded(statement: clingo.ast.AST) -> None:
        if failure:
            return
        try:
            callback(statement)
        except BaseException as exc:  # noqa: BLE001 - re-raised below, outside clingo
            failure.append(exc)
            raise _Stop from None

    try:
        clingo.ast.parse_string(text, guarded, logger=messages)
    except BaseException as exc:  # noqa: BLE001
        if failure:
            raise failure[0] from None
        if isinstance(exc, RuntimeError):
            _raise_clingo_error(program if program is not None else Program.from_text(text), messages, str(exc))
        raise


def unsupported_feature(statement: clingo.ast.AST, program: Program) -> ParseError:
    """``unsupported feature #minimize at line L`` for ``statement`` of ``program``, located in the
    user's file."""
    kind = statement.ast_type.name
    name = UNSUPPORTED_STATEMENTS.get(kind, kind)
    loc = statement.location.begin
    if kind == "Script":
        name = f"#script ({getattr(statement, 'name', '') or 'python'})"
    elif kind == "Minimize":
        lines = program.text.split("\n", loc.line)
        written = lines[loc.line - 1][loc.column - 1:] if len(lines) >= loc.line else ""
        name = "weak constraint (:~)" if written.startswith(":~") else "#minimize/#maximize"
    source, line, column = program.locate(loc.line, loc.column)
    return ParseError(f"unsupported feature {name} at line {line}", file=source, line=line, column=column,
                      hint="see docs/ILP.md for the supported subset of clingo programs")


def check_no_scripts(program: Program) -> None:
    """Refuse ``#script`` blocks: symlearn never runs code from a file (and the clingo wheel has no
    Python or Lua inside anyway). A plain substring test first: almost every program has none."""
    if "#script" not in program.text:
        return

    def visit(statement: clingo.ast.AST) -> None:
        if statement.ast_type == clingo.ast.ASTType.Script:
            raise unsupported_feature(statement, program)

    parse_statements(program.text, visit, program=program)


def check_supported(program: Program, *, allowed: Iterable[str] = ()) -> None:
    """Refuse the statements of :data:`UNSUPPORTED_STATEMENTS` (except those ``allowed``) with
    ``unsupported feature X at line L`` in the user's file. Only text with a ``#`` directive or a
    weak constraint is parsed."""
    text = program.text
    if "#" not in text and ":~" not in text:
        return
    refused = set(UNSUPPORTED_STATEMENTS) - set(allowed)

    def visit(statement: clingo.ast.AST) -> None:
        if statement.ast_type.name in refused:
            raise unsupported_feature(statement, program)

    parse_statements(text, visit, program=program)


def ground(program: Program, arguments: Sequence[str] = (), *,
           context: object | None = None) -> clingo.Control:
    """Add ``program`` to a new control object and ground it; clingo errors become ParseError."""
    check_no_scripts(program)
    check_characters(program)
    ctl, messages = control_for(arguments)
    try:
        ctl.add("base", [], program.text)
    except RuntimeError as exc:
        _raise_clingo_error(program, messages, str(exc))
    try:
        ctl.ground([("base", [])], context=context)
    except RuntimeError as exc:
        _raise_clingo_error(program, messages, str(exc))
    return ctl


def wait_seconds(timeout: float | None) -> float:
    """The argument for ``SolveHandle.wait``: -1 (no limit) for None, ``inf`` and anything above
    a billion seconds, which clingo would turn into a clock deadline that overflows into the past."""
    if timeout is None or not math.isfinite(timeout) or timeout > 1e9:
        return -1.0
    return max(float(timeout), 0.0)


def _solve(ctl: clingo.Control, *, timeout: float | None, on_model: Callable[[clingo.Model], bool | None],
           assumptions: Sequence[tuple[Symbol, bool]] = ()) -> tuple[bool, bool | None]:
    """Run one solve; returns (complete, satisfiable). Cancels when ``timeout`` seconds pass."""
    with ctl.solve(async_=True, on_model=on_model, assumptions=list(assumptions)) as handle:
        finished = handle.wait(wait_seconds(timeout))
        if not finished:
            handle.cancel()
            handle.wait()
        result = handle.get()
    complete = bool(finished) and not result.interrupted and result.exhausted
    sat = True if result.satisfiable else (False if result.unsatisfiable else None)
    return complete, sat


def solve(program: Program, *, max_models: int = 0, timeout: float | None = None,
          project: bool = False, shown_only: bool = False, arguments: Sequence[str] = (),
          assumptions: Sequence[tuple[Symbol, bool]] = ()) -> SolveOutcome:
    """Enumerate answer sets (all when ``max_models`` is 0) of ``program``.

    ``shown_only`` returns the atoms selected by ``#show`` instead of every atom; ``project``
    enumerates distinct projections on the shown atoms.
    """
    args = [str(max_models)]
    if project:
        args.append("--project")
    args.extend(arguments)
    start = time.perf_counter()
    ctl = ground(program, args)
    outcome = SolveOutcome()

    def on_model(model: clingo.Model) -> None:
        outcome.models.append(sorted(model.symbols(shown=True) if shown_only else model.symbols(atoms=True)))

    remaining = None if timeout is None else max(0.0, timeout - (time.perf_counter() - start))
    outcome.complete, outcome.satisfiable = _solve(ctl, timeout=remaining, on_model=on_model, assumptions=assumptions)
    if max_models and len(outcome.models) >= max_models:
        outcome.complete = False if outcome.satisfiable is None else outcome.complete
    outcome.seconds = time.perf_counter() - start
    return outcome


def answer_sets(program: Program, *, max_models: int = 0, timeout: float | None = None,
                shown_only: bool = False) -> list[list[Symbol]]:
    """The answer sets of ``program`` (each a sorted list of atoms)."""
    return solve(program, max_models=max_models, timeout=timeout, shown_only=shown_only).models


def is_satisfiable(program: Program, *, timeout: float | None = None) -> bool:
    """Does ``program`` have an answer set? Raises LimitExceededError when undecided in time."""
    outcome = solve(program, max_models=1, timeout=timeout)
    if outcome.models:
        return True
    if outcome.satisfiable is False:
        return False
    raise LimitExceededError(f"clingo did not decide satisfiability within {timeout} s",
                             hint="raise the timeout")


def consequences(program: Program, *, timeout: float | None = None) -> tuple[list[Symbol], list[Symbol]] | None:
    """(brave, cautious) consequences of ``program``: the atoms true in some and in every answer
    set, from one grounding; None when it has no answer set. Raises LimitExceededError when
    clingo does not finish within ``timeout``."""
    start = time.perf_counter()
    ctl = ground(program)
    found = []
    for mode in ("brave", "cautious"):
        ctl.configuration.solve.enum_mode = mode
        ctl.configuration.solve.models = "0"
        last: list[list[Symbol]] = []
        left = None if timeout is None else max(0.0, timeout - (time.perf_counter() - start))
        complete, satisfiable = _solve(ctl, timeout=left,
                                       on_model=lambda model: last.append(list(model.symbols(atoms=True))))
        if satisfiable is False:
            return None
        if not complete:
            raise LimitExceededError(f"clingo did not find the {mode} consequences within {timeout} s",
                                     hint="raise the timeout")
        found.append(sorted(last[-1]))
    return found[0], found[1]


def optimize(program: Program, *, timeout: float | None = None, arguments: Sequence[str] = (),
             on_improvement: Callable[[list[Symbol], list[int]], None] | None = None,
             shown_only: bool = True) -> SolveOutcome:
    """Minimise the program's ``#minimize`` statements; the last model is the best found.

    ``complete`` is True when clingo proved the last model optimal within ``timeout``.
    """
    start = time.perf_counter()
    ctl = ground(program, ["--opt-mode=opt", *arguments])
    outcome = SolveOutcome()

    def on_model(model: clingo.Model) -> None:
        symbols = sorted(model.symbols(shown=True) if shown_only else model.symbols(atoms=True))
        cost = list(model.cost)
        outcome.models.append(symbols)
        outcome.costs.append(cost)
        if on_improvement is not None:
            on_improvement(symbols, cost)

    remaining = None if timeout is None else max(0.0, timeout - (time.perf_counter() - start))
    outcome.complete, outcome.satisfiable = _solve(ctl, timeout=remaining, on_model=on_model)
    outcome.seconds = time.perf_counter() - start
    return outcome


def ground_atoms(program: Program, signatures: Iterable[tuple[str, int]] | None = None) -> list[Symbol]:
    """Atoms that ground to *facts* of a stratified program (no solving needed).

    Used by the learner to read ``fires(R, E)`` relations computed in a single grounding.
    ``signatures`` restricts the answer to those predicates.
    """
    ctl = ground(program)
    atoms = ctl.symbolic_atoms
    if signatures is None:
        return sorted(a.symbol for a in atoms if a.is_fact)
    result = []
    for name, arity in signatures:
        result.extend(a.symbol for a in atoms.by_signature(name, arity) if a.is_fact)
    return sorted(result)


def parse_term(text: str) -> Symbol:
    """A ground clingo term (``on(1,2)``); raises ParseError on bad syntax."""
    if not text.isascii() or "\x00" in text:  # what clingo's own error message could not carry
        try:
            check_characters(Program.from_text(text))
        except ParseError as exc:
            raise ParseError(f"not a ground term: {text!r} ({exc.message})", hint=exc.hint) from None
    try:
        return clingo.parse_term(text, logger=lambda _c, _m: None)
    except RuntimeError as exc:
        raise ParseError(f"not a ground term: {text!r}") from exc


def parse_rules(text: str, source: str = "<rules>") -> list[clingo.ast.AST]:
    """The clingo AST statements of ``text`` (the leading ``#program base.`` dropped)."""
    statements: list[clingo.ast.AST] = []
    parse_statements(text, statements.append, program=Program.from_text(text, source=source))
    skip = {clingo.ast.ASTType.Program, getattr(clingo.ast.ASTType, "Comment", None)}
    return [s for s in statements if s.ast_type not in skip]


@dataclass(frozen=True)
class PredicateUse:
    """One predicate atom of a program: ``name/arity``, where (1-based, in the program's text),
    and whether the statement *defines* it (a head or a fact) or *uses* it (a body, a condition)."""

    name: str
    arity: int
    line: int
    column: int
    defines: bool


def _atom_uses(statement: clingo.ast.AST) -> list[PredicateUse]:
    """The predicate atoms of one statement, walked through clingo's AST (every kind of statement)."""
    found: list[PredicateUse] = []

    def atoms(node: Any, defines: bool) -> None:
        if not isinstance(node, clingo.ast.AST):
            if isinstance(node, (list, tuple)) or type(node).__name__ == "ASTSequence":
                for item in node:
                    atoms(item, defines)
            return
        if node.ast_type == clingo.ast.ASTType.SymbolicAtom:
            symbol = node.symbol
            if symbol.ast_type == clingo.ast.ASTType.UnaryOperation:  # classical negation -a
                symbol = symbol.argument
            if symbol.ast_type == clingo.ast.ASTType.Pool and symbol.arguments:  # dir(north;south)
                symbol = symbol.arguments[0]
            if symbol.ast_type == clingo.ast.ASTType.Function:
                begin = symbol.location.begin
                found.append(PredicateUse(symbol.name, len(symbol.arguments), begin.line, begin.column, defines))
            return
        for key in node.child_keys:
            if key in ("condition", "body"):  # conditions of head elements and bodies use atoms
                atoms(getattr(node, key), False)
            else:
                atoms(getattr(node, key), defines)

    if statement.ast_type == clingo.ast.ASTType.Rule:
        atoms(statement.head, True)
        atoms(statement.body, False)
    return found


class PredicateUses:
    """Every predicate atom of a program's statements, in the order :func:`predicate_uses` lists
    them: ``signatures[i]`` = (name, arity, defines) of the i-th; :meth:`located` its position.

    A simple rule's atoms (see :func:`_simple_rule`) are read from its printed text and located
    only on demand, by the AST walk of that one statement, so a rule file of many rules costs
    a parse and a string split per rule; a message naming a position (a misspelt predicate)
    locates a handful of atoms."""

    def __init__(self, program: Program) -> None:
        self.signatures: list[tuple[str, int, bool]] = []
        self._statement_of: list[int] = []  # per atom: index into _statements
        self._statements: list[clingo.ast.AST] = []
        self._first: list[int] = []  # per statement: index of its first atom
        self._walked: dict[int, list[PredicateUse]] = {}

        def statement(node: clingo.ast.AST) -> None:
            if node.ast_type != clingo.ast.ASTType.Rule:
                return
            index = len(self._statements)
            self._statements.append(node)
            self._first.append(len(self.signatures))
            simple = _simple_rule(str(node))
            if simple is None:
                uses = self._walked[index] = _atom_uses(node)
                found = [(u.name, u.arity, u.defines) for u in uses]
            else:
                head, body = simple
                found = [(head[1], head[3], True)] if head is not None else []
                found += [(b[1], b[3], False) for b in body if not isinstance(b, str)]
            self.signatures.extend(found)
            self._statement_of.extend([index] * len(found))

        parse_statements(program.text, statement, program=program)

    def __len__(self) -> int:
        return len(self.signatures)

    def located(self, index: int) -> PredicateUse:
        """The ``index``-th atom with its line and column in the program's text."""
        statement = self._statement_of[index]
        if statement not in self._walked:
            self._walked[statement] = _atom_uses(self._statements[statement])
        return self._walked[statement][index - self._first[statement]]


def predicate_uses(program: Program) -> list[PredicateUse]:
    """Every predicate atom of ``program``'s statements (comparisons and built-ins are not atoms);
    syntax errors raise :class:`ParseError` located in the program's files. (Many statements and
    few positions wanted: :class:`PredicateUses`.)"""
    uses = PredicateUses(program)
    return [uses.located(i) for i in range(len(uses))]


Function = clingo.Function
Number = clingo.Number
String = clingo.String
SymbolType = clingo.SymbolType


# -- program rewriting -----------------------------------------------------------------------------

class _Tagger(clingo.ast.Transformer):
    """Add ``tag`` as the first argument of every predicate atom; guard every rule body."""

    def __init__(self, tag: clingo.ast.AST, guard: list[clingo.ast.AST], constraint_head: str | None = None,
                 untagged: frozenset[str] = frozenset()) -> None:
        self.tag = tag
        self.guard = guard
        self.constraint_head = constraint_head
        self.untagged = untagged

    def visit_SymbolicAtom(self, atom: clingo.ast.AST) -> clingo.ast.AST:
        term = atom.symbol
        loc = term.location
        if getattr(term, "name", None) in self.untagged:
            return atom
        if term.ast_type == clingo.ast.ASTType.Function and term.name:
            return atom.update(symbol=term.update(arguments=[self.tag, *term.arguments]))
        if term.ast_type == clingo.ast.ASTType.SymbolicTerm and term.symbol.type == clingo.SymbolType.Function \
                and not term.symbol.arguments:
            sign = term.symbol.negative
            func = clingo.ast.Function(loc, term.symbol.name, [self.tag], 0)
            if sign:
                func = clingo.ast.UnaryOperation(loc, clingo.ast.UnaryOperator.Minus, func)
            return atom.update(symbol=func)
        if term.ast_type == clingo.ast.ASTType.UnaryOperation:  # classical negation -p(X)
            inner = self.visit_SymbolicAtom(clingo.ast.SymbolicAtom(term.argument)).symbol
            return atom.update(symbol=term.update(argument=inner))
        if term.ast_type == clingo.ast.ASTType.Pool:
            return atom.update(symbol=term.update(arguments=[
                self.visit_SymbolicAtom(clingo.ast.SymbolicAtom(a)).symbol for a in term.arguments]))
        raise ParseError(f"cannot rewrite atom {atom} for example tagging")

    def visit_Rule(self, rule: clingo.ast.AST) -> clingo.ast.AST:
        head = rule.head
        if self.constraint_head and head.ast_type == clingo.ast.ASTType.Literal \
                and head.atom.ast_type == clingo.ast.ASTType.BooleanConstant and not head.atom.value:
            loc = head.location
            atom = clingo.ast.SymbolicAtom(clingo.ast.Function(loc, self.constraint_head, [self.tag], 0))
            head = clingo.ast.Literal(loc, clingo.ast.Sign.NoSign, atom)
        else:
            head = self.visit(head)
        rule = rule.update(head=head, body=[self.visit(b) for b in rule.body])
        return rule.update(body=[*rule.body, *self.guard])


# Rules whose every element is a plain atom, a comparison or #true/#false are copied from their
# printed text: walking the AST through clingo's Python bindings (a Transformer visit, ``update``
# per node) costs about 1 ms a rule, the text about 20 us. The printed text is clingo's own
# (``str(statement)``: canonical spacing, ``; `` between body elements, binary terms in
# parentheses), so the few forms read here are exact; anything else (aggregates, conditions,
# pools, disjunctions, strings, ...) goes the AST way. tests/logic/asp/test_tagging_fast_path.py
# compares both ways on thousands of generated rules.
_ATOM_TEXT = re.compile(r"(-?)(_*[a-z][A-Za-z0-9_']*)(?:\((.+)\))?\Z")
_NOT_SIMPLE = re.compile(r'["{}\[\]|&@:; ]|#(?!(?:inf|sup)\b)')  # in an atom's arguments
_COMPARISON = re.compile(r"[^\s]+(?: (?:=|!=|<|<=|>|>=) [^\s]+)+\Z")
_NOT_COMPARISON = re.compile(r'["{}\[\]|&@:;]|#(?!(?:inf|sup)\b)')


def _arity(args: str) -> int | None:
    """Number of arguments in ``args`` (the text between an atom's parentheses), None when its
    parentheses do not balance."""
    if "(" not in args:
        return None if ")" in args else args.count(",") + 1
    depth, commas = 0, 0
    for char in args:
        if char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
            if depth < 0:
                return None
        elif char == "," and not depth:
            commas += 1
    return commas + 1 if depth == 0 else None


def _simple_element(text: str, head: bool) -> tuple[str, str, str | None, int] | str | None:
    """An atom of a rule's printed text as (prefix, name, argument text or None, arity), where
    ``prefix`` is its ``not ``s and classical ``-``; a comparison or ``#true``/``#false`` of a body
    as its text; None for anything else."""
    rest = text
    nots = 0
    while rest.startswith("not "):
        rest = rest[4:]
        nots += 1
    if head and nots:
        return None
    if rest in ("#true", "#false"):
        return None if head else text
    match = _ATOM_TEXT.match(rest)
    if match is not None:
        minus, name, args = match.groups()
        if args is None:
            return text[:len(text) - len(rest)] + minus, name, None, 0
        if _NOT_SIMPLE.search(args) is None:
            arity = _arity(args)
            if arity is not None:
                return text[:len(text) - len(rest)] + minus, name, args, arity
        return None
    if not head and _COMPARISON.match(rest) and _NOT_COMPARISON.search(rest) is None:
        return text
    return None


def _simple_rule(text: str) -> tuple[tuple[str, str, str | None, int] | None, list] | None:
    """A rule's printed text as (head atom or None for ``#false``, body elements) when every
    element is simple (:func:`_simple_element`), else None."""
    if not text.endswith("."):
        return None
    head_text, separator, body_text = text[:-1].partition(" :- ")
    if head_text == "#false":
        head = None
    else:
        head = _simple_element(head_text, True)
        if head is None:
            return None
    body = []
    if separator:
        for piece in body_text.split("; "):
            element = _simple_element(piece, False)
            if element is None:
                return None
            body.append(element)
    return head, body


def simple_rule_length(text: str) -> int | None:
    """ILASP length (head atoms + body literals) of the rule printed as ``text`` when it is a
    simple rule (:func:`_simple_rule`: no conditions, aggregates or disjunctions), else None."""
    simple = _simple_rule(text)
    if simple is None:
        return None
    head, body = simple
    return (head is not None) + len(body)


def _tag_simple(text: str, tag: str, guard: Sequence[str], constraint_head: str | None,
                untagged: frozenset[str]) -> str | None:
    """What :class:`_Tagger` prints for the rule printed as ``text`` (``tag``, ``guard``: their
    printed forms), when the rule is simple and names no ``untagged`` predicate; else None."""
    simple = _simple_rule(text)
    if simple is None:
        return None
    head, body = simple

    def tagged(atom: tuple[str, str, str | None, int]) -> str | None:
        prefix, name, args, _arity = atom
        if name in untagged:
            return None
        return f"{prefix}{name}({tag},{args})" if args is not None else f"{prefix}{name}({tag})"

    if head is None:
        head_out = f"{constraint_head}({tag})" if constraint_head else "#false"
    else:
        head_out = tagged(head)
    parts = [head_out]
    for element in body:
        parts.append(element if isinstance(element, str) else tagged(element))
    if None in parts:
        return None
    elements = [*parts[1:], *guard]
    return f"{parts[0]} :- {'; '.join(elements)}." if elements else f"{parts[0]}."


def _ground_fact(statement: clingo.ast.AST) -> tuple[str, list[str], bool] | None:
    """(name, argument texts, classically negated) of a plain ground fact ``p(1,f(a)).``, else None."""
    if statement.body:
        return None
    head = statement.head
    if head.ast_type != clingo.ast.ASTType.Literal or head.sign != clingo.ast.Sign.NoSign:
        return None
    atom = head.atom
    if atom.ast_type != clingo.ast.ASTType.SymbolicAtom:
        return None
    term = atom.symbol
    negative = False
    if term.ast_type == clingo.ast.ASTType.UnaryOperation:
        negative, term = True, term.argument
    if term.ast_type == clingo.ast.ASTType.SymbolicTerm:
        symbol = term.symbol
        if symbol.type != clingo.SymbolType.Function or not symbol.name:
            return None
        return symbol.name, [str(a) for a in symbol.arguments], negative or symbol.negative
    if term.ast_type != clingo.ast.ASTType.Function or not term.name or term.external:
        return None
    args = [_ground_term_text(a) for a in term.arguments]
    if any(a is None for a in args):
        return None
    return term.name, args, negative


def is_ground_fact(statement: clingo.ast.AST | str) -> bool:
    """Whether a parsed statement (or its printed text) is a plain ground fact (``p(1,f(a)).``,
    ``-q.``): no body, no variable, no aggregate or choice in the head.

    Decided on the printed text by clingo's term parser, which accepts exactly ground terms;
    walking the AST through its Python bindings costs about 30 times more per fact."""
    text = str(statement)
    if not text.endswith("."):
        return False
    try:
        symbol = clingo.parse_term(text[:-1], logger=lambda _c, _m: None)
    except RuntimeError:
        return False
    return symbol.type == clingo.SymbolType.Function and bool(symbol.name)


def _ground_term_text(term: clingo.ast.AST) -> str | None:
    kind = term.ast_type
    if kind == clingo.ast.ASTType.SymbolicTerm:
        return str(term.symbol)
    if kind == clingo.ast.ASTType.Function and not term.external:
        args = [_ground_term_text(a) for a in term.arguments]
        if any(a is None for a in args):
            return None
        return f"{term.name}({','.join(args)})" if args or not term.name else term.name
    return None


def tag_program(program: Program, tag: str, guard: Sequence[str] = (), constraint_head: str | None = None,
                untagged: Iterable[str] = ()) -> str:
    """Rewrite ``program`` so that every predicate gets ``tag`` (a term or variable) as first argument.

    Used to put many copies of a program side by side in one grounding (one copy per example,
    ``tag`` = the example id). Every rule body gets the ``guard`` literals, which must bind a
    variable tag (e.g. ``tag="E"``, ``guard=["active(E)"]``). ``#show`` is dropped; statements
    that cannot be copied this way (``#minimize``, ``#external`` ...) raise ParseError
    ``unsupported feature X at line L`` located in the user's file.
    Predicates named in ``untagged`` are left alone.
    With ``constraint_head`` an integrity constraint ``:- body.`` becomes ``constraint_head(tag) :- body.``
    """
    return tag_programs([(program, tag, tuple(guard))], constraint_head=constraint_head, untagged=untagged)[0]


def tag_programs(pieces: Sequence[tuple[Program, str, Sequence[str]]], *, constraint_head: str | None = None,
                 untagged: Iterable[str] = ()) -> list[str]:
    """:func:`tag_program` for many (program, tag, guard) pieces with a single clingo parse."""
    return [p.text for p in tag_programs_located(pieces, constraint_head=constraint_head, untagged=untagged)]


def tag_programs_located(pieces: Sequence[tuple[Program, str, Sequence[str]]], *,
                         constraint_head: str | None = None, untagged: Iterable[str] = ()) -> list[Program]:
    """:func:`tag_programs` returning programs whose every line maps back to the statement it was
    made from, so clingo's errors on the tagged copy (an unsafe variable) name the user's file
    and line, not the generated text."""
    untagged = frozenset(untagged)
    if not pieces:
        return []
    combined = Program.compose(p for p, _t, _g in pieces)
    starts = []  # first line of each piece in the combined text
    line = 1
    for program, _tag, _guard in pieces:
        starts.append(line)
        line += sum(part.n_lines for part in program.parts) if program.parts else 0
        if not program.parts:
            starts[-1] = -1
    outputs: list[list[str]] = [[] for _ in pieces]
    positions: list[list[tuple[int, int]]] = [[] for _ in pieces]  # (line, column) in ``combined``
    taggers: dict[int, _Tagger] = {}

    nonempty = [i for i, start in enumerate(starts) if start > 0]
    nonempty_starts = [starts[i] for i in nonempty]

    def piece_of(statement_line: int) -> int:
        return nonempty[bisect.bisect_right(nonempty_starts, statement_line) - 1]

    printed: dict[int, tuple[str, list[str]]] = {}  # the tag and guard as clingo prints them

    def tagger(index: int) -> _Tagger:
        if index not in taggers:
            _program, tag, guard = pieces[index]
            parsed: list[clingo.ast.AST] = []
            guard_text = ", ".join(guard)
            clingo.ast.parse_string(f"__probe({tag}) :- {guard_text}." if guard_text else f"__probe({tag}).",
                                    parsed.append)
            rule = parsed[-1]
            taggers[index] = _Tagger(rule.head.atom.symbol.arguments[0], list(rule.body), constraint_head, untagged)
            printed[index] = (str(taggers[index].tag), [str(g) for g in taggers[index].guard])
        return taggers[index]

    def visit(statement: clingo.ast.AST) -> None:
        kind = statement.ast_type.name
        if kind in ("Program", "Comment", "ShowSignature", "ShowTerm"):
            return
        begin = statement.location.begin
        index = piece_of(begin.line)
        if kind in UNSUPPORTED_STATEMENTS:
            raise unsupported_feature(statement, combined)
        if kind == "Rule":
            fact = _ground_fact(statement)
            if fact is not None and fact[0] not in untagged:
                # fast path (contexts are mostly facts): the tagged text directly, no AST rewriting
                name, args, negative = fact
                _program, tag, guard = pieces[index]
                suffix = f" :- {', '.join(guard)}." if guard else "."
                text = f"{'-' if negative else ''}{name}({','.join([tag, *args])}){suffix}"
            else:
                rewriter = tagger(index)
                tag_text, guard_texts = printed[index]
                text = _tag_simple(str(statement), tag_text, guard_texts, constraint_head, untagged)
                if text is None:
                    text = str(rewriter.visit(statement))
        else:
            text = str(statement)
        outputs[index].append(text)
        where = (begin.line, begin.column)
        positions[index].append(where)
        if "\n" in text:
            positions[index].extend([where] * text.count("\n"))

    parse_statements(combined.text, visit, program=combined)
    return [Program((Part("\n".join(lines), combined.first_source or "<tagged>", origin=combined,
                          positions=tuple(where)),)) if lines else Program()
            for lines, where in zip(outputs, positions)]


class IncrementalOptimizer:
    """A grounded optimisation problem that can be re-solved after adding constraints.

    The learner's general path finds the cheapest hypothesis covering the positives, checks the
    negatives, and adds a constraint for each negative the hypothesis wrongly accepts; grounding the
    base program only once keeps those iterations cheap.
    """

    def __init__(self, program: Program, arguments: Sequence[str] = ()) -> None:
        self.program = program
        self.ctl = ground(program, ["--opt-mode=opt", *arguments])
        self._parts = 0

    def add(self, text: str) -> None:
        self._parts += 1
        name = f"extra_{self._parts}"
        try:
            self.ctl.add(name, [], text)
            self.ctl.ground([(name, [])])
        except RuntimeError as exc:  # our own generated text: a bug, not user input
            raise RuntimeError(f"clingo rejected generated constraint {text!r}: {exc}") from exc

    def optimize(self, timeout: float | None = None) -> SolveOutcome:
        start = time.perf_counter()
        outcome = SolveOutcome()

        def on_model(model: clingo.Model) -> None:
            outcome.models.append(sorted(model.symbols(shown=True)))
            outcome.costs.append(list(model.cost))

        outcome.complete, outcome.satisfiable = _solve(self.ctl, timeout=timeout, on_model=on_model)
        outcome.seconds = time.perf_counter() - start
        return outcome
