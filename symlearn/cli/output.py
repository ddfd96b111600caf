"""How commands print: a human text on stdout, or with ``--json`` exactly one JSON document."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TextIO


class Output:
    """Printing policy of one command invocation.

    Commands call :meth:`result` once with a JSON-ready document and a function that renders
    it for people; :meth:`note` sends side remarks to stderr (silenced by ``--quiet`` and, so
    stdout stays parseable, never on stdout).
    """

    def __init__(self, *, json_mode: bool = False, quiet: bool = False,
                 stdout: TextIO | None = None, stderr: TextIO | None = None) -> None:
        self.json_mode = json_mode
        self.quiet = quiet
        self.stdout = stdout or sys.stdout
        self.stderr = stderr or sys.stderr
        self._emitted = False

    def result(self, document: Any, render: Callable[[Any], str] | str | None = None) -> None:
        if self._emitted and self.json_mode:
            raise RuntimeError("a command may print only one JSON document")
        self._emitted = True
        if self.json_mode:
            self.stdout.write(json.dumps(document, indent=2, sort_keys=False, default=_json_default) + "\n")
            return
        text = render(document) if callable(render) else render
        if text is None:
            text = json.dumps(document, indent=2, default=_json_default)
        self.stdout.write(text.rstrip("\n") + "\n")

    def note(self, message: str) -> None:
        if not self.quiet:
            self.stderr.write(message.rstrip("\n") + "\n")


def _json_default(value: Any) -> Any:
    import numpy as np

    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (set, frozenset)):
        return sorted(value)
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


@contextmanager
def blame_file(path: Any) -> Iterator[None]:
    """Name ``path`` in data errors raised inside the block that do not name a file themselves.

    Learners and evaluators check arrays, not files; the command knows which file the arrays
    came from, so the user reads ``demos.npz: episode 3 has NaN`` instead of a bare message.
    """
    import copy

    from symlearn.errors import DataError, DemonstrationError

    try:
        yield
    except DataError as exc:
        # an error of the environment's own (its info["cost"]) is not the file's, whatever was read
        if path is None or exc.file or getattr(exc, "about_the_environment", False):
            raise
        located = copy.copy(exc)  # same type and fields (DemonstrationError keeps its index)
        located.file = str(path)
        if isinstance(exc, DemonstrationError) and exc.line is None and str(path).lower().endswith(".jsonl"):
            from symlearn.data.jsonl_locate import locate_step

            # "demonstration 3, step 5" -> the file's line and the column of that value
            found = locate_step(path, exc.demonstration, exc.key, exc.step)
            if found is not None:
                located.line, located.column = found
        raise located from None


def validation_line(validation: dict, held_out: str) -> str:
    """The one text line of a ``--validation`` report (``held_out``: what was counted, e.g.
    "held-out expert steps forbidden")."""
    v = validation
    return (f"validation: {v['forbidden']} of {v['steps']} {held_out} ({v['share']:.1%}; "
            f"{v['n_held_out']} demonstrations held out, {v['n_train']} learned from)")
