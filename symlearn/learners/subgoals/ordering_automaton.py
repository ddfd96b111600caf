"""The automaton of sub-goal orderings (thesis, Algorithm 6.2) and its probabilities (eqs. 6.2, 6.3).

A state is the *set* of sub-goals completed so far: reading symbol ``s`` in the state of set
``A`` leads to the state of ``A | {s}``, created the first time that set is seen. One pass over
all words builds the states, the transitions, the transition counts ``V[q][q']`` and the number
of words ending in each state; the states where a word ends are accepting. The language holds
every word shown, and also every ordering whose steps between sets were all shown (``a b c`` and
``b a d`` give ``a b d`` and ``b a c`` too): what has been completed, not in which order, decides
what may follow. The sets are bit masks and the transitions a dict keyed by ``(state, symbol)``,
so each letter costs O(1); identical words are tallied first and walked once with their count.
The pass is linear in the total length of the words (``benchmarks/subgoal_pdfa_scaling.py`` measures it).

Probabilities:

* ``"consistent"`` (default): in each state, the edges and stopping share the words that pass
  through it: ``p(q -> q') = V[q][q'] / (sum_q'' V[q][q''] + E[q])`` and termination
  ``E[q] / (same)``, ``E[q]`` = words ending in ``q``. Every state sums to 1, so the result is a
  proper distribution over words (the maximum-likelihood one for this structure): probabilities
  of words, sampling and the most probable word mean what they say.
* ``"thesis"``: eq. 6.2, edges normalised over the edges only, ``V[q][q'] / sum_q'' V[q][q'']``,
  and eq. 6.3, termination as a distribution over the accepting states,
  ``F(q) = sum_q' V[q'][q] / sum_{f in F} sum_q' V[q'][f]``. When every word completes the same
  set (one accepting state, with no edge out) both coincide; otherwise the thesis' values do not
  sum to 1 per state, so that PDFA is built without the normalisation check: eq. 6.1
  (``probability``) and greedy planning use its numbers as the thesis does, but sampling
  renormalises each state and its JSON cannot be loaded back as a PDFA.
  Eq. 6.3 counts entries into a state, so the initial state never terminates under it, even if
  some word is empty.

Symbols become one-hot guards: the letter of sub-goal ``s`` is ``s`` true and every other
sub-goal false, so the automaton is a deterministic :class:`~symlearn.logic.automata.PDFA` over
the sub-goal names as propositions.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from symlearn.errors import DataError
from symlearn.logic.automata.pdfa import PDFA
from symlearn.logic.guards import Guard

PROBABILITIES = ("consistent", "thesis")


@dataclass(frozen=True)
class OrderingCounts:
    """What Algorithm 6.2 counts: states as sets of completed sub-goals, transitions and visits."""

    alphabet: tuple[str, ...]
    sets: tuple[int, ...]  # state -> bit mask of completed sub-goals (bit i = alphabet[i])
    transitions: dict[tuple[int, int], int]  # (state, symbol index) -> state
    edge_counts: dict[tuple[int, int], int]  # (state, symbol index) -> V[q][delta(q, s)]
    end_counts: tuple[int, ...]  # words ending in each state
    n_words: int
    total_length: int

    @property
    def n_states(self) -> int:
        return len(self.sets)

    @property
    def accepting(self) -> frozenset[int]:
        return frozenset(q for q, n in enumerate(self.end_counts) if n > 0)

    def completed(self, state: int) -> tuple[str, ...]:
        mask = self.sets[state]
        return tuple(s for i, s in enumerate(self.alphabet) if mask >> i & 1)

    def named_edge_counts(self) -> dict[tuple[int, str], int]:
        """``{(state, sub-goal name): V}``."""
        return {(q, self.alphabet[i]): v for (q, i), v in self.edge_counts.items()}

    def state_name(self, state: int) -> str:
        return "{" + ",".join(self.completed(state)) + "}"


def count_orderings(words: Iterable[Sequence[str]], alphabet: Sequence[str] | None = None) -> OrderingCounts:
    """Algorithm 6.2: one pass over ``words`` (repetition-free sequences of sub-goal names).

    ``alphabet``: the sub-goal names (a symbol outside it is an error); default: the symbols of
    the words in order of appearance.
    """
    index: dict[str, int] = {}
    fixed = alphabet is not None
    if fixed:
        for s in alphabet:
            if not isinstance(s, str) or not s.isidentifier():
                raise DataError(f"sub-goal name {s!r} must be an identifier")
            if s in index:
                raise DataError(f"sub-goal {s!r} is named twice in the alphabet")
            index[s] = len(index)
    # Identical words are tallied first (hashing a tuple is one C-level pass over it), then the
    # automaton is walked once per distinct word with its count: still linear in the total
    # length, with the per-letter Python work paid once per distinct word.
    if not isinstance(words, (list, tuple)):
        words = list(words)  # read an iterator once
    try:
        tally: Counter[tuple] = Counter(words)  # C-level counting when the words are tuples
    except TypeError:  # unhashable words (lists): count them as tuples
        tally = Counter(_as_tuple(w) for w in words)
    for word in tally:
        if isinstance(word, str):
            raise DataError(f"word {word!r} is a string; give a sequence of sub-goal names")
        if type(word) is not tuple:
            raise DataError(f"word {word!r} is not a sequence of sub-goal names")
    sets = [0]
    state_of = {0: 0}
    transitions: dict[tuple[int, int], int] = {}
    counts: dict[tuple[int, int], int] = {}
    ends = [0]
    n_words = total = 0
    for word, times in tally.items():
        q = 0
        for symbol in word:
            i = index.get(symbol)
            if i is None:
                if fixed or not isinstance(symbol, str) or not symbol.isidentifier():
                    raise DataError(f"word {list(word)}: symbol {symbol!r} is not a sub-goal",
                                    hint="sub-goals: " + ", ".join(index) if fixed else
                                    "symbols must be identifiers (letters, digits, _)")
                i = index[symbol] = len(index)
            key = (q, i)
            target = transitions.get(key)
            if target is None:
                mask = sets[q]
                if mask >> i & 1:
                    raise DataError(f"word {list(word)} repeats sub-goal {symbol!r}",
                                    hint="words of sub-goals are repetition-free (Algorithm 6.1)")
                mask |= 1 << i
                target = state_of.get(mask)
                if target is None:
                    target = state_of[mask] = len(sets)
                    sets.append(mask)
                    ends.append(0)
                transitions[key] = target
                counts[key] = 0
            counts[key] += times
            q = target
        ends[q] += times
        n_words += times
        total += len(word) * times
    if n_words == 0:
        raise DataError("no words: there is nothing to build an automaton from")
    return OrderingCounts(tuple(index), tuple(sets), transitions, counts, tuple(ends), n_words, total)


def _as_tuple(word) -> tuple:
    if isinstance(word, str):
        raise DataError(f"word {word!r} is a string; give a sequence of sub-goal names")
    return tuple(word)


def letter_guards(alphabet: Sequence[str]) -> dict[str, Guard]:
    """The one-hot guard of each sub-goal symbol."""
    return {s: Guard.cube({t: t == s for t in alphabet}) for s in alphabet}


def ordering_pdfa(counts: OrderingCounts, probabilities: str = "consistent") -> PDFA:
    """The PDFA of ``counts`` with ``"consistent"`` or ``"thesis"`` probabilities (module doc)."""
    if probabilities not in PROBABILITIES:
        raise DataError(f"unknown probabilities {probabilities!r}", hint="use " + " or ".join(PROBABILITIES))
    guards = letter_guards(counts.alphabet)
    n = counts.n_states
    out_total = [0] * n
    into = [0] * n
    for (q, _), v in counts.edge_counts.items():
        out_total[q] += v
    for key, target in counts.transitions.items():
        into[target] += counts.edge_counts[key]
    accepting = counts.accepting
    if probabilities == "consistent":
        denominator = [out_total[q] + counts.end_counts[q] for q in range(n)]
        termination = [counts.end_counts[q] / denominator[q] for q in range(n)]
    else:
        denominator = out_total
        entered = sum(into[f] for f in accepting)
        termination = [into[q] / entered if q in accepting and entered else 0.0 for q in range(n)]
    transitions: dict[int, list] = {q: [] for q in range(n)}
    for (q, i), target in sorted(counts.transitions.items()):
        transitions[q].append((guards[counts.alphabet[i]], target, counts.edge_counts[(q, i)] / denominator[q]))
    names = [counts.state_name(q) for q in range(n)]
    tolerance = math.inf if probabilities == "thesis" else 1e-9
    return PDFA(counts.alphabet, n, 0, transitions, termination, accepting, names, tolerance=tolerance)


def pdfa_from_words(words: Iterable[Sequence[str]], alphabet: Sequence[str] | None = None, *,
                    probabilities: str = "consistent") -> PDFA:
    """Algorithm 6.2 and the probabilities in one call."""
    return ordering_pdfa(count_orderings(words, alphabet), probabilities)
