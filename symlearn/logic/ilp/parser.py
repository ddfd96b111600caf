"""Read ILASP-compatible task files (grammar ``grammars/ilasp_task.lark``).

>>> task = parse_task('''
... disk(1..3).
... #pos(p1, {}, {}, { on(1,2). }).
... #neg(n1@10, {}, {}, { on(2,1). }).
... #modeb(1, on(var(disk), var(disk))).
... #modeb(1, var(disk) < var(disk)).
... ''', source="demo.las")
>>> [e.id for e in task.examples], task.examples[1].penalty
(['p1', 'n1'], 10)

Errors name the file, line and column of the offending declaration. ILASP/FastLAS features
outside the supported subset are refused with ``unsupported feature X at line L``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from dataclasses import replace
from functools import cache
from pathlib import Path

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from symlearn.errors import ParseError, SymlearnError
from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program, as_program, check_nesting, expand_includes
from symlearn.logic.ilp.modes import (Literal_, ModeAtom, ModeComparison, ModeConditional, ModeDeclaration,
                                      ModeFunction, Placeholder)
from symlearn.logic.ilp.task import ILPTask, Example
from symlearn.resources import grammar_text

_TOKEN_NAMES = {
    "RPAR": "')'", "LPAR": "'('", "DOT": "'.'", "COMMA": "','", "LBRACE": "'{'", "RBRACE": "'}'",
    "NAME": "a name", "INT": "a number", "STRING": "a string", "CONTEXT": "a context '{ ... }'",
    "COLON": "':'", "BG_STATEMENT": "a background statement", "AT": "'@'",
}


@cache
def _parser() -> Lark:
    return Lark(grammar_text("ilasp_task"), parser="lalr", propagate_positions=True, maybe_placeholders=True)


class _Unsupported(Exception):
    def __init__(self, feature: str, token) -> None:
        super().__init__(feature)
        self.feature = feature
        self.line = getattr(token, "line", None)
        self.column = getattr(token, "column", None)


def _loc(node) -> tuple[int | None, int | None]:
    if isinstance(node, Token):
        return node.line, node.column
    meta = getattr(node, "meta", None)
    if meta is not None and not getattr(meta, "empty", True):
        return meta.line, meta.column
    return None, None


class _Build(Transformer):
    def __init__(self, source: str, text: str) -> None:
        super().__init__()
        self.source = source
        self.text = text

    # -- terms -------------------------------------------------------------------------------
    def signed_int(self, items):
        return -int(items[1]) if items[0] is not None else int(items[1])

    def gfunction(self, items):
        name, *args = items
        args = [a for a in args if a is not None]
        return cl.Function(str(name), args)

    def gtuple(self, items):
        return cl.Function("", list(items))

    def gnumber(self, items):
        return cl.Number(int(items[0]))

    def gstring(self, items):
        return cl.String(_unquote(items[0]))

    def mfunction(self, items):
        name, *args = items
        args = [a for a in args if a is not None]
        if str(name) in ("var", "const") and len(args) == 1 and isinstance(args[0], ModeFunction) and not args[0].args:
            return Placeholder(str(name), args[0].name)
        if str(name) == "num_var":
            raise _Unsupported("num_var", name)
        return ModeFunction(str(name), tuple(args))

    def mnumber(self, items):
        return Literal_(str(int(items[0])))

    def mstring(self, items):
        return Literal_(str(items[0]))

    def matom(self, items):
        name, *args = items
        args = tuple(a for a in args if a is not None)
        return ModeAtom(str(name), args)

    def naf(self, items):
        atom = items[-1]
        return ModeAtom(atom.name, atom.args, negated=True)

    def marith(self, items):
        return ("arith", items[0], str(items[1]), items[2])

    def comparison(self, items):
        left, op, right = items
        op = "=" if str(op) == "==" else str(op)
        if isinstance(right, tuple):
            _tag, a, arith, b = right
            return ModeComparison(op, left, a, arith, b)
        return ModeComparison(op, left, right)

    # -- declarations --------------------------------------------------------------------------
    @v_args(meta=True)
    def modeh(self, meta, items):
        recall, literal = items
        if not isinstance(literal, ModeAtom) or literal.negated:
            raise _Unsupported("non-atomic #modeh heads (only atoms may be heads)", meta)
        return ModeDeclaration("h", literal, _int(recall), False, meta.line, meta.column)

    @v_args(meta=True)
    def modeb(self, meta, items):
        recall, literal, flag = items
        positive = False
        if flag is not None:
            if flag != "positive":
                raise _Unsupported(f"mode flag ({flag})", meta)
            positive = True
        return ModeDeclaration("b", literal, _int(recall), positive, meta.line, meta.column)

    def flag(self, items):
        return str(items[0])

    @v_args(meta=True)
    def modec(self, meta, items):
        recall, literal, *condition = items
        if not isinstance(literal, ModeAtom):
            raise ParseError("the literal of a #modec must be an atom or 'not' atom", file=self.source,
                             line=meta.line, column=meta.column)
        if any(c.negated for c in condition):
            raise ParseError("the condition of a #modec must consist of positive atoms", file=self.source,
                             line=meta.line, column=meta.column)
        return ModeDeclaration("c", ModeConditional(literal, tuple(condition)), _int(recall), False,
                               meta.line, meta.column)

    def example_id(self, items):
        name, penalty = items
        return str(name), (None if penalty is None else int(penalty))

    def atom_set(self, items):
        return tuple(i for i in items if i is not None)

    @v_args(meta=True)
    def example(self, meta, items):
        kw, ident, incl, excl, context = items
        return ("example", kw, ident, incl, excl, context, meta)

    @v_args(meta=True)
    def constant(self, meta, items):
        return ("constant", str(items[0]), items[1], meta)

    def maxv(self, items):
        return ("maxv", int(items[0]), items[0])

    def max_penalty(self, items):
        return ("max_penalty", int(items[0]), items[0])

    def bias(self, items):
        return ("bias", _unquote(items[0]), items[0])

    def unsupported(self, items):
        token = items[0]
        name = str(token).split("(", 1)[0].split()[0]
        raise _Unsupported(name, token)

    def background(self, items):
        return ("background", items[0])


def _int(token) -> int | None:
    return None if token is None else int(token)


def _unquote(token) -> str:
    text = str(token)[1:-1]
    return text.encode("utf-8").decode("unicode_escape") if "\\" in text else text


DIALECTS = ("ilasp", "fastlas")


def parse_task(text: str, source: str = "<task>", extra_background: Iterable[Program | str | os.PathLike] = (),
               dialect: str = "ilasp") -> ILPTask:
    """Parse the text of a task file; ``extra_background`` programs/paths are appended to B.

    ``dialect`` only changes how ``#modeb`` atoms are used: ``"ilasp"`` (default) also allows
    them negated unless flagged ``(positive)``; ``"fastlas"`` uses every mode exactly as written
    and reads ``inclusion(a)``/``exclusion(a)`` facts of a context as that example's inclusions
    and exclusions (a convention of FastLAS's own test tasks).
    """
    if dialect not in DIALECTS:
        raise SymlearnError(f"unknown task dialect {dialect!r}", hint="use 'ilasp' or 'fastlas'")
    _refuse_early(text, source)
    check_nesting(text, source)
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as exc:
        raise _syntax_error(exc, text, source) from None
    try:
        items = _Build(source, text).transform(tree).children
    except VisitError as exc:
        inner = exc.orig_exc
        if isinstance(inner, _Unsupported):
            line, column = inner.line, inner.column
            if line is None:
                line, column = _loc(inner.__dict__.get("meta"))
            raise ParseError(f"unsupported feature {inner.feature} at line {line}", file=source, line=line,
                             column=column, hint="see docs/ILP.md for the supported ILASP subset") from None
        if isinstance(inner, SymlearnError):
            raise inner from None
        raise
    task = _assemble(items, source, extra_background)
    task.dialect = dialect
    if dialect == "fastlas":
        task.examples = [_context_inclusions(e) for e in task.examples]
    return task


# comments and strings first, so that '#script' inside them is not taken for the directive
_EARLY = re.compile(r'%\*.*?\*%|%[^\n]*|"(?:[^"\\\n]|\\.)*"|#script\s*\(\s*(\w*)|:~|#(?:heuristic|theory)\b',
                    re.S)


def _refuse_early(text: str, source: str) -> None:
    """``#script`` blocks hold Python or Lua code with periods of their own; a weak constraint and
    a ``#heuristic`` end in ``[...]`` after their period, a ``#theory`` has its own syntax: each
    would cut the background statement apart before clingo could name the feature, so they are
    refused first."""
    if not any(word in text for word in ("#script", ":~", "#heuristic", "#theory")):
        return
    for match in _EARLY.finditer(text):
        found = match.group(0)
        if found.startswith(("#script", ":~", "#heuristic", "#theory")):
            line = text.count("\n", 0, match.start()) + 1
            column = match.start() - (text.rfind("\n", 0, match.start()) + 1) + 1
            name = f"#script ({match.group(1) or '?'})" if found.startswith("#script") else \
                "weak constraint (:~)" if found == ":~" else found
            raise ParseError(f"unsupported feature {name} at line {line}", file=source, line=line, column=column,
                             hint="see docs/ILP.md for the supported subset")


def _context_inclusions(example: Example) -> Example:
    """FastLAS's test tasks may state inclusions and exclusions as ``inclusion(a)`` /
    ``exclusion(a)`` facts inside the context; read them as the example's own sets (the facts
    stay in the context, where no mode refers to them)."""
    text = "".join(part.text for part in example.context.parts)
    if "inclusion(" not in text and "exclusion(" not in text:
        return example
    found = cl.ground_atoms(example.context, [("inclusion", 1), ("exclusion", 1)])
    inclusions = tuple(a.arguments[0] for a in found if a.name == "inclusion")
    exclusions = tuple(a.arguments[0] for a in found if a.name == "exclusion")
    return replace(example, inclusions=example.inclusions + inclusions, exclusions=example.exclusions + exclusions)


def _assemble(items, source: str, extra_background) -> ILPTask:
    background = Program()
    examples: list[Example] = []
    task = ILPTask(background=background, examples=examples, source=source)
    seen_ids: dict[str, int] = {}
    counter = 0
    for item in items:
        if isinstance(item, ModeDeclaration):
            {"h": task.modeh, "b": task.modeb, "c": task.modec}[item.kind].append(item)
            if item.recall is not None and item.recall < 1:
                raise ParseError(f"recall must be at least 1, got {item.recall}", file=source, line=item.line,
                                 column=item.column)
            continue
        tag = item[0]
        if tag == "background":
            token = item[1]
            background = background + Program.from_text(str(token), source=source, line=token.line, column=token.column)
        elif tag == "example":
            _tag, kw, ident, incl, excl, context, meta = item
            counter += 1
            name, penalty = ident if ident is not None else (f"{str(kw)[1:]}{counter}", None)
            if name in seen_ids:
                raise ParseError(f"example id {name!r} is used twice (first at line {seen_ids[name]})",
                                 file=source, line=meta.line, column=meta.column, hint="give every example its own id")
            seen_ids[name] = meta.line
            ctx = Program()
            if context is not None:
                ctx = Program.from_text(str(context)[1:-1], source=source, line=context.line, column=context.column + 1)
                ctx = expand_includes(ctx)
                cl.check_supported(ctx)
            examples.append(Example(name, str(kw) == "#pos", tuple(incl), tuple(excl), ctx, penalty, meta.line))
        elif tag == "constant":
            _tag, type_, value, _meta = item
            task.constants.setdefault(type_, [])
            if value not in task.constants[type_]:
                task.constants[type_].append(value)
        elif tag == "maxv":
            if item[1] < 1:
                raise ParseError("#maxv must be at least 1", file=source, line=item[2].line, column=item[2].column)
            task.maxv = item[1]
        elif tag == "max_penalty":
            task.max_penalty = item[1]
        elif tag == "bias":
            task.bias.append(item[1])
    background = expand_includes(background)
    for extra in extra_background:
        background = background + as_program(Path(extra) if isinstance(extra, os.PathLike) else extra)
    cl.check_supported(background)
    task.background = background
    return task


def load_task(path: str | os.PathLike[str], extra_background: Iterable[str | os.PathLike | Program] = (),
              dialect: str = "ilasp") -> ILPTask:
    """Read a task file; ``extra_background`` paths (``.lp`` files) or programs are appended to B."""
    from symlearn.input_limits import read_input_text

    path = Path(path)
    text = read_input_text(path, what="task file")
    extras = [Path(e) if isinstance(e, str) else e for e in extra_background]
    return parse_task(text, source=str(path), extra_background=extras, dialect=dialect)


def _syntax_error(exc: UnexpectedInput, text: str, source: str) -> ParseError:
    line, column = getattr(exc, "line", None), getattr(exc, "column", None)
    if isinstance(exc, UnexpectedEOF) or line in (None, -1):
        lines = text.rstrip().splitlines() or [""]
        return ParseError("unexpected end of file (a declaration or statement is not finished with '.')",
                          file=source, line=len(lines), column=len(lines[-1]) + 1)
    statement = _statement_at(text, exc.pos_in_stream)
    if isinstance(exc, UnexpectedToken):
        expected = sorted(_TOKEN_NAMES.get(t, repr(t)) for t in exc.expected if not t.startswith("__"))
        got = exc.token.value if exc.token is not None else "end of file"
        if str(got).startswith("#") and exc.pos_in_stream:
            # the next declaration began before this one ended: name the unfinished one and
            # point just after its last character, where the '.' belongs
            line, column, end = _end_of_code_before(text, exc.pos_in_stream)
            previous = _statement_at(text, end - 1)
            return ParseError(f"the {previous} does not end with '.' (the next declaration, {got!r}, starts on line "
                              f"{exc.line})", file=source, line=line, column=column,
                              hint="end every declaration and statement with '.'")
        message = f"unexpected {got!r} in {statement}"
        if expected and len(expected) <= 6:
            message += f"; expected {' or '.join(expected)}"
    elif isinstance(exc, UnexpectedCharacters):
        message = f"unexpected character {text[exc.pos_in_stream]!r} in {statement}"
    else:  # pragma: no cover - lark raises only the kinds above
        message = str(exc).splitlines()[0]
    hint = "declarations look like #modeb(1, p(var(t))). and every statement ends with '.'"
    capital = re.match(r"[A-Z_][A-Za-z0-9_']*", text[exc.pos_in_stream:]) if exc.pos_in_stream is not None else None
    if capital and statement.startswith(("#constant", "#modeb", "#modeh", "#modec")):
        # '#constant(player, Bob).': a capital starts a variable in ASP, which a declaration cannot hold
        name = capital.group()
        hint = (f"{name} starts with a capital letter or '_', which makes it a variable in ASP: predicate, type and "
                f"constant names start lowercase ({name[:1].lower()}{name[1:]}); a constant may also be the string "
                f"\"{name}\", as the facts have it")
    return ParseError(message, file=source, line=line, column=column, hint=hint)


def _end_of_code_before(text: str, pos: int) -> tuple[int, int, int]:
    """(line, column, offset) just after the last character before ``pos`` that is neither blank
    nor inside a ``%`` comment."""
    lines = text[:pos].split("\n")
    offset = pos - len(lines[-1])
    for index in range(len(lines) - 1, -1, -1):
        code = lines[index].split("%", 1)[0].rstrip()
        if code:
            return index + 1, len(code) + 1, offset + len(code)
        if index:
            offset -= len(lines[index - 1]) + 1
    return 1, 1, 0


def _statement_at(text: str, pos: int | None) -> str:
    """Name the declaration that contains ``pos`` (e.g. '#modeb declaration starting at line 4')."""
    if pos is None:
        return "the task"
    start = text.rfind("#", 0, pos + 1)
    period = text.rfind(".\n", 0, pos)
    if start != -1 and start > period:
        keyword = text[start:].split("(", 1)[0].split()[0]
        return f"{keyword} declaration starting at line {text.count(chr(10), 0, start) + 1}"
    return "a background statement"
