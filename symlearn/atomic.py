"""Atomic file output: a result file is either the old one or the complete new one.

Writers create a temporary file in the destination directory (so the final rename never
crosses file systems), flush and fsync it, then ``os.replace`` it over the target.

Permissions: a new file gets ``0666`` minus the process umask (what ``open`` would give), and
replacing an existing file keeps that file's mode, so converting a ``0644`` file onto itself
leaves it ``0644`` (``tempfile.mkstemp`` alone would make every output ``0600``).

Text: UTF-8, with a lone surrogate -- what Python makes of a file name that is not UTF-8, say a
demonstrations file the header of a rule file names -- written as its escape (``\udcff``), so
such a name never makes a write fail. JSON readers refuse a lone surrogate (it is not a
character), so a demonstrations file that would carry one in its data is refused before anything
is written (``symlearn.data.files.save``).

Interruption: the temporary file is removed on any exception, ``KeyboardInterrupt`` included;
the CLI turns SIGTERM into an exception too (``symlearn.cli.main``), so a terminated write
leaves neither a partial target nor a ``.tmp`` file behind.
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO


@contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w", encoding: str | None = "utf-8") -> Iterator[IO]:
    """Open a temporary sibling of ``path`` for writing; replace ``path`` on success only."""
    if mode not in ("w", "wb"):
        raise ValueError("atomic_open only writes ('w' or 'wb')")
    target = Path(path)
    if len(os.fsencode(target.name)) > NAME_MAX:  # refused for the name the user gave, not the sibling's
        raise OSError(errno.ENAMETOOLONG, os.strerror(errno.ENAMETOOLONG), str(target))
    if target.is_dir():  # os.replace would fail naming the temporary sibling, not the user's path
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(target))
    stream = _stream_target(target)
    if stream is not None:  # a device or a pipe: written into, never replaced by a file
        text = "b" not in mode
        try:
            with os.fdopen(stream, mode, encoding=encoding if text else None,
                           errors="backslashreplace" if text else None) as handle:
                yield handle
        except BrokenPipeError:  # `--dot /dev/stdout | head -1`: the reader is gone
            raise OSError(errno.EPIPE, "the pipe's reader closed it before everything was written",
                          str(target)) from None
        return
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{_shortened(target.name)}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:  # named for the user's path, not the temporary sibling no one asked for
        raise OSError(exc.errno, exc.strerror, str(target)) from None
    try:
        os.fchmod(fd, _mode_for(target))
        text = "b" not in mode
        with os.fdopen(fd, mode, encoding=encoding if text else None,
                       errors="backslashreplace" if text else None) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp_name, target)
    except BaseException:
        try:
            os.unlink(tmp_name)
        except FileNotFoundError:
            pass
        raise


def _stream_target(target: Path) -> int | None:
    """A descriptor open for writing when ``target`` (symlinks followed) exists and is no regular
    file -- ``/dev/null``, ``/dev/stdout``, a terminal, a named pipe --, else None. Renaming a
    temporary file onto such a path would replace the device or pipe itself (for root, ``-o
    /dev/null`` would replace the system's ``/dev/null``); a stream has no partial file to avoid.
    A named pipe nobody reads is refused at once rather than blocking."""
    try:
        info = os.stat(target)
    except OSError:
        return None
    if stat.S_ISREG(info.st_mode) or stat.S_ISDIR(info.st_mode):
        return None
    fifo = stat.S_ISFIFO(info.st_mode)
    try:
        fd = os.open(target, os.O_WRONLY | (os.O_NONBLOCK if fifo else 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        if exc.errno == errno.ENXIO:  # a pipe without a reader, a socket
            raise OSError(errno.ENXIO, "nothing reads from this named pipe or socket", str(target)) from None
        raise OSError(exc.errno, exc.strerror, str(target)) from None
    if fifo:
        os.set_blocking(fd, True)
    return fd


#: bytes in one path component on Linux and macOS file systems
NAME_MAX = 255


def _shortened(name: str) -> str:
    """``name`` cut so ``.NAME.XXXXXXXX.tmp`` still fits in one path component."""
    room = NAME_MAX - len(". .12345678.tmp")
    encoded = os.fsencode(name)
    return name if len(encoded) <= room else os.fsdecode(encoded[:room])


def _umask() -> int:
    """The process umask, read without changing it where Linux shows it (``/proc/self/status``)."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    old = os.umask(0o022)  # elsewhere: set and restore (not thread-safe, but brief)
    os.umask(old)
    return old


def _mode_for(target: Path) -> int:
    """The mode the finished file gets: the existing target's, else ``0666 & ~umask``."""
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        return 0o666 & ~_umask()


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` to ``path`` atomically and return the path."""
    with atomic_open(path, "w") as handle:
        handle.write(text)
    return Path(path)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically and return the path."""
    with atomic_open(path, "wb") as handle:
        handle.write(data)
    return Path(path)
