"""Read LTLf formulas written in one of three dialects.

>>> parse("G(request -> F grant)")
Always(arg=Implies(left=Prop(name='request'), right=Eventually(arg=Prop(name='grant'))))
>>> parse("X a", dialect="spot") == parse("WX a")
True

Syntax (``grammars/ltlf.lark``): ``true false`` (also ``1 0``), propositions
``[a-z_][a-z0-9_]*`` or any double-quoted name (``"Door open"``, with ``\\"`` and ``\\\\``
escapes); ``! ~`` (not), ``& &&``, ``| ||``, ``->``, ``<->``; unary ``X`` ``X[!]`` (strong
next), ``N`` ``WX`` (weak next), ``F``, ``G``; binary ``U`` ``R`` ``W`` and ``T``
(``a T b`` = ``F(a & X[!] F b)``). Unicode ``¬ ∧ ∨ → ↔ ⊤ ⊥ ◇ □ ○`` are accepted too.
Unary operators bind tightest, then the binary temporal operators (grouping to the right),
then ``&``, ``|``, ``->`` (to the right) and ``<->``.

Dialects differ in two places only:

=========  ==============  ===============================================  ==================
dialect    bare ``X``      ``->`` versus ``<->``                            ``R`` versus ``U``
=========  ==============  ===============================================  ==================
ours       strong next     ``<->`` looser than ``->``                       one level
ltlf2dfa   strong next     ``<->`` looser than ``->`` (LTLf2DFA's grammar)  ``R`` tighter
spot       weak next       one level, grouping to the right (Spot's parser)  one level
=========  ==============  ===============================================  ==================

In the ``ltlf2dfa`` dialect the printer also parenthesises every chain of ``U``/``R``/``->``/
``<->`` (LTLf2DFA keeps such chains n-ary), so its output means the same to LTLf2DFA.

Syntax errors raise :class:`~symlearn.errors.ParseError` naming the column, showing the
formula with a caret under it, listing what was expected and, for common spellings from other
tools (``=>``, ``<>``, ``[]``, ``&&&``, ``and``...), the right one.

Well-formed formulas are read by :mod:`~symlearn.logic.ltlf.fast_parser` (no lark import, which
with the LALR construction was a third of a CLI command's start-up); the lark parser reads the
rest (it words the errors) and is built on first use.
"""

from __future__ import annotations

import re
from functools import cache

from symlearn.errors import ParseError, with_excerpt
from symlearn.logic.ltlf.ast import FALSE, TRUE, And, Formula, Next, Or, Prop, WeakNext
from symlearn.logic.ltlf.fast_parser import UNARY as _UNARY
from symlearn.logic.ltlf.fast_parser import fold_left, group_arrows, group_temporal, read

__all__ = ["DIALECTS", "parse", "check_dialect"]

DIALECTS = ("ours", "spot", "ltlf2dfa")

def check_dialect(dialect: str) -> str:
    if dialect not in DIALECTS:
        raise ParseError(f"unknown LTLf dialect {dialect!r}", hint=f"choose one of: {', '.join(DIALECTS)}")
    return dialect


@cache
def _parser(dialect: str):
    """The lark parser of ``grammars/ltlf.lark`` for ``dialect`` (imports lark on first use: the
    fast reader handles well-formed formulas, this one the rest and every error message)."""
    from lark import Lark, Transformer

    from symlearn.resources import grammar_text

    class _Build(Transformer):
        """Turns the chains of the grammar into nodes, grouping as the dialect says."""

        def __init__(self) -> None:
            super().__init__()
            self.bare_x = WeakNext if dialect == "spot" else Next

        def true(self, _):
            return TRUE

        def false(self, _):
            return FALSE

        def prop(self, items):
            return Prop(str(items[0]))

        def quoted_prop(self, items):
            return Prop(re.sub(r"\\(.)", r"\1", str(items[0])[1:-1]))

        def group(self, items):
            return items[0]

        def unary(self, items):
            if len(items) == 1:
                return items[0]
            op, arg = str(items[0]), items[1]
            return (self.bare_x if op == "X" else _UNARY[op])(arg)

        def temporal_chain(self, items):
            return group_temporal(items, dialect == "ltlf2dfa")  # LTLf2DFA: R binds tighter than U

        def and_chain(self, items):
            return fold_left(items, And)

        def or_chain(self, items):
            return fold_left(items, Or)

        def arrow_chain(self, items):
            return group_arrows(items, dialect == "spot")

    return Lark(grammar_text("ltlf"), parser="lalr", transformer=_Build(), maybe_placeholders=False)


def parse(text: str, dialect: str = "ours", *, source: str | None = None, line: int | None = None) -> Formula:
    """Parse ``text`` in ``dialect``; ``source``/``line`` locate it in a file for error messages."""
    check_dialect(dialect)
    if not isinstance(text, str):
        raise ParseError(f"an LTLf formula must be text, not {type(text).__name__}")
    if not text.strip():
        raise ParseError("empty formula", file=source, line=line, hint="write e.g. 'F goal'")
    formula = read(text, dialect)
    if formula is not None:
        return formula
    from lark.exceptions import UnexpectedInput, VisitError

    try:
        return _parser(dialect).parse(text)
    except UnexpectedInput as exc:
        raise _syntax_error(text, exc, source, line) from None
    except VisitError as exc:  # a node refused its arguments; should not happen with this grammar
        raise ParseError(f"cannot build formula: {exc.orig_exc}", file=source, line=line) from None
    except RecursionError:
        raise ParseError("formula is nested too deeply", file=source, line=line) from None


# -- error messages --------------------------------------------------------------------------

_TERMINAL_NAMES = {
    "NAME": "a proposition", "QUOTED": "a quoted proposition", "TRUE": "true", "FALSE": "false",
    "TOP": "1", "BOTTOM": "0", "UNARY_OP": "a unary operator (! X X[!] N F G)", "LPAR": "'('",
    "RPAR": "')'", "AND": "'&'", "OR": "'|'", "IMPLIES": "'->'", "IFF": "'<->'",
    "BINARY_TEMPORAL": "a binary temporal operator (U R W T)", "$END": "end of formula",
}

# spellings from other tools -> what to write here (checked against the operator run at the error)
_SYMBOL_HINTS = [
    (re.compile(r"&{3,}"), "write '&' or '&&' for 'and'"),
    (re.compile(r"\|{3,}"), "write '|' or '||' for 'or'"),
    (re.compile(r"<=+>"), "write '<->' for 'if and only if'"),
    (re.compile(r"=+>"), "write '->' for implication"),
    (re.compile(r"<-(?!>)"), "there is no '<-': write 'b -> a'"),
    (re.compile(r"<>"), "write 'F' for 'eventually' (Spin's '<>')"),
    (re.compile(r"\[\]"), "write 'G' for 'always' (Spin's '[]')"),
    (re.compile(r"!="), "write '!(a <-> b)' for 'not equal'"),
    (re.compile(r"=+"), "write '<->' for equivalence"),
    (re.compile(r"\^"), "exclusive or is not supported: write '!(a <-> b)'"),
    (re.compile(r"/\\"), "write '&' for 'and'"),
    (re.compile(r"\\/"), "write '|' for 'or'"),
    (re.compile(r"\["), "strong next is written 'X[!]'"),
]
_WORD_HINTS = {
    "and": "write '&' for 'and'", "or": "write '|' for 'or'", "not": "write '!' for 'not'",
    "implies": "write '->' for implication", "iff": "write '<->'", "xor": "write '!(a <-> b)'",
    "until": "write 'U'", "next": "write 'X'", "eventually": "write 'F'", "always": "write 'G'",
    "globally": "write 'G'", "finally": "write 'F'", "then": "write 'T'",
    "M": "strong release 'a M b' is not supported: write 'b U (a & b)'",
    "V": "write 'R' for release",
    "Y": "past-time operators are not supported (future LTLf only)",
    "O": "past-time operators are not supported (future LTLf only)",
    "H": "past-time operators are not supported (future LTLf only)",
    "S": "past-time operators are not supported (future LTLf only)",
    "Z": "past-time operators are not supported (future LTLf only)",
    "TRUE": "write 'true'", "True": "write 'true'", "FALSE": "write 'false'", "False": "write 'false'",
}
_OPERATOR_CHARS = set("&|=<>-![]~^/\\")


def _syntax_error(text: str, exc, source: str | None, line_offset: int | None) -> ParseError:
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

    lines = text.split("\n")
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        row = len(lines)
        col = len(lines[-1].rstrip()) + 1
        what = "unexpected end of formula"
    else:
        row, col = max(exc.line, 1), max(exc.column, 1)
        if isinstance(exc, UnexpectedCharacters):
            what = f"unexpected character {text[exc.pos_in_stream]!r}"
        else:
            token = exc.token
            what = f"unexpected {_describe_token(token)}"
    expected = _expected(exc)
    position = _offset(lines, row, col)
    hint = _hint(text, position)
    here = lines[row - 1]
    message = f"{what} at column {col}"
    if expected:
        message += f"; expected {expected}"
    message = with_excerpt(message, here, col)
    if len(lines) > 1:
        message = message.replace(" at column", f" at line {row}, column", 1)
    return ParseError(message, file=source, line=(row if line_offset is None else line_offset + row - 1),
                      column=col, hint=hint)


def _describe_token(token) -> str:
    if token.type in ("NAME", "QUOTED"):
        return f"proposition {str(token)!r}"
    return repr(str(token))


def _expected(exc) -> str:
    names = getattr(exc, "expected", None) or getattr(exc, "allowed", None) or ()
    friendly = sorted({_TERMINAL_NAMES.get(n, n.lower()) for n in names
                       if n not in ("QUOTED", "TOP", "BOTTOM")})
    if not friendly:
        return ""
    if len(friendly) == 1:
        return friendly[0]
    return "one of " + ", ".join(friendly)


def _offset(lines: list[str], row: int, col: int) -> int:
    return sum(len(l) + 1 for l in lines[: row - 1]) + col - 1


def _word_before(text: str, position: int) -> str | None:
    """'eventually door', 'always !lava': the operator's word was read as a proposition, and the
    error is at what follows it."""
    # the words looked for are short: a window, since a search anchored at "$" is quadratic in what it
    # is given ("F aaa...aé" with 40,000 a's took 29 s to report its error)
    before = re.search(r"(?<![a-z0-9_])([a-z_][a-z0-9_]{0,30})\s{1,80}$", text[max(position - 120, 0):position])
    if before and before.group(1) in _WORD_HINTS:
        return f"{before.group(1)!r} is read as a proposition here; {_WORD_HINTS[before.group(1)]}"
    return None


def _hint(text: str, position: int) -> str | None:
    if position >= len(text):
        return None
    word = re.match(r"[A-Za-z_][A-Za-z0-9_]*", text[position:])
    if word:
        name = word.group(0)
        if name in _WORD_HINTS:
            return _WORD_HINTS[name]
        if not re.fullmatch(r"[a-z_][a-z0-9_]*", name):
            return f'propositions are written in lowercase; quote other names: "{name}"'
        return _word_before(text, position)
    if _word_before(text, position):
        return _word_before(text, position)
    here = text[position]
    if here == "#":  # '--file' skips lines starting with '#'; a comment after a formula is not one
        return "a comment (#) takes a line of its own, before or after the formula"
    if here == '"':
        if not re.match(r'"(?:[^"\\]|\\.)*"', text[position:]):
            return 'a quoted name needs its closing quote: "door open"'
        if text[position:position + 2] == '""':
            return "a proposition name cannot be empty"
    # 'café', '2b': a name with a character outside [a-z0-9_] (or one that starts with a digit), read
    # up to that character; the whole name is what to quote (80 characters either side at most: a
    # search anchored at the end of a long line is quadratic)
    token = r"[^\s!&|()<>\-~\"]{0,80}"
    name = re.search(token + "$", text[max(position - 80, 0):position]).group() + \
        re.match(token, text[position:]).group()
    if name and (not here.isascii() or (here.isdigit() and not re.search(r"[a-z0-9_]$", text[:position]))):
        return f'propositions are written [a-z_][a-z0-9_]*; quote other names: "{name}"'
    start = end = position
    while start > 0 and text[start - 1] in _OPERATOR_CHARS:
        start -= 1
    while end < len(text) and text[end] in _OPERATOR_CHARS:
        end += 1
    run = text[start:end]
    for pattern, hint in _SYMBOL_HINTS:
        if pattern.search(run):
            return hint
    return None
