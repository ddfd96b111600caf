"""What every guarded automaton (DFA, PDFA, reward machine) shares.

Subclasses provide ``_edges``: one tuple per state of edges ``(guard, target, *extra)`` where
``extra`` is empty (DFA), a probability (PDFA) or a reward (reward machine); PDFAs and reward
machines store it, a DFA with symbolic transitions produces it on first use. They provide
``to_dict``/``from_dict``, ``to_dot`` and ``_key()`` (what equality compares); this base turns
those into JSON files, drawings, equality and immutability.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

from symlearn.errors import ModelError
from symlearn.logic.guards import Guard


class GuardedAutomaton:
    __slots__ = ()
    _what = "automaton"

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is immutable")

    def _init_fields(self, **fields) -> None:
        for name, value in fields.items():
            object.__setattr__(self, name, value)

    # -- structure --------------------------------------------------------------------------
    @property
    def states(self) -> range:
        return range(self.n_states)

    @property
    def n_edges(self) -> int:
        return sum(len(row) for row in self._edges)

    @property
    def transitions(self) -> dict[int, list[tuple]]:
        """``{state: [(guard, target, ...), ...]}`` as accepted by the constructor."""
        return {q: list(row) for q, row in enumerate(self._edges)}

    def successors(self, state: int) -> tuple[tuple, ...]:
        return self._edges[state]

    def edges(self):
        """Every edge as ``(source, guard, target, ...)``."""
        for source, row in enumerate(self._edges):
            for edge in row:
                yield (source, *edge)

    def name(self, state: int) -> str:
        return self.state_names[state] if self.state_names else str(state)

    # -- drawing and files ------------------------------------------------------------------
    def render(self, path: str | Path) -> Path:
        """Draw to ``.svg``/``.png``/``.pdf`` with Graphviz."""
        from symlearn.rendering import render_dot

        return render_dot(self.to_dot(), path)

    def _repr_svg_(self) -> str | None:
        from symlearn.rendering import dot_to_svg_text

        return dot_to_svg_text(self.to_dot())

    def to_json(self) -> str:
        """Versioned JSON text (see :mod:`symlearn.logic.automata.json_format`)."""
        from symlearn.logic.automata.json_format import dumps

        return dumps(self.to_dict())

    @classmethod
    def from_json(cls, text: str | Mapping, *, source: str | None = None):
        from symlearn.errors import SymlearnError
        from symlearn.logic.automata.json_format import located_in, loads

        if isinstance(text, Mapping):
            return cls.from_dict(text, source=source)
        document = loads(text, source=source)
        try:
            return cls.from_dict(document, source=source)
        except SymlearnError as exc:
            raise located_in(exc, text) from None

    def save(self, path: str | Path) -> Path:
        from symlearn.atomic import write_text

        return write_text(path, self.to_json())

    @classmethod
    def load(cls, path: str | Path):
        from symlearn.input_limits import read_input_text

        return cls.from_json(read_input_text(path), source=str(path))

    # -- identity ---------------------------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        """Structural equality (same numbering, guards, names, numbers)."""
        return type(other) is type(self) and other._key() == self._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __reduce__(self):  # copy and multiprocessing go through the JSON form (slots + immutability)
        return (type(self).from_dict, (self.to_dict(),))


def names_text(names: Iterable[str], limit: int = 20) -> str:
    """Sorted names as a list for a message, cut after ``limit`` (a 200,000-name alphabet made a
    2 MB error line)."""
    ordered = sorted(names)
    if len(ordered) <= limit:
        return str(ordered)
    return str(ordered[:limit])[:-1] + f", ... ({len(ordered):,} in all)]"


def check_n_states(n_states, what: str) -> int:
    if isinstance(n_states, bool) or not isinstance(n_states, int) or n_states < 1:
        raise ModelError(f"a {what} needs at least one state, got n_states={n_states!r}")
    return n_states


def check_names(state_names: Sequence[str] | None, n_states: int) -> tuple[str, ...] | None:
    if state_names is None:
        return None
    names = tuple(str(n) for n in state_names)
    if len(names) != n_states:
        raise ModelError(f"{len(names)} state names for {n_states} states")
    if len(set(names)) != len(names):  # two states one name: no output could tell them apart
        first: dict[str, int] = {}
        for q, name in enumerate(names):
            if name in first:
                raise ModelError(f"states {first[name]} and {q} are both named {name!r}",
                                 hint="state names must be unique")
            first[name] = q
    return names


def as_guard(value: Guard | str | bool) -> Guard:
    """Accept guards as :class:`Guard`, guard text or a bool constant."""
    if isinstance(value, Guard):
        return value
    if isinstance(value, bool):
        return Guard.true() if value else Guard.false()
    if isinstance(value, str):
        return Guard.parse(value)
    raise ModelError(f"an edge guard must be a Guard or guard text, not {type(value).__name__}")


def check_deterministic(source: int, edges: Sequence[tuple], what: str = "DFA") -> None:
    """Raise :class:`ModelError` if two edges of ``source`` share a label (targets differ).

    One pass: each guard is tested against the union of the guards before it, so the cost is
    linear in the number of edges (two BDD operations each), not quadratic in pairs; the pair
    that overlaps is searched only when the check fails, to name it in the message.
    """
    seen = Guard.false()
    for i, edge in enumerate(edges):
        guard = edge[0]
        if not (guard & seen).is_false():
            first = next(e for e in edges[:i] if not (e[0] & guard).is_false())
            overlap = first[0] & guard
            witness = sorted(overlap.satisfying_label() or ())
            raise ModelError(
                f"{what} is not deterministic: from state {source}, guards {str(first[0])!r} (to {first[1]}) "
                f"and {str(guard)!r} (to {edge[1]}) both match the label {{{', '.join(witness)}}}",
                hint="make the guards of one state mutually exclusive")
        seen = seen | guard


def check_state(state, n_states: int, what: str) -> int:
    if isinstance(state, bool) or not isinstance(state, int) or not 0 <= state < n_states:
        raise ModelError(f"{what} {state!r} is not a state (states are 0..{n_states - 1})")
    return state


def check_alphabet(alphabet: Iterable[str]) -> frozenset[str]:
    if isinstance(alphabet, str):
        raise ModelError(f"the alphabet must be a collection of proposition names, not the string {alphabet!r}")
    result = frozenset(alphabet)
    for name in result:
        if not isinstance(name, str) or not name:
            raise ModelError(f"proposition names must be non-empty strings, not {name!r}")
    return result


def weighted_edges(transitions: Mapping[int, Sequence[tuple]], n_states: int, alphabet: frozenset[str], what: str,
                   value_name: str, check_value) -> list[list[tuple[Guard, int, float]]]:
    """Validate ``{state: [(guard, target, value), ...]}`` of a PDFA or reward machine.

    Edges are kept as given (never merged: each carries its own number), sorted canonically and
    checked for overlaps; an edge with a false guard is dropped unless its value is non-zero,
    which is an error (it could never be taken).
    """
    if not isinstance(transitions, Mapping):
        raise ModelError(f"{what} transitions must map each state to a list of (guard, target, {value_name})")
    edges: list[list[tuple[Guard, int, float]]] = [[] for _ in range(n_states)]
    for source, row in transitions.items():
        check_state(source, n_states, f"{what} transition source")
        for edge in row:
            if not isinstance(edge, (tuple, list)) or len(edge) != 3:
                raise ModelError(f"{what} edge {edge!r} from state {source} is not (guard, target, {value_name})")
            guard = as_guard(edge[0])
            target = check_state(edge[1], n_states, f"{what} transition target (from state {source})")
            value = check_value(edge[2], f"{value_name} of edge {source} -> {target}")
            unknown = guard.propositions - alphabet
            if unknown:
                raise ModelError(f"{what} guard {str(guard)!r} on state {source} uses {names_text(unknown)} "
                                 f"outside the alphabet {names_text(alphabet)}",
                                 hint="add the propositions to the alphabet")
            if guard.is_false():
                if value != 0:
                    raise ModelError(f"edge {source} -> {target} has {value_name} {value} but its guard is false")
                continue
            edges[source].append((guard, target, value))
    for source, row in enumerate(edges):
        row.sort(key=lambda e: (e[0].sort_key, e[1]))
        check_deterministic(source, row, what)
    return edges
