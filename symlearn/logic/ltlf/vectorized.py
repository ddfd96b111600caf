"""Evaluate one LTLf formula on many traces at once with numpy.

Traces are packed once into a :class:`TraceBatch`: one boolean matrix ``[n_traces, max_len]``
per proposition plus the lengths. Evaluation keeps one such matrix per sub-formula (a row of
the "bit-matrix" per sub-formula) and computes every temporal operator for all traces and
all steps together, sweeping backwards in time with reversed cumulative operations:

* ``F a`` at step t: a reversed running OR of ``a`` (over live steps);
* ``a U b`` at t: the first ``b`` at or after t comes no later than the first ``!a`` (reversed
  running minimum of step indices);
* ``X``/``WX``: a shift by one step, with the end of each trace deciding the last step.

Learners that score thousands of candidate formulas against the same traces build the batch
once and call :func:`evaluate` repeatedly.

>>> from symlearn.logic.ltlf.parser import parse
>>> batch = TraceBatch.from_traces([[{"a"}, {"b"}], [{"b"}], [{"a"}]])
>>> evaluate(parse("a U b"), batch).tolist()
[True, True, False]

Empty traces get the verdict of :func:`~symlearn.logic.ltlf.progression.holds_at_end`, like
the DFA's on the empty word (``holds`` refuses them).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from symlearn.errors import DataError
from symlearn.logic.ltlf.ast import (
    Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil, subformulas,
)
from symlearn.logic.ltlf.progression import holds_at_end

__all__ = ["TraceBatch", "evaluate", "evaluate_many"]


@dataclass(frozen=True)
class TraceBatch:
    """Traces packed for vectorised evaluation (``props[name][i, t]``: name true at step t of trace i)."""

    props: Mapping[str, np.ndarray]
    lengths: np.ndarray

    @property
    def n_traces(self) -> int:
        return int(self.lengths.shape[0])

    @property
    def max_length(self) -> int:
        return max(1, int(self.lengths.max(initial=0)))

    @classmethod
    def from_traces(cls, traces: Iterable[Iterable[Iterable[str]]]) -> TraceBatch:
        traces = [list(t) for t in traces]
        lengths = np.array([len(t) for t in traces], dtype=np.int64)
        width = max(1, int(lengths.max(initial=0)))
        props: dict[str, np.ndarray] = {}
        for i, trace in enumerate(traces):
            for t, label in enumerate(trace):
                if isinstance(label, str):
                    raise DataError(f"trace {i}, step {t}: a label must be a set of names, not the string {label!r}")
                for name in label:
                    row = props.get(name)
                    if row is None:
                        row = props[name] = np.zeros((len(traces), width), dtype=bool)
                    row[i, t] = True
        return cls(props, lengths)

    @classmethod
    def from_columns(cls, traces: Sequence[Mapping[str, Sequence[int]]]) -> TraceBatch:
        """Traces as ``{proposition: [0/1 per step]}`` dictionaries (the benchmark JSON layout)."""
        lengths = np.array([len(next(iter(t.values()), ())) for t in traces], dtype=np.int64)
        width = max(1, int(lengths.max(initial=0)))
        props: dict[str, np.ndarray] = {}
        for i, trace in enumerate(traces):
            for name, values in trace.items():
                if len(values) != lengths[i]:
                    raise DataError(f"trace {i}: proposition {name!r} has {len(values)} values, expected {lengths[i]}")
                row = props.setdefault(name, np.zeros((len(traces), width), dtype=bool))
                row[i, : lengths[i]] = np.asarray(values, dtype=int) != 0
        return cls(props, lengths)


def _next_index(x: np.ndarray) -> np.ndarray:
    """For each step t, the first step >= t where x holds (the row width when there is none)."""
    width = x.shape[1]
    idx = np.where(x, np.arange(width), width)
    return np.minimum.accumulate(idx[:, ::-1], axis=1)[:, ::-1]


def _eventually(x: np.ndarray, alive: np.ndarray) -> np.ndarray:
    return np.logical_or.accumulate((x & alive)[:, ::-1], axis=1)[:, ::-1]


def _until(a: np.ndarray, b: np.ndarray, alive: np.ndarray) -> np.ndarray:
    first_b = _next_index(b & alive)
    return (first_b < a.shape[1]) & (first_b <= _next_index(~a & alive))


def _shift(x: np.ndarray, alive: np.ndarray, strong: bool) -> np.ndarray:
    out = np.empty_like(x)
    if strong:
        out[:, :-1] = alive[:, 1:] & x[:, 1:]
        out[:, -1] = False
    else:
        out[:, :-1] = ~alive[:, 1:] | x[:, 1:]
        out[:, -1] = True
    return out


def evaluate(formula: Formula, batch: TraceBatch) -> np.ndarray:
    """Verdicts (bool array, one per trace) of ``formula`` at the first step of each trace."""
    n, width = batch.n_traces, batch.max_length
    alive = np.arange(width)[None, :] < batch.lengths[:, None]
    rows: dict[Formula, np.ndarray] = {}
    for node in subformulas(formula):
        if node in rows:
            continue
        c = [rows[x] for x in node.children()]
        if isinstance(node, Const):
            m = np.full((n, width), node.value, dtype=bool)
        elif isinstance(node, Prop):
            m = batch.props.get(node.name)
            m = np.zeros((n, width), dtype=bool) if m is None else m
        elif isinstance(node, Not):
            m = ~c[0]
        elif isinstance(node, And):
            m = c[0] & c[1]
        elif isinstance(node, Or):
            m = c[0] | c[1]
        elif isinstance(node, Implies):
            m = ~c[0] | c[1]
        elif isinstance(node, Iff):
            m = c[0] == c[1]
        elif isinstance(node, (Next, WeakNext)):
            m = _shift(c[0], alive, isinstance(node, Next))
        elif isinstance(node, Eventually):
            m = _eventually(c[0], alive)
        elif isinstance(node, Always):
            m = ~_eventually(~c[0], alive)
        elif isinstance(node, Until):
            m = _until(c[0], c[1], alive)
        elif isinstance(node, Release):
            m = ~_until(~c[0], ~c[1], alive)
        elif isinstance(node, WeakUntil):
            m = _until(c[0], c[1], alive) | ~_eventually(~c[0], alive)
        elif isinstance(node, Then):
            later = _shift(_eventually(c[1], alive), alive, strong=True)
            m = _eventually(c[0] & later, alive)
        else:
            raise TypeError(f"not an LTLf formula node: {node!r}")
        rows[node] = m
    verdicts = rows[formula][:, 0].copy()
    empty = batch.lengths == 0
    if empty.any():
        verdicts[empty] = holds_at_end(formula)
    return verdicts


def evaluate_many(formula: Formula, traces: Iterable[Iterable[Iterable[str]]] | TraceBatch) -> np.ndarray:
    """:func:`evaluate` on a :class:`TraceBatch` or on plain traces (packed first)."""
    batch = traces if isinstance(traces, TraceBatch) else TraceBatch.from_traces(traces)
    return evaluate(formula, batch)
