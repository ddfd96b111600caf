"""Run a symlearn command on hostile input and check the "one clear line, exit 2" promise.

Every command that reads a file or a formula promises (issue 15, ``docs/ARCHITECTURE.md``
*CLI*): on bad input it exits 2 with exactly one line on stderr naming the file (and
``:line:col`` where there is one), prints no traceback, stays within time and memory bounds,
and leaves no partial output file behind. This module runs a command in a child process
with resource limits and checks that promise; the hostile-input tests (``tests/hostile/``)
and the long fuzz run (``benchmarks/fuzz_inputs.py``) both use it.

API (stable; other test files build on it)::

    from hostile import run_command, assert_refused, HostileRun

    result = run_command(["ltl", "dfa", "--file", path], cwd=tmp_path, timeout=20, memory_mb=1024)
    assert_refused(result, names=path.name, location=True, outputs=[tmp_path / "out.json"])

* ``run_command(args, *, cwd=None, stdin=None, timeout=60.0, memory_mb=1024, env=None,
  python=sys.executable) -> HostileRun``: runs ``python -m symlearn ARGS`` (strings, paths or
  numbers) in a new session with ``RLIMIT_AS = memory_mb`` MB and a ``timeout`` in wall-clock
  seconds (the whole process group is killed when it runs out). ``SYMLEARN_QUIET=1`` is set.
* ``run_python(code, *, cwd=None, timeout=60.0, memory_mb=1024, env=None)``: the same limits
  around ``python -c CODE`` (``tests/support`` on ``sys.path``), for in-process checks of a
  library function that must not take the test process down with it.
* ``HostileRun``: ``args``, ``returncode`` (negative: killed by that signal), ``stdout``,
  ``stderr``, ``seconds``, ``max_rss_mb`` (peak resident memory of the largest process of the child's group, polled from ``/proc``), ``timed_out``;
  ``stderr_lines`` (non-empty lines), ``describe()`` (for assertion messages).
* ``assert_refused(result, *, names=None, location=False, contains=None, outputs=(),
  max_seconds=None, max_rss_mb=None, exit_code=2)``: the promise. ``names``: a string (or
  strings) the error line must contain, usually the input file's name; ``location=True``: the
  line must carry ``:line:col`` (or ``:line``) right after a name; ``contains``: further
  substrings (e.g. the limit's name); ``outputs``: paths that must not exist afterwards (nor
  their ``.tmp`` siblings); bounds default to the run's own limits. "One line" is the line
  ``symlearn: error: ...``; a formula parse error may add its excerpt and caret (two indented
  lines, the hint after the caret), nothing else.
* ``assert_survived(result, ...)``: the weaker promise the fuzzer checks: exit 0 or 2, never a
  traceback, an internal error (exit 1), a signal, a timeout or a memory blow-up; on exit 2 one
  line on stderr.
* ``check(args, **kw)``: ``run_command`` then ``assert_refused`` with the keywords that belong
  to each; returns the ``HostileRun``.

Memory: ``RLIMIT_AS`` bounds address space, not resident memory; a command that tries to
allocate past it gets ``MemoryError`` (or a failed ``mmap``) instead of eating the machine, and
the check then fails on the exit code or the traceback. 1024 MB is enough for every command
(numpy, clingo and torch imports included) on valid input.
"""

from __future__ import annotations

import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["HostileRun", "run_command", "run_python", "assert_refused", "assert_survived", "check"]

_LOCATION = re.compile(r":\d+(:\d+)?[: ]")


@dataclass
class HostileRun:
    """What one command did: exit code, output, time and peak memory."""

    args: list[str]
    returncode: int
    stdout: str
    stderr: str
    seconds: float
    max_rss_mb: float
    timed_out: bool
    timeout: float = 60.0
    memory_mb: int = 1024
    cwd: str | None = None
    extra: dict = field(default_factory=dict)

    @property
    def stderr_lines(self) -> list[str]:
        return [line for line in self.stderr.splitlines() if line.strip()]

    def describe(self) -> str:
        out = self.stdout if len(self.stdout) < 2000 else self.stdout[:2000] + "...[cut]"
        err = self.stderr if len(self.stderr) < 4000 else self.stderr[:4000] + "...[cut]"
        return (f"symlearn {' '.join(self.args)}\n  exit {self.returncode}, {self.seconds:.2f} s, "
                f"{self.max_rss_mb:.0f} MB peak{' (TIMED OUT)' if self.timed_out else ''}\n"
                f"  stderr:\n{err}\n  stdout:\n{out}")


def _limits(memory_mb: int):
    def apply() -> None:
        os.setsid()
        if memory_mb:
            size = int(memory_mb) * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (size, size))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def run_python(code: str, *, cwd: str | os.PathLike | None = None, timeout: float = 60.0,
               memory_mb: int = 1024, env: Mapping[str, str] | None = None) -> HostileRun:
    """Run ``python -c CODE`` under the same limits as :func:`run_command`."""
    support = str(Path(__file__).resolve().parent)
    extra = dict(env or {})
    extra["PYTHONPATH"] = os.pathsep.join(p for p in (extra.get("PYTHONPATH", ""), support,
                                                      os.environ.get("PYTHONPATH", "")) if p)
    return run_command(["-c", code], cwd=cwd, timeout=timeout, memory_mb=memory_mb, env=extra, _module=None)


def run_command(args: Sequence[object], *, cwd: str | os.PathLike | None = None,
                stdin: bytes | str | None = None, timeout: float = 60.0, memory_mb: int = 1024,
                env: Mapping[str, str] | None = None, python: str = sys.executable,
                _module: str | None = "symlearn") -> HostileRun:
    """Run ``python -m symlearn ARGS`` under a time and address-space limit."""
    args = [str(a) for a in args]
    child_env = dict(os.environ)
    child_env["SYMLEARN_QUIET"] = "1"
    child_env.setdefault("PYTHONDONTWRITEBYTECODE", "1")
    # One BLAS/OpenMP thread: the limit is per process and pools reserve address space per thread.
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        child_env.setdefault(name, "1")
    if env:
        child_env.update(env)
    if isinstance(stdin, str):
        stdin = stdin.encode()
    with tempfile.TemporaryFile() as out_file, tempfile.TemporaryFile() as err_file, \
            tempfile.TemporaryFile() as in_file:
        if stdin is not None:
            in_file.write(stdin)
            in_file.seek(0)
        start = time.perf_counter()
        command = [python, "-m", _module, *args] if _module else [python, *args]
        proc = subprocess.Popen(command, cwd=cwd, env=child_env,
                                stdin=in_file if stdin is not None else subprocess.DEVNULL,
                                stdout=out_file, stderr=err_file, preexec_fn=_limits(memory_mb))
        timed_out = False
        status, usage = 0, None
        deadline = start + timeout
        delay = 0.005
        peaks: dict[int, int] = {}
        while True:
            _poll_peaks(proc.pid, peaks)
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() > deadline:
                timed_out = True
                try:
                    os.killpg(proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                _, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(delay)
            delay = min(delay * 1.5, 0.1)
        seconds = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)  # Popen must not wait again
        try:  # grandchildren (a worker process) must not outlive the check
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        out_file.seek(0)
        err_file.seek(0)
        stdout = out_file.read().decode("utf-8", "replace")
        stderr = err_file.read().decode("utf-8", "replace")
    if peaks:  # the largest process of the group, after its exec
        max_rss_mb = max(peaks.values()) / 1024.0
    else:  # no /proc: the kernel's figure, which counts the forked test process's memory too
        max_rss_mb = (usage.ru_maxrss / 1024.0) if usage is not None else 0.0  # Linux: KB
    return HostileRun(args=args, returncode=proc.returncode, stdout=stdout, stderr=stderr,
                      seconds=seconds, max_rss_mb=max_rss_mb, timed_out=timed_out,
                      timeout=timeout, memory_mb=memory_mb, cwd=str(cwd) if cwd else None)


def _poll_peaks(root: int, peaks: dict[int, int]) -> None:
    """Record ``VmHWM`` (peak resident KB) of ``root`` and its descendants into ``peaks``.

    Not ``wait4``'s ``ru_maxrss``: the child is forked from the test process, and Linux carries the
    parent's high-water mark into the child's figure at exec, so after a few hundred tests every
    child would "use" what pytest itself holds. ``VmHWM`` starts afresh with the exec'd program.
    A peak between two polls of a process that then exits can be missed; ``RLIMIT_AS`` still
    bounds it.
    """
    stack = [root]
    while stack:
        pid = stack.pop()
        try:
            with open(f"/proc/{pid}/status", "rb") as handle:
                for line in handle:
                    if line.startswith(b"VmHWM:"):
                        peaks[pid] = max(peaks.get(pid, 0), int(line.split()[1]))
                        break
            for task in os.listdir(f"/proc/{pid}/task"):
                with open(f"/proc/{pid}/task/{task}/children", "rb") as handle:
                    stack.extend(int(c) for c in handle.read().split())
        except (OSError, ValueError):
            continue


def _as_list(value: str | Iterable[str] | None) -> list[str]:
    if value is None:
        return []
    if isinstance(value, (str, os.PathLike)):
        return [str(value)]
    return [str(v) for v in value]


def _check_common(result: HostileRun, max_seconds: float | None, max_rss_mb: float | None) -> None:
    assert not result.timed_out, f"timed out after {result.timeout} s\n{result.describe()}"
    assert "Traceback" not in result.stderr, f"traceback on stderr\n{result.describe()}"
    assert "Traceback" not in result.stdout, f"traceback on stdout\n{result.describe()}"
    limit_s = result.timeout if max_seconds is None else max_seconds
    assert result.seconds <= limit_s, f"took {result.seconds:.1f} s > {limit_s} s\n{result.describe()}"
    limit_mb = result.memory_mb if max_rss_mb is None else max_rss_mb
    if limit_mb:
        assert result.max_rss_mb <= limit_mb, \
            f"peak memory {result.max_rss_mb:.0f} MB > {limit_mb} MB\n{result.describe()}"


def _check_outputs(outputs: Iterable[str | os.PathLike], base: str | None) -> None:
    for output in outputs:
        path = Path(output)
        if not path.is_absolute() and base:
            path = Path(base) / path
        assert not path.exists(), f"partial output left behind: {path}"
        leftovers = []
        if path.parent.exists():
            leftovers = [p.name for pattern in (f".{path.name}.*.tmp", f"{path.name}*.tmp")
                         for p in path.parent.glob(pattern)]
        assert not leftovers, f"temporary files left behind: {leftovers}"


def _error_line(result: HostileRun) -> str:
    """The one error line; a formula excerpt with its caret (two indented lines) may follow."""
    lines = result.stderr_lines
    assert lines, f"nothing on stderr\n{result.describe()}"
    rest = lines[1:]
    excerpt = (len(rest) == 2 and all(l[:1].isspace() for l in rest)
               and re.fullmatch(r"\s*[\^~]+( \(hint: .*\))?", rest[1]) is not None)
    assert not rest or excerpt, \
        f"expected exactly one line on stderr, got {len(lines)}\n{result.describe()}"
    assert lines[0].startswith("symlearn: error:"), f"not an error line\n{result.describe()}"
    return lines[0]


def assert_refused(result: HostileRun, *, names: str | Iterable[str] | None = None,
                   location: bool = False, contains: str | Iterable[str] | None = None,
                   outputs: Iterable[str | os.PathLike] = (), max_seconds: float | None = None,
                   max_rss_mb: float | None = None, exit_code: int = 2) -> str:
    """Check the promise; returns the one error line."""
    _check_common(result, max_seconds, max_rss_mb)
    assert result.returncode == exit_code, \
        f"exit {result.returncode}, expected {exit_code}\n{result.describe()}"
    line = _error_line(result)
    assert "internal error" not in line, f"internal error\n{result.describe()}"
    for name in _as_list(names):
        assert name in line, f"error line does not name {name!r}: {line}"
        if location:
            index = line.index(name) + len(name)
            assert _LOCATION.match(line[index:] + " "), f"no :line:col after {name!r}: {line}"
    if location and not _as_list(names):
        assert _LOCATION.search(line + " "), f"no :line:col in: {line}"
    for text in _as_list(contains):
        assert text.lower() in line.lower(), f"error line lacks {text!r}: {line}"
    _check_outputs(outputs, result.cwd)
    return line


def assert_survived(result: HostileRun, *, max_seconds: float | None = None,
                    max_rss_mb: float | None = None, outputs: Iterable[str | os.PathLike] = ()) -> None:
    """Exit 0 (the input happened to be fine) or a clean refusal; never a crash."""
    _check_common(result, max_seconds, max_rss_mb)
    assert result.returncode in (0, 2), f"exit {result.returncode}\n{result.describe()}"
    if result.returncode == 2:
        line = _error_line(result)
        assert "internal error" not in line, result.describe()
        _check_outputs(outputs, result.cwd)


_RUN_KEYS = {"cwd", "stdin", "timeout", "memory_mb", "env", "python"}


def check(args: Sequence[object], **keywords) -> HostileRun:
    """``run_command`` then ``assert_refused``; keywords go to whichever takes them."""
    run_kw = {k: v for k, v in keywords.items() if k in _RUN_KEYS}
    check_kw = {k: v for k, v in keywords.items() if k not in _RUN_KEYS}
    result = run_command(args, **run_kw)
    assert_refused(result, **check_kw)
    return result
