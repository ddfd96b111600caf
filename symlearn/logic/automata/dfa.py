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

from collections.abc import Iterable, Mapping, Sequence
from typing import AbstractSet

from symlearn.errors import ModelError
from symlearn.logic.automata.base import (
    GuardedAutomaton, as_guard, check_alphabet, check_deterministic, check_n_states, check_names, check_state,
)
from symlearn.logic.guards import Guard

Label = AbstractSet[str]
Word = Sequence[Label]


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


class DFA(GuardedAutomaton):
    """A deterministic finite automaton with states ``0..n_states-1`` and guarded edges."""

    __slots__ = ("alphabet", "n_states", "initial", "accepting", "state_names", "_edges")
    _what = "DFA"

    def __init__(
        self,
        alphabet: Iterable[str],
        n_states: int,
        initial: int,
        accepting: Iterable[int],
        transitions: Mapping[int, Sequence[tuple[Guard | str, int]]],
        state_names: Sequence[str] | None = None,
    ) -> None:
        n_states = check_n_states(n_states, "DFA")
        alphabet = check_alphabet(alphabet)
        self._init_fields(
            alphabet=alphabet,
            n_states=n_states,
            initial=check_state(initial, n_states, "initial state"),
            accepting=frozenset(check_state(q, n_states, "accepting state") for q in accepting),
            _edges=normalise_edges(n_states, transitions, alphabet),
            state_names=check_names(state_names, n_states),
        )

    @classmethod
    def _trusted(cls, alphabet, n_states, initial, accepting, edges, state_names=None) -> DFA:
        """Build from already canonical edges (internal: skips validation)."""
        dfa = object.__new__(cls)
        dfa._init_fields(alphabet=frozenset(alphabet), n_states=n_states, initial=initial,
                         accepting=frozenset(accepting),
                         _edges=tuple(tuple(sorted(row, key=lambda e: e[0].sort_key)) for row in edges),
                         state_names=None if state_names is None else tuple(state_names))
        return dfa

    # -- structure (states, edges, successors, transitions, n_edges, name: see GuardedAutomaton)
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

    def to_hoa(self, name: str | None = None, *, encoding: str = "alive") -> str:
        """HOA text; HOA has no finite-word acceptance, so ``encoding`` says how the DFA is
        encoded (``alive``: Spot's LTLf convention, the default; ``final-marks``), see
        :mod:`symlearn.logic.automata.hoa_export`."""
        from symlearn.logic.automata.hoa_export import to_hoa

        return to_hoa(self, name=name, encoding=encoding)

    def to_dict(self) -> dict:
        from symlearn.logic.automata.json_format import dfa_to_dict

        return dfa_to_dict(self)

    @classmethod
    def from_dict(cls, document: Mapping, *, source: str | None = None) -> DFA:
        from symlearn.logic.automata.json_format import dfa_from_dict

        return dfa_from_dict(document, source=source)

    # -- identity ---------------------------------------------------------------------------
    def _key(self) -> tuple:
        return (self.alphabet, self.n_states, self.initial, self.accepting, self._edges, self.state_names)

    def same_structure(self, other: DFA) -> bool:
        """Structural equality ignoring state names."""
        return (self.alphabet, self.n_states, self.initial, self.accepting, self._edges) == (
            other.alphabet, other.n_states, other.initial, other.accepting, other._edges)

    def __repr__(self) -> str:
        return (f"DFA({self.n_states} states, {self.n_edges} edges, alphabet {sorted(self.alphabet)}, "
                f"initial {self.initial}, accepting {sorted(self.accepting)})")
