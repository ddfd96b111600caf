"""The envelope symlearn's JSON files share: ``{"symlearn": MAGIC, "format_version": 1, ...}`` (groundings,
DNF formulas), read with located errors; ``JsonFile`` gives such a value ``save``/``load``;
:func:`load_option_json` reads JSON given on the command line (``--env-kwargs``) as strictly as
the file readers read theirs."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError
from symlearn.input_limits import load_json, read_input_text

#: nesting a JSON option may have (keyword arguments of a constructor need a few levels)
MAX_OPTION_DEPTH = 32
#: integers a JSON option may hold: what float64 and int64 parameters can take without overflow
MAX_OPTION_INTEGER = 2**63 - 1


def read_document(text: str | Mapping[str, Any], magic: str, version: int, *,
                  source: str | None = "<string>") -> Mapping[str, Any]:
    """The parsed document (text, or an already parsed mapping), after checking JSON syntax
    (line, column), magic and version."""
    if isinstance(text, Mapping):
        doc = text
    else:
        doc = load_json(text, source=source)  # syntax, nesting and duplicate keys located
    if not isinstance(doc, Mapping) or doc.get("symlearn") != magic:
        other = _other_kind(doc)
        raise DataError(f"not a symlearn {magic.replace('-', ' ')} (missing \"symlearn\": \"{magic}\")"
                        + (f": it is {other[0]}" if other else ""), file=source, hint=other[1] if other else None)
    if doc.get("format_version") != version:
        raise DataError(f"unsupported {magic} format_version {doc.get('format_version')!r}", file=source,
                        hint=f"this symlearn reads version {version}")
    return doc


#: what a file of another symlearn kind is, said where a reader is handed it (``train --cost`` given
#: the forbidden pairs ``learn constraints`` wrote), with where such a file goes instead
_KINDS = {
    "symlearn-constraints": ("the forbidden state-action pairs `learn constraints` writes",
                             "a shield removes them from an agent's choices (symlearn.backends.shield.Shield, "
                             "docs/SB3.md); `train --cost` reads a DNF file (learn dnf) or a neural cost (learn icrl)"),
    "symlearn-torch-module": ("the settings of a model (the .json written beside its .safetensors weights)",
                              "give the .safetensors file itself"),
}


def _other_kind(doc: Any) -> tuple[str, str | None] | None:
    """``(what the document is, where it goes)`` for a document of another symlearn kind, else None."""
    if not isinstance(doc, Mapping):
        return None
    if isinstance(doc.get("symlearn"), str):
        return f"a symlearn {doc['symlearn']} document", None
    found = doc.get("format")
    if isinstance(found, str) and found in _KINDS:
        return _KINDS[found]
    return None


class JsonFile:
    """``save(path)`` / ``load(path)`` for a value with ``to_json()`` and ``from_json(text, source=)``."""

    def save(self, path: str | os.PathLike[str]) -> Path:
        return write_text(path, self.to_json() + "\n")

    @classmethod
    def load(cls, path: str | os.PathLike[str]):
        path = Path(path)
        try:
            text = read_input_text(path)  # size cap, UTF-8 errors at line:col
        except OSError as exc:
            raise DataError(f"cannot read {path}: {exc.strerror}", file=str(path)) from None
        return cls.from_json(text, source=str(path))


def load_option_json(text: str, option: str, *, kind: type | None = dict) -> Any:
    """The JSON value of a command-line option such as ``--env-kwargs``, read like a file:
    duplicate keys, nesting deeper than :data:`MAX_OPTION_DEPTH`, NaN and infinities, and
    integers beyond int64 are refused (a :class:`DataError` naming ``option`` and the column);
    ``kind``: the type the value must have (``None``: any)."""

    def integer(literal: str) -> int:
        value = int(literal) if len(literal) <= 20 else MAX_OPTION_INTEGER + 1
        if abs(value) > MAX_OPTION_INTEGER:
            raise DataError(f"{option}: the integer {literal[:24]}{'...' if len(literal) > 24 else ''} is too large",
                            hint=f"integers up to {MAX_OPTION_INTEGER:,}")
        return value

    def number(literal: str) -> float:
        value = float(literal)
        if value != value or value in (float("inf"), float("-inf")):
            raise DataError(f"{option}: the number {literal[:24]} is too large for a float")
        return value

    def constant(literal: str) -> float:
        raise DataError(f"{option}: {literal} is not a JSON number", hint="give finite numbers")

    value = load_json(text, source=option, max_depth=MAX_OPTION_DEPTH, error=DataError, syntax="not JSON",
                      parse_int=integer, parse_float=number, parse_constant=constant)
    if kind is not None and not isinstance(value, kind):
        raise DataError(f"{option} must be a JSON {'object' if kind is dict else kind.__name__}, "
                        f"got {type(value).__name__}")
    return value
