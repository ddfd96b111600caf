"""Grounding and solving of user programs in a worker process bounded in time and memory.

clingo cannot interrupt grounding, and a two-line background (``n(X+1) :- n(X).`` or
``t(1..2147483647).``) grounds until the machine's memory is gone. No check of the program text
can rule that out (ASP with arithmetic and function symbols is Turing complete), so the commands
that ground a user's program run that work in a child process:

* the child is started with ``spawn`` (a fresh interpreter: nothing of the parent's threads or
  locks, on every platform) and sets ``RLIMIT_AS`` to the memory limit before it does anything,
  so an allocation past it fails inside clingo as ``MemoryError`` (clingo turns ``bad_alloc``
  into one) instead of taking the machine down; ``RLIMIT_CPU`` backs up the time limit;
* the parent waits on a pipe until the time limit (plus a grace of ``0.2 s + 2 %`` for the
  child to return a best-so-far answer itself) and then kills the child;
* either way the caller gets one :class:`~symlearn.errors.LimitExceededError` naming the limit,
  and a :class:`~symlearn.errors.SymlearnError` raised in the child arrives unchanged.

The function run in the child and its arguments must be picklable (module-level functions;
tasks, hypotheses and results of :mod:`symlearn.logic.ilp` are). The cost is one interpreter
start plus the imports the function needs, about 0.2 s (``docs/BENCHMARKS.md``).

>>> run_limited(sum, [1, 2, 3], seconds=10, memory_mb=512)
6

Memory limits count address space (``RLIMIT_AS``) *beyond the worker's start*: the child loads
numpy and clingo first (their libraries map ~100 MB, more on a machine with many cores), reads
the address space it then holds, and allows N MB on top of that, so that a limit means memory
for the work on every machine (with a bare N MB of address space, 200 MB could not check a
three-state domain). A limit of N MB leaves somewhat less than N MB of data; on systems without
``resource`` (Windows) only the time limit applies.
"""

from __future__ import annotations

import math
import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from typing import Any, TypeVar

from symlearn.errors import LimitExceededError, SymlearnError

T = TypeVar("T")

MEMORY_VARIABLE = "SYMLEARN_MAX_MEMORY_MB"
#: ``SYMLEARN_WORKER=off`` runs the function in the calling process, without limits (debugging,
#: and measuring what the worker costs: ``benchmarks/ilp_worker_overhead.py``)
IN_PROCESS_VARIABLE = "SYMLEARN_WORKER"
DEFAULT_MEMORY_MB = 1024
#: the smallest memory limit accepted (on top of the worker's libraries, see above): below it
#: the checks of a small domain folder (a few states) run out, so every run would fail the same way
MIN_MEMORY_MB = 192
#: Timeouts above this many seconds (about 31 years) mean "no limit": clingo converts a timeout
#: to a clock deadline, and ``1e308`` overflows it into "already passed".
NO_LIMIT_ABOVE = 1e9


def seconds_limit(value: float | str | None, *, name: str = "timeout") -> float | None:
    """A time limit as seconds, or None for none: ``inf`` and anything above :data:`NO_LIMIT_ABOVE`
    mean no limit; NaN, zero, negative numbers and non-numbers raise :class:`SymlearnError`."""
    if value is None:
        return None
    try:
        seconds = float(value)
    except (TypeError, ValueError):
        raise SymlearnError(f"{name} must be a number of seconds, not {value!r}",
                            hint="give a positive number of seconds ('inf' for no limit)") from None
    if math.isnan(seconds) or seconds <= 0:
        raise SymlearnError(f"{name} must be a positive number of seconds, not {value}",
                            hint="give a positive number of seconds ('inf' for no limit)")
    return None if seconds > NO_LIMIT_ABOVE else seconds


def memory_limit_mb(value: float | str | None = None, *, name: str = MEMORY_VARIABLE) -> int | None:
    """The memory limit in MB: ``value`` if given, else the environment variable
    ``SYMLEARN_MAX_MEMORY_MB``, else :data:`DEFAULT_MEMORY_MB`. ``0``, ``none``, ``inf`` or
    ``unlimited``: no limit (None)."""
    if value is None:
        value = os.environ.get(MEMORY_VARIABLE, "").strip() or DEFAULT_MEMORY_MB
        name = MEMORY_VARIABLE if os.environ.get(MEMORY_VARIABLE, "").strip() else name
    text = str(value).strip().lower()
    if text in ("0", "none", "inf", "unlimited"):
        return None
    try:
        megabytes = float(text)
    except ValueError:
        raise SymlearnError(f"{name} must be a number of megabytes, not {value!r}",
                            hint="give a positive number of MB, or 0 for no limit") from None
    if math.isnan(megabytes) or megabytes < 0:
        raise SymlearnError(f"{name} must be a positive number of megabytes, not {value}",
                            hint="give a positive number of MB, or 0 for no limit")
    if megabytes < MIN_MEMORY_MB:
        raise SymlearnError(f"{name} of {value} MB is too small to start the worker process",
                            hint=f"give at least {MIN_MEMORY_MB} MB, or 0 for no limit")
    return None if megabytes > 2**40 else int(megabytes)  # beyond a million terabytes: no limit


def grace_seconds(seconds: float) -> float:
    """How long after ``seconds`` the worker is killed: time to return a best-so-far answer
    (the search watches the same deadline and stops itself; only grounding cannot)."""
    return 0.2 + 0.02 * seconds


def remaining(started: float, seconds: float | None) -> float | None:
    """Seconds left of a budget that began at ``started`` (``time.monotonic()``, which is one
    system-wide clock on Linux and macOS, so a child can use its parent's start time)."""
    if seconds is None:
        return None
    return max(seconds - (time.monotonic() - started), 0.001)


class WorkerCrash(RuntimeError):
    """The worker raised something that is not a :class:`SymlearnError`: a bug, not bad input.
    ``child_traceback`` holds the child's traceback text."""

    def __init__(self, message: str, child_traceback: str = "") -> None:
        super().__init__(message)
        self.child_traceback = child_traceback


def _limit_resources(memory_bytes: int | None, cpu_seconds: float | None) -> None:
    try:
        import resource
    except ImportError:  # Windows: only the parent's wall-clock limit applies
        return
    if memory_bytes is not None:
        _one_malloc_arena()
        # OpenBLAS reserves a buffer per core when numpy loads (tens of MB on a large machine)
        # and prints to stderr when it cannot; the worker grounds and solves, one thread is plenty
        for variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
            os.environ.setdefault(variable, "1")
        memory_bytes += _baseline_bytes()
        _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        bound = memory_bytes if hard == resource.RLIM_INFINITY else min(memory_bytes, hard)
        resource.setrlimit(resource.RLIMIT_AS, (bound, hard))
    if cpu_seconds is not None:
        _soft, hard = resource.getrlimit(resource.RLIMIT_CPU)
        used = time.process_time()
        soft = int(math.ceil(used + cpu_seconds))
        bound = soft if hard == resource.RLIM_INFINITY else min(soft, hard)
        resource.setrlimit(resource.RLIMIT_CPU, (bound, hard))
    try:
        resource.setrlimit(resource.RLIMIT_CORE, (0, resource.getrlimit(resource.RLIMIT_CORE)[1]))
    except (ValueError, OSError):
        pass


def _baseline_bytes() -> int:
    """The address space of this worker once the libraries every worker's task uses are loaded
    (numpy and clingo: loaded here, before the limit, which the tasks would do anyway); 0 where
    ``/proc`` does not tell, and the limit is then the bare address space as before."""
    for module in ("numpy", "clingo"):
        try:
            __import__(module)
        except ImportError:
            pass
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as handle:
            for line in handle:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def _one_malloc_arena() -> None:
    """glibc reserves 64 MB of address space for each thread's malloc arena (clingo solves in a
    thread of its own); one shared arena keeps the address-space limit close to the data."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        ctypes.CDLL(None).mallopt(-8, 1)  # M_ARENA_MAX = 1
    except (OSError, AttributeError):
        pass


def _out_of_memory(exc: BaseException) -> bool:
    """Whether ``exc`` is the address-space limit speaking, not a bug: numpy's or clingo's
    extension unable to map its segments (an ImportError), or a thread that cannot get its stack
    (``Resource temporarily unavailable``)."""
    if isinstance(exc, ImportError):
        return True
    return isinstance(exc, RuntimeError) and ("Resource temporarily unavailable" in str(exc)
                                              or "bad_alloc" in str(exc))


def _watch_parent(parent: int) -> None:
    """End the child when its parent is gone (killed by a signal, so it could not kill us)."""
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os._exit(70)


def _child(connection, function, args, kwargs, memory_bytes, cpu_seconds, bars, parent) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's: it kills us
    # the worker loads what `import symlearn` loaded before the version became lazy: with ~10 MB
    # less mapped, a task at its address-space limit failed in clingo's thread creation (a glibc
    # abort line on stderr) instead of a MemoryError (tests/hostile/test_hostile_ilp.py)
    import symlearn._version  # noqa: F401

    _limit_resources(memory_bytes, cpu_seconds)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()
    payload: tuple
    try:
        from symlearn.progress import progress_bars

        with progress_bars(bars):
            payload = ("ok", function(*args, **kwargs))
    except MemoryError:
        payload = ("memory",)
    except (SymlearnError, OSError) as exc:  # bad input (a missing file too): the caller reports it
        exc.__traceback__ = None
        payload = ("error", exc)
    except BaseException as exc:  # noqa: BLE001 - reported to the parent as a crash
        import traceback

        if memory_bytes is not None and _out_of_memory(exc):
            payload = ("memory",)
        else:
            payload = ("crash", f"{type(exc).__name__}: {exc}", traceback.format_exc())
    try:
        connection.send(payload)
    except MemoryError:
        connection.send(("memory",))
    except Exception as exc:  # noqa: BLE001 - an unpicklable result is a bug of the caller
        connection.send(("crash", f"cannot return the result: {type(exc).__name__}: {exc}", ""))
    connection.close()


def run_limited(function: Callable[..., T], /, *args: Any, seconds: float | None = None,
                memory_mb: int | None = DEFAULT_MEMORY_MB, what: str = "grounding and solving",
                time_hint: str = "raise the time limit", memory_hint: str | None = None,
                started: float | None = None, **kwargs: Any) -> T:
    """``function(*args, **kwargs)`` in a worker process; its result, or the error it raised.

    ``seconds``: wall-clock limit from ``started`` (``time.monotonic()``; default: now; None: no
    limit); the worker is killed
    :func:`grace_seconds` later, so a function that watches the same budget can still return
    what it has. ``memory_mb``: the worker's address-space limit (None: none). ``what`` names
    the work in the limit errors (``"time limit of 5 s reached while {what}"``).
    """
    import multiprocessing

    from symlearn.progress import progress_enabled

    if os.environ.get(IN_PROCESS_VARIABLE, "").strip().lower() in ("off", "0", "no", "false"):
        return function(*args, **kwargs)  # debugging and measuring the worker's cost: no limits

    if memory_hint is None:
        memory_hint = f"raise the memory limit ({MEMORY_VARIABLE}=<MB>, 0: none) if the program is trusted"
    context = multiprocessing.get_context("spawn")
    receiver, sender = context.Pipe(duplex=False)
    memory_bytes = None if memory_mb is None else int(memory_mb) * 2**20
    kill_after = None if seconds is None else seconds + grace_seconds(seconds)
    cpu = None if kill_after is None else kill_after + 5.0  # backstop only: the parent kills first
    process = context.Process(target=_child, name="symlearn-worker", daemon=True,
                              args=(sender, function, args, kwargs, memory_bytes, cpu, progress_enabled(),
                                    os.getpid()))
    start = time.monotonic() if started is None else started
    process.start()
    sender.close()
    payload = None
    timed_out = False
    try:
        while True:
            wait = None if kill_after is None else kill_after - (time.monotonic() - start)
            if wait is not None and wait <= 0:
                timed_out = True
                break
            # in slices: select() refuses timeouts beyond about 24 days
            if receiver.poll(3600.0 if wait is None else min(wait, 3600.0)):
                try:
                    payload = receiver.recv()
                except (EOFError, OSError):  # the child died without an answer
                    payload = None
                break
    finally:
        if process.is_alive():
            process.kill()
        process.join()
        receiver.close()
    if timed_out:
        raise LimitExceededError(f"time limit of {seconds:g} s reached while {what}", hint=time_hint)
    if payload is None:
        code = process.exitcode
        name = _signal_name(-code) if code is not None and code < 0 else f"exit code {code}"
        if code is not None and -code in (getattr(signal, "SIGXCPU", -1),):
            raise LimitExceededError(f"time limit of {seconds:g} s reached while {what}", hint=time_hint)
        if memory_mb is not None:
            raise LimitExceededError(f"the worker stopped ({name}) while {what}; it may have reached the memory "
                                     f"limit of {memory_mb} MB", hint=memory_hint)
        raise WorkerCrash(f"the worker process stopped ({name}) while {what}")
    kind = payload[0]
    if kind == "ok":
        return payload[1]
    if kind == "error":
        raise payload[1]
    if kind == "memory":
        if memory_mb is None:
            raise LimitExceededError(f"out of memory while {what}", hint="free memory or simplify the program")
        raise LimitExceededError(f"memory limit of {memory_mb} MB reached while {what}", hint=memory_hint)
    raise WorkerCrash(payload[1], payload[2]) from _ChildTraceback(payload[2])


class _ChildTraceback(Exception):
    """Carries the worker's traceback text, so ``--debug`` shows where the child failed."""

    def __str__(self) -> str:
        return "traceback of the worker process:\n" + str(self.args[0])


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"
