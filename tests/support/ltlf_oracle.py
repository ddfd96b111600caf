"""Compare our DFA with MONA's: language (symbolic product) and state counts."""

from __future__ import annotations

from symlearn.logic.automata.dfa import DFA
from symlearn.logic.ltlf.mona import MonaDFA


def compare(ours: DFA, mona: MonaDFA) -> list[str]:
    """Problems found (empty when the languages and state counts agree)."""
    problems = []
    start = (ours.initial, mona.word_start)
    seen, stack = {start}, [start]
    while stack:
        q, m = stack.pop()
        if (q in ours.accepting) != (m in mona.accepting):
            problems.append(f"acceptance differs at ours {q} / MONA {m}")
            break
        for g, t in ours.successors(q):
            for h, u in mona.edges[m]:
                if not (g & h).is_false() and (t, u) not in seen:
                    seen.add((t, u))
                    stack.append((t, u))
    expected = len(mona.word_states())
    if ours.n_states != expected:
        problems.append(f"{ours.n_states} states, MONA's minimal DFA has {expected} (+1 start state)")
    return problems
