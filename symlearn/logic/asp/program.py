"""ASP programs composed from files and strings, remembering where every line came from.

A :class:`Program` is clingo text plus a list of :class:`Part` records. When clingo reports an
error at ``<block>:LINE:COL`` of the composed text, :meth:`Program.locate` answers with the file,
line and column the user wrote -- also for pieces cut out of a larger file (an example context
inside a task file starts in the middle of a line, so its first line carries a column offset).

>>> p = Program.from_text("a.", source="one.lp") + Program.from_text("b :- a.", source="two.lp")
>>> p.locate(2, 3)
('two.lp', 1, 3)

``#include "file.lp".`` is resolved against the folder of the file that contains it (clingo itself
would use the current folder) and replaced by that file's program, so positions in an included
file are reported in that file. As in clingo, a file is included once (which also ends cycles).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

from symlearn.errors import ParseError


@dataclass(frozen=True)
class Part:
    """One piece of a program: its text and where it starts in its source."""

    text: str
    source: str
    line: int = 1  # line of the source on which ``text`` starts
    column: int = 1  # column of the source at which the first line of ``text`` starts
    # generated text (a tagged copy): line i of ``text`` was made from the statement at
    # ``positions[i]`` (line, column) of ``origin``, which locates it further
    origin: Program | None = field(default=None, compare=False, repr=False)
    positions: tuple[tuple[int, int], ...] | None = field(default=None, compare=False, repr=False)

    @cached_property  # Program.locate asks for every message: counted once, not once a message
    def n_lines(self) -> int:
        return self.text.count("\n") + 1


@dataclass(frozen=True)
class Program:
    """Immutable clingo program text with a source map. Compose with ``+``."""

    parts: tuple[Part, ...] = ()

    @classmethod
    def from_text(cls, text: str, source: str = "<string>", line: int = 1, column: int = 1) -> Program:
        return cls((Part(text, source, line, column),))

    @classmethod
    def from_file(cls, path: str | os.PathLike[str], *, expand: bool = True, within: Path | None = None) -> Program:
        """The program in ``path`` (UTF-8, at most ``SYMLEARN_MAX_INPUT_MB``), its ``#include``
        directives replaced by the included files (unless ``expand=False``); ``within``: a
        folder every included file must lie in (see :func:`expand_includes`)."""
        from symlearn.input_limits import read_input_text

        path = Path(path)
        text = read_input_text(path, what="program file")
        check_nesting(text, str(path))
        program = cls.from_text(text, source=str(path))
        return expand_includes(program, within=within) if expand else program

    @classmethod
    def compose(cls, pieces: Iterable[Program | str | os.PathLike[str]]) -> Program:
        """Join programs, strings (as program text) and paths (``Path`` objects are read)."""
        parts: list[Part] = []
        for piece in pieces:
            parts.extend(as_program(piece).parts)
        return cls(tuple(parts))

    def __add__(self, other: Program | str) -> Program:
        other = as_program(other)
        return Program(self.parts + other.parts)

    @property
    def text(self) -> str:
        return "\n".join(part.text for part in self.parts)

    @property
    def first_source(self) -> str | None:
        return self.parts[0].source if self.parts else None

    def locate(self, line: int, column: int) -> tuple[str | None, int, int]:
        """Map a 1-based position in :attr:`text` to (source, line, column) of the original."""
        start = 1
        for part in self.parts:
            end = start + part.n_lines
            if line < end:
                local = line - start
                if part.origin is not None and part.positions:
                    at_line, at_column = part.positions[min(local, len(part.positions) - 1)]
                    return part.origin.locate(at_line, at_column)
                col = column + (part.column - 1 if local == 0 else 0)
                return part.source, part.line + local, col
            start = end
        return self.first_source, line, column

    def __str__(self) -> str:
        return self.text

    def is_empty(self) -> bool:
        return not any(part.text.strip() for part in self.parts)


def as_program(value: Program | str | os.PathLike[str] | None) -> Program:
    """Accept a Program, program text, or a ``Path`` to an ``.lp`` file."""
    if value is None:
        return Program()
    if isinstance(value, Program):
        return value
    if isinstance(value, os.PathLike):
        return Program.from_file(value)
    if isinstance(value, str):
        return Program.from_text(value)
    raise TypeError(f"expected Program, str or Path, got {type(value).__name__}")


# -- nesting ----------------------------------------------------------------------------------------

#: Terms and braces nested deeper than this are refused: real programs nest a few levels, and
#: clingo crashes (segmentation fault) grounding a term nested 100,000 deep.
MAX_NESTING = 100

# an unclosed %* runs to the end (clingo refuses it as an unexpected end of file): matched once,
# not rescanned from every later %* as ".*?\*%" alone would (quadratic)
_SKIP = re.compile(r'%\*(?:.*?\*%|.*\Z)|%[^\n]*|"(?:[^"\\\n]|\\.)*"', re.S)
_NOT_BRACKET = re.compile(r"[^()\[\]{}]+")
_PAIR = re.compile(r"\(\)|\[\]|\{\}")


def _nests_deeper(text: str, limit: int) -> bool:
    """Whether brackets nest deeper than ``limit`` (comments and strings skipped): C-speed regex
    passes, one per level present, no Python loop over characters."""
    if text.count("(") + text.count("[") + text.count("{") <= limit:
        return False
    brackets = _NOT_BRACKET.sub("", _SKIP.sub("", text))
    for _ in range(limit):
        reduced = _PAIR.sub("", brackets)
        if not reduced or reduced == brackets:  # done, or unbalanced (clingo reports that)
            return False
        brackets = reduced
    return True


def check_nesting(text: str, source: str | None, line: int = 1, column: int = 1,
                  limit: int = MAX_NESTING) -> None:
    """Raise :class:`ParseError` at the position where ``text`` nests deeper than ``limit``."""
    if not _nests_deeper(text, limit):
        return
    depth, offset = 0, 0
    for match in re.finditer(r'%\*.*?\*%|%[^\n]*|"(?:[^"\\\n]|\\.)*"|[(\[{]|[)\]}]', text, re.S):
        token = match.group(0)
        if token in "([{":
            depth += 1
            if depth > limit:
                offset = match.start()
                break
        elif token in ")]}":
            depth -= 1
    at_line = text.count("\n", 0, offset)
    at_column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    raise ParseError(f"terms nested more than {limit} levels deep", file=source, line=line + at_line,
                     column=at_column + (column - 1 if at_line == 0 else 0),
                     hint="a program nests a few levels; check for a runaway generator")


# -- #include ---------------------------------------------------------------------------------------

# comments and strings are matched first so that an #include inside them is left alone
# (clingo allows comments between the directive's words: `#include %* c *% "f".` was left to
# clingo, which read the file from outside a domain folder -- held-out pass, 2026-12-07).
# Every piece matches one way only, so the patterns stay linear: a block comment ends at its
# first `*%` (an unclosed one runs to the end of the text, which clingo refuses as a lexer error;
# `%\*.*?\*%` with a line-comment fallback rescanned the rest of the text at every unclosed `%*`,
# quadratic), and a line comment inside the directive runs to the end of its line (`%[^\n]*`
# repeated could split a run of `%` in exponentially many ways)
_BLOCK_COMMENT = r'%\*(?:[^*]|\*(?!%))*(?:\*%|\Z)'
_LINE_COMMENT = r'%(?!\*)[^\n]*'
_GAP = r'(?:\s|' + _BLOCK_COMMENT + '|' + _LINE_COMMENT + r'(?=\n|\Z))*'
_STRING = r'"(?:[^"\\\n]|\\.)*"'
_INCLUDE = re.compile(_BLOCK_COMMENT + '|' + _LINE_COMMENT + '|' + _STRING
                      + r'|#include' + _GAP + r'(?:"((?:[^"\\\n]|\\.)*)"|<([^>\n]*)>)' + _GAP + r'\.')


#: any ``#include`` outside comments and strings, whatever follows it: where no directive is
#: allowed, one without its final ``.`` must be refused too -- a state's facts get a ``.``
#: appended before clingo reads them, which completes ``#include "f"`` into a directive
_INCLUDE_TOKEN = re.compile(_BLOCK_COMMENT + '|' + _LINE_COMMENT + '|' + _STRING + r'|#include\b')


def find_include(text: str) -> tuple[int, int] | None:
    """(line, column) of the first ``#include`` of ``text`` (comments and strings skipped),
    complete directive or not, or None."""
    if "#include" not in text:
        return None
    for match in _INCLUDE_TOKEN.finditer(text):
        if match.group(0).startswith("#include"):
            return _position(text, match.start(), Part(text, "<text>"))
    return None


def _position(text: str, offset: int, part: Part) -> tuple[int, int]:
    """(line, column) in ``part``'s source of character ``offset`` of ``part.text``."""
    line = text.count("\n", 0, offset)
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return part.line + line, column + (part.column - 1 if line == 0 else 0)


def _folder_of(source: str) -> Path:
    path = Path(source)
    return path.parent if source and not source.startswith("<") and path.is_file() else Path.cwd()


def _refuse_unread_include(piece: str, part: Part, offset: int) -> None:
    """An ``#include`` left in ``piece`` (one the directive pattern did not read) would be
    followed by clingo itself, past the folder check: refused at its place."""
    found = find_include(piece)
    if found is not None:
        line, column = _position(part.text, offset + _offset_of(piece, *found), part)
        raise ParseError("an #include symlearn cannot read (write it as #include \"file.lp\".)", file=part.source,
                         line=line, column=column)


def _offset_of(text: str, line: int, column: int) -> int:
    start = 0
    for _ in range(line - 1):
        start = text.index("\n", start) + 1
    return start + column - 1


def expand_includes(program: Program, *, seen: set[Path] | None = None, within: Path | None = None) -> Program:
    """Replace every ``#include "f".`` of ``program`` by the program of ``f``, resolved against
    the folder of the file holding the directive (the current folder for text without a file).

    A file already included (or the including file itself) is skipped, as clingo does; a missing
    file or ``#include <name>.`` (clingo's built-in programs) is a :class:`ParseError` at the
    directive. With ``within`` (a domain folder), a file that resolves outside that folder
    (symlinks followed) is refused at the directive too, before it is opened: neither its
    content nor whether it exists shows in the message."""
    if not any("#include" in part.text for part in program.parts):
        return program
    seen = set() if seen is None else seen
    for part in program.parts:
        if part.origin is None and part.source and not part.source.startswith("<"):
            try:
                seen.add(Path(part.source).resolve())
            except OSError:
                pass
    parts: list[Part] = []
    for part in program.parts:
        if part.origin is not None or "#include" not in part.text:
            parts.append(part)
            continue
        text, done = part.text, 0
        for match in _INCLUDE.finditer(text):
            if not match.group(0).startswith("#include"):
                continue
            line, column = _position(text, match.start(), part)
            if match.group(2) is not None:
                raise ParseError(f"unsupported feature #include <{match.group(2)}> at line {line}", file=part.source,
                                 line=line, column=column, hint="include files by name: #include \"file.lp\".")
            before = text[done:match.start()]
            _refuse_unread_include(before, part, done)
            if before.strip():
                at_line, at_column = _position(text, done, part)
                parts.append(Part(before, part.source, at_line, at_column))
            done = match.end()
            name = match.group(1).encode("utf-8").decode("unicode_escape") if "\\" in match.group(1) \
                else match.group(1)
            target = _folder_of(part.source) / name
            try:
                resolved = target.resolve()
            except OSError:
                resolved = target
            if within is not None and not resolved.is_relative_to(within.resolve()):
                raise ParseError(f"#include \"{name}\" names a file outside the folder {str(within)!r}", file=part.source,
                                 line=line, column=column,
                                 hint="a domain's programs include files of its own folder only (--allow-outside "
                                      "lifts this for a trusted folder)")
            if resolved in seen:
                continue
            if not target.is_file():
                raise ParseError(f"#include \"{name}\": no such file {str(target)!r}", file=part.source, line=line,
                                 column=column, hint="an included file is looked up next to the file that includes it")
            seen.add(resolved)
            included = Program.from_file(target, expand=False)
            parts.extend(expand_includes(included, seen=seen, within=within).parts)
        rest = text[done:]
        _refuse_unread_include(rest, part, done)
        if rest.strip():
            at_line, at_column = _position(text, done, part)
            parts.append(Part(rest, part.source, at_line, at_column))
    return Program(tuple(parts))
