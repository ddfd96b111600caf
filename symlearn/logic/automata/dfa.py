"""Deterministic finite automata over a proposition alphabet, with guarded edges.

A letter is a *label*: the set of propositions true at one step. A DFA never lists letters;
each edge carries a :class:`~symlearn.logic.guards.Guard`, and edges leaving one state must not
overlap (checked on construction, :class:`~symlearn.errors.ModelError` otherwise). A DFA may be
partial: a label no edge matches rejects the word (``step`` returns ``None``); :meth:`DFA.complete`
adds an explicit rejecting sink.

>>> from symlearn.logic.guards import Guard
>>> a = Guard.var("a")
>>> eventually_a = DFA({"a"}, 2, 0, [1], {0: [(~a, 0), (a, 1)], 1: [(Guard.true(), 1)]})
>>> eventually_a.accepts([set(), {"a"}]), eventually_a.accepts([set()])
(True, False)
>>> eventually_a.shortest_accepted()
[frozenset({'a'})]

Edges to the same target are merged into one guard and ordered canonically, so two DFAs built
from the same transition function compare ``==``. Objects are immutable; every operation
returns a new DFA. The algorithms live in :mod:`symlearn.logic.automata.operations`.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import AbstractSet

from symlearn.errors import ModelError
from symlearn.logic.guards import Guard

Label = AbstractSet[str]
Word = Sequence[Label]


def as_guard(value: Guard | str | bool) -> Guard:
    """Accept guards as :class:`Guard`, guard text or a bool constant."""
    if isinstance(value, Guard):
        return value
    if isinstance(value, bool):
        return Guard.true() if value else Guard.false()
    if isinstance(value, str):
        return Guard.parse(value)
    raise ModelError(f"an edge guard must be a Guard or guard text, not {type(value).__name__}")


def normalise_edges(
    n_states: int, transitions: Mapping[int, Sequence[tuple]], alphabet: frozenset[str], what: str = "DFA"
) -> tuple[tuple[tuple[Guard, int], ...], ...]:
    """Validate and canonicalise ``{state: [(guard, target), ...]}`` (merging per target)."""
    if not isinstance(transitions, Mapping):
        raise ModelError(f"{what} transitions must map each state to a list of (guard, target) pairs")
    merged: list[dict[int, Guard]] = [{} for _ in range(n_states)]
    for source, edges in transitions.items():
        check_state(source, n_states, f"{what} transition source")
        for edge in edges:
            if not isinstance(edge, (tuple, list)) or len(edge) != 2:
                raise ModelError(f"{what} edge {edge!r} from state {source} is not a (guard, target) pair")
            guard, target = as_guard(edge[0]), edge[1]
            check_state(target, n_states, f"{what} transition target (from state {source})")
            unknown = guard.propositions - alphabet
            if unknown:
                raise ModelError(
                    f"{what} guard {str(guard)!r} on state {source} uses {sorted(unknown)} outside the alphabet "
                    f"{sorted(alphabet)}", hint="add the propositions to the alphabet")
            if not guard.is_false():
                row = merged[source]
                row[target] = row[target] | guard if target in row else guard
    result = []
    for source, row in enumerate(merged):
        items = sorted(((g, t) for t, g in row.items()), key=lambda e: e[0].sort_key)
        check_deterministic(source, items, what)
        result.append(tuple(items))
    return tuple(result)


def check_deterministic(source: int, edges: Sequence[tuple], what: str = "DFA") -> None:
    """Raise :class:`ModelError` if two edges of ``source`` share a label (targets differ)."""
    for i, first in enumerate(edges):
        for second in edges[i + 1:]:
            overlap = first[0] & second[0]
            if not overlap.is_false():
                witness = sorted(overlap.satisfying_label() or ())
                raise ModelError(
                    f"{what} is not deterministic: from state {source}, guards {str(first[0])!r} (to {first[1]}) "
                    f"and {str(second[0])!r} (to {second[1]}) both match the label {{{', '.join(witness)}}}",
                    hint="make the guards of one state mutually exclusive")


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


class DFA:
    """A deterministic finite automaton with states ``0..n_states-1`` and guarded edges."""

    __slots__ = ("alphabet", "n_states", "initial", "accepting", "state_names", "_edges")

    def __init__(
        self,
        alphabet: Iterable[str],
        n_states: int,
        initial: int,
        accepting: Iterable[int],
        transitions: Mapping[int, Sequence[tuple[Guard | str, int]]],
        state_names: Sequence[str] | None = None,
    ) -> None:
        if isinstance(n_states, bool) or not isinstance(n_states, int) or n_states < 1:
            raise ModelError(f"a DFA needs at least one state, got n_states={n_states!r}")
        alphabet = check_alphabet(alphabet)
        set_ = object.__setattr__
        set_(self, "alphabet", alphabet)
        set_(self, "n_states", n_states)
        set_(self, "initial", check_state(initial, n_states, "initial state"))
        set_(self, "accepting", frozenset(check_state(q, n_states, "accepting state") for q in accepting))
        set_(self, "_edges", normalise_edges(n_states, transitions, alphabet))
        if state_names is not None:
            state_names = tuple(str(n) for n in state_names)
            if len(state_names) != n_states:
                raise ModelError(f"{len(state_names)} state names for {n_states} states")
        set_(self, "state_names", state_names)

    def __setattr__(self, name, value):
        raise AttributeError("DFA is immutable")

    @classmethod
    def _trusted(cls, alphabet, n_states, initial, accepting, edges, state_names=None) -> DFA:
        """Build from already canonical edges (internal: skips validation)."""
        dfa = object.__new__(cls)
        set_ = object.__setattr__
        set_(dfa, "alphabet", frozenset(alphabet))
        set_(dfa, "n_states", n_states)
        set_(dfa, "initial", initial)
        set_(dfa, "accepting", frozenset(accepting))
        set_(dfa, "_edges", tuple(tuple(sorted(row, key=lambda e: e[0].sort_key)) for row in edges))
        set_(dfa, "state_names", None if state_names is None else tuple(state_names))
        return dfa

    # -- structure --------------------------------------------------------------------------
    @property
    def transitions(self) -> dict[int, list[tuple[Guard, int]]]:
        """``{state: [(guard, target), ...]}`` as accepted by the constructor."""
        return {q: list(row) for q, row in enumerate(self._edges)}

    def successors(self, state: int) -> tuple[tuple[Guard, int], ...]:
        return self._edges[state]

    def edges(self) -> Iterator[tuple[int, Guard, int]]:
        """Every edge as ``(source, guard, target)``."""
        for source, row in enumerate(self._edges):
            for guard, target in row:
                yield source, guard, target

    @property
    def n_edges(self) -> int:
        return sum(len(row) for row in self._edges)

    @property
    def states(self) -> range:
        return range(self.n_states)

    def name(self, state: int) -> str:
        return self.state_names[state] if self.state_names else str(state)

    def is_accepting(self, state: int) -> bool:
        return state in self.accepting

    def is_complete(self) -> bool:
        return all(Guard.any_of(g for g, _ in row).is_true() for row in self._edges)

    # -- running ----------------------------------------------------------------------------
    def step(self, state: int, label: Label) -> int | None:
        """The successor of ``state`` under ``label``, or ``None`` if no edge matches."""
        for guard, target in self._edges[state]:
            if guard.evaluate(label):
                return target
        return None

    def run(self, word: Word, start: int | None = None) -> list[int]:
        """States visited reading ``word``: ``[start, q1, ...]``.

        The list stops early (is shorter than ``len(word) + 1``) where no edge matches.
        """
        state = self.initial if start is None else start
        visited = [state]
        for label in word:
            state = self.step(state, label)
            if state is None:
                break
            visited.append(state)
        return visited

    def accepts(self, word: Word) -> bool:
        visited = self.run(word)
        return len(visited) == len(word) + 1 and visited[-1] in self.accepting

    __call__ = accepts

    # -- algorithms (see operations.py) -------------------------------------------------------
    def complete(self) -> DFA:
        """The same language with a total transition function (adds a rejecting sink if needed)."""
        from symlearn.logic.automata.operations import complete

        return complete(self)

    def reachable_states(self) -> frozenset[int]:
        from symlearn.logic.automata.operations import reachable_states

        return reachable_states(self)

    def live_states(self) -> frozenset[int]:
        """States from which an accepting state can be reached."""
        from symlearn.logic.automata.operations import live_states

        return live_states(self)

    def minimize(self) -> DFA:
        """The minimal *complete* DFA of the language, states numbered canonically (BFS order)."""
        from symlearn.logic.automata.operations import minimize

        return minimize(self)

    def trim(self) -> DFA:
        """Drop unreachable states and states that cannot reach acceptance (partial result)."""
        from symlearn.logic.automata.operations import trim

        return trim(self)

    def product(self, other: DFA, mode: str = "and", max_states: int | None = None) -> DFA:
        """Synchronous product; ``mode`` is ``and``, ``or``, ``xor`` or ``minus``."""
        from symlearn.logic.automata.operations import product

        return product(self, other, mode, max_states=max_states)

    def intersection(self, other: DFA) -> DFA:
        return self.product(other, "and")

    def union(self, other: DFA) -> DFA:
        return self.product(other, "or")

    def difference(self, other: DFA) -> DFA:
        return self.product(other, "minus")

    __and__ = intersection
    __or__ = union
    __sub__ = difference

    def complement(self) -> DFA:
        from symlearn.logic.automata.operations import complement

        return complement(self)

    __invert__ = complement

    def is_empty(self) -> bool:
        return self.shortest_accepted() is None

    def is_universal(self) -> bool:
        return self.shortest_rejected() is None

    def shortest_accepted(self, start: int | None = None) -> list[frozenset[str]] | None:
        """A shortest accepted word (from ``start``, default initial), or ``None`` if there is none."""
        from symlearn.logic.automata.operations import shortest_word

        return shortest_word(self, self.accepting, start)

    def shortest_rejected(self, start: int | None = None) -> list[frozenset[str]] | None:
        from symlearn.logic.automata.operations import shortest_rejected

        return shortest_rejected(self, start)

    def equivalent(self, other: DFA) -> tuple[bool, list[frozenset[str]] | None]:
        """``(True, None)`` if the languages are equal, else ``(False, word)`` with a shortest
        word accepted by exactly one of them."""
        from symlearn.logic.automata.operations import equivalent

        return equivalent(self, other)

    def rename_states(self, names: Sequence[str] | None) -> DFA:
        if names is not None and len(names) != self.n_states:
            raise ModelError(f"{len(names)} state names for {self.n_states} states")
        return DFA._trusted(self.alphabet, self.n_states, self.initial, self.accepting, self._edges, names)

    def with_alphabet(self, alphabet: Iterable[str]) -> DFA:
        """The same automaton over a larger alphabet (the language ignores the new propositions)."""
        alphabet = check_alphabet(alphabet)
        if not self.alphabet <= alphabet:
            raise ModelError(f"cannot drop propositions {sorted(self.alphabet - alphabet)} from the alphabet")
        return DFA._trusted(alphabet, self.n_states, self.initial, self.accepting, self._edges, self.state_names)

    # -- formats ----------------------------------------------------------------------------
    def to_dot(self, title: str | None = None, *, unicode: bool = False) -> str:
        from symlearn.logic.automata.dot_export import dfa_to_dot

        return dfa_to_dot(self, title=title, unicode=unicode)

    def render(self, path: str | Path) -> Path:
        """Draw to ``.svg``/``.png``/``.pdf`` with Graphviz."""
        from symlearn.rendering import render_dot

        return render_dot(self.to_dot(), path)

    def _repr_svg_(self) -> str | None:
        from symlearn.rendering import dot_to_svg_text

        return dot_to_svg_text(self.to_dot())

    def to_hoa(self, name: str | None = None) -> str:
        from symlearn.logic.automata.hoa_export import to_hoa

        return to_hoa(self, name=name)

    def to_dict(self) -> dict:
        from symlearn.logic.automata.json_format import dfa_to_dict

        return dfa_to_dict(self)

    def to_json(self) -> str:
        from symlearn.logic.automata.json_format import dumps

        return dumps(self.to_dict())

    @classmethod
    def from_dict(cls, document: Mapping, *, source: str | None = None) -> DFA:
        from symlearn.logic.automata.json_format import dfa_from_dict

        return dfa_from_dict(document, source=source)

    @classmethod
    def from_json(cls, text: str | Mapping, *, source: str | None = None) -> DFA:
        from symlearn.logic.automata.json_format import loads

        document = text if isinstance(text, Mapping) else loads(text, source=source)
        return cls.from_dict(document, source=source)

    def save(self, path: str | Path) -> Path:
        from symlearn.atomic import write_text

        return write_text(path, self.to_json())

    @classmethod
    def load(cls, path: str | Path) -> DFA:
        text = Path(path).read_text(encoding="utf-8")
        return cls.from_json(text, source=str(path))

    # -- identity ---------------------------------------------------------------------------
    def _key(self) -> tuple:
        return (self.alphabet, self.n_states, self.initial, self.accepting, self._edges, self.state_names)

    def __eq__(self, other: object) -> bool:
        """Structural equality (same numbering, guards, names); see :meth:`equivalent` for languages."""
        return isinstance(other, DFA) and type(other) is type(self) and other._key() == self._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def same_structure(self, other: DFA) -> bool:
        """Structural equality ignoring state names."""
        return (self.alphabet, self.n_states, self.initial, self.accepting, self._edges) == (
            other.alphabet, other.n_states, other.initial, other.accepting, other._edges)

    def __repr__(self) -> str:
        return (f"DFA({self.n_states} states, {self.n_edges} edges, alphabet {sorted(self.alphabet)}, "
                f"initial {self.initial}, accepting {sorted(self.accepting)})")
