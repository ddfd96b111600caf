"""Per-iteration training logs: a CSV file written as training goes, and TensorBoard scalars.

``TrainingLog(csv="run.csv", tensorboard="runs/")`` is a :func:`~symlearn.rl.ppo.train_ppo`
callback (``log(record, policy)``) and takes plain rows too (``log.write({...})``, as the ICRL
learners' histories). One row per iteration, one column per number: a tuple field (``mean_cost``,
``multipliers``, one entry per constraint) becomes ``mean_cost_0``, ``mean_cost_1``, ...; ``None``
and NaN are written as empty cells.

Why rows are appended and flushed one by one: a long run can be watched with ``tail -f`` or
re-plotted while it runs, and a run that is killed keeps every iteration it finished. The header
is the first row's columns; when a later row brings a column the header lacks (a constraint whose
first cost arrived late), the whole file is rewritten once, atomically, with the wider header,
so the file on disk is always one well-formed table.

TensorBoard needs the ``tensorboard`` package (not a dependency of symlearn); asking for it without
the package is refused before training starts.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from symlearn.atomic import atomic_open
from symlearn.errors import SymlearnError


def flat_row(row: Mapping[str, Any]) -> dict[str, float | int | str | None]:
    """``row`` with sequences spread over numbered columns and non-finite numbers as ``None``."""
    flat: dict[str, float | int | str | None] = {}
    for key, value in row.items():
        if isinstance(value, (list, tuple)):
            for i, item in enumerate(value):
                flat[f"{key}_{i}"] = _cell(item)
        else:
            flat[key] = _cell(value)
    return flat


def _cell(value: Any) -> float | int | str | None:
    if value is None or isinstance(value, bool):
        return None if value is None else int(value)
    if isinstance(value, (int, float)) or hasattr(value, "__float__"):
        number = float(value)
        if not math.isfinite(number):
            return None
        return int(value) if isinstance(value, int) else number
    return str(value)


class TrainingLog:
    """Rows to a CSV file (``csv``) and/or TensorBoard (``tensorboard``: a log directory)."""

    def __init__(self, csv: str | os.PathLike[str] | None = None, tensorboard: str | os.PathLike[str] | None = None,
                 *, step_key: str = "steps") -> None:
        self.path = None if csv is None else Path(csv)
        self.step_key = step_key
        self.rows: list[dict[str, Any]] = []
        self.columns: list[str] = []
        self._writer = None
        if self.path is not None:
            if self.path.is_dir():
                raise SymlearnError(f"{self.path}: is a directory; --log names a CSV file to write")
            with atomic_open(self.path) as handle:  # refuses an unwritable place now, not after training
                handle.write("")
        if tensorboard is not None:
            self._writer = _summary_writer(Path(tensorboard))

    def __call__(self, record: Any, policy: Any = None) -> None:
        self.write(record.as_dict() if hasattr(record, "as_dict") else dict(record))

    def write(self, row: Mapping[str, Any]) -> None:
        flat = flat_row(row)
        self.rows.append(flat)
        if self.path is not None:
            new = [key for key in flat if key not in self.columns]
            if new:
                self.columns.extend(new)
                self._rewrite()
            else:
                with open(self.path, "a", encoding="utf-8", newline="") as handle:
                    csv.DictWriter(handle, self.columns, lineterminator="\n").writerow(flat)
        if self._writer is not None:
            step = flat.get(self.step_key)
            step = int(step) if isinstance(step, (int, float)) else len(self.rows)
            for key, value in flat.items():
                if key != self.step_key and isinstance(value, (int, float)):
                    self._writer.add_scalar(f"train/{key}", value, step)
            self._writer.flush()

    def _rewrite(self) -> None:
        text = io.StringIO()
        writer = csv.DictWriter(text, self.columns, lineterminator="\n")
        writer.writeheader()
        writer.writerows(self.rows)
        with atomic_open(self.path) as handle:
            handle.write(text.getvalue())

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            self._writer = None

    def __enter__(self) -> TrainingLog:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _summary_writer(folder: Path) -> Any:
    try:
        import tensorboard  # noqa: F401  (torch's writer needs it and says so less clearly)
        from torch.utils.tensorboard import SummaryWriter
    except ImportError:
        raise SymlearnError("--tensorboard needs the tensorboard package",
                            hint="pip install tensorboard (or log a CSV with --log FILE.csv)") from None
    if folder.exists() and not folder.is_dir():
        raise SymlearnError(f"{folder}: exists and is not a directory; --tensorboard names a log directory")
    return SummaryWriter(log_dir=str(folder))


__all__ = ["TrainingLog", "flat_row"]
