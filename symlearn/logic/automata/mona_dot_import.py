"""Read the Graphviz DOT that MONA (``mona -gw``) and LTLf2DFA write for a DFA.

Both come from MONA and share its layout: one statement per line, accepting states listed after
``node [shape = doublecircle];``, others after ``node [shape = circle];`` (and, in raw MONA
output, "don't-care" states after ``node [shape = box];``, which we treat as rejecting), an
invisible ``init`` node with ``init -> q;`` and edges ``p -> q [label="..."];``. A state listed
under two shapes keeps the first, as Graphviz does. The two differ in what matters:

* **LTLf2DFA** (``LTLfParser()(f).to_dfa()``): MONA's extra initial state 0 is already removed
  and the initial state is 1. Labels are Boolean expressions over the proposition names as
  sympy prints them: ``~`` for negation, ``&``, ``|``, parentheses, ``true``/``false``.
* **raw MONA**: state 0 is MONA's technical initial state; its single edge reads one
  don't-care symbol (``"X\\nX"``) into the real initial state, and we drop it (like LTLf2DFA)
  when it has exactly that shape. Labels give one line (``\\n``) per free variable, in the
  order MONA declares them, each with one character per alternative (``0``, ``1``, ``X`` =
  either; alternatives separated by spaces or commas); the DOT text does not name the
  variables, so pass ``variables=[...]`` (MONA prints them as "DFA for formula with free
  variables: ..."), else they are called ``v1..vk``.

The DOT that symlearn itself writes (``DFA.to_dot``, ``automaton convert X.dot``) reads back too:
its start marker is ``__start -> q;`` and each state has a statement of its own (``1 [label="1",
shape=doublecircle];``); guards are our own syntax, which the expression reader takes. What the
drawing does not show is lost: propositions no guard mentions leave the alphabet, and state names
become the state numbers.

States are renumbered ``0..n-1`` in increasing MONA order and keep their MONA numbers as
state names. A state must be declared in a node list or have edges of its own (LTLf2DFA lists
only some states, and MONA's automata are complete): an edge or ``init ->`` naming a state that
is neither, a typo in a hand-edited file, is refused at its line instead of silently creating a
dead-end state. The reader is a line parser (no ``eval``, no Graphviz); problems raise
:class:`~symlearn.errors.ParseError` with the line and column.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

from symlearn.errors import ParseError, SymlearnError
from symlearn.logic.guards import Guard

_HEADER = re.compile(r"\s*digraph\s+(\w+)?\s*\{\s*$")
# quoted strings may hold escaped quotes and ']' (symlearn.rendering.quote writes \" for a quoted
# proposition, and such a DOT file was refused at its first edge)
_ATTRS = r'(?:[^\]"]|"(?:[^"\\]|\\.)*")*'  # attributes up to ']', quoted strings whole
_ATTRIBUTE = re.compile(r"\s*(\w+\s*=\s*(\"(?:[^\"\\]|\\.)*\"|[\w.]+)\s*;\s*)+$")  # one or more graph attributes
_DEFAULTS = re.compile(r"\s*(node|edge|graph)\s*\[(?P<attrs>" + _ATTRS + r")\]\s*;(?P<states>(\s*\w+\s*;)*)\s*$")
# the start marker: MONA's and LTLf2DFA's ``init``, or ``__start`` in the DOT symlearn writes
_INIT_NODE = re.compile(r"\s*(init|__start)\s*\[" + _ATTRS + r"\]\s*;\s*$")
_INIT_EDGE = re.compile(r"\s*(init|__start)\s*->\s*(?P<target>\d+)\s*;\s*$")
_EDGE = re.compile(r"\s*(?P<source>\d+)\s*->\s*(?P<target>\d+)\s*\[\s*label\s*=\s*\"(?P<label>(?:[^\"\\]|\\.)*)\"\s*"
                   r"(,(?:[^\]\"]|\"(?:[^\"\\]|\\.)*\")*)?\]\s*;\s*$")
# one state with its own attributes, as symlearn writes them: ``1 [label="1", shape=doublecircle];``
_NODE = re.compile(r"\s*(?P<state>\d+)\s*\[(?P<attrs>" + _ATTRS + r")\]\s*;\s*$")
_SHAPE = re.compile(r"shape\s*=\s*(\w+)")
_BITS = re.compile(r"[01X ,]+(\\n[01X ,]+)*")


def parse_mona_dot(text: str, *, source: str | None = None, variables: Sequence[str] | None = None,
                   dialect: str = "auto"):
    """A :class:`~symlearn.logic.automata.dfa.DFA` from MONA/LTLf2DFA DOT text.

    ``dialect`` is ``ltlf2dfa``, ``mona`` or ``auto`` (raw MONA when ``init`` points to state 0
    and the labels are bit columns).
    """
    from symlearn.logic.automata.dfa import DFA

    if dialect not in ("auto", "ltlf2dfa", "mona"):
        raise ParseError(f"unknown MONA DOT dialect {dialect!r}", hint="use 'auto', 'ltlf2dfa' or 'mona'")
    shape: dict[int, str] = {}
    edges: list[tuple[int, int, str, int, int]] = []  # source, target, label, line, label column
    initial = None
    initial_at: tuple[int, str] | None = None
    seen_header = seen_end = False
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if seen_end:
            raise _error("text after the closing '}'", source, number, line)
        if not seen_header:
            if not _HEADER.match(line):
                raise _error("expected 'digraph NAME {' opening the automaton", source, number, line)
            seen_header = True
            continue
        if stripped == "}":
            seen_end = True
            continue
        if match := _EDGE.match(line):
            label_column = match.start("label") + 1
            edges.append((_state(match["source"], source, number, line), _state(match["target"], source, number, line),
                          re.sub(r'\\(["\\])', r"\1", match["label"]), number, label_column))
        elif match := _INIT_EDGE.match(line):
            if initial is not None:
                raise _error("a second 'init ->' edge: the automaton has one initial state", source, number, line)
            initial = _state(match["target"], source, number, line)
            initial_at = (number, line)
        elif match := _DEFAULTS.match(line):
            found = _SHAPE.search(match["attrs"])
            if found and match["states"]:
                for state in re.findall(r"\w+", match["states"]):
                    if not state.isdigit():
                        raise _error(f"state {state!r} is not a number", source, number, line, state)
                    shape.setdefault(_state(state, source, number, line), found.group(1))
        elif match := _NODE.match(line):
            found = _SHAPE.search(match["attrs"])
            shape.setdefault(_state(match["state"], source, number, line), found.group(1) if found else "circle")
        elif _INIT_NODE.match(line) or _ATTRIBUTE.match(line):
            continue
        else:
            raise _error("expected an edge 'p -> q [label=\"...\"];', a node list, 'init -> q;' or an attribute",
                         source, number, line)
    if not seen_header:
        raise ParseError("empty DOT text: expected 'digraph MONA_DFA {'", file=source, line=1, column=1)
    if not seen_end:
        raise ParseError("the DOT text ends before the closing '}'", file=source,
                         line=len(text.splitlines()) or 1, hint="the file may be truncated")
    if initial is None:
        raise ParseError("no 'init -> q;' edge, so the initial state is unknown", file=source)

    raw = dialect == "mona" or (dialect == "auto" and initial == 0 and edges
                                and all(_BITS.fullmatch(label) for _, _, label, _, _ in edges))
    guards = _bit_guards(edges, variables, source) if raw else _expression_guards(edges, source)
    known = set(shape) | {e[0] for e in edges}
    if initial not in known:
        number, line = initial_at
        raise _error(f"'init ->' names state {initial}, which is neither declared in a node list nor has edges",
                     source, number, line, str(initial))
    for s, t, _, number, _ in edges:
        if t not in known:
            raise ParseError(f"the edge {s} -> {t} names state {t}, which is neither declared in a node list nor "
                             "has edges of its own", file=source, line=number,
                             column=_column_of_state(text.splitlines()[number - 1].split("->", 1)[1], t)
                             + len(text.splitlines()[number - 1].split("->", 1)[0]) + 2,
                             hint="fix the state number, or declare it in 'node [shape = circle]; ...;'")

    if raw:
        leaving = [(t, g) for (s, t, _, _, _), g in zip(edges, guards) if s == initial]
        if len(leaving) == 1 and leaving[0][1].is_true() and shape.get(initial) != "doublecircle":
            dropped, initial = initial, leaving[0][0]
            keep = [(e, g) for e, g in zip(edges, guards) if e[0] != dropped]
            edges, guards = [e for e, _ in keep], [g for _, g in keep]
            shape.pop(dropped, None)
            if any(e[1] == dropped for e in edges):
                raise ParseError("MONA's initial state 0 has incoming edges; cannot drop it", file=source)
    states = sorted({initial, *shape, *(e[0] for e in edges), *(e[1] for e in edges)})
    index = {q: i for i, q in enumerate(states)}
    transitions: dict[int, list] = {}
    alphabet: set[str] = set(variables or ())
    for (s, t, _, _, _), g in zip(edges, guards):
        transitions.setdefault(index[s], []).append((g, index[t]))
        alphabet |= g.propositions
    accepting = [index[q] for q in states if shape.get(q) == "doublecircle"]
    try:
        return DFA(alphabet, len(states), index[initial], accepting, transitions, [str(q) for q in states])
    except SymlearnError as exc:
        exc.file = exc.file or source
        raise


def _column_of_state(line: str, state: int) -> int:
    found = re.search(rf"(?<!\d){state}(?!\d)", line)
    return found.start() + 1 if found else 1


def _expression_guards(edges, source) -> list[Guard]:
    guards = []
    for _, _, label, number, column in edges:
        try:
            guards.append(Guard.parse(label))
        except SymlearnError as exc:
            hint = exc.hint
            if re.search(r" / -?[\d.]", label):
                # 'guard / number': the drawing `automaton convert` writes of a reward machine or a PDFA
                hint = ("this is a drawing of a reward machine or PDFA (guard / reward or probability labels), "
                        "which is not read back: read the automaton from its .json (or reward-machine .txt)")
            raise ParseError(f"edge label: {exc.message}", file=source, line=number,
                             column=column + (exc.column or 1) - 1, hint=hint) from None
    return guards


def _bit_guards(edges, variables, source) -> list[Guard]:
    guards = []
    for _, _, label, number, column in edges:
        rows = [re.split(r"[ ,]", row.strip()) for row in label.split("\\n")]
        names = list(variables) if variables is not None else [f"v{i + 1}" for i in range(len(rows))]
        if len(rows) != len(names):
            raise ParseError(f"edge label has {len(rows)} variable rows but {len(names)} variables were given",
                             file=source, line=number, column=column)
        width = len(rows[0])
        if any(len(row) != width for row in rows):
            raise ParseError("edge label rows have different numbers of alternatives", file=source, line=number,
                             column=column)
        guard = Guard.false()
        for k in range(width):
            cube = {}
            for name, row in zip(names, rows):
                if row[k] in ("0", "1"):
                    cube[name] = row[k] == "1"
                elif row[k] != "X":
                    raise ParseError(f"bad bit {row[k]!r} in edge label (expected 0, 1 or X)", file=source,
                                     line=number, column=column)
            guard = guard | Guard.cube(cube)
        guards.append(guard)
    return guards


def _state(text: str, source, number: int, line: str) -> int:
    """A state number of at most 18 digits (MONA numbers its states from 0; a longer one is no
    state of a file we could read, and Python refuses to convert one of more than 4300 digits)."""
    if len(text) > 18:
        raise _error(f"state number {text[:20]}... ({len(text):,} digits) is too large", source, number, line, text)
    return int(text)


def _error(message: str, source, number: int, line: str, near: str | None = None) -> ParseError:
    column = (line.find(near) if near else len(line) - len(line.lstrip())) + 1
    return ParseError(message, file=source, line=number, column=column)


def read_mona_dot(path: str | Path, *, variables: Sequence[str] | None = None, dialect: str = "auto"):
    """Read a DOT file written by MONA or LTLf2DFA."""
    from symlearn.input_limits import read_input_text

    return parse_mona_dot(read_input_text(path), source=str(path), variables=variables,
                          dialect=dialect)
