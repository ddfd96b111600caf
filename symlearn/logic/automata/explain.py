"""Why does a trace violate a DFA, and what is the smallest change that satisfies it?

:func:`explain` runs the trace and reports where it fails: the step at which it entered a
state from which no accepting state is reachable (``dead``), the step no edge matched
(``stuck``), or, when every step was fine but the last state is not accepting, the end of the
trace (``incomplete``). It then computes a **shortest fix**: a minimum number of step edits
(keep a step for free; substitute, delete or insert a step for cost 1 each) turning the trace
into an accepted one — a Levenshtein distance to the language, found with Dijkstra over
(trace position, automaton state) pairs. A substituted step is the label closest to the
original one (fewest propositions flipped) that takes the chosen edge; an inserted step is the
edge guard's label with fewest true propositions.

>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.guards import Guard
>>> a, b = Guard.var("a"), Guard.var("b")
>>> never_b_then_a = DFA({"a", "b"}, 3, 0, [1], {0: [(~a & ~b, 0), (a & ~b, 1), (b, 2)],
...                                              1: [(~b, 1), (b, 2)], 2: [(Guard.true(), 2)]})
>>> report = explain(never_b_then_a, [set(), {"b"}, {"a"}])
>>> report.reason, report.failure_step
('dead', 1)
>>> [str(e) for e in report.edits]
['replace step 1 {b} by {}']
"""

from __future__ import annotations

import heapq
import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field

from symlearn.errors import ModelError


def _text(label) -> str:
    return "{" + ", ".join(sorted(label)) + "}"


@dataclass(frozen=True)
class Edit:
    """One change to a trace; ``position`` indexes the original trace (0-based)."""

    kind: str  # "substitute", "delete" or "insert" (before ``position``)
    position: int
    old: frozenset[str] | None = None
    new: frozenset[str] | None = None
    at_end: bool = False  # an insertion after the trace's last step (no step ``position`` to be before)

    def __str__(self) -> str:
        if self.kind == "substitute":
            return f"replace step {self.position} {_text(self.old)} by {_text(self.new)}"
        if self.kind == "delete":
            return f"delete step {self.position} ({_text(self.old)})"
        if self.at_end:
            return f"append {_text(self.new)} at the end"
        return f"insert {_text(self.new)} before step {self.position}"

    def to_dict(self) -> dict:
        return {"kind": self.kind, "position": self.position,
                "old": None if self.old is None else sorted(self.old),
                "new": None if self.new is None else sorted(self.new)}


@dataclass(frozen=True)
class Explanation:
    accepted: bool
    states: list[int]  # the run (shorter than the trace + 1 when it got stuck)
    reason: str  # accepted | dead | stuck | incomplete | empty-language
    failure_step: int | None  # index into the trace; len(trace) for "incomplete"
    edits: list[Edit] = field(default_factory=list)
    fixed_trace: list[frozenset[str]] | None = None

    def to_dict(self) -> dict:
        return {"accepted": self.accepted, "states": self.states, "reason": self.reason,
                "failure_step": self.failure_step, "edits": [e.to_dict() for e in self.edits],
                "fixed_trace": None if self.fixed_trace is None else [sorted(s) for s in self.fixed_trace]}

    def summary(self) -> str:
        if self.accepted:
            return "the trace is accepted"
        if self.reason == "empty-language":
            return "the automaton accepts no trace at all, so no fix exists"
        where = {
            "dead": f"at step {self.failure_step} the trace reaches a state from which acceptance is impossible",
            "stuck": f"at step {self.failure_step} no transition matches the label",
            "incomplete": "the trace ends before reaching an accepting state",
        }[self.reason]
        fix = "; ".join(str(e) for e in self.edits)
        return f"{where}; shortest fix ({len(self.edits)} edit{'s' if len(self.edits) != 1 else ''}): {fix}"


def explain(dfa, trace: Sequence) -> Explanation:
    """Explain how ``trace`` (a sequence of label sets) fails ``dfa`` and how to fix it."""
    trace = [frozenset(step) for step in trace]
    run = dfa.run(trace)
    if len(run) == len(trace) + 1 and run[-1] in dfa.accepting:
        return Explanation(True, run, "accepted", None, [], list(trace))
    live = dfa.live_states()
    if dfa.initial not in live:
        return Explanation(False, run, "empty-language", 0, [], None)
    if len(run) < len(trace) + 1:
        dead_at = next((i for i, q in enumerate(run[1:]) if q not in live), None)
        reason, step = ("dead", dead_at) if dead_at is not None else ("stuck", len(run) - 1)
    else:
        dead_at = next((i for i, q in enumerate(run[1:]) if q not in live), None)
        reason, step = ("dead", dead_at) if dead_at is not None else ("incomplete", len(trace))
    edits, fixed = shortest_fix(dfa, trace, live)
    return Explanation(False, run, reason, step, edits, fixed)


def shortest_fix(dfa, trace: list[frozenset[str]], live=None) -> tuple[list[Edit], list[frozenset[str]]]:
    """Fewest substitutions, deletions and insertions making ``trace`` accepted (Dijkstra)."""
    live = dfa.live_states() if live is None else live
    if dfa.initial not in live:
        raise ModelError("the automaton accepts no trace, so no fix exists")
    n = len(trace)
    start = (0, dfa.initial)
    best = {start: 0}
    parent: dict[tuple[int, int], tuple[tuple[int, int], Edit | None, frozenset[str] | None]] = {}
    counter = itertools.count()  # tie-break: earlier pushes first, keeps results deterministic
    heap = [(0, next(counter), start)]
    while heap:
        cost, _, node = heapq.heappop(heap)
        if cost > best[node]:
            continue
        i, q = node
        if i == n and q in dfa.accepting:
            return _path(parent, node)
        moves = []
        if i < n:
            kept = dfa.step(q, trace[i])
            if kept is not None and kept in live:
                moves.append((0, (i + 1, kept), None, trace[i]))
            for guard, target in dfa.successors(q):
                if target in live and target != kept:
                    new = guard.closest_label(trace[i])
                    moves.append((1, (i + 1, target), Edit("substitute", i, trace[i], new), new))
            moves.append((1, (i + 1, q), Edit("delete", i, trace[i]), None))
        for guard, target in dfa.successors(q):
            if target in live:
                new = guard.satisfying_label()
                moves.append((1, (i, target), Edit("insert", i, None, new, at_end=i == len(trace)), new))
        for step_cost, target_node, edit, emitted in moves:
            new_cost = cost + step_cost
            if new_cost < best.get(target_node, float("inf")):
                best[target_node] = new_cost
                parent[target_node] = (node, edit, emitted)
                heapq.heappush(heap, (new_cost, next(counter), target_node))
    raise ModelError("no accepted trace is reachable by editing")  # pragma: no cover - live initial state


def _path(parent, node) -> tuple[list[Edit], list[frozenset[str]]]:
    edits, emitted_steps = [], []
    while node in parent:
        node, edit, emitted = parent[node]
        if edit is not None:
            edits.append(edit)
        if emitted is not None:
            emitted_steps.append(emitted)
    return edits[::-1], emitted_steps[::-1]
