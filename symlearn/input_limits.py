"""Reading a user's file without trusting it: size caps, UTF-8 and JSON with located errors.

Every reader of a user's file goes through these functions, so one hostile file (a 200-byte
header declaring gigabytes, ``/dev/zero``, 100,000 nested brackets, a stray Latin-1 byte)
stops with one :class:`~symlearn.errors.SymlearnError` naming the file, never a traceback or an
exhausted machine.

Limits (each overridable by an environment variable, documented in ``docs/FORMATS.md``):

* ``SYMLEARN_MAX_INPUT_MB`` (64): bytes read from one text input (JSON, JSONL, formulas, DOT);
* ``SYMLEARN_MAX_ARRAY_MB`` (256): bytes one NPZ archive may decompress to (declared by its member
  headers, checked before anything is decompressed), and the size of the archive file itself;
* ``SYMLEARN_MAX_STATES`` (1000000): states an automaton file may declare;
* ``SYMLEARN_MAX_BDD_NODES`` (2000000): nodes of the shared guard table (about 250 bytes each;
  read once, when :mod:`symlearn.logic.guards` is imported);
* ``SYMLEARN_MAX_TRANSLATION_NODES`` (5000000): nodes of one LTLf -> DFA translation's own BDD,
  dropped when it is done (``F p1 & ... & F p18``, 262,144 states, peaks near 1.2 GB; at the
  limit a translation holds about 1.5 GB, under the 2 GB a refusal may take);
* ``SYMLEARN_MAX_FORMULAS`` (10000): formulas one file may give ``ltl dfa --file`` (each is
  translated; 10,000 one-proposition formulas take a few seconds, 500,000 took minutes);

A value of ``0`` or ``none`` lifts a limit. :func:`limit` reads them at call time, so a test
(or a long-running service) can change them between reads.

JSON: :func:`load_json` refuses nesting deeper than :data:`MAX_JSON_DEPTH` levels and duplicate
keys in an object (``{"a": 1, "a": 2}`` keeps only one value silently in ``json.loads``), both
with line and column.
"""

from __future__ import annotations

import json
import os
import re
import stat
from pathlib import Path
from typing import Any

from symlearn.errors import LimitExceededError, ParseError, SymlearnError

__all__ = ["limit", "load_toml", "open_input", "read_input_bytes", "read_input_text", "decode_utf8", "load_json", "MAX_JSON_DEPTH",
           "check_size", "describe_bytes", "depth"]

_DEFAULTS = {
    "SYMLEARN_MAX_INPUT_MB": 64 * 2**20,
    "SYMLEARN_MAX_ARRAY_MB": 256 * 2**20,
    "SYMLEARN_MAX_STATES": 1_000_000,
    "SYMLEARN_MAX_BDD_NODES": 2_000_000,
    "SYMLEARN_MAX_TRANSLATION_NODES": 5_000_000,
    "SYMLEARN_MAX_FORMULAS": 10_000,
}
_IN_MEGABYTES = {"SYMLEARN_MAX_INPUT_MB", "SYMLEARN_MAX_ARRAY_MB"}

#: JSON nested deeper than this is refused (our formats need fewer than 10 levels; Python's
#: decoder would raise RecursionError near 1000).
MAX_JSON_DEPTH = 200


def limit(variable: str) -> int | None:
    """The limit named by ``variable`` (bytes for ``*_MB``, a count otherwise); ``None`` = no limit."""
    if variable not in _DEFAULTS:
        raise KeyError(variable)
    raw = os.environ.get(variable, "").strip()
    if not raw:
        return _DEFAULTS[variable]
    if raw.lower() in ("0", "none", "inf", "unlimited"):
        return None
    try:
        value = float(raw)
    except ValueError:
        raise LimitExceededError(f"{variable}={raw!r} is not a number",
                                 hint=f"set {variable} to a positive number, or 0 for no limit") from None
    if not value > 0 or value != value or value == float("inf"):
        raise LimitExceededError(f"{variable}={raw!r} must be a positive number",
                                 hint=f"set {variable} to a positive number, or 0 for no limit")
    return int(value * 2**20) if variable in _IN_MEGABYTES else int(value)


def describe_bytes(n: int) -> str:
    for unit, size in (("GB", 2**30), ("MB", 2**20), ("KB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n} bytes"


def check_size(size: int, variable: str, *, what: str, file: str | os.PathLike | None = None,
               line: int | None = None) -> None:
    """Raise :class:`LimitExceededError` when ``size`` exceeds the limit ``variable`` names."""
    bound = limit(variable)
    if bound is None or size <= bound:
        return
    if variable in _IN_MEGABYTES:
        amount, allowed = describe_bytes(size), describe_bytes(bound)
        hint = f"raise the limit with {variable}=<megabytes> (0: no limit) if the file is trusted"
    else:
        amount, allowed = f"{size:,}", f"{bound:,}"
        hint = f"raise the limit with {variable}=<count> (0: no limit) if the file is trusted"
    raise LimitExceededError(f"{what} ({amount}) exceeds the limit of {allowed}", file=file, line=line,
                             hint=hint)


def read_input_bytes(path: str | os.PathLike, *, variable: str = "SYMLEARN_MAX_INPUT_MB",
                     what: str = "input file") -> bytes:
    """The bytes of ``path``, at most the limit (reads a device or pipe only up to it)."""
    path = Path(path)
    bound = limit(variable)
    with open_input(path) as handle:
        info = os.fstat(handle.fileno())
        if stat.S_ISREG(info.st_mode):
            check_size(info.st_size, variable, what=f"{what} size", file=path)
            data = handle.read()
        elif bound is None:
            data = handle.read()
        else:
            data = _read_upto(handle, bound + 1)
    if bound is not None and len(data) > bound:  # a device or pipe: stopped reading at the limit
        raise LimitExceededError(f"{what} is larger than the limit of {describe_bytes(bound)} (reading stopped there)",
                                 file=path, hint=f"raise the limit with {variable}=<megabytes> (0: no limit) "
                                                 "if the file is trusted")
    return data


def open_input(path: str | os.PathLike):
    """``path`` opened for reading in binary, without blocking on a named pipe nobody writes to.

    ``open()`` of a FIFO waits until a writer opens it, forever if none does; here it is opened
    non-blocking (which returns at once), then reads block as usual: a pipe with a writer is read
    to its end, one without reads as empty. A directory raises :class:`IsADirectoryError`."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise IsADirectoryError(21, "Is a directory", str(path))
        if not stat.S_ISREG(info.st_mode):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _read_upto(handle, size: int, chunk: int = 1 << 20) -> bytes:
    """At most ``size`` bytes of a device or pipe, read in chunks: ``read(size)`` would reserve
    ``size`` bytes up front, which a small memory limit (``RLIMIT_AS``) refuses."""
    parts, total = [], 0
    while total < size:
        part = handle.read(min(chunk, size - total))
        if not part:
            break
        parts.append(part)
        total += len(part)
    return b"".join(parts)


def decode_utf8(data: bytes, *, source: str | os.PathLike | None = None) -> str:
    """UTF-8 text (a leading byte-order mark is dropped); a bad byte -> ParseError at its line:col."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        start = exc.start
        line = data.count(b"\n", 0, start) + 1
        column = start - (data.rfind(b"\n", 0, start) + 1) + 1
        raise ParseError(f"not UTF-8 text: byte 0x{data[start]:02x} cannot start or continue a character",
                         file=None if source is None else str(source), line=line, column=column,
                         hint="save the file as UTF-8") from None
    return text[1:] if text.startswith("\ufeff") else text


def read_input_text(path: str | os.PathLike, *, variable: str = "SYMLEARN_MAX_INPUT_MB",
                    what: str = "input file") -> str:
    """:func:`read_input_bytes` then :func:`decode_utf8`."""
    return decode_utf8(read_input_bytes(path, variable=variable, what=what), source=path)


def _reject_duplicates(pairs: list[tuple[str, Any]]) -> dict:
    result = dict(pairs)
    if len(result) != len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:
            if key in seen:
                raise _DuplicateKey(key)
            seen.add(key)
    return result


class _DuplicateKey(ValueError):
    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key


def _too_deep_at(text: str, depth: int) -> tuple[int, int] | None:
    """(line, column) where nesting first exceeds ``depth`` (strings skipped); None if never."""
    level, line, column, in_string, escaped = 0, 1, 0, False, False
    for char in text:
        column += 1
        if in_string:
            if escaped:
                escaped = False
            elif char == "\\":
                escaped = True
            elif char == '"':
                in_string = False
            elif char == "\n":
                line, column = line + 1, 0
            continue
        if char == '"':
            in_string = True
        elif char in "[{":
            level += 1
            if level > depth:
                return line, column
        elif char in "]}":
            level -= 1
        elif char == "\n":
            line, column = line + 1, 0
    return None


_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
_NOT_BRACKET = re.compile(r"[^\[\]{}]+")
_EMPTY_PAIR = re.compile(r"\[\]|\{\}")


def _deeper_than(text: str, depth: int) -> bool:
    """Whether valid JSON ``text`` nests more than ``depth`` levels (C-speed regex passes, one
    per level actually present; no Python loop over the values)."""
    if text.count("[") + text.count("{") <= depth:
        return False
    brackets = _NOT_BRACKET.sub("", _STRING.sub("", text))
    for _ in range(depth):
        brackets = _EMPTY_PAIR.sub("", brackets)
        if not brackets:
            return False
    return bool(brackets)


def depth(value: Any) -> int:
    """Nesting depth of a parsed JSON value (``[]`` is 1), without recursion; for the free-form
    parts of a document (metadata, info) that a reader passes on unchecked."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict):
            deepest = max(deepest, level)
            stack.extend((v, level + 1) for v in item.values() if isinstance(v, (dict, list)))
        elif isinstance(item, list):
            deepest = max(deepest, level)
            stack.extend((v, level + 1) for v in item if isinstance(v, (dict, list)))
    return deepest


def load_json(text: str, *, source: str | os.PathLike | None = None, line: int | None = None,
              allow_duplicates: bool = False, max_depth: int | None = MAX_JSON_DEPTH,
              error: type[SymlearnError] = ParseError, syntax: str = "invalid JSON", **keywords: Any) -> Any:
    """``json.loads`` with located errors: syntax, nesting deeper than ``max_depth`` and (unless
    ``allow_duplicates``) a key given twice in one object. ``line``: the line ``text`` starts on
    in the file (JSONL readers pass each line's number); further keywords go to ``json.loads``.

    ``max_depth=None`` skips the depth check of a parsed value (a reader whose fields are all
    type-checked, and that checks its free-form parts with :func:`depth`, saves the scan);
    nesting too deep for Python's decoder is refused either way. ``error`` and ``syntax``: the
    error class raised and the words a syntax error starts with (readers keep their own)."""
    file = None if source is None else str(source)
    offset = 0 if line is None else line - 1
    hook = None if allow_duplicates else _reject_duplicates
    try:
        value = json.loads(text, object_pairs_hook=hook, **keywords)
    except json.JSONDecodeError as exc:
        # a comment is the most common hand-written JSON(L) mistake: say so where the error points at one
        at = text[exc.pos:exc.pos + 2]
        hint = ("JSON has no comments: delete the line, or keep a note in a string field"
                if at[:1] == "#" or at in ("//", "/*") else None)
        raise error(f"{syntax}: {exc.msg}", file=file, line=exc.lineno + offset, column=exc.colno,
                    hint=hint) from None
    except RecursionError:
        bound = MAX_JSON_DEPTH if max_depth is None else max_depth
        where = _too_deep_at(text, bound) or (None, None)
        raise error(f"JSON nested more than {bound} levels deep", file=file,
                         line=None if where[0] is None else where[0] + offset, column=where[1]) from None
    except _DuplicateKey as exc:
        key = json.dumps(exc.key)
        position = text.find(key, text.find(key) + 1)
        at_line = text.count("\n", 0, position) + 1 if position >= 0 else None
        at_column = position - (text.rfind("\n", 0, position) + 1) + 1 if position >= 0 else None
        raise error(f"key {key} appears twice in one object", file=file,
                         line=None if at_line is None else at_line + offset, column=at_column,
                         hint="keep one of them") from None
    except ValueError as exc:  # Python refuses to convert an integer of more than 4300 digits
        too_long = _long_integer(text, exc, error, file, offset)
        if too_long is None:
            raise  # a caller's parse_* hook refusing a value: its own error
        raise too_long from None
    if max_depth is not None and isinstance(value, (dict, list)) and _deeper_than(text, max_depth):
        where = _too_deep_at(text, max_depth) or (None, None)
        raise error(f"JSON nested more than {max_depth} levels deep", file=file,
                    line=None if where[0] is None else where[0] + offset, column=where[1])
    if _SURROGATE_ESCAPE.search(text) and _holds_lone_surrogate(value):
        at_line, at_column = _line_column(text, _lone_surrogate_escape(text))
        raise error("a \\u escape is half of a surrogate pair (not a character): the text cannot be printed "
                    "or saved", file=file, line=at_line + offset, column=at_column,
                    hint="write the character itself, or both halves of its pair (\\ud83d\\ude00)")
    return value


def load_toml(text: str, *, source: str | os.PathLike | None = None) -> dict:
    """``tomllib.loads``, with an integer past Python's 4300-digit conversion refused at its
    line:col (tomllib lets that ``ValueError`` out); its own errors are left to the caller."""
    import tomllib

    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        raise
    except ValueError as exc:
        too_long = _long_integer(text, exc, ParseError, None if source is None else str(source))
        if too_long is None:
            raise
        raise too_long from None


def _long_integer(text: str, exc: ValueError, error: type, file: str | None, offset: int = 0):
    """The located refusal of an integer literal past Python's 4300-digit conversion, where that
    is what ``exc`` (a parser's ``ValueError``) says, else None."""
    found = _LONG_INTEGER.search(text)
    if found is None or "integer string conversion" not in str(exc):
        return None
    at_line, at_column = _line_column(text, found.start())
    return error(f"integer of {len(found.group().lstrip('-')):,} digits is too large", file=file,
                 line=at_line + offset, column=at_column)


#: an integer literal longer than Python converts (``sys.get_int_max_str_digits``, 4300)
_LONG_INTEGER = re.compile(r"-?[0-9_]{4301,}")
#: a ``\uD800``..``\uDFFF`` escape: paired (high then low) it is one character, alone it is none
_SURROGATE_ESCAPE = re.compile(r"\\u[dD][89a-fA-F][0-9a-fA-F]{2}")
_PAIRED = re.compile(r"\\u[dD][89abAB][0-9a-fA-F]{2}\\u[dD][c-fC-F][0-9a-fA-F]{2}")
_LONE = re.compile("[\ud800-\udfff]")


def _line_column(text: str, position: int) -> tuple[int, int]:
    return text.count("\n", 0, position) + 1, position - (text.rfind("\n", 0, position) + 1) + 1


def _holds_lone_surrogate(value: Any) -> bool:
    """Whether a parsed value holds a string (key or value) with a lone surrogate; walked only
    when the text has a surrogate escape at all."""
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            if _LONE.search(item):
                return True
        elif isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
    return False


def lone_surrogate_at(value: Any, where: str = "") -> str | None:
    """Where in ``value`` (dicts, lists, tuples, numpy string arrays) a string holds a lone
    surrogate -- ``'metadata["note"]'``, ``'[3]'`` -- or None. Writers ask before they write:
    the readers refuse such text (not a character; it cannot be printed or saved), so a file
    written with one could not be read back."""
    stack: list[tuple[str, Any]] = [(where, value)]
    while stack:
        at, item = stack.pop()
        if isinstance(item, str):
            if _LONE.search(item):
                return at or "a string"
        elif isinstance(item, dict):
            for key, inner in item.items():
                if isinstance(key, str) and _LONE.search(key):
                    return f"{at} key {ascii(key)}".strip()
                stack.append((f"{at}[{ascii(key) if isinstance(key, str) else key}]", inner))
        elif isinstance(item, (list, tuple)):
            stack.extend((f"{at}[{i}]", inner) for i, inner in enumerate(item))
        elif getattr(getattr(item, "dtype", None), "kind", None) in ("U", "O"):
            stack.extend((f"{at}[{i}]", inner) for i, inner in enumerate(item.tolist()))
    return None


def _lone_surrogate_escape(text: str) -> int:
    """Position of the first surrogate escape that is not half of a pair (0 if none is found)."""
    paired = {i for found in _PAIRED.finditer(text) for i in (found.start(), found.start() + 6)}
    return next((found.start() for found in _SURROGATE_ESCAPE.finditer(text) if found.start() not in paired), 0)
