"""Read traces from JSONL: one trace per line, a list of steps, each a list of true propositions.

>>> traces = read_traces_text('[["a"], [], ["a", "b"]]\\n[["b"]]\\n')
>>> [[sorted(step) for step in trace] for trace in traces]
[[['a'], [], ['a', 'b']], [['b']]]

Blank lines are skipped. Mistakes raise :class:`~symlearn.errors.DataError` with
``file:line:col`` (the column of the offending value where it can be found); an empty trace
``[]`` is one (LTLf formulas are evaluated on non-empty traces, as ``semantics.holds`` does).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from symlearn.errors import DataError
from symlearn.input_limits import load_json

__all__ = ["read_traces", "read_traces_text"]


def read_traces(path: str | Path) -> list[list[frozenset[str]]]:
    from symlearn.input_limits import read_input_text

    return read_traces_text(read_input_text(path, what="traces file"), source=str(path))


def read_traces_text(text: str, source: str | None = None) -> list[list[frozenset[str]]]:
    traces = []
    for number, line in enumerate(text.split("\n"), start=1):
        if not line.strip():
            continue
        try:
            value = load_json(line, source=source, line=number, max_depth=None,  # steps type-checked below
                              error=DataError, syntax="not valid JSON")
        except DataError as exc:
            raise DataError(exc.message, file=source, line=exc.line, column=exc.column,
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
    if not value:
        raise DataError("an empty trace: LTLf formulas are evaluated on traces of at least one step", file=source,
                        line=number, column=len(line) - len(line.lstrip()) + 1,
                        hint='a step where nothing holds is written [], e.g. [[]] is a one-step trace')
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
                # [[["a"], []], [["b"]]]: a JSON list of traces on one line, where one trace per line is read
                several = isinstance(name, list) and all(isinstance(v, list) for v in step)
                raise DataError(f"step {index}: a proposition name must be a non-empty string, not {shown}",
                                file=source, line=number, column=_column(line, shown),
                                hint="the file holds one trace per line (JSONL): this line looks like a list "
                                     "of traces; write each trace on a line of its own" if several else None)
        steps.append(frozenset(step))
    return steps
