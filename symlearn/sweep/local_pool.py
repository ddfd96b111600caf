"""``--local``: cells in a pool of worker processes on this machine, without Ray.

Not :class:`concurrent.futures.ProcessPoolExecutor`: one worker that dies there breaks the whole
pool, and a running task cannot be stopped. Here each worker is a ``spawn``ed process with a pipe
of its own; a worker that dies (killed, out of memory, a segfault in an extension) costs only its
cell, recorded as ``crash``, and a cell past its time limit is stopped by killing its worker
(``timeout``); either way a fresh worker takes the slot. Workers live for the whole sweep, so a
cell pays for its imports once per worker, not once per cell.

Workers are not daemonic, so a cell may start processes of its own (a daemonic process may not
have children: Scarlet's adapter, a learner's own pool); the driver stops them in every case
(closing the pool kills them; a killed driver is noticed by their watch thread).

Jobs and records cross the pipe as JSON text. A worker's stdout and stderr go to
``logs/worker-N.log`` in the results folder (a cell's prints never reach the terminal), and a
worker ends itself when the driver is gone.
"""

from __future__ import annotations

import json
import os
import signal
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from symlearn.sweep.cell import failure


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os._exit(70)


def _worker_main(connection, log_path: str, parent: int, threads: int) -> None:
    """The loop of one worker: a job (JSON text) in, its record (JSON text) out."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the driver's; it stops us
    for variable in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS"):
        os.environ[variable] = str(threads)  # one cell, its share of the cores (before numpy loads)
    os.environ.setdefault("SYMLEARN_QUIET", "1")
    log = os.open(log_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    os.dup2(log, 1)
    os.dup2(log, 2)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()
    from symlearn.sweep.cell import execute_text

    while True:
        try:
            job = connection.recv_bytes()
        except (EOFError, OSError):
            return
        connection.send_bytes(execute_text(job.decode("utf-8")).encode("utf-8"))


@dataclass
class _Slot:
    number: int
    process: Any = None
    connection: Any = None
    job: dict[str, Any] | None = None
    started: float = 0.0


class LocalPool:
    """``workers`` worker processes; :meth:`submit` a job to a free one, :meth:`wait` for records."""

    name = "local"

    def __init__(self, workers: int, log_folder: str | Path, *, threads: int = 1) -> None:
        import multiprocessing

        self._context = multiprocessing.get_context("spawn")
        self.slots = [_Slot(i) for i in range(max(1, workers))]
        self.capacity = len(self.slots)
        self.log_folder = Path(log_folder)
        self.log_folder.mkdir(parents=True, exist_ok=True)
        self.threads = max(1, int(threads))
        for slot in self.slots:  # all start together: the interpreters boot in parallel
            self._start(slot)

    def _start(self, slot: _Slot) -> None:
        receiver, sender = self._context.Pipe(duplex=True)
        process = self._context.Process(
            target=_worker_main, name=f"symlearn-sweep-{slot.number}", daemon=False,
            args=(sender, str(self.log_folder / f"worker-{slot.number}.log"), os.getpid(), self.threads))
        process.start()
        sender.close()
        slot.process, slot.connection, slot.job = process, receiver, None

    def _stop(self, slot: _Slot) -> None:
        if slot.process is not None:
            if slot.process.is_alive():
                slot.process.kill()
            slot.process.join()
            slot.connection.close()
        slot.process = slot.connection = slot.job = None

    def running(self) -> int:
        return sum(slot.job is not None for slot in self.slots)

    def free(self) -> int:
        return self.capacity - self.running()

    def submit(self, job: dict[str, Any]) -> None:
        slot = next(s for s in self.slots if s.job is None)
        if slot.process is None or not slot.process.is_alive():
            self._stop(slot)
            self._start(slot)
        try:
            slot.connection.send_bytes(json.dumps(job).encode("utf-8"))
        except (BrokenPipeError, OSError):  # died since the check: a fresh one
            self._stop(slot)
            self._start(slot)
            slot.connection.send_bytes(json.dumps(job).encode("utf-8"))
        slot.job, slot.started = job, time.monotonic()

    def wait(self, timeout: float) -> list[dict[str, Any]]:
        """Records of the attempts that ended within ``timeout`` seconds (maybe none)."""
        from multiprocessing.connection import wait

        busy = [s for s in self.slots if s.job is not None]
        if not busy:
            return []
        now = time.monotonic()
        deadlines = [s.started + s.job["timeout"] - now for s in busy if s.job.get("timeout")]
        limit = max(0.0, min([timeout, *deadlines]))
        waitables = {}
        for slot in busy:
            waitables[slot.connection] = slot
            waitables[slot.process.sentinel] = slot
        ready = {waitables[obj].number for obj in wait(list(waitables), timeout=limit)}
        records = []
        for slot in busy:
            if slot.number in ready:
                records.append(self._collect(slot))
            elif slot.job.get("timeout") and time.monotonic() - slot.started > slot.job["timeout"]:
                job, seconds = slot.job, time.monotonic() - slot.started
                self._stop(slot)
                records.append(failure(job, "timeout", f"time limit of {job['timeout']:g} s reached; the worker "
                                                       "was stopped", seconds))
        return records

    def _collect(self, slot: _Slot) -> dict[str, Any]:
        job, seconds = slot.job, time.monotonic() - slot.started
        try:
            if slot.connection.poll():
                record = json.loads(slot.connection.recv_bytes().decode("utf-8"))
                slot.job = None
                return record
        except (EOFError, OSError):
            pass
        slot.process.join(timeout=5)
        code = slot.process.exitcode
        self._stop(slot)
        return failure(job, "crash", f"the worker process stopped ({_describe(code)}) while running the cell",
                       seconds)

    def close(self) -> None:
        for slot in self.slots:
            self._stop(slot)


def _describe(code: int | None) -> str:
    if code is None:
        return "still running"
    if code < 0:
        try:
            return signal.Signals(-code).name
        except ValueError:
            return f"signal {-code}"
    return f"exit code {code}"
