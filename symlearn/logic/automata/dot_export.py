"""Graphviz DOT text for DFAs, PDFAs and reward machines.

Layout conventions, the same for every automaton kind: left-to-right, an arrow from an
invisible point into the initial state, accepting states double-circled, states that can no
longer reach acceptance (rejecting sinks) drawn grey, terminal states of a reward machine
filled. Edge labels are the guards as printed by :class:`~symlearn.logic.guards.Guard`
(a minimal sum of products), followed by ``/ p`` (probability) or ``/ r`` (reward) where the
kind has them.

>>> from symlearn.logic.automata import DFA
>>> print(DFA({"a"}, 1, 0, [0], {0: [("a", 0)]}).to_dot())  # doctest: +NORMALIZE_WHITESPACE
digraph automaton {
  rankdir=LR;
  node [shape=circle, fontname="Helvetica"];
  edge [fontname="Helvetica"];
  __start [shape=point, width=0.1, label=""];
  0 [label="0", shape=doublecircle];
  __start -> 0;
  0 -> 0 [label="a"];
}
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Sequence

from symlearn.rendering import quote


def automaton_dot(
    n_states: int,
    initial: int,
    edges: Iterable[tuple[int, str, int]],
    *,
    names: Sequence[str] | None = None,
    accepting: Collection[int] = (),
    dead: Collection[int] = (),
    terminal: Collection[int] = (),
    extra_labels: Sequence[str] | None = None,
    title: str | None = None,
) -> str:
    """DOT for states ``0..n_states-1`` and ``(source, label, target)`` edges."""
    lines = ["digraph automaton {", "  rankdir=LR;"]
    if title:
        lines.append(f"  label={quote(title)}; labelloc=t;")
    lines += ['  node [shape=circle, fontname="Helvetica"];', '  edge [fontname="Helvetica"];',
              '  __start [shape=point, width=0.1, label=""];']
    for q in range(n_states):
        label = names[q] if names else str(q)
        if extra_labels and extra_labels[q]:
            label += "\n" + extra_labels[q]
        attributes = [f"label={quote(label)}"]
        if q in accepting:
            attributes.append("shape=doublecircle")
        if q in terminal:
            attributes.append('style=filled, fillcolor="#e8e8e8"')
        if q in dead and q not in accepting:
            attributes.append('color=gray50, fontcolor=gray50')
        lines.append(f"  {q} [{', '.join(attributes)}];")
    lines.append(f"  __start -> {initial};")
    for source, label, target in edges:
        lines.append(f"  {source} -> {target} [label={quote(label)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def guard_text(guard, unicode: bool) -> str:
    return guard.to_text(unicode=unicode)


def dfa_to_dot(dfa, *, title: str | None = None, unicode: bool = False) -> str:
    dead = set(dfa.states) - set(dfa.live_states())
    edges = ((s, guard_text(g, unicode), t) for s, g, t in dfa.edges())
    return automaton_dot(dfa.n_states, dfa.initial, edges, names=dfa.state_names, accepting=dfa.accepting,
                         dead=dead, title=title)


def pdfa_to_dot(pdfa, *, title: str | None = None, unicode: bool = False, digits: int = 3) -> str:
    edges = ((s, f"{guard_text(g, unicode)} / {p:.{digits}g}", t) for s, g, t, p in pdfa.edges())
    stops = [f"stop {p:.{digits}g}" if p > 0 else "" for p in pdfa.termination]
    return automaton_dot(pdfa.n_states, pdfa.initial, edges, names=pdfa.state_names, accepting=pdfa.accepting,
                         extra_labels=stops, title=title)


def reward_machine_to_dot(rm, *, title: str | None = None, unicode: bool = False, digits: int = 3) -> str:
    edges = ((s, f"{guard_text(g, unicode)} / {r:.{digits}g}", t) for s, g, t, r in rm.edges())
    return automaton_dot(rm.n_states, rm.initial, edges, names=rm.state_names, accepting=rm.accepting,
                         terminal=rm.terminal, title=title)
