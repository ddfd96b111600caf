"""Where a demonstration (and one of its values) is in a JSONL demonstrations file.

Learners check arrays, not files, so their errors say "demonstration 3, step 5";
:func:`locate_step` turns that into the file's line and column (1-based): the line of the
fourth trajectory (blank lines and the header skipped, as the reader does) and the column of
the sixth value of its ``states`` or ``actions`` list, for ``path:line:column: ...`` messages.
"""

from __future__ import annotations

import json
import os

from symlearn.input_limits import read_input_text

_DECODER = json.JSONDecoder()


def locate_step(path: str | os.PathLike[str], demonstration: int, key: str | None = None,
                step: int | None = None) -> tuple[int, int | None] | None:
    """``(line, column)`` of demonstration ``demonstration`` (0-based) of the JSONL file ``path``;
    the column of ``key``'s value (of its ``step``-th element) where those are given and found,
    else None. None when the file cannot be read or has no such trajectory."""
    try:
        lines = read_input_text(path, what="demonstrations file").splitlines()
    except Exception:  # noqa: BLE001 -- locating is a courtesy: the original error is what counts
        return None
    numbers = [n for n, raw in enumerate(lines, start=1) if raw.strip()][1:]  # the first is the header
    if not 0 <= demonstration < len(numbers):
        return None
    number = numbers[demonstration]
    column = None
    if key is not None:
        try:
            column = value_column(lines[number - 1], key, step)
        except (ValueError, IndexError):
            column = None
    return number, column


def _skip(raw: str, i: int) -> int:
    while i < len(raw) and raw[i] in " \t\r\n":
        i += 1
    return i


def value_column(raw: str, key: str, step: int | None = None) -> int | None:
    """1-based column of ``raw``'s top-level ``key`` value, or of its ``step``-th list element."""
    i = _skip(raw, 0)
    if raw[i] != "{":
        return None
    i += 1
    while True:
        i = _skip(raw, i)
        if raw[i] == "}":
            return None
        name, i = _DECODER.raw_decode(raw, i)
        i = _skip(raw, i)
        if raw[i] != ":":
            return None
        i = _skip(raw, i + 1)
        if name == key:
            break
        _, i = _DECODER.raw_decode(raw, i)
        i = _skip(raw, i)
        if raw[i] == ",":
            i += 1
    if step is None or raw[i] != "[":
        return i + 1
    i += 1
    for n in range(step + 1):
        i = _skip(raw, i)
        if raw[i] == "]":
            return None
        if n == step:
            return i + 1
        _, i = _DECODER.raw_decode(raw, i)
        i = _skip(raw, i)
        if raw[i] == ",":
            i += 1
    return None


__all__ = ["locate_step", "value_column"]
