"""Choose the file format from the suffix and turn OS errors into readable ones."""

from __future__ import annotations

import os
from pathlib import Path

from symlearn.data.demonstrations import Demonstrations
from symlearn.errors import DataError

SUFFIXES = (".jsonl", ".npz")


def _format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise DataError(
            f"unknown demonstrations format {suffix or '(no suffix)'!r}",
            file=path,
            hint="use .jsonl for symbolic/discrete traces or .npz for numeric/image arrays",
        )
    return suffix


def save(demos: Demonstrations, path: str | os.PathLike[str]) -> None:
    """Write ``demos`` to ``path`` (``.jsonl`` or ``.npz``); the old file survives any failure."""
    path = Path(path)
    if _format_of(path) == ".jsonl":
        from symlearn.data.jsonl_format import write_jsonl

        write_jsonl(demos, path)
    else:
        from symlearn.data.npz_format import write_npz

        write_npz(demos, path)


def load(path: str | os.PathLike[str]) -> Demonstrations:
    """Read demonstrations written by :func:`save`."""
    path = Path(path)
    fmt = _format_of(path)
    if not path.exists():
        raise DataError("no such file", file=path)
    if path.is_dir():
        raise DataError("is a directory, expected a demonstrations file", file=path)
    if fmt == ".jsonl":
        from symlearn.data.jsonl_format import read_jsonl

        return read_jsonl(path)
    from symlearn.data.npz_format import read_npz

    return read_npz(path)
