"""Probabilistic DFAs: a guarded DFA with edge and termination probabilities.

In state ``q`` the process stops with probability ``termination[q]`` or takes edge ``e`` with
probability ``p(e)`` and emits a label satisfying the edge's guard. The probabilities leaving a
state (edges plus termination) must sum to 1 (:class:`~symlearn.errors.ModelError` naming the
state otherwise).

**Symbolic guards.** An edge's probability is the probability of its *guard class*, not of a
single label. :meth:`PDFA.probability` therefore gives the probability that a generated word
follows the same edges as ``word`` and stops at its end — for guards that are single letters
(cubes over the whole alphabet) that is the usual word probability. With
``per_label=True`` each step is additionally divided by the number of labels over the alphabet
that satisfy the guard, i.e. labels within a guard are taken as uniformly distributed, which
is exactly how :meth:`PDFA.sample` draws them with ``label_choice="uniform"``.

>>> from symlearn.logic.guards import Guard
>>> a = Guard.var("a")
>>> p = PDFA({"a"}, 2, 0, {0: [(a, 1, 0.5), (~a, 0, 0.5)], 1: [(Guard.true(), 1, 0.5)]}, [0.0, 0.5])
>>> p.probability([{"a"}]), p.probability([set(), {"a"}, {"a"}])
(0.25, 0.0625)
>>> p.most_probable_accepted()
([frozenset({'a'})], 0.25)
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable, Mapping, Sequence

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata.base import (
    GuardedAutomaton, check_alphabet, check_n_states, check_names, check_state, weighted_edges,
)
from symlearn.logic.automata.dfa import DFA, Word
from symlearn.logic.guards import Guard

TOLERANCE = 1e-9


class PDFA(GuardedAutomaton):
    """A probabilistic DFA with states ``0..n_states-1``; immutable."""

    __slots__ = ("alphabet", "n_states", "initial", "accepting", "termination", "state_names", "_edges")
    _what = "PDFA"

    def __init__(
        self,
        alphabet: Iterable[str],
        n_states: int,
        initial: int,
        transitions: Mapping[int, Sequence[tuple[Guard | str, int, float]]],
        termination: Sequence[float],
        accepting: Iterable[int] | None = None,
        state_names: Sequence[str] | None = None,
        *,
        tolerance: float = TOLERANCE,
    ) -> None:
        n_states = check_n_states(n_states, "PDFA")
        alphabet = check_alphabet(alphabet)
        termination = tuple(_probability(p, f"termination probability of state {q}")
                            for q, p in enumerate(termination))
        if len(termination) != n_states:
            raise ModelError(f"{len(termination)} termination probabilities for {n_states} states")
        edges = weighted_edges(transitions, n_states, alphabet, "PDFA", "probability", _probability)
        for source, row in enumerate(edges):
            total = sum(p for _, _, p in row) + termination[source]
            if abs(total - 1.0) > tolerance:
                raise ModelError(
                    f"PDFA state {source}: outgoing probabilities plus termination sum to {total:.6g}, not 1",
                    hint="normalise each state's edge and termination probabilities")
        accepting = (frozenset(q for q, p in enumerate(termination) if p > 0) if accepting is None
                     else frozenset(check_state(q, n_states, "accepting state") for q in accepting))
        self._init_fields(
            alphabet=alphabet, n_states=n_states, initial=check_state(initial, n_states, "initial state"),
            accepting=accepting, termination=termination, state_names=check_names(state_names, n_states),
            _edges=tuple(tuple(row) for row in edges))

    @classmethod
    def from_dfa(cls, dfa: DFA, termination: float = 0.2) -> PDFA:
        """A random walk on ``dfa``'s useful part that samples its language.

        Useless states (unreachable or unable to accept) are dropped. An accepting state stops
        with probability ``termination``; the rest is split over the edges in proportion to how
        many labels each guard matches, so with uniform labels every label is equally likely.
        """
        if not 0 < termination <= 1:
            raise ModelError(f"termination must be in (0, 1], got {termination}")
        useful = dfa.trim()
        if not useful.accepting:
            raise ModelError("the DFA accepts no word, so there is nothing to sample")
        transitions, stops = {}, []
        for q in useful.states:
            stop = termination if q in useful.accepting else 0.0
            row = useful.successors(q)
            weights = [g.count(useful.alphabet) for g, _ in row]
            if not row:
                stop = 1.0
            total = sum(weights)
            transitions[q] = [(g, t, (1 - stop) * w / total) for (g, t), w in zip(row, weights)]
            stops.append(stop)
        return cls(useful.alphabet, useful.n_states, useful.initial, transitions, stops, useful.accepting,
                   useful.state_names)

    # -- structure (states, edges, successors, transitions, n_edges, name: see GuardedAutomaton)
    @property
    def dfa(self) -> DFA:
        """The underlying DFA (same states, accepting states, guards)."""
        return DFA(self.alphabet, self.n_states, self.initial, self.accepting,
                   {q: [(g, t) for g, t, _ in row] for q, row in enumerate(self._edges)}, self.state_names)

    def _edge(self, state: int, label) -> tuple[Guard, int, float] | None:
        for edge in self._edges[state]:
            if edge[0].evaluate(label):
                return edge
        return None

    # -- probabilities ----------------------------------------------------------------------
    def log_probability(self, word: Word, *, per_label: bool = False) -> float:
        """Natural log of :meth:`probability` (``-inf`` when it is 0)."""
        total, state = 0.0, self.initial
        for label in word:
            edge = self._edge(state, label)
            if edge is None or edge[2] == 0:
                return -math.inf
            total += math.log(edge[2])
            if per_label:
                total -= math.log(edge[0].count(self.alphabet))
            state = edge[1]
        stop = self.termination[state]
        return total + math.log(stop) if stop > 0 else -math.inf

    def probability(self, word: Word, *, per_label: bool = False) -> float:
        """Probability of generating ``word``'s edge sequence and stopping (see module doc)."""
        return math.exp(self.log_probability(word, per_label=per_label))

    def most_probable_accepted(self) -> tuple[list[frozenset[str]], float] | None:
        """The most probable word ending in an accepting state, and its probability.

        Dijkstra on edge costs ``-log p`` with a final ``-log termination``; each letter is the
        guard's :meth:`~symlearn.logic.guards.Guard.satisfying_label` (fewest true propositions),
        and the probability is that of the guard sequence (``per_label=False``).
        """
        done = self.n_states  # virtual node reached by stopping in an accepting state
        best = {self.initial: 0.0}
        parent: dict[int, tuple[int, Guard | None]] = {}
        heap = [(0.0, self.initial)]
        while heap:
            cost, q = heapq.heappop(heap)
            if q == done:
                word, node = [], done
                while node in parent:
                    node, guard = parent[node]
                    if guard is not None:
                        word.append(guard.satisfying_label())
                return word[::-1], math.exp(-cost)
            if cost > best.get(q, math.inf):
                continue
            moves = [(g, t, p) for g, t, p in self._edges[q]]
            if q in self.accepting and self.termination[q] > 0:
                moves.append((None, done, self.termination[q]))
            for guard, target, p in moves:
                if p <= 0:
                    continue
                new = cost - math.log(p)
                if new < best.get(target, math.inf):
                    best[target] = new
                    parent[target] = (q, guard)
                    heapq.heappush(heap, (new, target))
        return None

    def sample(self, rng, *, max_length: int = 10_000, label_choice: str = "uniform") -> list[frozenset[str]]:
        """Draw one word. ``label_choice``: ``uniform`` (a uniformly random label satisfying the
        taken edge's guard) or ``minimal`` (its satisfying label with fewest true propositions)."""
        if label_choice not in ("uniform", "minimal"):
            raise ModelError(f"unknown label_choice {label_choice!r}", hint="use 'uniform' or 'minimal'")
        word, state = [], self.initial
        while True:
            row = self._edges[state]
            weights = [self.termination[state]] + [p for _, _, p in row]
            pick = int(rng.choice(len(weights), p=_normalised(weights)))
            if pick == 0:
                return word
            guard, state, _ = row[pick - 1]
            word.append(guard.sample_label(self.alphabet, rng) if label_choice == "uniform"
                        else guard.satisfying_label())
            if len(word) > max_length:
                raise LimitExceededError(f"a sampled word exceeded {max_length} letters without stopping",
                                         hint="raise max_length or the termination probabilities")

    # -- formats ----------------------------------------------------------------------------
    def to_dot(self, title: str | None = None, *, unicode: bool = False) -> str:
        from symlearn.logic.automata.dot_export import pdfa_to_dot

        return pdfa_to_dot(self, title=title, unicode=unicode)

    def to_dict(self) -> dict:
        from symlearn.logic.automata.json_format import header, write_transitions

        document = header("pdfa", self)
        document["termination"] = list(self.termination)
        document["transitions"] = write_transitions(self, "probability")
        return document

    @classmethod
    def from_dict(cls, document, *, source: str | None = None) -> PDFA:
        from symlearn.logic.automata.json_format import construct, read_header, read_transitions

        reader, f = read_header(document, "pdfa", source)
        termination = reader.list_of(document, "", "termination", "number")
        transitions = read_transitions(reader, document, "probability")
        return construct(reader, lambda: cls(f["alphabet"], f["n_states"], f["initial"], transitions,
                                             termination, f["accepting"], f["state_names"]))

    def _key(self):
        return (self.alphabet, self.n_states, self.initial, self.accepting, self.termination, self.state_names,
                self._edges)

    def __repr__(self) -> str:
        return f"PDFA({self.n_states} states, {self.n_edges} edges, alphabet {sorted(self.alphabet)})"


def _probability(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value <= 1 or value != value:
        raise ModelError(f"{what} must be a number in [0, 1], got {value!r}")
    return float(value)


def _normalised(weights: list[float]) -> list[float]:
    total = sum(weights)
    return [w / total for w in weights]
