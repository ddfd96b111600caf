"""The ground-truth PDFA of a scripted demonstrator that orders sub-goals by preference weights.

The demonstrators of the block world and the drone pick the next sub-goal among those whose
prerequisites are done, with probability proportional to its weight (a Plackett-Luce draw with
precedences). The states of that process are the sets of sub-goals done, so its exact
distribution over orderings is a PDFA of the same shape the sub-goal learner builds -- what a
learned automaton is scored against.
"""

from __future__ import annotations

from collections.abc import Sequence

from symlearn.errors import DataError


def available(done: frozenset[int], requires: Sequence[frozenset[int]]) -> list[int]:
    return [j for j in range(len(requires)) if j not in done and requires[j] <= done]


def preferred_order(weights: Sequence[float], requires: Sequence[frozenset[int]]) -> list[int]:
    """Always the heaviest available sub-goal next (ties to the lower index)."""
    done: frozenset[int] = frozenset()
    order = []
    while len(order) < len(weights):
        options = available(done, requires)
        if not options:
            raise DataError("the precedences are cyclic")
        j = max(options, key=lambda i: (weights[i], -i))
        order.append(j)
        done |= {j}
    return order


def draw_order(weights: Sequence[float], requires: Sequence[frozenset[int]], rng) -> list[int]:
    """One Plackett-Luce ordering respecting the precedences."""
    done: frozenset[int] = frozenset()
    order = []
    while len(order) < len(weights):
        options = available(done, requires)
        w = [weights[j] for j in options]
        total = sum(w)
        j = options[int(rng.choice(len(options), p=[x / total for x in w]))]
        order.append(j)
        done |= {j}
    return order


def preference_pdfa(names: Sequence[str], weights: Sequence[float], requires: Sequence[frozenset[int]]):
    """The exact distribution over orderings as a PDFA over one-hot sub-goal letters."""
    from symlearn.logic.automata.pdfa import PDFA
    from symlearn.logic.guards import Guard

    guards = {j: Guard.cube({n: n == names[j] for n in names}) for j in range(len(names))}
    index = {frozenset(): 0}
    sets: list[frozenset[int]] = [frozenset()]
    transitions: dict[int, list] = {}
    frontier = [frozenset()]
    while frontier:
        done = frontier.pop(0)
        options = available(done, requires)
        total = sum(weights[j] for j in options)
        row = []
        for j in options:
            nxt = done | {j}
            if nxt not in index:
                index[nxt] = len(sets)
                sets.append(nxt)
                frontier.append(nxt)
            row.append((guards[j], index[nxt], weights[j] / total))
        transitions[index[done]] = row
    termination = [0.0 if available(s, requires) else 1.0 for s in sets]
    state_names = ["{" + ",".join(names[j] for j in sorted(s)) + "}" for s in sets]
    return PDFA(list(names), len(sets), 0, transitions, termination, None, state_names)
