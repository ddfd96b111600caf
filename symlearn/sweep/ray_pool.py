"""Cells as Ray tasks: an embedded Ray on this machine by default, or a running cluster
(``--address``), so one sweep file runs on a laptop and on a cluster alike.

Each cell is one task reserving ``cpus`` CPUs; Ray's own retries are off (``max_retries=0``) so
that every attempt, failed ones included, is recorded once by the driver and the retry budget is
the sweep's. A worker that dies surfaces as a Ray error on the task (recorded as ``crash``); a
cell past its time limit is cancelled with ``force=True``, which kills its worker (``timeout``).
Jobs and records travel as JSON text.

On a cluster, every node needs symlearn (and whatever the cell imports) installed, and a
``file.py:function`` path must exist on the nodes (a shared folder) -- or name the function by
module.
"""

from __future__ import annotations

import json
import logging
import os
import signal
import sys
import time
from typing import Any

from symlearn.errors import OptionalDependency, SymlearnError
from symlearn.sweep.cell import execute_text, failure

RAY = OptionalDependency(
    "Ray", "install the sweep extra: installed by `make test`; else .venv/bin/pip install -e '.[sweep]' "
           "(from a wheel: pip install 'symlearn[sweep]'); or run with --local (a process pool on this machine)")
#: the object store of an embedded Ray: cells exchange small JSON texts, so the minimum is plenty
#: and leaves the machine's memory to the cells
EMBEDDED_OBJECT_STORE_BYTES = 80 * 2**20


def import_ray(purpose: str = "running a sweep on Ray"):
    try:
        import ray
    except ImportError:
        raise RAY.error(purpose) from None
    return ray


def _run_cell(job_text: str) -> str:
    return execute_text(job_text)


class RayPool:
    """Cells as Ray tasks, at most ``workers`` at once (None: as many as the cluster has CPUs
    for)."""

    name = "ray"

    def __init__(self, workers: int | None, *, address: str | None = None, cpus: float = 1.0,
                 log_folder: str | os.PathLike | None = None) -> None:
        ray = self._ray = import_ray()
        self._started_here = False
        self._node_file = None
        self._stdout = None
        if not ray.is_initialized():
            options: dict[str, Any] = dict(include_dashboard=False, log_to_driver=False,
                                           logging_level=logging.ERROR, configure_logging=True)
            if address is None:  # embedded: Ray's processes on this machine, for this command only
                total = os.cpu_count() or 1
                options.update(num_cpus=int(max(cpus, (workers or total) * cpus)),
                               object_store_memory=EMBEDDED_OBJECT_STORE_BYTES)
                os.environ.setdefault("SYMLEARN_QUIET", "1")  # Ray's processes inherit the driver's environment
                if log_folder is not None:
                    end_leftovers(log_folder)
            else:
                options.update(address=address)
            try:
                ray.init(**options)
            except ConnectionError as exc:
                raise SymlearnError(
                    f"cannot reach the Ray cluster at {address}: {exc}",
                    hint="start it with 'ray start --head'; a cluster with token authentication (the default of "
                         "'ray start' in Ray 2.60) needs RAY_AUTH_MODE=token in this shell (the token is read from "
                         "~/.ray/auth_token or RAY_AUTH_TOKEN); or leave out --address for a Ray on this "
                         "machine") from None
            self._started_here = True
            if address is None and log_folder is not None:
                os.makedirs(log_folder, exist_ok=True)
                self._node_file = os.path.join(log_folder, NODE_FILE)
                from symlearn.atomic import write_text

                write_text(self._node_file, json.dumps({"node_id": ray.get_runtime_context().get_node_id(),
                                                        "driver": os.getpid(),
                                                        "driver_start": _start_time(os.getpid())}) + "\n")
        if log_folder is not None:
            # Ray's driver prints the raylet's notices ("a worker died ...") on sys.stdout from a
            # thread of its own, even with log_to_driver=False; stdout is the command's (one
            # JSON document with --json), and the store records those events already.
            os.makedirs(log_folder, exist_ok=True)
            self._stdout = sys.stdout
            sys.stdout = open(os.path.join(log_folder, "ray-driver.log"), "a", encoding="utf-8")
        cluster_cpus = ray.cluster_resources().get("CPU", 1.0)
        self.capacity = max(1, int(workers if workers else cluster_cpus // cpus or 1))
        self._remote = ray.remote(num_cpus=cpus, max_retries=0)(_run_cell)
        self._running: dict[Any, tuple[dict[str, Any], float]] = {}

    def running(self) -> int:
        return len(self._running)

    def free(self) -> int:
        return self.capacity - len(self._running)

    def submit(self, job: dict[str, Any]) -> None:
        ref = self._remote.remote(json.dumps(job))
        self._running[ref] = (job, time.monotonic())

    def wait(self, timeout: float) -> list[dict[str, Any]]:
        ray = self._ray
        if not self._running:
            return []
        now = time.monotonic()
        deadlines = [started + job["timeout"] - now for job, started in self._running.values() if job.get("timeout")]
        limit = max(0.0, min([timeout, *deadlines]))
        refs = list(self._running)
        ready, _ = ray.wait(refs, num_returns=1, timeout=limit)
        if ready:  # and whatever else is done by now
            ready, _ = ray.wait(refs, num_returns=len(refs), timeout=0)
        records = []
        for ref in ready:
            job, started = self._running.pop(ref)
            try:
                records.append(json.loads(ray.get(ref)))
            except ray.exceptions.RayError as exc:  # the worker died (or the node): not the cell's answer
                records.append(failure(job, "crash", _first_line(exc), time.monotonic() - started))
        now = time.monotonic()
        for ref, (job, started) in list(self._running.items()):
            if job.get("timeout") and now - started > job["timeout"]:
                ray.cancel(ref, force=True)
                del self._running[ref]
                records.append(failure(job, "timeout", f"time limit of {job['timeout']:g} s reached; the task "
                                                       "was cancelled", now - started))
        return records

    def close(self) -> None:
        for ref in list(self._running):
            try:
                self._ray.cancel(ref, force=True)
            except Exception:  # noqa: BLE001 - shutting down anyway
                pass
        self._running.clear()
        if self._started_here:
            self._ray.shutdown()
            if self._node_file is not None and os.path.exists(self._node_file):
                os.unlink(self._node_file)
        if self._stdout is not None:
            log, sys.stdout, self._stdout = sys.stdout, self._stdout, None
            log.close()


NODE_FILE = "ray-node.json"


def end_leftovers(log_folder: str | os.PathLike) -> list[int]:
    """End what is left of the embedded Ray of a driver that was killed (SIGKILL gives it no
    chance to shut Ray down, and Ray's agent processes outlive their raylet): the processes of
    this machine whose environment carries that run's ``RAY_NODE_ID``, recorded in
    ``logs/ray-node.json`` by the run; nothing else. Returns their ids."""
    path = os.path.join(log_folder, NODE_FILE)
    try:
        with open(path, encoding="utf-8") as handle:
            recorded = json.load(handle)
        node, driver = str(recorded["node_id"]), int(recorded["driver"])
        started = recorded.get("driver_start")
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return []
    if _alive(driver, started) and driver != os.getpid():
        return []  # that run is still going (the store's lock refuses it anyway)
    marker = f"RAY_NODE_ID={node}".encode()
    ended = []
    for entry in os.listdir("/proc") if os.path.isdir("/proc") else []:
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open(f"/proc/{entry}/environ", "rb") as handle:
                if marker not in handle.read().split(b"\0"):
                    continue
            os.kill(int(entry), signal.SIGKILL)
            ended.append(int(entry))
        except OSError:  # gone meanwhile, or not ours to read
            continue
    os.unlink(path)
    return ended


def _alive(pid: int, started: Any = None) -> bool:
    """Whether the process ``pid`` still runs; with ``started`` (its start time as recorded), also
    that it is the same process: pids are reused (32,768 of them by default), and a busy machine
    hands a dead driver's pid to a new process within minutes."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True
    if started is None:
        return True
    now = _start_time(pid)
    return now is None or now == started


def _start_time(pid: int) -> int | None:
    """The process's start time in clock ticks since boot (field 22 of ``/proc/PID/stat``), or
    None where /proc does not say."""
    try:
        with open(f"/proc/{pid}/stat", encoding="utf-8", errors="replace") as handle:
            text = handle.read()
        # the command name (field 2) is in parentheses and may itself hold spaces or ')'
        return int(text[text.rindex(")") + 2:].split()[19])
    except (OSError, ValueError, IndexError):
        return None


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    kind = type(exc).__name__
    return f"{kind}: {text[0]}" if text else kind
