"""An error raised by the code of the user's environment, as one located line.

``train`` steps the environment deep inside a learner (our PPO's rollouts, stable-baselines3's);
an exception there (a ``RuntimeError("motor fault")`` in the user's ``step``) is not symlearn's
bug. :func:`raised_by_environment` turns an exception whose traceback passes through the file
that defines the environment's class into a :class:`~symlearn.errors.DataError` naming that
file and line (the deepest frame in it) and what was being done; any other exception is left
as it is (an internal error, with ``--debug`` for the traceback).
"""

from __future__ import annotations

import inspect
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from symlearn.errors import DataError, SymlearnError


def environment_file(env: Any) -> str | None:
    """The file that defines the unwrapped environment's class (None where it has none)."""
    try:
        return os.path.realpath(inspect.getfile(type(getattr(env, "unwrapped", env))))
    except (TypeError, OSError):
        return None


@contextmanager
def raised_by_environment(env_file: str | None, doing: str) -> Iterator[None]:
    """Re-raise an exception from ``env_file``'s code as a located one-line :class:`DataError`."""
    try:
        yield
    except SymlearnError:
        raise
    except Exception as exc:
        if env_file is None:
            raise
        tb, line = exc.__traceback__, None
        while tb is not None:
            if os.path.realpath(tb.tb_frame.f_code.co_filename) == env_file:
                line = tb.tb_lineno
            tb = tb.tb_next
        if line is None:
            raise
        raise DataError(f"{doing}: the environment raised {type(exc).__name__}: {exc}", file=env_file,
                        line=line) from None


__all__ = ["environment_file", "raised_by_environment"]
