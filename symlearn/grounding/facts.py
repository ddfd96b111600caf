"""Fact groundings: which ASP facts describe a state, an action, or a state-action pair.

A learned rule such as ``:- alarm, move(_).`` only means something together with the facts
that say when ``alarm`` holds. A :class:`FactGrounding` is that translation for a finite domain
with integer state and action ids:

* ``state_facts[s]``: the facts of state ``s`` (``("at(0,0).", "loaded.")``);
* ``action_atoms[a]``: the atom of action ``a`` (``"move(north)"``);
* optionally ``pair_facts[(s, a)]``: the whole context of one pair, for domains whose action
  atom depends on the state (Hanoi: "top disk of peg 0 to peg 2" is ``move(D, 2)`` with ``D``
  the disk on top). A pair listed there ignores the two tables above.

The example context of a pair is the state's facts followed by the action's atom as a fact.
Every fact is checked with clingo's parser when the grounding is built, so a typo is reported
where it was written. :meth:`FactGrounding.from_jsonl` reads the two files of a domain folder
(``states.jsonl``: ``{"id": 0, "facts": "at(0,0). loaded."}``; ``actions.jsonl``:
``{"id": 0, "atom": "move(north)"}``), :meth:`FactGrounding.save_jsonl` writes them.

>>> g = FactGrounding({0: "at(0,0). loaded.", 1: ["at(0,1)."]}, ["move(north)", "drop"])
>>> g.facts(0, 1)
('at(0,0).', 'loaded.', 'drop.')
>>> g.n_states, g.n_actions, g.action_index("move(north)")
(2, 2, 0)
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError, ParseError, SymlearnError

Facts = tuple[str, ...]


def split_facts(text: str | Iterable[str], *, source: str = "<facts>", line: int = 1, column: int = 1) -> Facts:
    """Normalised ground facts (``"p(1)."``) from program text or a list of facts.

    Uses clingo's parser (a ``"."`` inside a string or a comment is handled correctly); anything
    that is not a plain fact -- a rule, a variable, a constraint -- is a :class:`ParseError`
    pointing at it.
    """
    from symlearn.logic.asp.clingo_adapter import is_ground_fact, parse_rules

    pieces = [text] if isinstance(text, str) else list(text)
    found: list[str] = []
    for piece in pieces:
        if not isinstance(piece, str):
            raise DataError(f"facts must be text, got {type(piece).__name__}", file=source, line=line)
        stripped = piece.strip()
        if not stripped:
            continue
        if not stripped.endswith("."):  # a single atom written without its full stop
            stripped += "."
        try:
            statements = parse_rules(stripped, source=source)
        except ParseError as exc:
            offset = len(piece) - len(piece.lstrip())  # the error's column within the piece
            where = column + offset + (exc.column - 1 if exc.line == 1 and exc.column else 0)
            raise ParseError(exc.message, file=source, line=line, column=where,
                             hint=_fact_hint(stripped) or exc.hint) from None
        for statement in statements:
            text_form = str(statement)
            if not is_ground_fact(statement):
                at, hint = _variable_in(piece, statement)
                raise ParseError(f"{text_form!r} is not a ground fact", file=source, line=line, column=column + at,
                                 hint=hint)
            found.append(text_form)
    return tuple(found)


def split_fact_groups(groups: Sequence[str | Iterable[str]], *, source: str = "<facts>",
                      lines: Mapping[int, int] | None = None, columns: Mapping[int, int] | None = None) -> list[Facts]:
    """:func:`split_facts` of many groups (one per state or pair) with a single clingo parse.

    Each group is put on a line of its own and the statements are sorted back by line, so a
    domain with thousands of contexts is checked in one call. When anything is wrong, the groups
    are read one by one to report the first mistake where it was written (``lines[i]`` is the
    file line of group ``i``, ``columns[i]`` the column where its text starts there).
    """
    from symlearn.logic.asp.clingo_adapter import is_ground_fact, parse_rules

    def one_by_one() -> list[Facts]:
        return [split_facts(g, source=source, line=(lines or {}).get(i, 1), column=(columns or {}).get(i, 1))
                for i, g in enumerate(groups)]

    texts = []
    for group in groups:
        pieces = [group] if isinstance(group, str) else list(group)
        if any(not isinstance(p, str) or "\n" in p for p in pieces):
            return one_by_one()
        stripped = [p.strip() for p in pieces if p.strip()]
        texts.append(" ".join(p if p.endswith(".") else p + "." for p in stripped))
    try:
        statements = parse_rules("\n".join(texts), source=source)
    except ParseError:
        return one_by_one()
    found: list[list[str]] = [[] for _ in texts]
    for statement in statements:
        if not is_ground_fact(statement):
            return one_by_one()
        found[statement.location.begin.line - 1].append(str(statement))
    return [tuple(f) for f in found]


def _atom(text: str, *, source: str, line: int, column: int = 1) -> str:
    facts = split_facts(text, source=source, line=line, column=column)
    if len(facts) != 1:
        raise ParseError(f"an action atom must be exactly one atom, got {text!r}", file=source, line=line,
                         column=column)
    return facts[0][:-1]


class FactGrounding:
    """State facts, action atoms and optional per-pair contexts of a finite domain (see module)."""

    def __init__(self, state_facts: Mapping[int, str | Iterable[str]] | Sequence[str | Iterable[str]],
                 action_atoms: Mapping[int, str] | Sequence[str], *,
                 pair_facts: Mapping[tuple[int, int], str | Iterable[str]] | None = None,
                 source: str = "<fact grounding>", lines: Mapping[int, int] | None = None,
                 columns: Mapping[int, int] | None = None) -> None:
        # every fact is checked and normalised by clingo's parser, one call for all states
        self._states = tuple(split_fact_groups(_dense(state_facts, "state", source), source=source, lines=lines,
                                               columns=columns))
        self._lines = dict(lines or {})
        actions = _dense(action_atoms, "action", source)
        self._actions = tuple(_atom(a, source=source, line=i + 1) if isinstance(a, str) else _bad_atom(a, source)
                              for i, a in enumerate(actions))
        if len(set(self._actions)) != len(self._actions):
            dup = next(a for a in self._actions if self._actions.count(a) > 1)
            raise DataError(f"action atom {dup!r} names two actions", file=source)
        pairs = dict(pair_facts or {})
        for s, a in pairs:
            if not (0 <= int(s) < len(self._states) and 0 <= int(a) < len(self._actions)):
                raise DataError(f"pair ({s}, {a}) is outside {len(self._states)} states x {len(self._actions)} actions",
                                file=source)
        self._pairs: dict[tuple[int, int], Facts] = {
            (int(s), int(a)): facts
            for (s, a), facts in zip(pairs, split_fact_groups(list(pairs.values()), source=source))}
        self.source = source
        self.state_names: tuple[str, ...] | None = None  # optional readable names ("name" in states.jsonl)

    # --- reading --------------------------------------------------------------------------
    @property
    def n_states(self) -> int:
        return len(self._states)

    @property
    def n_actions(self) -> int:
        return len(self._actions)

    @property
    def action_atoms(self) -> tuple[str, ...]:
        return self._actions

    def state_facts(self, state: int) -> Facts:
        return self._states[int(state)]

    def action_atom(self, action: int) -> str:
        return self._actions[int(action)]

    def action_index(self, atom: str) -> int:
        """The id of the action whose atom is ``atom`` (spaces ignored)."""
        key = atom.replace(" ", "").rstrip(".")
        for i, known in enumerate(self._actions):
            if known.replace(" ", "") == key:
                return i
        raise DataError(f"unknown action atom {atom!r}", hint="known: " + ", ".join(self._actions[:10]))

    def facts(self, state: int, action: int) -> Facts:
        """The example context of a pair: state facts, then the action atom as a fact."""
        pair = self._pairs.get((int(state), int(action)))
        if pair is not None:
            return pair
        return (*self._states[int(state)], f"{self._actions[int(action)]}.")

    @property
    def has_pair_facts(self) -> bool:
        return bool(self._pairs)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FactGrounding):
            return NotImplemented
        return (self._states, self._actions, self._pairs) == (other._states, other._actions, other._pairs)

    def __repr__(self) -> str:
        extra = f", {len(self._pairs)} pair contexts" if self._pairs else ""
        return f"FactGrounding({self.n_states} states, {self.n_actions} actions{extra})"

    # --- files ----------------------------------------------------------------------------
    @classmethod
    def from_jsonl(cls, states_path: str | os.PathLike[str], actions_path: str | os.PathLike[str]) -> FactGrounding:
        """Read ``states.jsonl`` (``{"id", "facts"}``) and ``actions.jsonl`` (``{"id", "atom"}``)."""
        names: dict[int, str] = {}
        state_columns: dict[int, int] = {}
        action_columns: dict[int, int] = {}
        states = _read_table(Path(states_path), "facts", names, state_columns)
        actions = _read_table(Path(actions_path), "atom", columns=action_columns)
        atoms = {i: _atom(text, source=str(actions_path), line=line, column=action_columns.get(i, 1))
                 for i, (text, line) in actions.items()}
        _refuse_repeats(atoms, {i: line for i, (_, line) in actions.items()}, str(actions_path), "action atom",
                        "every action needs its own atom")
        if names:
            _refuse_repeats(names, {i: line for i, (_, line) in states.items()}, str(states_path), "state name",
                            "\"name\" is optional; states without one are named by their id")
        grounding = cls({i: text for i, (text, _) in states.items()}, atoms, source=str(states_path),
                        lines={i: line for i, (_, line) in states.items()}, columns=state_columns)
        grounding.state_names = tuple(names.get(i, str(i)) for i in range(len(states))) if names else None
        if names and len(set(grounding.state_names)) != len(grounding.state_names):
            raise DataError("state names must be unique", file=str(states_path),
                            hint="\"name\" is optional; states without one are named by their id")
        return grounding

    def state_line(self, state: int) -> int | None:
        """The line of ``states.jsonl`` a state was read from (None when built in Python)."""
        return self._lines.get(int(state))

    def save_jsonl(self, states_path: str | os.PathLike[str], actions_path: str | os.PathLike[str]) -> None:
        """Write the two tables (per-pair contexts have no place in this format: refused)."""
        if self._pairs:
            raise SymlearnError("this grounding has per-pair contexts, which states.jsonl/actions.jsonl cannot hold")
        names = self.state_names or ()
        write_text(states_path, "".join(json.dumps({"id": i, "facts": " ".join(f),
                                                    **({"name": names[i]} if names else {})}) + "\n"
                                        for i, f in enumerate(self._states)))
        write_text(actions_path, "".join(json.dumps({"id": i, "atom": a}) + "\n" for i, a in enumerate(self._actions)))


def _text_column(raw: str, key: str) -> int:
    """The column where the string value of ``key`` starts on the JSON line ``raw`` (just after
    its opening quote; escapes before the mistake shift it), 1 when it cannot be found."""
    from symlearn.data.jsonl_locate import value_column

    try:
        found = value_column(raw, key)
    except (ValueError, IndexError):
        return 1
    return found + 1 if found else 1


def _variable_in(piece: str, statement: Any) -> tuple[int, str]:
    """Where in ``piece`` a non-ground statement's first variable is (0-based; 0 when none is
    found) and the hint that names it: a capitalised name is a variable in ASP."""
    import re

    generic = 0, "write facts such as at(0,1). or loaded."
    if ":-" in str(statement) or str(statement).lstrip()[:1] in "{#":  # a rule, a choice, a directive
        return generic
    begin = statement.location.begin
    start = 0
    if begin.line == 1:
        start = max(0, begin.column - 1) + len(piece) - len(piece.lstrip())
    body = re.sub(r'"(?:[^"\\]|\\.)*"', lambda m: " " * len(m.group()), piece)  # strings are constants
    found = re.compile(r"(?<![A-Za-z0-9_'])([A-Z_][A-Za-z0-9_']*)").search(body, start)
    if not found:
        return generic
    return found.start(), (f"{found.group(1)} starts with a capital letter or '_', which makes it a variable in ASP: "
                           "predicate and constant names start with a lowercase letter (write it in lowercase or "
                           "as a string, \"" + found.group(1) + "\")")


def _fact_hint(text: str) -> str | None:
    """What a clingo syntax error in a state's facts most likely means, in the user's terms."""
    import re

    if re.search(r"\d\.\d", text):
        return ("ASP has no decimal numbers: write 21.5 as a scaled integer (temp(215)) or a string "
                "(temp(\"21.5\")); numeric features belong in features.json")
    capital = re.search(r"(?:^|[\s.,;(])([A-Z_][A-Za-z0-9_']*)\s*\(", text)
    if capital:
        return (f"{capital.group(1)} starts with a capital letter or '_', which makes it a variable in ASP: "
                "predicate and constant names start with a lowercase letter")
    return None


def _refuse_repeats(values: Mapping[int, str], lines: Mapping[int, int], source: str, what: str, hint: str) -> None:
    """A value (an action atom, a state name) given to two ids: name both, at the second's line."""
    first: dict[str, int] = {}
    for i in sorted(values):
        value = values[i]
        if value in first:
            raise DataError(f"{what} {value!r} of id {i} is already that of id {first[value]}", file=source,
                            line=lines.get(i), hint=hint)
        first[value] = i


def _bad_atom(value: Any, source: str) -> str:
    raise DataError(f"an action atom must be text, got {value!r}", file=source)


def _dense(table: Any, what: str, source: str) -> list[Any]:
    """A mapping id -> value or a sequence, as a list indexed 0..n-1 (every id present)."""
    if isinstance(table, Mapping):
        ids = sorted(table)
        if any(not isinstance(i, int) or isinstance(i, bool) for i in ids):
            raise DataError(f"{what} ids must be integers", file=source)
        missing = sorted(set(range(len(ids))) - set(ids))
        if missing or (ids and ids[0] != 0):
            raise DataError(f"{what} ids must be 0..{len(ids) - 1}; {what} {missing[0] if missing else ids[0]} "
                            "is missing", file=source)
        return [table[i] for i in ids]
    return list(table)


def _read_table(path: Path, key: str, names: dict[int, str] | None = None,
                columns: dict[int, int] | None = None) -> dict[int, tuple[str, int]]:
    """``{id: (value, line)}`` of a JSONL file with objects ``{"id": int, key: str}``; optional
    ``"name"`` strings are collected into ``names`` when it is given, and the column where each
    value's text starts on its line into ``columns`` (so a syntax error in it is located)."""
    try:
        from symlearn.input_limits import read_input_text

        # \n (or \r\n) only: splitlines would cut a JSON string holding U+2028 or U+0085
        lines = [line.rstrip("\r") for line in read_input_text(path).split("\n")]
    except OSError as exc:
        raise DataError(f"cannot read {path}: {exc.strerror}", file=str(path)) from None
    table: dict[int, tuple[str, int]] = {}
    for number, text in enumerate(lines, start=1):
        if not text.strip():
            continue
        from symlearn.input_limits import load_json

        item = load_json(text, source=str(path), line=number)  # syntax, nesting, duplicate keys
        if not isinstance(item, dict) or "id" not in item or key not in item:
            raise DataError(f"expected an object with \"id\" and \"{key}\"", file=str(path), line=number)
        ident, value = item["id"], item[key]
        if isinstance(ident, bool) or not isinstance(ident, int) or ident < 0:
            raise DataError(f"\"id\" must be a non-negative integer, got {ident!r}", file=str(path), line=number)
        if not isinstance(value, str):
            raise DataError(f"\"{key}\" must be a string, got {type(value).__name__}", file=str(path), line=number)
        if "#include" in value:
            from symlearn.logic.asp.program import find_include

            if find_include(value) is not None:  # clingo would read the named file into the facts
                raise DataError(f"\"{key}\" holds an #include directive", file=str(path), line=number,
                                hint="a state's facts and an action atom are plain facts; put shared rules "
                                     "in the background program")
        if ident in table:
            raise DataError(f"id {ident} appears twice (first on line {table[ident][1]})", file=str(path), line=number)
        if names is not None and "name" in item:
            if not isinstance(item["name"], str) or not item["name"]:
                raise DataError("\"name\" must be a non-empty string", file=str(path), line=number)
            names[ident] = item["name"]
        table[ident] = (value, number)
        if columns is not None:
            columns[ident] = _text_column(text, key)
    if not table:
        raise DataError("the file lists nothing", file=str(path))
    largest = max(table)  # the line to look at on a gap: usually a typo in the largest id
    if largest != len(table) - 1:  # ids are distinct and >= 0: a gap exactly when the largest is too large
        # the first missing id from the sorted ids, not from range(largest + 1): an id of 10^18
        # made that a set of 10^18 numbers (reported as the worker's memory limit)
        missing = next(i for i, ident in enumerate(sorted(table)) if ident != i)
        shown = str(largest) if largest < 10**20 else f"{str(largest)[:6]}... ({len(str(largest))} digits)"
        raise DataError(f"ids must be 0..{shown} without gaps; id {missing} is missing", file=str(path),
                        line=table[largest][1], hint=f"this line has id {shown}; ids count 0, 1, 2, ... in any order")
    return table


__all__ = ["FactGrounding", "Facts", "split_fact_groups", "split_facts"]
