"""Running a sweep: the cells not finished yet, on an executor, each record appended as it comes.

The driver keeps every worker busy, appends one record per attempt to the store, and puts a cell
that raised, crashed or timed out back in the queue until it has had ``1 + retries`` attempts in
this run; then it counts as failed and the sweep goes on. A re-run of the same command skips
the finished cells (those with an ``ok`` record) and tries the failed ones again. Ctrl-C or a
killed driver loses only the cells in flight.
"""

from __future__ import annotations

import os
import sys
import time
from collections import Counter, deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symlearn.errors import SymlearnError
from symlearn.sweep.spec import Cell, SweepSpec
from symlearn.sweep.store import ResultsStore

#: how long the driver sleeps in one wait for records: the bar's refresh period
POLL_SECONDS = 0.5


@dataclass
class SweepSummary:
    name: str
    out: str
    backend: str
    workers: int
    cells: int
    skipped: int = 0
    finished: int = 0
    failed: int = 0
    attempts: int = 0
    retried: int = 0
    seconds: float = 0.0
    failures: list[dict[str, Any]] = field(default_factory=list)

    def as_dict(self) -> dict[str, Any]:
        return dict(self.__dict__)


def job_of(spec: SweepSpec, cell: Cell, attempt: int) -> dict[str, Any]:
    return {"cell": cell.id, "params": cell.params, "seed": cell.seed, "attempt": attempt,
            "function": spec.function, "command": spec.command, "metrics": spec.metrics,
            "timeout": spec.timeout, "base": str(spec.path.parent.resolve()), "sys_path": [os.getcwd()]}


def make_pool(backend: str, workers: int | None, log_folder: Path, *, cpus: float, address: str | None):
    if backend == "local":
        from symlearn.sweep.local_pool import LocalPool

        count = workers or max(1, int((os.cpu_count() or 1) // cpus))
        return LocalPool(count, log_folder, threads=max(1, int(cpus)))
    from symlearn.sweep.ray_pool import RayPool

    return RayPool(workers, address=address, cpus=cpus, log_folder=log_folder)


def run_sweep(spec: SweepSpec, out: str | Path, *, backend: str = "ray", workers: int | None = None,
              retries: int | None = None, force: bool = False, address: str | None = None,
              progress: bool | None = None) -> SweepSummary:
    """Run the unfinished cells of ``spec`` into the results folder ``out``."""
    if backend not in ("ray", "local"):
        raise SymlearnError(f"unknown backend {backend!r} (ray or local)")
    if workers is not None and workers < 1:
        raise SymlearnError(f"--workers must be at least 1, not {workers}")
    if retries is not None and retries < 0:
        raise SymlearnError(f"--retries must be at least 0, not {retries}")
    if backend == "ray":
        from symlearn.sweep.ray_pool import import_ray

        import_ray()  # the missing-extra error before anything is written
    retries = spec.retries if retries is None else retries
    cells = spec.cells()
    started = time.monotonic()
    out = Path(out)
    with ResultsStore(out, spec.fingerprint(), {"spec": spec.to_json(), "cells": len(cells)}, force=force) as store:
        done = store.finished()
        todo = deque(c for c in cells if c.id not in done)
        summary = SweepSummary(spec.name, str(out), backend, 0, len(cells), skipped=len(cells) - len(todo))
        if not todo:
            summary.seconds = time.monotonic() - started
            return summary
        recorded = store.attempts()
        tries: Counter = Counter()
        by_id = {c.id: c for c in cells}
        limit = workers
        if backend == "local":  # no more worker processes than cells left
            limit = min(workers or max(1, int((os.cpu_count() or 1) // spec.cpus)), len(todo))
        pool = make_pool(backend, limit, out / "logs", cpus=spec.cpus, address=address)
        summary.workers = pool.capacity
        bar = _Bar(len(cells), summary.skipped, spec.name, progress)
        try:
            while todo or pool.running():
                while todo and pool.free() > 0:
                    cell = todo.popleft()
                    recorded[cell.id] += 1
                    pool.submit(job_of(spec, cell, recorded[cell.id]))
                bar.refresh(summary, pool.running())
                for record in pool.wait(POLL_SECONDS):
                    store.append(record)
                    summary.attempts += 1
                    if record["status"] == "ok":
                        summary.finished += 1
                    else:
                        tries[record["cell"]] += 1
                        cell = by_id[record["cell"]]
                        if tries[record["cell"]] <= retries:
                            summary.retried += 1
                            todo.appendleft(cell)  # first in line: a retry should not wait for the whole grid
                        else:
                            summary.failed += 1
                            error = record.get("error") or {}
                            summary.failures.append({"cell": record["cell"], "label": cell.label(),
                                                     "status": record["status"],
                                                     "message": f"{error.get('type')}: {error.get('message')}"})
                    bar.update(record["status"] == "ok", summary, pool.running())
        finally:
            pool.close()
            bar.close()
        summary.seconds = time.monotonic() - started
        return summary


class _Bar:
    """The bar over cells: finished and skipped ones fill it; running and failed counts beside it,
    and tqdm's ETA from this run's pace."""

    def __init__(self, total: int, skipped: int, name: str, enabled: bool | None) -> None:
        from symlearn.progress import progress_enabled

        self._bar = None
        if enabled if enabled is not None else progress_enabled():
            from tqdm import tqdm

            self._bar = tqdm(total=total, initial=skipped, desc=name, unit="cell", file=sys.stderr, leave=False,
                             dynamic_ncols=True)

    def update(self, finished: bool, summary: SweepSummary, running: int) -> None:
        if self._bar is not None:
            if finished:
                self._bar.update(1)
            self.refresh(summary, running)

    def refresh(self, summary: SweepSummary, running: int) -> None:
        if self._bar is not None:
            self._bar.set_postfix_str(f"running {running}, finished {summary.finished + summary.skipped}, "
                                      f"failed {summary.failed}, retried {summary.retried}", refresh=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
