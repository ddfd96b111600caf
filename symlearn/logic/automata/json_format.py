"""Versioned JSON for DFAs, PDFAs and reward machines (format version 1).

One document per automaton::

    {
      "format": "symlearn-automaton", "version": 1, "kind": "dfa" | "pdfa" | "reward_machine",
      "alphabet": ["a", "b"],            # proposition names, sorted
      "states": 3,                       # states are 0..states-1
      "initial": 0,
      "accepting": [2],
      "state_names": ["q0", ...] | null,
      "transitions": [{"source": 0, "target": 1, "guard": "a & !b"}, ...]
    }

A PDFA adds ``"termination": [p_0, ...]`` and a ``"probability"`` per transition; a reward
machine adds ``"terminal": [...]``, a ``"reward"`` per transition and optionally
``"shaping": {"gamma": g, "potential": [...]}``. This one codec serves all three kinds:
:func:`header`/:func:`read_header` and :func:`write_transitions`/:func:`read_transitions` cover
the shared fields, each class's ``to_dict``/``from_dict`` adds only its own. Guards are guard
text (``grammars/guard.lark``); numbers are written with Python's shortest round-trip repr, so
``from_json(to_json(x)) == x`` exactly. Reading never executes anything; every problem is
reported with the JSON path of the offending field (``transitions[3].guard``) and, for JSON
syntax errors, the line and column.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from symlearn.errors import ParseError, SymlearnError
from symlearn.input_limits import check_size, load_json, read_input_text
from symlearn.json_position import locate
from symlearn.logic.guards import Guard

FORMAT = "symlearn-automaton"
VERSION = 1
KINDS = ("dfa", "pdfa", "reward_machine")


def dumps(document: Mapping) -> str:
    return json.dumps(document, indent=1, ensure_ascii=False, allow_nan=False) + "\n"


def loads(text: str, *, source: str | None = None) -> Any:
    """The JSON document; syntax errors, nesting and duplicate keys located (line, column)."""
    return load_json(text, source=source, syntax="not valid JSON")


class _Reader:
    """Checked access to a JSON document; errors name the path of the field."""

    def __init__(self, document: Any, source: str | None) -> None:
        self.document = document
        self.source = source

    def fail(self, path: str, message: str, hint: str | None = None) -> ParseError:
        where = f"{path}: " if path else ""
        error = ParseError(f"{where}{message}", file=self.source, hint=hint)
        error.json_path = _path_parts(path)  # read by located_in(): the field's line and column
        return error

    def get(self, obj: Any, path: str, key: str, kind, *, optional: bool = False, default=None):
        if not isinstance(obj, dict):
            raise self.fail(path, f"expected an object, got {_json_type(obj)}")
        full = f"{path}.{key}" if path else key
        if key not in obj or obj[key] is None:
            if optional:
                return default
            raise self.fail(full, "missing field")
        value = obj[key]
        return self.check(value, full, kind)

    def check(self, value: Any, path: str, kind):
        if kind == "int":
            if isinstance(value, bool) or not isinstance(value, int):
                raise self.fail(path, f"expected an integer, got {_json_type(value)}")
        elif kind == "number":
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not _finite_float(value):
                raise self.fail(path, f"expected a finite number, got {_json_type(value)}")
            value = float(value)
        elif kind == "str":
            if not isinstance(value, str):
                raise self.fail(path, f"expected text, got {_json_type(value)}")
        elif kind == "list":
            if not isinstance(value, list):
                raise self.fail(path, f"expected a list, got {_json_type(value)}")
        elif kind == "dict":
            if not isinstance(value, dict):
                raise self.fail(path, f"expected an object, got {_json_type(value)}")
        return value

    def list_of(self, obj, path, key, kind, *, optional=False):
        items = self.get(obj, path, key, "list", optional=optional)
        if items is None:
            return None
        full = f"{path}.{key}" if path else key
        return [self.check(v, f"{full}[{i}]", kind) for i, v in enumerate(items)]

    def guard(self, value, path: str) -> Guard:
        text = self.check(value, path, "str")
        try:
            return Guard.parse(text)
        except SymlearnError as exc:
            raise self.fail(path, exc.message, exc.hint) from None


def _path_parts(path: str) -> tuple[str | int, ...]:
    """``transitions[3].guard`` as ``("transitions", 3, "guard")`` (the reader writes only such paths)."""
    return tuple(int(index) if index else key for key, index in re.findall(r"([^.\[\]]+)|\[(\d+)\]", path))


def located_in(error: SymlearnError, text: str) -> SymlearnError:
    """``error`` with the line and column of the field it names (its ``json_path``) in ``text``,
    the document it was read from, so a field's mistake reads ``FILE:LINE:COL`` like a syntax error."""
    path = getattr(error, "json_path", None)
    if path is not None and error.line is None:
        # a missing field has no position of its own: the object that lacks it has
        for end in range(len(path), -1, -1):
            position = locate(text, path[:end])
            if position is not None:
                error.line, error.column = position
                break
    return error


def _finite_float(value: int | float) -> bool:
    """Whether ``value`` is a finite float64 (an integer such as 10**400 is not: it overflows)."""
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _json_type(value: Any) -> str:
    return {dict: "an object", list: "a list", str: "text", bool: "a boolean", type(None): "null"}.get(
        type(value), f"the number {value!r}" if isinstance(value, (int, float)) else type(value).__name__)


def header(kind: str, automaton) -> dict:
    return {
        "format": FORMAT, "version": VERSION, "kind": kind,
        "alphabet": sorted(automaton.alphabet),
        "states": automaton.n_states,
        "initial": automaton.initial,
        "accepting": sorted(automaton.accepting),
        "state_names": None if automaton.state_names is None else list(automaton.state_names),
    }


def read_header(document: Any, kind: str | None, source: str | None) -> tuple[_Reader, dict]:
    reader = _Reader(document, source)
    if not isinstance(document, dict):
        raise reader.fail("", f"an automaton document must be a JSON object, got {_json_type(document)}")
    fmt = reader.get(document, "", "format", "str")
    if fmt != FORMAT:
        raise reader.fail("format", f"expected {FORMAT!r}, got {fmt!r}")
    version = reader.get(document, "", "version", "int")
    if version != VERSION:
        raise reader.fail("version", f"unsupported version {version} (this symlearn reads version {VERSION})",
                          hint="upgrade symlearn")
    found = reader.get(document, "", "kind", "str")
    if found not in KINDS:
        raise reader.fail("kind", f"unknown automaton kind {found!r}", hint=f"one of {', '.join(KINDS)}")
    if kind is not None and found != kind:
        raise reader.fail("kind", f"expected a {kind}, the file holds a {found}")
    fields = {
        "kind": found,
        "alphabet": _unique(reader, "alphabet", reader.list_of(document, "", "alphabet", "str"), "proposition"),
        "n_states": _state_count(reader, document),
        "initial": reader.get(document, "", "initial", "int"),
        # a reward machine ends in its "terminal" states; "accepting" is only a DFA's and PDFA's
        # notion, so a hand-written machine without it was refused as "accepting: missing field"
        "accepting": reader.list_of(document, "", "accepting", "int", optional=found == "reward_machine") or [],
        "state_names": _unique(reader, "state_names",
                               reader.list_of(document, "", "state_names", "str", optional=True), "state name"),
    }
    reader.fields = fields  # read_transitions checks each edge's states and propositions against them
    _state(reader, fields["initial"], "initial", "initial state")
    for i, q in enumerate(fields["accepting"]):
        _state(reader, q, f"accepting[{i}]", "accepting state")
    names = fields["state_names"]
    if names is not None and len(names) != fields["n_states"]:
        raise reader.fail("state_names", f"{len(names)} state names for {fields['n_states']} states")
    return reader, fields


def _unique(reader: _Reader, path: str, values: list | None, what: str) -> list | None:
    """``values`` when no entry repeats; a repeated proposition or state name is a mistake that a
    set would hide (two states called "q1" cannot be told apart in any output)."""
    if values is None:
        return None
    first: dict[Any, int] = {}
    for i, value in enumerate(values):
        if value in first:
            raise reader.fail(f"{path}[{i}]", f"{what} {value!r} appears twice (first at {path}[{first[value]}])")
        first[value] = i
    return values


def _state_count(reader: _Reader, document: dict) -> int:
    """``states``, checked against ``SYMLEARN_MAX_STATES`` before anything is built for them."""
    n = reader.get(document, "", "states", "int")
    if n < 1:
        raise reader.fail("states", f"an automaton needs at least one state, got {n}")
    try:
        check_size(n, "SYMLEARN_MAX_STATES", what="states: the declared number of states")
    except SymlearnError as exc:
        exc.file = reader.source
        raise
    return n


def write_transitions(automaton, extra: str | None = None) -> list[dict]:
    """The ``transitions`` field: one object per edge, ``extra`` naming its number (PDFA, RM)."""
    rows = []
    for source, guard, target, *value in automaton.edges():
        row = {"source": source, "target": target, "guard": str(guard)}
        if extra:
            row[extra] = value[0]
        rows.append(row)
    return rows


def read_transitions(reader: _Reader, document: dict, extra: str | None) -> dict[int, list[tuple]]:
    """``{source: [(guard, target[, extra]), ...]}``, as the constructors take it, every field checked."""
    result: dict[int, list[tuple]] = {}
    reader.edges, reader.edge_paths = result, {}  # construct() names the edge that breaks determinism
    for i, item in enumerate(reader.get(document, "", "transitions", "list")):
        path = f"transitions[{i}]"
        source = _state(reader, reader.get(item, path, "source", "int"), f"{path}.source", "source")
        target = _state(reader, reader.get(item, path, "target", "int"), f"{path}.target", "target")
        guard = reader.guard(reader.get(item, path, "guard", "str"), f"{path}.guard")
        outside = sorted(guard.propositions - set(reader.fields["alphabet"]))
        if outside:
            # checked here, with the edge's path, rather than by the constructor, which cannot
            # say where in the file the edge is
            raise reader.fail(f"{path}.guard", f"guard {str(guard)!r} uses {', '.join(outside)}, outside "
                              f"the alphabet ({', '.join(reader.fields['alphabet']) or 'empty'})",
                              hint="add the propositions to \"alphabet\" or correct the guard")
        edge = (guard, target) + ((reader.get(item, path, extra, "number"),) if extra else ())
        result.setdefault(source, []).append(edge)
        reader.edge_paths[source, len(result[source]) - 1] = path
    return result


def _state(reader: _Reader, value: int, path: str, what: str) -> int:
    n = reader.fields["n_states"]
    if not 0 <= value < n:
        raise reader.fail(path, f"{what} {value} is not a state (states are 0..{n - 1}, as \"states\": {n} "
                                "declares)")
    return value


def construct(reader: _Reader, build):
    """Run a constructor, locating its model errors in the file."""
    try:
        return build()
    except SymlearnError as exc:
        overlap = re.match(r"[\w ]+? is not deterministic: from state (\d+),", exc.message)
        edges = getattr(reader, "edges", {}).get(int(overlap.group(1))) if overlap else None
        if edges:
            # the constructor cannot say where the edge is: find the first guard that meets one before
            # it (the constructor's own order), only now that the check has failed
            from symlearn.logic.guards import Guard

            seen = Guard.false()
            for k, edge in enumerate(edges):
                if not (edge[0] & seen).is_false():
                    path = f"{reader.edge_paths[int(overlap.group(1)), k]}.guard"
                    located = type(exc)(f"{path}: {exc.message}", file=reader.source, hint=exc.hint)  # still a ModelError
                    located.json_path = _path_parts(path)
                    raise located from None
                seen = seen | edge[0]
        if exc.file is None:
            exc.file = reader.source
        raise


# -- DFA -------------------------------------------------------------------------------------
def dfa_to_dict(dfa) -> dict:
    document = header("dfa", dfa)
    document["transitions"] = write_transitions(dfa)
    return document


def dfa_from_dict(document: Any, *, source: str | None = None):
    from symlearn.logic.automata.dfa import DFA

    reader, f = read_header(document, "dfa", source)
    transitions = read_transitions(reader, document, None)
    return construct(reader, lambda: DFA(f["alphabet"], f["n_states"], f["initial"], f["accepting"],
                                         transitions, f["state_names"]))


def load_automaton(path: str | Path):
    """Read any automaton file (DFA, PDFA or reward machine), dispatching on ``kind``."""
    source = str(path)
    text = read_input_text(path)
    document = loads(text, source=source)
    try:
        _, fields = read_header(document, None, source)
        kind = fields["kind"]
        if kind == "dfa":
            return dfa_from_dict(document, source=source)
        if kind == "pdfa":
            from symlearn.logic.automata.pdfa import PDFA

            return PDFA.from_dict(document, source=source)
        from symlearn.logic.automata.reward_machine import RewardMachine

        return RewardMachine.from_dict(document, source=source)
    except SymlearnError as exc:
        raise located_in(exc, text) from None
