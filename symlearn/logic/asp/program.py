"""ASP programs composed from files and strings, remembering where every line came from.

A :class:`Program` is clingo text plus a list of :class:`Part` records. When clingo reports an
error at ``<block>:LINE:COL`` of the composed text, :meth:`Program.locate` answers with the file,
line and column the user wrote -- also for pieces cut out of a larger file (an example context
inside a task file starts in the middle of a line, so its first line carries a column offset).

>>> p = Program.from_text("a.", source="one.lp") + Program.from_text("b :- a.", source="two.lp")
>>> p.locate(2, 3)
('two.lp', 1, 3)
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from symlearn.errors import SymlearnError


@dataclass(frozen=True)
class Part:
    """One piece of a program: its text and where it starts in its source."""

    text: str
    source: str
    line: int = 1  # line of the source on which ``text`` starts
    column: int = 1  # column of the source at which the first line of ``text`` starts

    @property
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
    def from_file(cls, path: str | os.PathLike[str]) -> Program:
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise SymlearnError(f"not UTF-8 text: {exc.reason}", file=path) from exc
        return cls.from_text(text, source=str(path))

    @classmethod
    def compose(cls, pieces: Iterable[Program | str | os.PathLike[str]]) -> Program:
        """Join programs, strings (as program text) and paths (``Path`` objects are read)."""
        result = cls()
        for piece in pieces:
            result = result + as_program(piece)
        return result

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
