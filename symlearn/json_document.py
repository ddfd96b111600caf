"""The envelope symlearn's JSON files share: ``{"symlearn": MAGIC, "format_version": 1, ...}`` (groundings,
DNF formulas), read with located errors; ``JsonFile`` gives such a value ``save``/``load``."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError
from symlearn.input_limits import load_json, read_input_text


def read_document(text: str | Mapping[str, Any], magic: str, version: int, *,
                  source: str | None = "<string>") -> Mapping[str, Any]:
    """The parsed document (text, or an already parsed mapping), after checking JSON syntax
    (line, column), magic and version."""
    if isinstance(text, Mapping):
        doc = text
    else:
        doc = load_json(text, source=source)  # syntax, nesting and duplicate keys located
    if not isinstance(doc, Mapping) or doc.get("symlearn") != magic:
        raise DataError(f"not a symlearn {magic.replace('-', ' ')} (missing \"symlearn\": \"{magic}\")", file=source)
    if doc.get("format_version") != version:
        raise DataError(f"unsupported {magic} format_version {doc.get('format_version')!r}", file=source,
                        hint=f"this symlearn reads version {version}")
    return doc


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
