"""Comparing an inferred machine with the ground truth: graph isomorphism and proposition matching.

Inferred propositions are named ``p0, p1, ...`` and the truth's after configurations, so
:func:`isomorphic` compares the machines as graphs: states, the edges between different states,
the initial state and the accepting states, names ignored. :func:`state_matching`
goes further when every frame carries its ground-truth proposition: each inferred state is named
by the truth label of its prototype frame, and :func:`same_machine` checks that renaming the
inferred propositions this way gives exactly the true transitions.

>>> from symlearn.learners.reward_machines.machine_building import machine_from_edges
>>> a = machine_from_edges(["p0", "p1", "p2"], {(0, "p1"): 1, (1, "p2"): 2}, 0, [2])
>>> b = machine_from_edges(["s", "x", "y"], {(0, "y"): 2, (2, "x"): 1}, 0, [1])
>>> isomorphic(a, b)
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from symlearn.logic.automata import RewardMachine


def isomorphic(a: RewardMachine, b: RewardMachine) -> bool:
    """Whether the two machines have the same transition graph (names and rewards ignored).

    Backtracking over bijections that fix the initial state and keep acceptance, in- and
    out-degrees; machines inferred from demonstrations have a handful of states, so this is
    instant (and needs no graph library)."""
    if a.n_states != b.n_states:
        return False
    ea, eb = edge_set(a), edge_set(b)
    if len(ea) != len(eb):
        return False

    def signature(machine, edges, u):
        return (u == machine.initial, u in machine.accepting, sum(1 for x, _ in edges if x == u),
                sum(1 for _, y in edges if y == u))

    sig_a = [signature(a, ea, u) for u in range(a.n_states)]
    sig_b = [signature(b, eb, v) for v in range(b.n_states)]
    order = sorted(range(a.n_states), key=lambda u: (u != a.initial, u))
    mapping: dict[int, int] = {}
    used: set[int] = set()

    def extend(i: int) -> bool:
        if i == len(order):
            return True
        u = order[i]
        for v in range(b.n_states):
            if v in used or sig_a[u] != sig_b[v]:
                continue
            if all(((u, x) in ea) == ((v, y) in eb) and ((x, u) in ea) == ((y, v) in eb) for x, y in mapping.items()):
                mapping[u] = v
                used.add(v)
                if extend(i + 1):
                    return True
                del mapping[u]
                used.discard(v)
        return False

    return extend(0)


def edge_set(machine: RewardMachine) -> set[tuple[int, int]]:
    return {(u, edge[1]) for u in range(machine.n_states) for edge in machine.successors(u) if edge[1] != u}


def same_machine(inferred: RewardMachine, truth: RewardMachine, state_names: Sequence[str | None],
                 truth_propositions: Sequence[str]) -> bool:
    """Whether naming inferred state ``k`` after truth proposition ``state_names[k]`` maps the
    inferred machine's states, edges, initial and accepting states exactly onto the truth's
    (truth state ``i`` has proposition ``truth_propositions[i]``)."""
    index = {p: i for i, p in enumerate(truth_propositions)}
    if any(name not in index for name in state_names) or len(set(state_names)) != len(state_names):
        return False
    to_truth = [index[name] for name in state_names]
    if inferred.n_states != truth.n_states or to_truth[inferred.initial] != truth.initial:
        return False
    if {to_truth[u] for u in inferred.accepting} != set(truth.accepting):
        return False
    return {(to_truth[u], to_truth[v]) for u, v in edge_set(inferred)} == edge_set(truth)


def state_matching(labels_of_prototypes: Sequence[frozenset[str]]) -> list[str | None]:
    """The single truth proposition of each prototype frame (None when it has none or several)."""
    return [next(iter(label)) if len(label) == 1 else None for label in labels_of_prototypes]


def machine_summary(machine: RewardMachine) -> Mapping[str, object]:
    return {"states": machine.n_states, "edges": sorted(edge_set(machine)), "initial": machine.initial,
            "accepting": sorted(machine.accepting)}


__all__ = ["edge_set", "isomorphic", "machine_summary", "same_machine", "state_matching"]
