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

A DFA holds its transitions in one of two forms. *Explicit*: per state, guarded edges, as
given to the constructor. *Symbolic* (large automata from the LTLf translation, products and
minimisation of symbolic DFAs): a shared decision diagram per automaton whose leaves are
states (:mod:`~symlearn.logic.automata.transition_diagram`), always complete. Running, products,
minimisation, complement, emptiness, shortest words and equivalence work on the diagram
directly; ``successors``/``edges``/``transitions`` (DOT, JSON, ``explain``) produce guarded
edges on first use, refusing beyond
:data:`~symlearn.logic.automata.transition_diagram.MAX_MATERIALISED_EDGES` with a
:class:`~symlearn.errors.LimitExceededError` that says so. :meth:`DFA.is_symbolic` tells them
apart; :meth:`DFA.count_edges` counts edges without producing them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import AbstractSet

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata.base import (
    GuardedAutomaton, as_guard, check_alphabet, check_deterministic, check_n_states, check_names, check_state,
    names_text,
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
                    f"{what} guard {str(guard)!r} on state {source} uses {names_text(unknown)} outside the alphabet "
                    f"{names_text(alphabet)}", hint="add the propositions to the alphabet")
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

    __slots__ = ("alphabet", "n_states", "initial", "accepting", "state_names", "_explicit", "_diagram", "_roots")
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
            _explicit=normalise_edges(n_states, transitions, alphabet),
            state_names=check_names(state_names, n_states),
            _diagram=None, _roots=None,
        )

    @classmethod
    def _trusted(cls, alphabet, n_states, initial, accepting, edges, state_names=None, *, ordered=False) -> DFA:
        """Build from already canonical edges (internal: skips validation). ``ordered``: each
        row is in label_key order already (the translation sorts its rows to number the states,
        and sorting again cost a key lookup per edge)."""
        dfa = object.__new__(cls)
        dfa._init_fields(alphabet=frozenset(alphabet), n_states=n_states, initial=initial,
                         accepting=frozenset(accepting),
                         # a DFA state's guards are disjoint: label_key orders them as sort_key does
                         _explicit=(tuple(tuple(row) for row in edges) if ordered else
                                    tuple(tuple(sorted(row, key=lambda e: e[0].label_key)) for row in edges)),
                         state_names=None if state_names is None else tuple(state_names),
                         _diagram=None, _roots=None)
        return dfa

    @classmethod
    def _symbolic(cls, alphabet, n_states, initial, accepting, diagram, roots, state_names=None) -> DFA:
        """A complete DFA whose state ``q`` moves by ``diagram`` from ``roots[q]`` (internal)."""
        dfa = object.__new__(cls)
        dfa._init_fields(alphabet=frozenset(alphabet), n_states=n_states, initial=initial,
                         accepting=frozenset(accepting), _explicit=None, _diagram=diagram, _roots=tuple(roots),
                         state_names=None if state_names is None else tuple(state_names))
        return dfa

    # -- the two forms of transitions --------------------------------------------------------
    @property
    def _edges(self) -> tuple[tuple[tuple[Guard, int], ...], ...]:
        """Guarded edges per state, produced from the diagram on first use (symbolic DFAs)."""
        if self._explicit is None:
            from symlearn.logic.automata.transition_diagram import materialise

            rows = materialise(self._diagram, self._roots)
            object.__setattr__(self, "_explicit",
                               tuple(tuple(sorted(row, key=lambda e: e[0].label_key)) for row in rows))
        return self._explicit

    def is_symbolic(self) -> bool:
        """Whether the transitions are a decision diagram (edges only produced on demand)."""
        return self._diagram is not None

    def transition_diagram(self):
        """``(diagram, roots)`` of the *completed* DFA (:meth:`complete` adds a sink when needed;
        its state numbers then follow ``self.complete()``)."""
        if self._diagram is not None:
            return self._diagram, self._roots
        from symlearn.logic.automata.transition_diagram import from_guarded

        total = self.complete()
        return from_guarded(sorted(total.alphabet), [total.successors(q) for q in total.states])

    def count_edges(self, limit: int | None = None) -> int | None:
        """Number of guarded edges without producing them; ``None`` when above ``limit``."""
        if self._explicit is not None:
            n = sum(len(row) for row in self._explicit)
            return None if limit is not None and n > limit else n
        from symlearn.logic.automata.transition_diagram import count_edges

        return count_edges(self._diagram, self._roots, limit)

    @property
    def n_edges(self) -> int:
        if self._explicit is None:
            from symlearn.logic.automata.transition_diagram import MAX_MATERIALISED_EDGES, count_edges

            n = count_edges(self._diagram, self._roots, MAX_MATERIALISED_EDGES)
            if n is None:
                raise LimitExceededError(
                    f"this symbolic DFA ({self.n_states:,} states) has more than {MAX_MATERIALISED_EDGES:,} edges",
                    hint="count_edges(limit=None) counts them all (slowly); diagram_nodes() is the symbolic size")
            return n
        return sum(len(row) for row in self._explicit)

    def sink_states(self) -> frozenset[int]:
        """Rejecting states that every label keeps in place (in a minimal DFA: the dead state)."""
        if self._diagram is not None:
            return frozenset(q for q, root in enumerate(self._roots) if root == ~q and q not in self.accepting)
        return frozenset(q for q, row in enumerate(self._explicit)
                         if q not in self.accepting and len(row) == 1 and row[0][1] == q and row[0][0].is_true())

    def diagram_nodes(self) -> int | None:
        """Internal nodes of the transition diagram (``None`` for an explicit DFA)."""
        return None if self._diagram is None else len(self._diagram)

    # -- structure (states, edges, successors, transitions, n_edges, name: see GuardedAutomaton)
    def is_accepting(self, state: int) -> bool:
        return state in self.accepting

    def is_complete(self) -> bool:
        if self._diagram is not None:
            return True  # diagrams map every label somewhere
        return all(Guard.any_of(g for g, _ in row).is_true() for row in self._edges)

    # -- running ----------------------------------------------------------------------------
    def step(self, state: int, label: Label) -> int | None:
        """The successor of ``state`` under ``label``, or ``None`` if no edge matches."""
        if self._diagram is not None:
            return self._diagram.step(self._roots[state], label)
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
        if self._diagram is not None:
            return DFA._symbolic(self.alphabet, self.n_states, self.initial, self.accepting, self._diagram,
                                 self._roots, names)
        return DFA._trusted(self.alphabet, self.n_states, self.initial, self.accepting, self._edges, names)

    def with_alphabet(self, alphabet: Iterable[str]) -> DFA:
        """The same automaton over a larger alphabet (the language ignores the new propositions)."""
        alphabet = check_alphabet(alphabet)
        if not self.alphabet <= alphabet:
            raise ModelError(f"cannot drop propositions {sorted(self.alphabet - alphabet)} from the alphabet")
        if self._diagram is not None:  # the diagram keeps its own proposition list
            return DFA._symbolic(alphabet, self.n_states, self.initial, self.accepting, self._diagram,
                                 self._roots, self.state_names)
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

    def _transitions_equal(self, other: DFA) -> bool:
        if self._diagram is None and other._diagram is None:
            return self._explicit == other._explicit
        if not (self.is_complete() and other.is_complete()):
            return False  # symbolic DFAs are complete
        from symlearn.logic.automata.transition_diagram import canonical_form

        return canonical_form(*self.transition_diagram()) == canonical_form(*other.transition_diagram())

    def __eq__(self, other: object) -> bool:
        """Structural equality (same numbering, transitions, names), whichever form holds them."""
        return (type(other) is type(self) and (self.alphabet, self.n_states, self.initial, self.accepting,
                                               self.state_names)
                == (other.alphabet, other.n_states, other.initial, other.accepting, other.state_names)
                and self._transitions_equal(other))

    def __hash__(self) -> int:  # transitions left out: equal DFAs of the two forms must hash alike
        return hash((self.alphabet, self.n_states, self.initial, self.accepting, self.state_names))

    def same_structure(self, other: DFA) -> bool:
        """Structural equality ignoring state names."""
        return ((self.alphabet, self.n_states, self.initial, self.accepting)
                == (other.alphabet, other.n_states, other.initial, other.accepting)
                and self._transitions_equal(other))

    def __repr__(self) -> str:
        if self._explicit is None:
            return (f"DFA({self.n_states} states, symbolic transitions ({len(self._diagram)} diagram nodes), "
                    f"alphabet {sorted(self.alphabet)}, initial {self.initial}, accepting {len(self.accepting)} states)")
        return (f"DFA({self.n_states} states, {self.n_edges} edges, alphabet {sorted(self.alphabet)}, "
                f"initial {self.initial}, accepting {sorted(self.accepting)})")
