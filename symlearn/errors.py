"""Error types shared by every layer.

Every mistake a user can make (a malformed file, a bad formula, an impossible setting) raises a
:class:`SymlearnError` subclass. The CLI turns those into one line and exit code 2; anything else
is a bug in symlearn and exits 1. Location fields are optional because much input has no file.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from os import PathLike

#: characters that would break an error line apart or disguise it on a terminal: C0/C1 controls
#: (tab excepted), the line and paragraph separators ``str.splitlines`` also breaks at, and the
#: bidirectional overrides and isolates
_UNPRINTABLE = re.compile("[\x00-\x08\x0a-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")
#: a formula parse error's excerpt: the offending line and a caret under the column, each indented
_EXCERPT = re.compile(r"\n  ([^\n]*)\n  ( *)\^\Z")


def printable(text: object) -> str:
    """``text`` on one line: every character of :data:`_UNPRINTABLE` written as its escape
    (``\\n``, ``\\x1b``, ``\\u2028``), so a file name or a quoted input with a newline in it
    cannot split an error message into several lines."""
    return _UNPRINTABLE.sub(_escape, str(text))


def with_excerpt(message: str, line: str, column: int) -> str:
    """``message`` followed by the excerpt :class:`SymlearnError` prints under it (:data:`_EXCERPT`):
    the offending ``line`` and a caret under its ``column`` (1-based), each indented."""
    return f"{message}\n  {line}\n  {' ' * (column - 1)}^"


def clipped(text: str, width: int = 40) -> str:
    """``text`` cut to ``width`` characters, ``...`` marking the cut: a value quoted from a file
    (a hand-edited field, a huge number) keeps its error message short."""
    return text if len(text) <= width else text[:width - 3] + "..."


#: characters of an error line's message (and of its excerpt line) past which the middle is cut:
#: a message quoting a 40 MB token from a file, or the excerpt of a 40 MB line, stays readable
MAX_MESSAGE = 2000
#: characters of the excerpt line kept on either side of its caret
EXCERPT_SIDE = 60


def bounded(text: str, limit: int = MAX_MESSAGE) -> str:
    """``text`` with its middle replaced by ``...[N characters]...`` when it is longer than
    ``limit``: the start (what went wrong) and the end (the hint, the file) stay."""
    if len(text) <= limit:
        return text
    head, tail = limit * 2 // 3, limit // 3
    return f"{text[:head]}...[{len(text) - head - tail} characters]...{text[-tail:]}"


def _excerpt_window(line: str, column: int) -> tuple[str, int]:
    """The part of an excerpt ``line`` around ``column`` (0-based) and the column within it."""
    start, end = max(0, column - EXCERPT_SIDE), column + EXCERPT_SIDE
    if start == 0 and len(line) <= end:
        return line, column
    prefix = "..." if start > 0 else ""
    return prefix + line[start:end] + ("..." if end < len(line) else ""), len(prefix) + column - start


def _escape(match: re.Match) -> str:
    return repr(match.group())[1:-1] if match.group() not in "\u2028\u2029" else f"\\u{ord(match.group()):04x}"


class SymlearnError(Exception):
    """A problem with the user's input or settings, reported without a traceback.

    ``file``, ``line`` and ``column`` (1-based) locate the problem when it comes from text;
    ``hint`` suggests a fix.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | PathLike[str] | None = None,
        line: int | None = None,
        column: int | None = None,
        hint: str | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.file = None if file is None else str(file)
        self.line = line
        self.column = column
        self.hint = hint

    @property
    def location(self) -> str:
        """``file:line:col`` with the parts that are known, or ``""``."""
        parts = [p for p in (self.file, self.line, self.column) if p is not None]
        return ":".join(str(p) for p in parts)

    def __str__(self) -> str:
        """One line (plus a formula excerpt and its caret where there is one): whatever the file
        name, message and hint hold, unprintable characters are escaped (:func:`printable`)."""
        message, excerpt = self.message, ""
        found = _EXCERPT.search(message)
        if found:  # escape the excerpt line by line and move the caret under the same character
            line, column = _excerpt_window(found.group(1), len(found.group(2)))
            message = message[:found.start()]
            excerpt = f"\n  {printable(line)}\n  {' ' * len(printable(line[:column]))}^"
        location = bounded(printable(self.location))
        text = f"{location}: {bounded(printable(message))}" if location else bounded(printable(message))
        text += excerpt
        if self.hint:
            text += f" (hint: {bounded(printable(self.hint))})"
        return text

    def __reduce__(self):  # keep the fields when copied or sent between processes
        return (_rebuild, (type(self), self.message, self.file, self.line, self.column, self.hint))


def _rebuild(cls, message, file, line, column, hint):
    return cls(message, file=file, line=line, column=column, hint=hint)


class ParseError(SymlearnError):
    """Text that does not follow its grammar (formulas, task files, JSONL lines)."""


class DataError(SymlearnError):
    """Demonstrations or arrays that are malformed: ragged, NaN/inf, mismatched lengths, empty."""


class DemonstrationError(DataError):
    """A mistake in one demonstration: ``demonstration`` is its index in the file (0-based), and
    where known ``key`` (``"states"``/``"actions"``) and ``step`` say which value. A command that
    knows which file the demonstrations came from turns them into the file's line and column
    (:func:`symlearn.cli.output.blame_file`)."""

    def __init__(self, message: str, *, demonstration: int, key: str | None = None, step: int | None = None,
                 **location) -> None:
        super().__init__(message, **location)
        self.demonstration, self.key, self.step = demonstration, key, step

    def __reduce__(self):
        return (_rebuild_demonstration, (type(self), self.message, self.file, self.line, self.column, self.hint,
                                         self.demonstration, self.key, self.step))


def _rebuild_demonstration(cls, message, file, line, column, hint, demonstration, key, step):
    return cls(message, file=file, line=line, column=column, hint=hint, demonstration=demonstration, key=key,
               step=step)


class UnknownNameError(DataError):
    """A name that is none of the known ones (environment, task, domain); the hint lists them."""


class ModelError(SymlearnError):
    """An inconsistent model: a transition tensor that is not stochastic, an unknown state, ..."""


class LimitExceededError(SymlearnError):
    """A bounded computation (state limit, size limit) would exceed its bound."""


class MissingDependencyError(SymlearnError):
    """An optional engine is not installed; the message says how to install it."""


@dataclass(frozen=True)
class OptionalDependency:
    """An optional package or program and how to get it."""

    name: str
    install_hint: str

    def error(self, purpose: str) -> MissingDependencyError:
        return MissingDependencyError(
            f"{purpose} needs {self.name}, which is not installed", hint=self.install_hint
        )
