"""Read and write the text format of the public reward-machines code (Toro Icarte et al.).

The format, one item per line::

    0                                         # initial state
    [2]                                       # terminal states (a Python-style list)
    (0,0,'!e&!n',ConstantRewardFunction(0))   # (from, to, 'guard', ConstantRewardFunction(reward))
    (0,1,'e&!g&!n',ConstantRewardFunction(0))
    (1,2,'g&!n',ConstantRewardFunction(1))

Guards use ``&``, ``|``, ``!`` over proposition names (single letters in the original code)
and ``True``/``False``. Some versions of that code omit the terminal-state line; then a state
is terminal when it has no outgoing transition, or only a ``True`` self-loop with reward 0.
We read the file with a small tokenizer (no ``eval``); ``#`` starts a comment. State numbers may
be any integers (``-1`` is common for a failure state); they are renumbered ``0..n-1`` in
increasing order and kept as state names when they differ from that numbering.

**Unmatched labels.** In the original code a label no transition of the current state matches
sends the machine to a terminal failure state with reward 0. With ``unmatched="terminal"``
(default) the import reproduces that with an explicit terminal state ``fail`` reached by the
uncovered labels; ``unmatched="stay"`` keeps symlearn's implicit self-loop instead.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from symlearn.errors import ModelError, ParseError, SymlearnError
from symlearn.logic.guards import Guard

_TOKEN = re.compile(r"""
    (?P<ws>\s+)
  | (?P<number>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)
  | (?P<string>'(?:[^'\\]|\\.)*'|"(?:[^"\\]|\\.)*")
  | (?P<name>[A-Za-z_]\w*)
  | (?P<punct>[()\[\]{},])
""", re.VERBOSE)


class _Line:
    """Tokens of one line with their 1-based columns; errors carry file, line and column."""

    def __init__(self, text: str, number: int, source: str | None) -> None:
        self.text, self.number, self.source = text, number, source
        self.tokens: list[tuple[str, str, int]] = []
        pos = 0
        while pos < len(text):
            match = _TOKEN.match(text, pos)
            if match is None:
                raise self.error(f"unexpected character {text[pos]!r}", pos + 1)
            if match.lastgroup != "ws":
                self.tokens.append((match.lastgroup, match.group(), pos + 1))
            pos = match.end()
        self.index = 0

    def error(self, message: str, column: int | None = None, hint: str | None = None) -> ParseError:
        return ParseError(message, file=self.source, line=self.number, column=column, hint=hint)

    def _here(self) -> int:
        if self.index < len(self.tokens):
            return self.tokens[self.index][2]
        return len(self.text.rstrip()) + 1

    def expect(self, kind: str, value: str | None = None, what: str | None = None) -> tuple[str, int]:
        what = what or (repr(value) if value else kind)
        if self.index >= len(self.tokens):
            raise self.error(f"expected {what} but the line ended", self._here())
        got_kind, got, column = self.tokens[self.index]
        if got_kind != kind or (value is not None and got != value):
            raise self.error(f"expected {what}, found {got!r}", column)
        self.index += 1
        return got, column

    def peek(self) -> str | None:
        return self.tokens[self.index][1] if self.index < len(self.tokens) else None

    def state(self) -> int:
        text, column = self.expect("number", what="a state number")
        if not re.fullmatch(r"[-+]?\d+", text):
            raise self.error(f"a state number must be an integer, found {text!r}", column)
        if len(text.lstrip("+-")) > 18:
            raise self.error(f"state number {text[:20]}... ({len(text):,} characters) is too large", column)
        return int(text)

    def end(self) -> None:
        if self.index < len(self.tokens):
            raise self.error(f"unexpected {self.tokens[self.index][1]!r} after the end of the item",
                             self.tokens[self.index][2])


def _strip_comment(line: str) -> str:
    # '#' inside a quoted guard is not a comment; guards never contain quotes themselves
    out, quote = [], None
    for ch in line:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch == "#":
            break
        out.append(ch)
    return "".join(out)


def parse_rm_text(text: str, *, source: str | None = None, unmatched: str = "terminal"):
    """Parse reward-machine text into a :class:`RewardMachine` (see the module docstring)."""
    from symlearn.logic.automata.reward_machine import RewardMachine

    if unmatched not in ("terminal", "stay"):
        raise ModelError(f"unknown unmatched policy {unmatched!r}", hint="use 'terminal' or 'stay'")
    lines = [(i + 1, _strip_comment(raw)) for i, raw in enumerate(text.splitlines())]
    lines = [(n, body) for n, body in lines if body.strip()]
    if not lines:
        raise ParseError("empty reward machine file: expected the initial state on the first line", file=source,
                         line=1, column=1)
    first = _Line(lines[0][1], lines[0][0], source)
    initial = first.state()
    first.end()

    terminal: list[int] | None = None
    rest = lines[1:]
    if rest and rest[0][1].lstrip()[:1] in "[{" or (rest and rest[0][1].strip() == "set()"):
        terminal = _terminal_list(_Line(rest[0][1], rest[0][0], source))
        rest = rest[1:]

    edges: list[tuple[int, int, Guard, float, _Line, int]] = []
    for number, body in rest:
        line = _Line(body, number, source)
        line.expect("punct", "(", "'(' starting a transition (u1, u2, 'guard', ConstantRewardFunction(r))")
        u1 = line.state()
        line.expect("punct", ",")
        u2 = line.state()
        line.expect("punct", ",")
        quoted, column = line.expect("string", what="a quoted guard such as '!a&b'")
        guard = _guard(quoted[1:-1], line, column + 1)
        line.expect("punct", ",")
        function, fcolumn = line.expect("name", what="ConstantRewardFunction(...)")
        if function != "ConstantRewardFunction":
            raise line.error(f"only ConstantRewardFunction rewards can be read, found {function!r}", fcolumn,
                             hint="other reward functions depend on the environment's state")
        line.expect("punct", "(")
        value, vcolumn = line.expect("number", what="a reward number")
        if not math.isfinite(float(value)):
            # 1e400 reads as inf; the machine refuses it later, but then without the line it came from
            raise line.error(f"reward {value} is too large: it reads as infinity", vcolumn,
                             hint="rewards are finite numbers (at most about 1.8e308)")
        line.expect("punct", ")")
        line.expect("punct", ")")
        line.end()
        earlier = next((e for e in edges if (e[0], e[1]) == (u1, u2)), None)
        if earlier is not None:
            # the public code stores one guard per (u1, u2): a second line silently replaced the first there
            raise line.error(f"a second transition from {u1} to {u2} (the first is on line {earlier[4].number}): "
                             "the public reward-machine code keeps only one guard and reward per pair of states",
                             1, hint="write one transition with the guards joined by '|'")
        if guard.is_false():
            continue  # 'False': never taken (the public code never matches it); the machine has no such edge
        edges.append((u1, u2, guard, float(value), line, column))

    ids = sorted({initial, *(terminal or ()), *(e[0] for e in edges), *(e[1] for e in edges)})
    index = {u: i for i, u in enumerate(ids)}
    names = None if ids == list(range(len(ids))) else [str(u) for u in ids]
    transitions: dict[int, list[tuple[Guard, int, float]]] = {}
    for u1, u2, guard, reward, line, column in edges:
        row = transitions.setdefault(index[u1], [])
        for other, target, _ in row:
            if target != index[u2] and other.intersects(guard):
                witness = sorted((other & guard).satisfying_label() or ())
                raise ModelError(f"transition from {u1} with guard {str(guard)!r} overlaps an earlier one from {u1} "
                                 f"(both match {{{', '.join(witness)}}})", file=source, line=line.number,
                                 column=column, hint="the guards leaving one state must be mutually exclusive")
        row.append((guard, index[u2], reward))

    if terminal is None:
        terminal = [u for u in ids if all(t == index[u] and g.is_true() and r == 0
                                          for g, t, r in transitions.get(index[u], []))]
    terminal_ids = {index[u] for u in terminal}
    alphabet = set().union(*(g.propositions for _, _, g, _, _, _ in edges))
    n_states = len(ids)
    if unmatched == "terminal":
        uncovered = {q: ~Guard.any_of(g for g, _, _ in transitions.get(q, [])) for q in range(n_states)
                     if q not in terminal_ids}
        uncovered = {q: g for q, g in uncovered.items() if not g.is_false()}
        if uncovered:
            fail = n_states
            n_states += 1
            for q, g in uncovered.items():
                transitions.setdefault(q, []).append((g, fail, 0.0))
            terminal_ids.add(fail)
            names = (names or [str(u) for u in ids]) + ["fail"]
    try:
        return RewardMachine(alphabet, n_states, index[initial], transitions, terminal_ids, (), names)
    except SymlearnError as exc:
        exc.file = exc.file or source
        raise


def _terminal_list(line: _Line) -> list[int]:
    if line.peek() == "set":
        line.expect("name")
        line.expect("punct", "(")
        line.expect("punct", ")")
        line.end()
        return []
    opening, column = line.expect("punct", what="'[' starting the list of terminal states")
    closing = {"[": "]", "{": "}"}.get(opening)
    if closing is None:
        raise line.error("expected '[' starting the list of terminal states", column)
    states = []
    while line.peek() != closing:
        states.append(line.state())
        if line.peek() == ",":
            line.expect("punct", ",")
        elif line.peek() != closing:
            line.expect("punct", closing, f"',' or {closing!r}")
    line.expect("punct", closing)
    line.end()
    return states


def _guard(text: str, line: _Line, column: int) -> Guard:
    try:
        return Guard.parse(text)
    except SymlearnError as exc:
        inner = (exc.column or 1) - 1
        raise line.error(exc.message, column + inner, exc.hint) from None


def read_rm_text(path: str | Path, *, unmatched: str = "terminal"):
    """Read a reward-machine text file."""
    from symlearn.input_limits import read_input_text

    return parse_rm_text(read_input_text(path), source=str(path), unmatched=unmatched)


def to_rm_text(rm) -> str:
    """Write ``rm`` in the public code's format: DNF guards without spaces, ``True`` for true.

    The public code evaluates guards letter by letter, so it understands only single-letter
    proposition names; longer names are written as they are. States keep the numbers they were
    read with (the reader keeps a file's own numbers, ``-1`` for a failure state, as state names),
    so text -> JSON -> text gives the file's numbering back; other names are numbered ``0..n-1``.
    """
    fail = _implicit_fail(rm)
    number = _state_numbers(rm, skip=fail)
    lines = [number[rm.initial], "[" + ", ".join(number[q] for q in sorted(rm.terminal, key=int) if q != fail) + "]"]
    for source, guard, target, reward in rm.edges():
        if fail is not None and fail in (source, target):
            continue  # the reader sends every label no transition matches there again
        if guard.is_true():
            text = "True"
        else:
            text = "|".join("&".join(("" if v else "!") + n for n, v in sorted(cube.items()))
                            for cube in guard.cubes())
        value = int(reward) if float(reward).is_integer() else reward
        lines.append(f"({number[source]},{number[target]},'{text}',ConstantRewardFunction({value}))")
    return "\n".join(lines) + "\n"


def _implicit_fail(rm) -> int | None:
    """The state ``fail`` the reader added for labels no transition of a file matched, or None.

    Written out, it became a numbered state of its own and the file's numbers were lost (a file of
    states 0..3 and -5 came back as 0..5); left implicit, reading the text again rebuilds it. Only
    where re-reading rebuilds exactly it: the last state, named ``fail``, terminal, entered with
    reward 0 and left by no edge, and every other non-terminal state's guards covering every label."""
    names = rm.state_names
    fail = rm.n_states - 1
    if not names or names[fail] != "fail" or fail not in rm.terminal or fail == rm.initial:
        return None
    edges = list(rm.edges())
    if any((t == fail and r != 0) or (s == fail and t != fail) for s, _, t, r in edges):
        return None
    for q in range(fail):
        if q not in rm.terminal and not Guard.any_of(g for s, g, _, _ in edges if s == q).is_true():
            return None
    return fail


def _state_numbers(rm, skip: int | None = None) -> list[str]:
    """The text's number of each state: its name where every name is a distinct integer in
    increasing state order (the order the reader numbers them in), else its index (``skip``, the
    implicit failure state, is not written)."""
    names = rm.state_names
    if skip is not None and names:
        kept = _state_numbers(_Named(names[:skip] + names[skip + 1:]))
        return kept[:skip] + ["fail"] + kept[skip:]  # never written: no edge or list names it
    if names and all(re.fullmatch(r"[-+]?\d{1,18}", n) for n in names):
        values = [int(n) for n in names]
        if all(a < b for a, b in zip(values, values[1:])):
            return [str(v) for v in values]
    return [str(q) for q in range(rm.n_states)]


class _Named:
    """Just the state names, for :func:`_state_numbers` on a machine with a state left out."""

    def __init__(self, names: list[str]) -> None:
        self.state_names, self.n_states = names, len(names)
