"""The sub-goal PDFA drawn with sub-goal names and probabilities on the edges.

``PDFA.to_dot`` prints each edge's guard, which for a one-hot letter over ``G`` sub-goals is a
cube of ``G`` literals (``red_0 & !blue_0 & ...``); here the edge says only the sub-goal, its
probability and, when counts are given, how many demonstrations took it. States are named by
their sets of completed sub-goals (drawn as ellipses); accepting states have a double outline and
their termination probability; the greedy plan's edges are bold.
"""

from __future__ import annotations

from collections.abc import Sequence

from symlearn.logic.automata.dot_export import automaton_dot


def subgoal_pdfa_dot(pdfa, *, plan_states: Sequence[int] = (), edge_counts=None, title: str | None = None,
                     digits: int = 3) -> str:
    """DOT text of a sub-goal PDFA (see the module doc). ``edge_counts``: ``{(state, sub-goal
    name): count}`` (``OrderingCounts.named_edge_counts()``)."""
    on_plan = set(zip(plan_states, plan_states[1:]))
    edges = []
    for source, guard, target, p in pdfa.edges():
        (symbol,) = guard.satisfying_label()
        label = f"{symbol}\n{p:.{digits}g}"
        if edge_counts is not None:
            label += f" ({edge_counts.get((source, symbol), 0)})"
        edges.append((source, label, target))
    stops = [f"stop {p:.{digits}g}" if p > 0 else "" for p in pdfa.termination]
    dot = automaton_dot(pdfa.n_states, pdfa.initial, edges, names=pdfa.state_names, accepting=pdfa.accepting,
                        extra_labels=stops, title=title)
    # bold the plan's edges: automaton_dot writes "  s -> t [label=...];" lines
    # state names are sets of sub-goals: ellipses stay compact where circles grow with the name
    dot = dot.replace("node [shape=circle", "node [shape=ellipse").replace("shape=doublecircle", "peripheries=2")
    lines = []
    for line in dot.splitlines():
        head = line.strip().split(" [", 1)[0]
        if "->" in head and not head.startswith("__start"):
            s, t = (int(x) for x in head.split(" -> "))
            if (s, t) in on_plan:
                line = line[:-2] + ", penwidth=2.5];"
        lines.append(line)
    return "\n".join(lines) + "\n"
