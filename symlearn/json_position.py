"""Where a value sits in JSON text: :func:`locate` turns a path of object keys and list indexes
(``("negative_traces", 0, "key", 2)``) into the 1-based line and column of the value's first
character, so a reader that checks a decoded document can still name the file's line and column
of what it refuses (:class:`JsonPathError`).

Only called on an error, so a plain forward scan is enough: linear in the text before the value,
iterative (no recursion, whatever the nesting), and it assumes text ``json.loads`` accepted (the
readers decode first); on anything else it gives up with None rather than guess.
"""

from __future__ import annotations

from collections.abc import Sequence
from json.decoder import scanstring

from symlearn.errors import DataError

__all__ = ["JsonPathError", "locate", "located", "path_text"]

_SPACE = " \t\n\r"


class JsonPathError(DataError):
    """A value of a decoded JSON document that a reader refuses; ``path`` (keys and indexes from
    the root) says which: the message starts with it (:func:`path_text`, ``positive_traces[0].a[1]: ...``)
    and :func:`located` turns it into a line and column."""

    def __init__(self, message: str, *, path: Sequence[str | int], **location) -> None:
        super().__init__(f"{path_text(path)}: {message}", **location)
        self.path = tuple(path)
        self.detail = message

    def __reduce__(self):
        return (_rebuild, (type(self), self.detail, self.path, self.file, self.line, self.column, self.hint))


def _rebuild(cls, detail, path, file, line, column, hint):
    return cls(detail, path=path, file=file, line=line, column=column, hint=hint)


def path_text(path: Sequence[str | int]) -> str:
    """``("positive_traces", 0, "a", 1)`` as ``positive_traces[0].a[1]``; the root is ``$``."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text or "$"


def located(error: JsonPathError, text: str) -> JsonPathError:
    """``error`` with the line and column of its path in ``text`` (unchanged where not found)."""
    if error.line is None:
        position = locate(text, error.path)
        if position is not None:
            error.line, error.column = position
    return error


def locate(text: str, path: Sequence[str | int]) -> tuple[int, int] | None:
    """The line and column (1-based) where the value at ``path`` starts in ``text``, or None."""
    try:
        offset = _offset(text, path)
    except (IndexError, ValueError):   # text json.loads would refuse: no position to give
        return None
    if offset is None:
        return None
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _offset(text: str, path: Sequence[str | int]) -> int | None:
    pos = _skip_space(text, 0)
    for part in path:
        opener = text[pos]
        if opener == "{" and isinstance(part, str):
            pos = _member(text, pos, part)
        elif opener == "[" and isinstance(part, int) and not isinstance(part, bool):
            pos = _element(text, pos, part)
        else:
            return None
        if pos is None:
            return None
    return pos


def _member(text: str, pos: int, key: str) -> int | None:
    """The offset of ``key``'s value in the object at ``pos``."""
    pos = _skip_space(text, pos + 1)
    while text[pos] != "}":
        name, pos = scanstring(text, pos + 1)
        pos = _skip_space(text, _skip_space(text, pos) + 1)   # past the ':'
        if name == key:
            return pos
        pos = _skip_space(text, _skip_value(text, pos))
        if text[pos] == ",":
            pos = _skip_space(text, pos + 1)
    return None


def _element(text: str, pos: int, index: int) -> int | None:
    """The offset of element ``index`` of the list at ``pos``."""
    pos = _skip_space(text, pos + 1)
    count = 0
    while text[pos] != "]":
        if count == index:
            return pos
        pos = _skip_space(text, _skip_value(text, pos))
        if text[pos] == ",":
            pos = _skip_space(text, pos + 1)
        count += 1
    return None


def _skip_value(text: str, pos: int) -> int:
    """The offset just past the value starting at ``pos``."""
    if text[pos] == '"':
        return scanstring(text, pos + 1)[1]
    if text[pos] not in "{[":   # a number or a literal: up to the next delimiter
        while pos < len(text) and text[pos] not in ",]}" + _SPACE:
            pos += 1
        return pos
    depth = 0
    while True:
        char = text[pos]
        if char == '"':
            pos = scanstring(text, pos + 1)[1]
            continue
        if char in "{[":
            depth += 1
        elif char in "}]":
            depth -= 1
            if depth == 0:
                return pos + 1
        pos += 1


def _skip_space(text: str, pos: int) -> int:
    while pos < len(text) and text[pos] in _SPACE:
        pos += 1
    return pos
