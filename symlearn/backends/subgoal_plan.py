"""Plans from a sub-goal PDFA, and executing them with replanning (thesis, section 6.4.3).

The PDFA's letters are sub-goals (one-hot guards, see
:mod:`symlearn.learners.subgoals.ordering_automaton`); a plan is a sequence of sub-goal names.

* :func:`greedy_plan` -- the thesis' planner: from a state, take the most probable transition,
  until an accepting state is reached. In an accepting state that has edges too, stopping is one
  of the choices, with its termination probability ("until an accepting state is reached" when
  the demonstrators mostly stopped there). Sub-goals in ``excluded`` are not taken. When the
  greedy walk runs into a state with no allowed move, the plan falls back to
  :func:`best_plan` from the start state (so a plan that exists is found). With
  ``first_only=True`` the excluded sub-goals are only not taken *now* (postponed, not dropped).
* :func:`best_plan` -- the most probable accepted continuation (Dijkstra on ``-log p``, stopping
  weighted by the termination probability), the analogue of ``PDFA.most_probable_accepted``
  from any state and with excluded sub-goals.
* :func:`execute` -- run a plan with a low-level controller: ``controller(subgoal) -> bool``
  drives the environment to one sub-goal and reports success; ``reachable(subgoal) -> bool``
  (optional) says whether it can be attempted now (e.g. its object is detected). Before each
  step the plan is recomputed from the current automaton state without the sub-goals that are
  unreachable now or that failed in this state; the report lists every replan.

>>> from symlearn.learners.subgoals.ordering_automaton import pdfa_from_words
>>> pdfa = pdfa_from_words([("a", "b")] * 3 + [("b", "a")])
>>> greedy_plan(pdfa).subgoals, greedy_plan(pdfa, excluded={"a"}, first_only=True).subgoals
(('a', 'b'), ('b', 'a'))
>>> greedy_plan(pdfa, excluded={"a"})  # every accepted word needs a
Plan(subgoals=(), states=(0,), probability=0.0, accepted=False)
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, field

from symlearn.errors import DataError, ModelError


@dataclass(frozen=True)
class Plan:
    """Sub-goals to achieve in order, the automaton states visited (``len(subgoals) + 1``) and
    the probability of this continuation (edges times the final termination)."""

    subgoals: tuple[str, ...]
    states: tuple[int, ...]
    probability: float
    accepted: bool  # ends in an accepting state

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Replan:
    """A plan was recomputed in ``state`` without the ``excluded`` sub-goals."""

    state: int
    excluded: tuple[str, ...]
    reason: str
    plan: tuple[str, ...]

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Execution:
    """What :func:`execute` did: the sub-goals achieved in order, the states, every replan."""

    success: bool  # ended in an accepting state
    achieved: tuple[str, ...]
    states: tuple[int, ...]
    initial_plan: tuple[str, ...]
    replans: tuple[Replan, ...] = ()
    attempts: int = 0
    failures: tuple[tuple[int, str], ...] = field(default=())  # (state, sub-goal) the controller failed

    def as_dict(self) -> dict:
        return {"success": self.success, "achieved": list(self.achieved), "states": list(self.states),
                "initial_plan": list(self.initial_plan), "replans": [r.as_dict() for r in self.replans],
                "attempts": self.attempts, "failures": [list(f) for f in self.failures]}


def symbol_of(guard, alphabet) -> str:
    """The sub-goal a one-hot guard stands for."""
    label = guard.satisfying_label()
    if label is None or len(label) != 1:
        raise ModelError(f"edge guard {guard} is not one sub-goal", hint="sub-goal PDFAs have one-hot guards")
    return next(iter(label))


def _moves(pdfa, state: int, excluded: frozenset[str]):
    for guard, target, p in pdfa.successors(state):
        symbol = symbol_of(guard, pdfa.alphabet)
        if symbol not in excluded and p > 0:
            yield symbol, target, p


def _check_excluded(pdfa, excluded: Iterable[str]) -> frozenset[str]:
    excluded = frozenset(excluded)
    unknown = sorted(excluded - set(pdfa.alphabet))
    if unknown:
        raise DataError(f"sub-goal {unknown[0]!r} is not a symbol of the automaton",
                        hint="its sub-goals: " + ", ".join(sorted(pdfa.alphabet)))
    return excluded


def _start(pdfa, state: int | None) -> int:
    state = pdfa.initial if state is None else state
    if not isinstance(state, int) or not 0 <= state < pdfa.n_states:
        raise DataError(f"state {state!r} is not a state of the automaton (0..{pdfa.n_states - 1})")
    return state


def greedy_plan(pdfa, state: int | None = None, excluded: Iterable[str] = (), *, first_only: bool = False) -> Plan:
    """The thesis' plan: the most probable transition at each state (see the module doc)."""
    excluded = _check_excluded(pdfa, excluded)
    q = start = _start(pdfa, state)
    subgoals, states, log_p = [], [q], 0.0
    for _ in range(pdfa.n_states + 1):
        avoid = excluded if not (first_only and subgoals) else frozenset()
        moves = sorted(_moves(pdfa, q, avoid), key=lambda m: (-m[2], m[0]))
        stop = pdfa.termination[q] if q in pdfa.accepting else 0.0
        if q in pdfa.accepting and (not moves or stop >= moves[0][2]):
            return Plan(tuple(subgoals), tuple(states), math.exp(log_p + math.log(stop)) if stop > 0 else 0.0,
                        True)
        if not moves:
            break
        symbol, q, p = moves[0]
        subgoals.append(symbol)
        states.append(q)
        log_p += math.log(p)
    return best_plan(pdfa, start, excluded, first_only=first_only)  # a dead end (or a loop): search instead


def best_plan(pdfa, state: int | None = None, excluded: Iterable[str] = (), *, first_only: bool = False) -> Plan:
    """The most probable accepted continuation from ``state`` avoiding ``excluded`` (Dijkstra;
    with ``first_only``, only as the first move); an empty, not accepted plan when there is none."""
    excluded = _check_excluded(pdfa, excluded)
    start = _start(pdfa, state)
    done = -1  # virtual node: stopped in an accepting state
    best = {start: 0.0}
    parent: dict[int, tuple[int, str | None]] = {}
    heap = [(0.0, start)]
    while heap:
        cost, q = heapq.heappop(heap)
        if q == done:
            subgoals, states, node = [], [], done
            while node in parent:
                node, symbol = parent[node]
                states.append(node)
                if symbol is not None:
                    subgoals.append(symbol)
            return Plan(tuple(subgoals[::-1]), tuple(states[::-1]), math.exp(-cost), True)
        if cost > best.get(q, math.inf):
            continue
        moves = list(_moves(pdfa, q, excluded if not first_only or (q == start and cost == 0.0) else frozenset()))
        if q in pdfa.accepting:
            # a stop weighted 0 (thesis probabilities of an unentered state) still ends a plan
            moves.append((None, done, pdfa.termination[q] if pdfa.termination[q] > 0 else 1e-300))
        for symbol, target, p in moves:
            new = cost - math.log(p)
            if new < best.get(target, math.inf):
                best[target] = new
                parent[target] = (q, symbol)
                heapq.heappush(heap, (new, target))
    return Plan((), (start,), 0.0, False)


def step(pdfa, state: int, subgoal: str) -> int:
    """The state after achieving ``subgoal`` in ``state``."""
    for symbol, target, _ in _moves(pdfa, state, frozenset()):
        if symbol == subgoal:
            return target
    raise DataError(f"sub-goal {subgoal!r} has no transition from state {pdfa.name(state)}")


def execute(pdfa, controller: Callable[[str], bool], *, reachable: Callable[[str], bool] | None = None,
            planner: Callable = greedy_plan, max_attempts: int | None = None) -> Execution:
    """Achieve an accepted sequence of sub-goals, replanning around unreachable ones.

    Per step, the sub-goals ``reachable`` says are unreachable now, and those the controller
    failed in this state, are *excluded*, and the plan is recomputed from the current state by
    ``planner`` (``greedy_plan`` or ``best_plan``): first without them altogether (another
    accepted set of sub-goals may avoid them), else without them as the next move only
    (postponed: an object may be detected again later), else with one of them allowed next, the
    one that failed longest ago first (retry). The plan's first sub-goal is attempted. Execution succeeds at an accepting state where the plan says stop,
    and fails when no plan is left or after ``max_attempts`` controller calls (default
    ``4 * (number of sub-goals + 1)``).
    """
    q = pdfa.initial
    max_attempts = max_attempts if max_attempts is not None else 4 * (len(pdfa.alphabet) + 1)
    achieved: list[str] = []
    states = [q]
    replans: list[Replan] = []
    failures: list[tuple[int, str]] = []
    failed_here: dict[str, int] = {}  # sub-goal -> attempt at which it last failed in this state
    initial = plan = planner(pdfa, q)
    attempts = 0
    while attempts < max_attempts:
        excluded = set(failed_here)
        if reachable is not None:
            excluded |= {s for s, _, _ in _moves(pdfa, q, frozenset()) if s not in excluded and not reachable(s)}
        if excluded:
            blocked = ", ".join(sorted(excluded))
            plan = planner(pdfa, q, excluded)
            reason = f"without {blocked}"
            if not plan.accepted:
                plan = planner(pdfa, q, excluded, first_only=True)
                reason = f"{blocked} postponed"
            # nothing avoids them: retry one, the one that failed longest ago first (unreachable
            # now but never tried counts as oldest), so one stubborn sub-goal cannot starve the rest
            for retry in sorted(excluded, key=lambda g: (failed_here.get(g, -1), g)):
                if plan.accepted:
                    break
                plan = planner(pdfa, q, excluded - {retry}, first_only=True)
                reason = f"no plan avoids {blocked}; retrying {retry}"
            if not plan.accepted:
                plan = planner(pdfa, q)
                reason = f"no plan avoids {blocked}; retrying"
            replans.append(Replan(q, tuple(sorted(excluded)), reason, plan.subgoals))
        elif plan.states[:1] != (q,):
            plan = planner(pdfa, q)
        if not plan.accepted:
            break
        if not plan.subgoals:
            return Execution(True, tuple(achieved), tuple(states), initial.subgoals, tuple(replans), attempts,
                             tuple(failures))
        subgoal = plan.subgoals[0]
        attempts += 1
        if controller(subgoal):
            q = step(pdfa, q, subgoal)
            achieved.append(subgoal)
            states.append(q)
            failed_here = {}
            plan = Plan(plan.subgoals[1:], plan.states[1:], plan.probability, plan.accepted)
        else:
            failures.append((q, subgoal))
            failed_here[subgoal] = attempts
    return Execution(False, tuple(achieved), tuple(states), initial.subgoals, tuple(replans), attempts,
                     tuple(failures))
