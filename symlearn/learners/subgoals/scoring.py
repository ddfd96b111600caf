"""Scoring a learned sub-goal PDFA against a known one (benchmarks, tests, the demo).

* :func:`renamed` -- the automaton with its sub-goal symbols renamed (learned names -> truth
  names, from :meth:`~symlearn.grounding.subgoals.SubGoalSet.match`);
* :func:`edge_deviations` -- per transition of the truth, the learned probability, the true one,
  the visits of its source state and the deviation in binomial standard errors
  ``|p_hat - p| / sqrt(p (1 - p) / n)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass

from symlearn.errors import DataError
from symlearn.learners.subgoals.ordering_automaton import OrderingCounts
from symlearn.logic.automata.dfa import DFA
from symlearn.logic.automata.pdfa import PDFA


def renamed(pdfa: PDFA, mapping: Mapping[str, str], alphabet=None) -> DFA:
    """The language of ``pdfa`` as a DFA whose symbols are renamed by ``mapping`` (every symbol
    must be mapped), over ``alphabet`` (default: the renamed symbols)."""
    missing = sorted(set(pdfa.alphabet) - set(mapping))
    if missing:
        raise DataError(f"sub-goal {missing[0]!r} has no counterpart", hint="raise the matching tolerance")
    alphabet = sorted(alphabet if alphabet is not None else mapping.values())
    from symlearn.learners.subgoals.ordering_automaton import letter_guards

    guards = letter_guards(alphabet)
    transitions: dict[int, list] = {}
    for source, guard, target, _ in pdfa.edges():
        (symbol,) = guard.satisfying_label()
        transitions.setdefault(source, []).append((guards[mapping[symbol]], target))
    return DFA(alphabet, pdfa.n_states, pdfa.initial, pdfa.accepting, transitions, pdfa.state_names)


@dataclass(frozen=True)
class EdgeDeviation:
    source: str
    symbol: str
    learned: float
    truth: float
    visits: int
    standard_errors: float

    def as_dict(self) -> dict:
        return asdict(self)


def edge_deviations(learned: PDFA, counts: OrderingCounts, truth: PDFA, mapping: Mapping[str, str]) -> list[EdgeDeviation]:
    """Walk both automata together from their initial states; for every transition of the truth,
    compare probabilities (a transition the learner never saw counts as learned 0)."""
    visits = [0] * counts.n_states
    for (q, _), v in counts.edge_counts.items():
        visits[q] += v
    for q, n in enumerate(counts.end_counts):
        visits[q] += n
    result = []
    seen = {(learned.initial, truth.initial)}
    frontier = [(learned.initial, truth.initial)]
    while frontier:
        mine, theirs = frontier.pop()
        row = {}
        for guard, target, p in learned.successors(mine):
            (symbol,) = guard.satisfying_label()
            row[mapping.get(symbol, symbol)] = (target, p)
        for guard, target, p in truth.successors(theirs):
            (symbol,) = guard.satisfying_label()
            learned_target, p_hat = row.get(symbol, (None, 0.0))
            n = visits[mine]
            se = math.sqrt(p * (1 - p) / n) if n and 0 < p < 1 else 0.0
            deviation = abs(p_hat - p) / se if se else (0.0 if abs(p_hat - p) < 1e-12 else math.inf)
            result.append(EdgeDeviation(learned.name(mine), symbol, p_hat, p, n, deviation))
            if learned_target is not None and (learned_target, target) not in seen:
                seen.add((learned_target, target))
                frontier.append((learned_target, target))
    return result
