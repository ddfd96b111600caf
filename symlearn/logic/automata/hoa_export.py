"""HOA v1 text (the Hanoi Omega-Automata format) for Spot and other HOA readers.

HOA describes ω-automata: it has no finite-word acceptance, so a DFA cannot be written as
itself. Two encodings, both declared in the file's header (``name`` and a comment), never only
here:

* ``encoding="alive"`` (the default): Spot's convention for LTLf (``spot.from_ltlf``). A fresh
  proposition ``alive`` (``alive_`` ... if the alphabet uses that name) holds along the finite
  word and never after it. Every DFA edge ``[g] q'`` becomes ``[alive & g] q'``, every final
  state gets ``[!alive] end``, and the one extra state ``end`` loops on ``[!alive]`` and is the
  only Büchi-accepting state. The Büchi language is exactly ``{w·∅^ω : w accepted by the
  DFA}`` with ``alive`` true on ``w``, so ω-automata algorithms (Spot's ``product``,
  ``equivalent_to`` against ``from_ltlf(f)``) give the right answers.
* ``encoding="final-marks"``: the states of the DFA only, mark ``{0}`` on final states and
  ``acc-name: Buchi``; this is *not* the DFA's language under Büchi semantics (read the marks as
  final states yourself); the header says so in ``name`` and a comment.

Propositions are numbered in sorted order (``AP: 2 "a" "b"``, then ``alive``) and guards become
HOA label expressions over those numbers (``0&!1``), printed from the guard's compact text, so a
guard with an exponential sum of products stays small here too.

>>> from symlearn.logic.automata import DFA
>>> print(DFA({"a"}, 1, 0, [0], {0: [("a", 0)]}).to_hoa(name="G a"))  # doctest: +NORMALIZE_WHITESPACE
HOA: v1
name: "G a (finite words: alive marks the word, Buchi on end)"
States: 2
Start: 0
AP: 2 "a" "alive"
acc-name: Buchi
Acceptance: 1 Inf(0)
properties: trans-labels explicit-labels state-acc deterministic
/* finite-word DFA encoded as in Spot's from_ltlf: "alive" holds along the word, then never */
--BODY--
State: 0
[0&1] 0
[!1] 1
State: 1 "end" {0}
[!1] 1
--END--
"""

from __future__ import annotations

import re

from symlearn.logic.guards import Guard

__all__ = ["to_hoa", "hoa_label", "ENCODINGS"]

ENCODINGS = ("alive", "final-marks")
_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[A-Za-z_][A-Za-z0-9_]*|\s+')


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def hoa_label(guard: Guard, index: dict[str, int]) -> str:
    """A HOA label expression for ``guard`` over numbered propositions (``t``, ``f``, ``!``,
    ``&``, ``|``, parentheses), read off the guard's printed form."""
    if guard.is_true():
        return "t"
    if guard.is_false():
        return "f"

    def number(match: re.Match) -> str:
        token = match.group(0)
        if token.isspace():
            return ""
        if token in ("true", "false"):
            return token[0]
        name = re.sub(r"\\(.)", r"\1", token[1:-1]) if token.startswith('"') else token
        return str(index[name])

    text = _TOKEN.sub(number, str(guard))
    return text.replace("|", " | ")


def _fresh(name: str, taken) -> str:
    while name in taken:
        name += "_"
    return name


def to_hoa(dfa, *, name: str | None = None, encoding: str = "alive") -> str:
    """The DFA as HOA text in one of :data:`ENCODINGS` (see the module docstring)."""
    if encoding not in ENCODINGS:
        raise ValueError(f"unknown HOA encoding {encoding!r}; use one of {', '.join(ENCODINGS)}")
    props = sorted(dfa.alphabet)
    alive = _fresh("alive", dfa.alphabet) if encoding == "alive" else None
    index = {p: i for i, p in enumerate(props)}
    aps = props + ([alive] if alive else [])
    if alive:
        note = f"finite words: {alive} marks the word, Buchi on end"
        comment = (f"/* finite-word DFA encoded as in Spot's from_ltlf: {_quote(alive)} holds along the word, "
                   "then never */")
    else:
        note = "finite words: marked states are FINAL states, not Buchi-accepting"
        comment = "/* DFA with final states marked {0}; under Buchi semantics this is a different language */"
    end = dfa.n_states
    lines = ["HOA: v1", f"name: {_quote(f'{name} ({note})' if name else note)}"]
    lines += [
        f"States: {dfa.n_states + (1 if alive else 0)}",
        f"Start: {dfa.initial}",
        f"AP: {len(aps)}" + "".join(f" {_quote(p)}" for p in aps),
        "acc-name: Buchi",
        "Acceptance: 1 Inf(0)",
        "properties: trans-labels explicit-labels state-acc deterministic",
        comment,
        "--BODY--",
    ]
    live = str(len(props))
    for q in dfa.states:
        state_name = f" {_quote(dfa.state_names[q])}" if dfa.state_names else ""
        mark = " {0}" if (q in dfa.accepting and not alive) else ""
        lines.append(f"State: {q}{state_name}{mark}")
        for guard, target in dfa.successors(q):
            label = hoa_label(guard, index)
            if alive:
                label = live if label == "t" else f"({label})&{live}" if "|" in label else f"{label}&{live}"
            lines.append(f"[{label}] {target}")
        if alive and q in dfa.accepting:
            lines.append(f"[!{live}] {end}")
    if alive:
        lines += [f'State: {end} "end" {{0}}', f"[!{live}] {end}"]
    lines.append("--END--")
    return "\n".join(lines) + "\n"
