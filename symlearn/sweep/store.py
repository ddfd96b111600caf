"""The results folder of a sweep: ``sweep.json`` (which sweep wrote it) and ``results.jsonl``.

Why JSON lines: one record per line is appended and made durable with one ``write`` and one
``fsync``, so a driver killed at any moment leaves every finished record whole and at most one
torn last line, which readers skip and the next run cuts off; it needs no library to read
(``pandas.read_json(path, lines=True)``, DuckDB ``read_json_auto``, ``jq``, a text editor). A
Parquet file cannot be appended to in place: it would mean one file per cell or rewriting the
file after every cell.

A record (one line, ``results.jsonl``)::

    {"cell": "3f0c...", "params": {"p": 0.3}, "seed": 1, "attempt": 1, "status": "ok",
     "metrics": {"reward": 0.91}, "error": null, "seconds": 0.52, "host": "...", "pid": 123,
     "finished": "2026-11-30T12:00:00.000+00:00"}

``status`` is ``ok``, ``error`` (the function raised: ``error`` has type, message, traceback),
``crash`` (the worker process died) or ``timeout``. Every attempt is recorded; a cell is finished
when it has an ``ok`` record, and a re-run skips it. ``cell`` is the hash of what the cell
computes (:func:`symlearn.sweep.spec.cell_id`).

``sweep.json`` (written atomically) holds the sweep's spec and its fingerprint; a folder written
by a sweep with another fingerprint is refused unless ``force``. A lock file keeps two drivers
from writing one folder at once.
"""

from __future__ import annotations

import json
import os
import stat
from collections import Counter
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError, LimitExceededError
from symlearn.input_limits import decode_utf8, describe_bytes, limit, load_json, open_input, read_input_bytes
from symlearn.json_document import read_document

MAGIC = "sweep"
FORMAT_VERSION = 1
META = "sweep.json"
RESULTS = "results.jsonl"
LOCK = ".lock"
STATUSES = ("ok", "error", "crash", "timeout")


def read_meta(folder: str | Path) -> dict[str, Any]:
    """The ``sweep.json`` of a results folder."""
    path = Path(folder) / META
    if not path.is_file():
        raise DataError(f"{folder} is no sweep results folder (it has no {META})",
                        hint="give the --out folder of 'symlearn sweep run'")
    return dict(read_document(decode_utf8(read_input_bytes(path), source=path), MAGIC, FORMAT_VERSION,
                              source=str(path)))


def read_records(folder: str | Path) -> list[dict[str, Any]]:
    """Every whole record of ``results.jsonl``, in order; a torn last line (the driver was
    killed while writing it) is skipped. Records are read without a size cap on the file (a long
    sweep's store is large by right), but each line is capped by ``SYMLEARN_MAX_INPUT_MB`` and
    the store must be a regular file (a device or an endless line stops there); each line is
    checked as JSON with its line number."""
    path = Path(folder) / RESULTS
    if not path.exists():
        return []
    records = []
    bound = limit("SYMLEARN_MAX_INPUT_MB")
    with open_input(path) as handle:  # a named pipe without a writer must not block the open
        if not stat.S_ISREG(os.fstat(handle.fileno()).st_mode):  # /dev/zero would be one endless line
            raise DataError("the results store is not a regular file", file=path)
        number = 0
        while raw := handle.readline(-1 if bound is None else bound + 1):
            number += 1
            if bound is not None and len(raw) > bound:
                raise LimitExceededError(f"record is longer than the limit of {describe_bytes(bound)} "
                                         "(reading stopped there)", file=path, line=number,
                                         hint="raise the limit with SYMLEARN_MAX_INPUT_MB=<megabytes> "
                                              "(0: no limit) if the file is trusted")
            if not raw.endswith(b"\n"):
                break  # torn last line: never acknowledged, so never counted
            text = decode_utf8(raw, source=path).rstrip("\r\n")
            if not text.strip():
                continue
            record = load_json(text, source=path, line=number, error=DataError)
            if not isinstance(record, dict) or "cell" not in record or record.get("status") not in STATUSES:
                raise DataError("not a sweep record (needs \"cell\" and a \"status\")", file=path, line=number)
            records.append(record)
    return records


class ResultsStore:
    """The open results folder of a running sweep: :meth:`append` one record per attempt."""

    def __init__(self, folder: str | Path, fingerprint: str, meta: dict[str, Any], *, force: bool = False) -> None:
        self.folder = Path(folder)
        self.path = self.folder / RESULTS
        self.folder.mkdir(parents=True, exist_ok=True)
        self._lock = _lock(self.folder)
        try:
            self.reused = self._claim(fingerprint, meta, force)
            self._cut_torn_line()
            self.records = read_records(self.folder)
            self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
        except BaseException:
            os.close(self._lock)
            raise

    def _claim(self, fingerprint: str, meta: dict[str, Any], force: bool) -> bool:
        meta_path = self.folder / META
        existed = meta_path.exists()
        if existed:
            old = read_meta(self.folder)
            if old.get("fingerprint") != fingerprint and not force:
                recorded = old.get("spec")  # a hand-edited sweep.json may hold anything here
                wrote = recorded.get("path") if isinstance(recorded, dict) else None
                wrote = wrote if isinstance(wrote, str) else "another sweep file"
                mine = (meta.get("spec") or {}).get("path")
                which = (f"an earlier version of {wrote}" if mine is not None and Path(mine).resolve() ==
                         Path(wrote).resolve() else f"another sweep ({wrote})")
                raise DataError(f"{self.folder} holds the results of {which}: its grid, seeds, "
                                "metrics or function differ from this file's",
                                hint="choose another --out folder, or --force to adopt it (finished cells with "
                                     "the same function, parameters and seed are kept; the others are ignored)")
        elif any(p.name != LOCK for p in self.folder.iterdir()) and not force:
            raise DataError(f"{self.folder} is not empty and holds no sweep results",
                            hint="choose a new or empty --out folder, or --force to write into it")
        doc = {"symlearn": MAGIC, "format_version": FORMAT_VERSION, "fingerprint": fingerprint, **meta,
               "updated": datetime.now(timezone.utc).isoformat(timespec="seconds")}
        write_text(meta_path, json.dumps(doc, indent=1) + "\n")
        return existed

    def _cut_torn_line(self) -> None:
        """A line without its newline was being written when the driver died: drop it, so the
        next record starts on a line of its own."""
        if not self.path.exists() or self.path.stat().st_size == 0:
            return
        with open(self.path, "rb+") as handle:
            handle.seek(0, os.SEEK_END)
            size = handle.tell()
            handle.seek(size - 1)
            if handle.read(1) == b"\n":
                return
            keep = size
            while keep > 0:
                step = min(65536, keep)
                handle.seek(keep - step)
                chunk = handle.read(step)
                cut = chunk.rfind(b"\n")
                if cut >= 0:
                    keep = keep - step + cut + 1
                    break
                keep -= step
            handle.truncate(keep)
            handle.flush()
            os.fsync(handle.fileno())

    def finished(self) -> set[str]:
        return {r["cell"] for r in self.records if r["status"] == "ok"}

    def attempts(self) -> Counter:
        return Counter(r["cell"] for r in self.records)

    def append(self, record: dict[str, Any]) -> None:
        """Append one record durably: a single ``write`` of the whole line (``O_APPEND``), then
        ``fsync``; only then is the cell counted as finished."""
        data = (json.dumps(record, allow_nan=False, separators=(",", ":")) + "\n").encode("utf-8")
        view = memoryview(data)
        while view:
            written = os.write(self._fd, view)
            view = view[written:]
        os.fsync(self._fd)
        self.records.append(record)

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None
        if self._lock is not None:
            os.close(self._lock)
            self._lock = None

    def __enter__(self) -> "ResultsStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _lock(folder: Path) -> int:
    """An exclusive lock on ``folder/.lock`` for the life of the driver (released by the kernel
    when it dies, so a killed driver never leaves the folder locked)."""
    import fcntl

    fd = os.open(folder / LOCK, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise DataError(f"another 'symlearn sweep run' is writing {folder}",
                        hint="wait for it to finish (or stop it), then run again to resume") from None
    return fd
