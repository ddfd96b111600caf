"""HOA v1 text (the Hanoi Omega-Automata format) for Spot and other HOA readers.

HOA describes ω-automata and has no finite-word acceptance, so we use the common convention
for DFAs in HOA: state-based acceptance with one set (``Acceptance: 1 Inf(0)``, ``acc-name:
Buchi``) whose mark ``{0}`` means *final state*. ``spot.automaton(text)`` reads the file;
read the marks as final states (under Büchi semantics the automaton would mean something
else, so do not feed it to ω-language algorithms unchanged). Propositions are numbered
in sorted order (``AP: 2 "a" "b"``) and guards become HOA label expressions over those
numbers (``[0&!1]``), one edge per target.

>>> from symlearn.logic.automata import DFA
>>> print(DFA({"a"}, 1, 0, [0], {0: [("a", 0)]}).to_hoa(name="G a"))  # doctest: +NORMALIZE_WHITESPACE
HOA: v1
name: "G a"
States: 1
Start: 0
AP: 1 "a"
acc-name: Buchi
Acceptance: 1 Inf(0)
properties: trans-labels explicit-labels state-acc deterministic
--BODY--
State: 0 {0}
[0] 0
--END--
"""

from __future__ import annotations

from symlearn.logic.guards import Guard


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def hoa_label(guard: Guard, index: dict[str, int]) -> str:
    """A HOA label expression for ``guard`` over numbered propositions."""
    if guard.is_true():
        return "t"
    if guard.is_false():
        return "f"
    terms = []
    for cube in guard.cubes():
        literals = [("" if value else "!") + str(index[name]) for name, value in sorted(cube.items())]
        terms.append("&".join(literals))
    if len(terms) == 1:
        return terms[0]
    return " | ".join(f"({t})" if "&" in t else t for t in terms)


def to_hoa(dfa, *, name: str | None = None) -> str:
    props = sorted(dfa.alphabet)
    index = {p: i for i, p in enumerate(props)}
    lines = ["HOA: v1"]
    if name:
        lines.append(f"name: {_quote(name)}")
    lines += [
        f"States: {dfa.n_states}",
        f"Start: {dfa.initial}",
        f"AP: {len(props)}" + "".join(f" {_quote(p)}" for p in props),
        "acc-name: Buchi",
        "Acceptance: 1 Inf(0)",
        "properties: trans-labels explicit-labels state-acc deterministic",
        "--BODY--",
    ]
    for q in dfa.states:
        state_name = f" {_quote(dfa.state_names[q])}" if dfa.state_names else ""
        mark = " {0}" if q in dfa.accepting else ""
        lines.append(f"State: {q}{state_name}{mark}")
        for guard, target in dfa.successors(q):
            lines.append(f"[{hoa_label(guard, index)}] {target}")
    lines.append("--END--")
    return "\n".join(lines) + "\n"
