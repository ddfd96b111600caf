"""Progress bars that show on a terminal and stay silent in pipes, CI and ``--quiet`` runs.

Library code calls :func:`progress` around long loops; whether a bar is drawn is decided here
once, so no learner needs to know about terminals.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TypeVar

T = TypeVar("T")

# None: decide from the terminal; True/False: forced (CLI --quiet, tests, notebooks).
_forced: ContextVar[bool | None] = ContextVar("symlearn_progress_forced", default=None)


def progress_enabled() -> bool:
    """Whether a bar would be drawn now."""
    forced = _forced.get()
    if forced is not None:
        return forced
    if os.environ.get("CI") or os.environ.get("SYMLEARN_QUIET"):
        return False
    return sys.stderr.isatty()


@contextmanager
def progress_bars(enabled: bool | None):
    """Force bars on or off inside a block (``None`` restores automatic detection)."""
    token = _forced.set(enabled)
    try:
        yield
    finally:
        _forced.reset(token)


def progress(
    iterable: Iterable[T], *, total: int | None = None, desc: str | None = None, unit: str = "it"
) -> Iterator[T]:
    """Iterate over ``iterable``, drawing a bar on stderr when :func:`progress_enabled`."""
    if not progress_enabled():
        yield from iterable
        return
    # the plain text bar on stderr: tqdm.auto would pick the notebook widget (and warn without ipywidgets)
    from tqdm import tqdm

    yield from tqdm(iterable, total=total, desc=desc, unit=unit, file=sys.stderr, leave=False)


class ProgressBar:
    """A bar advanced by hand, with a few numbers beside it (``return=1.2 cost=0.3``): for loops
    whose progress is worth a glance at what they are learning, not only how far they are.
    Silent (every method a no-op) where :func:`progress_enabled` says no bar is drawn."""

    def __init__(self, total: int | None, desc: str | None = None, unit: str = "it") -> None:
        self._bar = None
        if progress_enabled():
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False)

    def update(self, n: int = 1, **numbers: float | None) -> None:
        """Advance by ``n`` and show ``numbers`` (None and NaN are left out)."""
        if self._bar is None:
            return
        shown = {key: f"{value:.3g}" for key, value in numbers.items() if value is not None and value == value}
        if shown:
            self._bar.set_postfix(shown, refresh=False)
        self._bar.update(n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
