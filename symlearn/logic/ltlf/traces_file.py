"""Read traces from JSONL: one trace per line, a list of steps, each a list of true propositions.

>>> traces = read_traces_text('[["a"], [], ["a", "b"]]\\n[["b"]]\\n')
>>> [[sorted(step) for step in trace] for trace in traces]
[[['a'], [], ['a', 'b']], [['b']]]

Blank lines are skipped. Mistakes raise :class:`~symlearn.errors.DataError` with
``file:line:col`` (the column of the offending value where it can be found).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from symlearn.errors import DataError

__all__ = ["read_traces", "read_traces_text"]


def read_traces(path: str | Path) -> list[list[frozenset[str]]]:
    with open(path, encoding="utf-8") as handle:
        return read_traces_text(handle.read(), source=str(path))


def read_traces_text(text: str, source: str | None = None) -> list[list[frozenset[str]]]:
    traces = []
    for number, line in enumerate(text.split("\n"), start=1):
        if not line.strip():
            continue
        try:
            value = json.loads(line)
        except json.JSONDecodeError as exc:
            raise DataError(f"not valid JSON: {exc.msg}", file=source, line=number, column=exc.colno,
                            hint='each line is one trace, e.g. [["a"], [], ["a", "b"]]') from None
        traces.append(_trace(value, line, number, source))
    return traces


def _column(line: str, needle: str, occurrence: int = 0) -> int | None:
    positions = [m.start() for m in re.finditer(re.escape(needle), line)]
    return positions[occurrence] + 1 if len(positions) > occurrence else None


def _trace(value, line: str, number: int, source: str | None) -> list[frozenset[str]]:
    if not isinstance(value, list):
        raise DataError(f"a trace must be a JSON list of steps, not {type(value).__name__}", file=source,
                        line=number, column=len(line) - len(line.lstrip()) + 1,
                        hint='write e.g. [["a"], [], ["a", "b"]]')
    steps = []
    for index, step in enumerate(value):
        if not isinstance(step, list):
            shown = json.dumps(step)
            raise DataError(f"step {index} must be a list of proposition names, not {shown}", file=source,
                            line=number, column=_column(line, shown),
                            hint=f"write [{shown}] if {shown} is the only true proposition"
                            if isinstance(step, str) else None)
        for name in step:
            if not isinstance(name, str) or not name:
                shown = json.dumps(name)
                raise DataError(f"step {index}: a proposition name must be a non-empty string, not {shown}",
                                file=source, line=number, column=_column(line, shown))
        steps.append(frozenset(step))
    return steps
