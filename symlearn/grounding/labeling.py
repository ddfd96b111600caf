"""Labelings: which propositions are true in which environment state.

A learned formula means nothing without the labeling it was learned under, so a labeling is a
value of its own: it prints, compares, saves to versioned JSON and loads again. Three forms share
one interface (``propositions``, ``meanings``, ``label(state) -> frozenset``, ``label_word``):

* :class:`Labeling`: a finite table state -> propositions (this module);
* :class:`~symlearn.grounding.feature_labeling.FeatureLabeling`: propositions defined by
  inequalities over named features, for continuous states and image features;
* :class:`~symlearn.grounding.feature_labeling.CallableLabeling`: a Python function.

:func:`load_labeling` reads either saved form (the JSON ``kind`` says which). When a learner
invents propositions (for instance "the agent is in this cell"), it returns a *new* labeling with
the proposition added, in order of discovery, together with its meaning.
"""

from __future__ import annotations

import json
import os
from collections.abc import Hashable, Iterable, Mapping
from pathlib import Path
from typing import Any

from symlearn.errors import DataError
from symlearn.json_document import JsonFile, read_document
from symlearn.json_position import JsonPathError, located

FORMAT_VERSION = 1
MAGIC = "labeling"


def _state_to_json(state: Hashable) -> Any:
    if isinstance(state, tuple):
        return [_state_to_json(s) for s in state]
    if isinstance(state, (bool, int, str)) or state is None:
        return state
    if hasattr(state, "item"):  # numpy scalar
        return state.item()
    raise DataError(f"state {state!r} cannot be written to JSON; use ids, strings or tuples of them")


def _state_from_json(value: Any) -> Hashable:
    return tuple(_state_from_json(v) for v in value) if isinstance(value, list) else value


def _hashable(state: Any) -> Hashable:
    if hasattr(state, "item") and getattr(state, "ndim", 1) == 0:
        return state.item()
    if isinstance(state, list) or (hasattr(state, "tolist") and getattr(state, "ndim", 0) >= 1):
        return tuple(state.tolist() if hasattr(state, "tolist") else state)
    return state


class LabelingBase:
    """The interface every labeling shares: ``propositions`` (declared, in order), ``meanings``,
    ``label(state) -> frozenset`` (also by calling the labeling) and ``label_word(states)``."""

    _meanings: dict[str, str]

    @property
    def propositions(self) -> tuple[str, ...]:  # pragma: no cover - every labeling defines it
        raise NotImplementedError

    @property
    def meanings(self) -> dict[str, str]:
        return dict(self._meanings)

    def label(self, state: Any) -> frozenset[str]:  # pragma: no cover - every labeling defines it
        raise NotImplementedError

    def __call__(self, state: Any) -> frozenset[str]:
        return self.label(state)

    def label_word(self, states: Iterable[Any]) -> tuple[frozenset[str], ...]:
        return tuple(self.label(s) for s in states)


class Labeling(LabelingBase, JsonFile):
    """A finite table from states to the propositions true in them.

    ``meanings`` says in words what each proposition stands for. States absent from the table
    satisfy no proposition.

    >>> lab = Labeling({0: {"coffee"}, 5: {"office"}}, meanings={"coffee": "at the coffee machine"})
    >>> sorted(lab.label(0)), sorted(lab.label(3))
    (['coffee'], [])
    >>> lab2 = lab.with_proposition("p0", [3], "agent in cell 3")
    >>> sorted(lab2.label(3)), lab2.propositions
    (['p0'], ('coffee', 'office', 'p0'))
    """

    def __init__(self, table: Mapping[Hashable, Iterable[str]], *, meanings: Mapping[str, str] | None = None,
                 propositions: Iterable[str] = ()) -> None:
        clean: dict[Hashable, frozenset[str]] = {}
        for state, props in table.items():
            props = frozenset(props)
            for p in props:
                if not isinstance(p, str) or not p:
                    raise DataError(f"labeling of state {state!r}: {p!r} is not a proposition name")
            if props:
                clean[_hashable(state)] = props
        self._table = clean
        declared = set(propositions) | {p for props in clean.values() for p in props} | set(meanings or {})
        self._meanings = {p: (meanings or {}).get(p, "") for p in declared}
        self._order = tuple(list(dict.fromkeys([*propositions])) + sorted(declared - set(propositions)))

    @property
    def propositions(self) -> tuple[str, ...]:
        """Declared propositions: first those given in order, then the rest sorted."""
        return self._order

    def label(self, state: Any) -> frozenset[str]:
        return self._table.get(_hashable(state), frozenset())

    def items(self) -> list[tuple[Hashable, frozenset[str]]]:
        """Every labelled state with its propositions (states with none are not listed)."""
        return list(self._table.items())

    def restrict(self, propositions: Iterable[str]) -> Labeling:
        """A copy that keeps only ``propositions`` (in this labeling's order) and their meanings."""
        keep = frozenset(propositions)
        unknown = sorted(keep - set(self._order))
        if unknown:
            raise DataError(f"unknown proposition {unknown[0]!r}", hint="known: " + ", ".join(self._order))
        order = [p for p in self._order if p in keep]
        table = {s: props & keep for s, props in self._table.items() if props & keep}
        return Labeling(table, meanings={p: self._meanings[p] for p in order}, propositions=order)

    def states_where(self, proposition: str) -> list[Hashable]:
        return [s for s, props in self._table.items() if proposition in props]

    def with_proposition(self, name: str, states: Iterable[Any], meaning: str = "") -> Labeling:
        """A copy in which ``name`` is also true in ``states`` (learners grow labelings this way)."""
        if name in self._meanings:
            raise DataError(f"proposition {name!r} already exists in this labeling")
        table = {s: set(p) for s, p in self._table.items()}
        for state in states:
            table.setdefault(_hashable(state), set()).add(name)
        meanings = {**self._meanings, name: meaning}
        return Labeling(table, meanings=meanings, propositions=[*self._order, name])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Labeling):
            return NotImplemented
        return (self._table, self._meanings, self._order) == (other._table, other._meanings, other._order)

    def __repr__(self) -> str:
        return f"Labeling({len(self._order)} propositions over {len(self._table)} labelled states)"

    # --- persistence ----------------------------------------------------------------------
    def to_json(self) -> str:
        doc = {
            "symlearn": MAGIC,
            "format_version": FORMAT_VERSION,
            "kind": "table",
            "propositions": [{"name": p, "meaning": self._meanings[p]} for p in self._order],
            "table": [[_state_to_json(s), sorted(props)] for s, props in self._table.items()],
        }
        return json.dumps(doc, indent=1)

    @classmethod
    def from_json(cls, text: str, *, source: str = "<string>") -> Labeling:
        try:
            return cls.from_document(read_document(text, MAGIC, FORMAT_VERSION, source=source), source=source)
        except JsonPathError as exc:  # the mistake's line and column in the text
            raise located(exc, text) from None

    @classmethod
    def from_document(cls, doc: dict[str, Any], *, source: str = "<string>") -> Labeling:
        if doc.get("kind", "table") != "table":
            raise DataError(f"this labeling is of kind {doc.get('kind')!r}, not a table", file=source,
                            hint="read it with symlearn.grounding.load_labeling")
        props, entries = _read_table_document(doc, source)
        _check_file_table(props, entries, source)
        table = dict(entries)
        try:
            return cls(table, meanings=dict(props), propositions=[name for name, _ in props])
        except DataError as exc:
            raise DataError(exc.message, file=source) from None



_SHAPE = "expected 'propositions': [{\"name\": ..., \"meaning\": ...}], 'table': [[state, [propositions]], ...]"


def _read_table_document(doc: Mapping[str, Any], source: str) -> tuple[list, list]:
    """``(name, meaning)`` per proposition and ``(state, names)`` per table entry, each part's
    shape checked with its JSON path (located in the file by :func:`load_labeling_text`)."""
    for key in ("propositions", "table"):
        if not isinstance(doc.get(key), list):
            what = f"expected a list, got {_json_kind(doc.get(key))}" if key in doc else f"missing key {key!r}"
            raise JsonPathError(what, path=(key,) if key in doc else (), file=source, hint=_SHAPE)
    props = []
    for i, p in enumerate(doc["propositions"]):
        if not isinstance(p, Mapping) or "name" not in p:
            raise JsonPathError(f"expected an object with a \"name\" (and a \"meaning\"), got {_json_kind(p)}",
                                path=("propositions", i), file=source, hint=_SHAPE)
        props.append((p["name"], p.get("meaning", "")))
    entries = []
    for i, entry in enumerate(doc["table"]):
        if not isinstance(entry, list) or len(entry) != 2:
            raise JsonPathError(f"expected [state, [propositions]], got {_json_kind(entry)}", path=("table", i),
                                file=source, hint=_SHAPE)
        entries.append((_state_from_json(entry[0]), entry[1]))
    return props, entries


def _json_kind(value: Any) -> str:
    if isinstance(value, str):
        return f"text {json.dumps(value)[:40]}"
    return {dict: "an object", list: "a list", bool: "a boolean", type(None): "null"}.get(
        type(value), f"the number {value!r}" if isinstance(value, (int, float)) else type(value).__name__)


def _check_file_table(props: list[tuple[Any, Any]], entries: list[tuple[Hashable, Any]], source: str) -> None:
    """What a labeling *file* must get right (a labeling built in Python may grow propositions):
    proposition names given once, each state listed once, only declared propositions used."""
    declared: dict[Any, int] = {}
    for i, (name, _) in enumerate(props):
        if not isinstance(name, str) or not name:
            raise JsonPathError(f"a name must be a non-empty string, got {json.dumps(name)}",
                                path=("propositions", i), file=source)
        if name in declared:
            raise JsonPathError(f"proposition {name!r} is declared twice (first at "
                                f"propositions[{declared[name]}])", path=("propositions", i), file=source)
        declared[name] = i
    seen: dict[Hashable, int] = {}
    for i, (state, names) in enumerate(entries):
        try:
            key = _hashable(state)
            hash(key)  # an object ({"a": 1}) is no state: it could not be looked up
        except TypeError:
            raise JsonPathError(f"state {json.dumps(state)} cannot be used as a state", path=("table", i),
                                file=source) from None
        if key in seen:
            raise JsonPathError(f"state {json.dumps(_state_to_json(state))} is listed twice (first at "
                                f"table[{seen[key]}])", path=("table", i), file=source, hint="merge the two entries")
        seen[key] = i
        if isinstance(names, str) or not isinstance(names, list):
            raise JsonPathError("the propositions of a state must be a list of names", path=("table", i),
                                file=source)
        for j, name in enumerate(names):
            if name not in declared:
                raise JsonPathError(f"proposition {json.dumps(name)} is not declared in 'propositions'",
                                    path=("table", i), file=source, hint="declare it with its meaning, or fix the name")


def load_labeling_text(text: str, *, source: str = "<string>"):
    """A :class:`Labeling` or :class:`~symlearn.grounding.feature_labeling.FeatureLabeling`
    from its JSON text, chosen by the document's ``kind`` (``table`` when absent)."""
    doc = read_document(text, MAGIC, FORMAT_VERSION, source=source)
    kind = doc.get("kind", "table")
    if kind == "table":
        try:
            return Labeling.from_document(doc, source=source)
        except JsonPathError as exc:
            raise located(exc, text) from None
    if kind == "features":
        from symlearn.grounding.feature_labeling import FeatureLabeling

        return FeatureLabeling.from_document(doc, source=source)
    raise DataError(f"unknown labeling kind {kind!r}", file=source, hint="use 'table' or 'features'")


def load_labeling(path: str | os.PathLike[str]):
    """Read a saved labeling of either kind (see :func:`load_labeling_text`)."""
    path = Path(path)
    try:
        from symlearn.input_limits import read_input_text

        text = read_input_text(path, what="labeling file")
    except OSError as exc:
        raise DataError(f"cannot read the labeling: {exc.strerror}", file=str(path)) from None
    return load_labeling_text(text, source=str(path))
