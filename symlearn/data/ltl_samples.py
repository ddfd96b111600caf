"""Labelled trace samples for LTLf learning, in the JSON format of the public LTLf learning benchmarks.

A sample is a set of positive and a set of negative finite traces over named atomic
propositions. On disk (the schema of the LTLf_Learning_Benchmarks suite, which
``/work/shared/benchmarks/ltlf_learning`` follows)::

    {"atomic_propositions": ["a", "b"],
     "positive_traces": [{"a": [1, 0, 1], "b": [0, 0, 1]}],
     "negative_traces": [{"a": [0, 0], "b": [1, 0]}],
     "smallest_known_formula": "F(a && X[!] b)",      # Spot dialect, optional, "" if unknown
     ...}                                               # other keys are kept as metadata

A trace maps every proposition to a list of 0/1 values (ints, or the strings ``"0"``/``"1"``),
one per step; all lists of a trace have the same length. A trace may also be written as a list
of steps, each the list of propositions true there (``[["a"], [], ["a", "b"]]``, the form of
traces files); when every trace is written so, ``atomic_propositions`` may be left out and is
then the sorted set of names the traces use. In memory a trace is a tuple of
labels, each the frozenset of propositions true at that step (the convention of
:func:`symlearn.logic.ltlf.semantics.holds`).

Rejected, with the file and the JSON path of the offending value: a ``trace_type`` other than
``"finite"`` (infinite or lasso traces would be learned with the wrong semantics), a proposition that is not
declared in ``atomic_propositions``, a value other than 0/1, ragged or empty traces, an empty
positive or negative set, and a trace that is both positive and negative (no formula can
separate such a sample).

>>> s = sample_from_traces([[{"a"}, set()]], [[set()]], propositions=["a"])
>>> document = sample_to_document(s)
>>> document["positive_traces"]
[{'a': [1, 0]}]
>>> parse_sample(document) == s
True
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError
from symlearn.json_position import JsonPathError, located

__all__ = ["LtlSample", "load_sample", "parse_sample", "save_sample", "sample_to_document", "sample_from_traces"]

Trace = tuple[frozenset[str], ...]

_OWN_KEYS = {"atomic_propositions", "positive_traces", "negative_traces", "smallest_known_formula",
             "number_atomic_propositions", "number_traces", "number_positive_traces",
             "number_negative_traces", "max_length_traces", "trace_type"}


@dataclass(frozen=True)
class LtlSample:
    """Positive and negative finite traces over ``propositions`` (validated on construction)."""

    propositions: tuple[str, ...]
    positive: tuple[Trace, ...]
    negative: tuple[Trace, ...]
    smallest_known_formula: str | None = None
    metadata: Mapping[str, Any] = field(default_factory=dict, compare=False)
    source: str | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        _validate(self)

    @property
    def max_length(self) -> int:
        return max(len(t) for t in self.positive + self.negative)

    def __repr__(self) -> str:
        return (f"LtlSample({len(self.propositions)} propositions, {len(self.positive)} positive, "
                f"{len(self.negative)} negative, max length {self.max_length})")


def sample_from_traces(positive: Iterable[Iterable[Iterable[str]]], negative: Iterable[Iterable[Iterable[str]]],
                       *, propositions: Sequence[str] | None = None, smallest_known_formula: str | None = None,
                       metadata: Mapping[str, Any] | None = None) -> LtlSample:
    """A sample from traces given as sequences of label sets; propositions default to those used."""
    pos = tuple(_as_trace(t, f"positive_traces[{i}]") for i, t in enumerate(positive))
    neg = tuple(_as_trace(t, f"negative_traces[{i}]") for i, t in enumerate(negative))
    if propositions is None:
        propositions = sorted(set().union(*(label for t in pos + neg for label in t)))
    return LtlSample(tuple(propositions), pos, neg, smallest_known_formula or None, dict(metadata or {}))


def _as_trace(trace: Iterable[Iterable[str]], where: str, source: str | None = None) -> Trace:
    labels = []
    for step, label in enumerate(trace):
        if isinstance(label, str):
            raise DataError(f"{where}[{step}]: a label must be a set of proposition names, not the string {label!r}",
                            file=source)
        labels.append(frozenset(label))
    return tuple(labels)


def _validate(sample: LtlSample) -> None:
    where = sample.source
    props = sample.propositions
    if len(set(props)) != len(props):
        raise DataError("atomic_propositions: a proposition is listed twice", file=where)
    known = set(props)
    for kind, traces in (("positive", sample.positive), ("negative", sample.negative)):
        if not traces:
            raise DataError(f"{kind}_traces: the sample has no {kind} traces", file=where,
                            hint="a separating formula needs at least one positive and one negative trace")
        for i, trace in enumerate(traces):
            if not trace:
                raise DataError(f"{kind}_traces[{i}]: empty trace (LTLf traces have at least one step)", file=where)
            for step, label in enumerate(trace):
                unknown = label - known
                if unknown:
                    raise DataError(f"{kind}_traces[{i}][{step}]: unknown proposition {sorted(unknown)[0]!r}",
                                    file=where, hint=f"declared propositions: {', '.join(props) or '(none)'}")
    both = set(sample.positive) & set(sample.negative)
    if both:
        trace = next(t for t in sample.positive if t in both)
        i, j = sample.positive.index(trace), sample.negative.index(trace)
        raise DataError(f"contradictory sample: positive_traces[{i}] and negative_traces[{j}] are the same trace",
                        file=where, hint="no formula can accept and reject the same trace; remove one of them")


def parse_sample(document: Any, *, source: str | None = None) -> LtlSample:
    """Validate a JSON document (already decoded) and build the sample; errors name the JSON path."""
    if not isinstance(document, dict):
        raise JsonPathError(f"expected a JSON object, found {type(document).__name__}", file=source, path=())
    for key in ("positive_traces", "negative_traces"):
        if key not in document:
            raise JsonPathError(f"missing key {key!r}", file=source, path=(),
                                hint="an LTL learning sample has atomic_propositions, positive_traces and negative_traces")
    if "atomic_propositions" not in document:
        # traces written as lists of steps name their propositions themselves; the columns of
        # the benchmark schema do not say which names a trace may leave out
        named = _named_propositions(document, source)
        if named is None:
            raise JsonPathError("missing key 'atomic_propositions'", file=source, path=(),
                                hint="an LTL learning sample has atomic_propositions, positive_traces and "
                                     "negative_traces (it may be left out when every trace is a list of steps, "
                                     'e.g. [["a"], [], ["a", "b"]])')
        document = {**document, "atomic_propositions": named}
    trace_type = document.get("trace_type", "finite")
    if trace_type != "finite":
        raise JsonPathError(f"{json.dumps(trace_type)[:40]} traces are not read (LTLf is about finite traces)",
                            file=source, path=("trace_type",),
                            hint='a sample of finite traces says "trace_type": "finite" (or leaves it out)')
    props = document["atomic_propositions"]
    if not isinstance(props, list) or not all(isinstance(p, str) and p for p in props):
        raise JsonPathError("expected a list of non-empty strings", file=source, path=("atomic_propositions",))
    pos = _read_traces(document["positive_traces"], "positive_traces", props, source)
    neg = _read_traces(document["negative_traces"], "negative_traces", props, source)
    formula = document.get("smallest_known_formula") or None
    if formula is not None and not isinstance(formula, str):
        raise JsonPathError("expected a string", file=source, path=("smallest_known_formula",))
    metadata = {k: v for k, v in document.items() if k not in _OWN_KEYS}
    return LtlSample(tuple(props), pos, neg, formula, metadata, source)


def _read_traces(value: Any, key: str, props: list[str], source: str | None) -> tuple[Trace, ...]:
    if not isinstance(value, list):
        raise JsonPathError(f"expected a list of traces, found {type(value).__name__}", file=source, path=(key,))
    known = set(props)
    traces = []
    for i, trace in enumerate(value):
        if isinstance(trace, list):
            traces.append(_step_list(trace, known, props, source, (key, i)))
            continue
        if not isinstance(trace, dict):
            raise JsonPathError("expected an object mapping propositions to 0/1 lists, or a list of steps (each a "
                                "list of the propositions true there)", file=source, path=(key, i))
        length = None
        columns: dict[str, list[bool]] = {}
        for name, values in trace.items():
            if name not in known:
                raise JsonPathError(f"unknown proposition {name!r}", file=source, path=(key, i, name),
                                    hint=f"declared atomic_propositions: {', '.join(props) or '(none)'}")
            if not isinstance(values, list):
                raise JsonPathError("expected a list of 0/1 values", file=source, path=(key, i, name))
            if length is not None and len(values) != length:
                raise JsonPathError(f"{len(values)} values where the other propositions have {length}", file=source,
                                    path=(key, i, name), hint="all value lists of a trace have the trace's length")
            length = len(values)
            columns[name] = [_bit(v, source, (key, i, name, step)) for step, v in enumerate(values)]
        if not length:
            raise JsonPathError("empty trace (LTLf traces have at least one step)", file=source, path=(key, i))
        missing = [p for p in props if p not in columns]
        if missing:
            raise JsonPathError(f"no values for proposition {missing[0]!r}", file=source, path=(key, i))
        traces.append(tuple(frozenset(p for p in props if columns[p][step]) for step in range(length)))
    return tuple(traces)


def _named_propositions(document: dict, source: str | None) -> list[str] | None:
    """The propositions named by a sample whose traces are all lists of steps, sorted; None when a
    trace is in the column form (whose names must be declared)."""
    names: set[str] = set()
    for key in ("positive_traces", "negative_traces"):
        traces = document[key]
        if not isinstance(traces, list):
            raise JsonPathError(f"expected a list of traces, found {type(traces).__name__}", file=source, path=(key,))
        for trace in traces:
            if not isinstance(trace, list):
                return None
            for step in trace:
                if isinstance(step, list):
                    names.update(name for name in step if isinstance(name, str) and name)
    return sorted(names)


def _step_list(trace: list, known: set[str], props: list[str], source: str | None,
               where: tuple[str | int, ...]) -> Trace:
    """A trace written as a list of steps, each the list of propositions true there (the form of
    ``symlearn ltl eval`` traces files and ``automaton explain --trace``)."""
    if not trace:
        raise JsonPathError("empty trace (LTLf traces have at least one step)", file=source, path=where,
                            hint="a step where nothing holds is written [], e.g. [[]] is a one-step trace")
    steps = []
    for step, label in enumerate(trace):
        if not isinstance(label, list):
            raise JsonPathError(f"expected a list of the propositions true at this step, found {json.dumps(label)[:40]}",
                                file=source, path=(*where, step),
                                hint=f"write [{json.dumps(label)}] if it is the only true proposition"
                                if isinstance(label, str) else None)
        for k, name in enumerate(label):
            if not isinstance(name, str) or not name:
                raise JsonPathError(f"expected a proposition name, found {json.dumps(name)[:40]}", file=source,
                                    path=(*where, step, k))
            if name not in known:
                raise JsonPathError(f"unknown proposition {name!r}", file=source, path=(*where, step, k),
                                    hint=f"declared atomic_propositions: {', '.join(props) or '(none)'}")
        steps.append(frozenset(label))
    return tuple(steps)


def _bit(value: Any, source: str | None, where: tuple[str | int, ...]) -> bool:
    if value in (0, 1) and not isinstance(value, float) or value in ("0", "1"):
        return value in (1, "1")  # bool is an int too: True/False are accepted as 1/0
    raise JsonPathError(f"expected 0 or 1, found {json.dumps(value)}", file=source, path=where)


def load_sample(path: str | PathLike[str]) -> LtlSample:
    """Read a sample file (JSON in the benchmark schema)."""
    path = Path(path)
    from symlearn.input_limits import load_json, read_input_text

    text = read_input_text(path, what="sample file")
    document = load_json(text, source=str(path), error=DataError, syntax="not valid JSON")
    try:
        return parse_sample(document, source=str(path))
    except JsonPathError as exc:   # the decoded document's path back to the file's line and column
        raise located(exc, text) from None


def sample_to_document(sample: LtlSample) -> dict[str, Any]:
    """The JSON document of a sample (benchmark schema, with the counting fields filled in)."""

    def encode(trace: Trace) -> dict[str, list[int]]:
        return {p: [int(p in label) for label in trace] for p in sample.propositions}

    document: dict[str, Any] = {
        "positive_traces": [encode(t) for t in sample.positive],
        "negative_traces": [encode(t) for t in sample.negative],
        "smallest_known_formula": sample.smallest_known_formula or "",
    }
    document.update({k: v for k, v in sample.metadata.items() if k not in _OWN_KEYS})
    document.update({
        "atomic_propositions": list(sample.propositions),
        "number_atomic_propositions": len(sample.propositions),
        "number_traces": len(sample.positive) + len(sample.negative),
        "number_positive_traces": len(sample.positive),
        "number_negative_traces": len(sample.negative),
        "max_length_traces": sample.max_length,
        "trace_type": "finite",
    })
    return document


def save_sample(sample: LtlSample, path: str | PathLike[str]) -> None:
    """Write a sample as JSON (atomically)."""
    write_text(path, json.dumps(sample_to_document(sample), indent=1) + "\n")
