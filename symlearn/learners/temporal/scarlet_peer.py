"""Run the Scarlet LTL learner (``Scarlet-ltl`` on PyPI) on a sample, as a benchmark peer.

Scarlet reads its own ``.trace`` format (one trace a line, steps separated by ``;``, the
proposition values of a step by ``,``; then ``---``, the negatives, ``---``, the operators,
``---``, the alphabet). It searches formulas over ``F G X ! & |`` and writes every improvement
to a CSV file; it runs in a child process here so that a timeout can stop it, and the best
formula written before the timeout is reported (``finished=False``).

>>> from symlearn.data.ltl_samples import sample_from_traces
>>> print(scarlet_trace_text(sample_from_traces([[{"a"}, set()]], [[set()]], propositions=["a", "b"])))
1,0;0,0
---
0,0
---
F,G,X,!,&,|
---
a,b
"""

from __future__ import annotations

import csv
import multiprocessing
import queue
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from symlearn.data.ltl_samples import LtlSample
from symlearn.optional import require

__all__ = ["ScarletResult", "run_scarlet", "scarlet_trace_text"]

SCARLET_OPERATORS = ("F", "G", "X", "!", "&", "|")


@dataclass(frozen=True)
class ScarletResult:
    formula: str | None  # Scarlet's own printing
    size: int | None  # syntax-tree nodes (Scarlet's treeSize)
    seconds: float
    finished: bool  # False when stopped by the timeout


def scarlet_trace_text(sample: LtlSample) -> str:
    def line(trace) -> str:
        return ";".join(",".join("1" if p in label else "0" for p in sample.propositions) for label in trace)

    parts = ["\n".join(line(t) for t in sample.positive), "\n".join(line(t) for t in sample.negative),
             ",".join(SCARLET_OPERATORS), ",".join(sample.propositions)]
    return "\n---\n".join(parts)


def _child(trace_file: str, csv_file: str, answer) -> None:
    import logging

    from Scarlet.inferLTL import inferLTL
    from Scarlet.sample import Sample

    logging.disable(logging.CRITICAL)
    sample = Sample(positive=[], negative=[])
    sample.readFromFile(trace_file)
    formula = inferLTL(sample, csv_file, list(SCARLET_OPERATORS), "SC", 0, False, False, 0, {})
    if formula is not None:
        answer.put((formula.prettyPrint(top=True), formula.treeSize()))
    else:
        answer.put((None, None))


def run_scarlet(sample: LtlSample, timeout: float = 10.0) -> ScarletResult:
    """Scarlet's answer on ``sample`` within ``timeout`` seconds (wall clock, process start included)."""
    require("scarlet", "comparing with Scarlet")
    context = multiprocessing.get_context("fork")
    with tempfile.TemporaryDirectory(prefix="scarlet-") as folder:
        trace_file, csv_file = Path(folder) / "sample.trace", Path(folder) / "result.csv"
        trace_file.write_text(scarlet_trace_text(sample) + "\n")  # scratch input for the peer, not a result
        answer = context.Queue()
        start = time.monotonic()
        process = context.Process(target=_child, args=(str(trace_file), str(csv_file), answer), daemon=True)
        process.start()
        try:
            # Poll rather than block for the whole timeout, so a crashed peer is noticed at once.
            deadline = start + timeout
            while True:
                try:
                    formula, size = answer.get(timeout=max(0.0, min(0.2, deadline - time.monotonic())))
                except queue.Empty:
                    if process.is_alive() and time.monotonic() < deadline:
                        continue
                    try:  # an answer put just before the child exited may still be in flight
                        formula, size = answer.get(timeout=0.5 if not process.is_alive() else 0.0)
                    except queue.Empty:
                        seconds = time.monotonic() - start
                        return ScarletResult(*_best_so_far(csv_file), seconds, False)
                seconds = time.monotonic() - start
                process.join(5)
                return ScarletResult(formula, size, seconds, True)
        finally:
            if process.is_alive():
                process.terminate()
                process.join(5)


def _best_so_far(csv_file: Path) -> tuple[str | None, int | None]:
    """The last improvement Scarlet wrote before it was stopped (its CSV counts distinct subformulas)."""
    try:
        rows = list(csv.reader(csv_file.open()))[1:]
    except OSError:
        return None, None
    rows = [r for r in rows if len(r) >= 3]
    if not rows:
        return None, None
    return rows[-1][2], None
