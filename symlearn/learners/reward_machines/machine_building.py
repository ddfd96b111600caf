"""Algorithm 7.1 and the reward machine it describes.

:func:`infer_transitions` is the thesis' Algorithm 7.1: every machine state ``u_i`` stands for a
sub-goal ``i`` with proposition ``p_i``; reading the abstract demonstrations (label sequences)
from the initial state, the first time ``p_i`` is read in state ``u`` the transition
``delta_u(u, p_i) = u_i`` is defined, and the machine moves to ``u_i``. (Reading ``p_i`` in
``u_i`` itself is the self-loop every reward machine has implicitly.) Afterwards the existing
transition is followed, so a later demonstration extends the machine where it differs.

:func:`machine_from_edges` turns such transitions into a :class:`RewardMachine`: the guard of
``u -> v`` reads ``p_v`` and none of the other propositions ``u`` has an edge for (the guards of a
state must exclude each other, and a frame that matches two sub-goals at once is no evidence
of either), reward 1 on entering an accepting state, accepting states terminal. The same
function builds the ground-truth machines of the rendered block tasks, so inferred and true
machines have the same shape and compare directly.

>>> edges = infer_transitions([[{"p0"}, set(), {"p1"}, {"p2"}], [{"p0"}, {"p2"}]], {"p0": 0, "p1": 1, "p2": 2}, 0)
>>> sorted(edges.items())
[((0, 'p1'), 1), ((0, 'p2'), 2), ((1, 'p2'), 2)]
>>> rm = machine_from_edges(["p0", "p1", "p2"], edges, 0, [2])
>>> rm.run([{"p1"}, {"p1"}, {"p2"}])
([0, 1, 1, 2], [0.0, 0.0, 1.0])
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from symlearn.errors import DataError
from symlearn.logic.automata import RewardMachine
from symlearn.logic.guards import Guard


def infer_transitions(words: Iterable[Sequence[Iterable[str]]], state_of: Mapping[str, int],
                      initial: int) -> dict[tuple[int, str], int]:
    """Algorithm 7.1: ``{(u, p_i): u_i}`` from label sequences (see the module docstring)."""
    delta: dict[tuple[int, str], int] = {}
    for word in words:
        u = initial
        for label in word:
            for p in sorted(label):
                if p not in state_of:
                    raise DataError(f"proposition {p!r} names no machine state")
                if state_of[p] == u:
                    continue
                delta.setdefault((u, p), state_of[p])
                u = delta[(u, p)]
    return delta


def machine_from_edges(propositions: Sequence[str], edges: Mapping[tuple[int, str], int], initial: int,
                       accepting: Iterable[int], *, reward: float = 1.0, state_names: Sequence[str] | None = None
                       ) -> RewardMachine:
    """The sparse reward machine of ``edges`` over states ``0..len(propositions)-1``."""
    n = len(propositions)
    accepting = frozenset(accepting)
    outgoing: dict[int, list[tuple[str, int]]] = {u: [] for u in range(n)}
    for (u, p), v in sorted(edges.items()):
        outgoing[u].append((p, v))
    transitions = {}
    for u, row in outgoing.items():
        if u in accepting:
            continue  # accepting states are terminal: nothing is read there
        names = [p for p, _ in row]
        transitions[u] = [(Guard.cube({q: q == p for q in names}), v, reward if v in accepting else 0.0)
                          for p, v in row]
    return RewardMachine(propositions, n, initial, transitions, terminal=accepting, accepting=accepting,
                         state_names=state_names)


__all__ = ["infer_transitions", "machine_from_edges"]
