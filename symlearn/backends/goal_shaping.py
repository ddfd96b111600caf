"""Potential-based shaping by the distance to the goal in the machine: ``Psi(u) = gamma ** d(u)``.

The thesis' eqs. 7.6-7.7: ``d(u)`` is the number of edges on a shortest path from machine state
``u`` to an accepting state, ``Psi(u) = gamma ** d(u)`` and every transition pays
``delta_r(u, u') + gamma * Psi(u') - Psi(u)``. With the sparse ``delta_r`` (1 on entering an
accepting state) this gives exactly the properties section 7.4.4 lists, tested in
``tests/backends/test_goal_shaping.py``:

* moving one step closer (``d(u') = d(u) - 1``): ``gamma ** d - gamma ** d = 0``;
* staying (``u' = u``): ``(gamma - 1) * gamma ** d``, slightly negative;
* moving away (``d(u') = d(u) + 1``): ``(gamma ** 2 - 1) * gamma ** d``, more negative;
* reaching the goal from ``d = 1``: ``1 + gamma * 1 - gamma = 1``.

A state from which no accepting state can be reached has ``d = inf`` and ``Psi = 0`` (the limit of
``gamma ** d``), so entering it costs ``-Psi(u)``. Staying must be paid too, so :func:`shape` adds
to every non-terminal state an explicit self-loop for the labels none of its edges read (the
implicit self-loop of a reward machine pays one ``default_reward`` for all states, but the
staying reward depends on ``d(u)``). Terminal states pay nothing, as before.

This is the thesis' potential; :meth:`RewardMachine.from_dfa` (``shaping=True``) keeps its own
linear, non-negative potential. Both fold the shaping into the stored edge rewards and record the
potential and ``gamma`` on the machine.

>>> from symlearn.logic.automata import RewardMachine
>>> rm = RewardMachine({"a", "b"}, 3, 0, {0: [("a", 1, 0.0)], 1: [("b", 2, 1.0)]}, terminal=[2], accepting=[2])
>>> shaped = shape(rm, 0.9)
>>> [round(shaped.step(0, x)[1], 3) for x in ({"a"}, set())], round(shaped.step(1, {"b"})[1], 3)
([0.0, -0.081], 1.0)
"""

from __future__ import annotations

import math

from symlearn.errors import ModelError
from symlearn.logic.automata import RewardMachine
from symlearn.logic.guards import Guard


def goal_distances(machine: RewardMachine) -> list[float]:
    """Edges on a shortest path from every state to an accepting state (``inf`` if none)."""
    distance = [math.inf] * machine.n_states
    frontier = sorted(machine.accepting)
    for q in frontier:
        distance[q] = 0
    predecessors: dict[int, set[int]] = {q: set() for q in range(machine.n_states)}
    for q in range(machine.n_states):
        for edge in machine.successors(q):
            target = edge[1]
            if target != q:
                predecessors[target].add(q)
    while frontier:
        nxt = []
        for q in frontier:
            for p in predecessors[q]:
                if distance[p] == math.inf:
                    distance[p] = distance[q] + 1
                    nxt.append(p)
        frontier = nxt
    return distance


def goal_potential(machine: RewardMachine, gamma: float) -> list[float]:
    """``Psi(u) = gamma ** d(u)`` (0 where the goal cannot be reached)."""
    if not 0 < gamma < 1:
        raise ModelError(f"gamma must be in (0, 1) for goal-distance shaping, got {gamma}")
    return [0.0 if d == math.inf else gamma ** d for d in goal_distances(machine)]


def shape(machine: RewardMachine, gamma: float = 0.9) -> RewardMachine:
    """``machine`` with every edge reward ``r + gamma * Psi(u') - Psi(u)`` and explicit staying
    self-loops (see the module docstring); the potential and gamma are stored on the result."""
    if machine.potential is not None:
        raise ModelError("the machine is shaped already", hint="shape the sparse machine")
    psi = goal_potential(machine, gamma)
    transitions = {}
    for u in range(machine.n_states):
        row = [(g, v, r + gamma * psi[v] - psi[u]) for g, v, r in machine.successors(u)]
        if u not in machine.terminal:
            unmatched = ~Guard.any_of(g for g, _, _ in machine.successors(u))
            if not unmatched.is_false():
                row.append((unmatched, u, machine.default_reward + gamma * psi[u] - psi[u]))
        transitions[u] = row
    return RewardMachine(machine.alphabet, machine.n_states, machine.initial, transitions, machine.terminal,
                         machine.accepting, machine.state_names, default_reward=machine.default_reward,
                         gamma=gamma, potential=psi)


__all__ = ["goal_distances", "goal_potential", "shape"]
