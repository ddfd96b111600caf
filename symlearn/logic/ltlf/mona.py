"""LTLf2DFA + MONA as an independent oracle (optional engine ``mona``).

LTLf2DFA turns a formula into a MONA program; MONA builds the minimal DFA of its models. We
run MONA ourselves on that program (LTLf2DFA's own ``to_dfa`` writes a fixed file inside its
package folder, which races when two runs overlap) and read MONA's transition table exactly,
without LTLf2DFA's sympy rewriting of guards.

MONA's conventions, and how they map to ours:

* MONA's state 0 is an extra start state that reads a dummy first position; its one edge
  leads to the state where the word starts (LTLf2DFA's DOT drops state 0 and starts there).
  So MONA's automaton of an LTLf formula has our state count **plus one**, except when the
  language is empty including the empty word: then MONA prints a single looping state 0
  ("Formula is unsatisfiable") and both counts are 1.
* The sink is explicit in both (MONA's automata are complete, like ours).
* The empty word is decided the same way (negation as complement, see
  :func:`symlearn.logic.ltlf.progression.holds_at_end`).
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
import time
from dataclasses import dataclass

from symlearn.errors import ModelError
from symlearn.logic.guards import Guard
from symlearn.logic.ltlf.ast import (
    Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release, Then, Until,
    WeakNext, WeakUntil, propositions, subformulas,
)

__all__ = ["MonaDFA", "mona_dfa", "to_ltlf2dfa_text", "ltlf2dfa_dot"]


@dataclass(frozen=True)
class MonaDFA:
    """MONA's automaton read back: states as MONA numbers them (0 is its dummy start)."""

    n_states: int
    accepting: frozenset[int]
    edges: dict[int, list[tuple[Guard, int]]]
    seconds: float

    @property
    def word_start(self) -> int:
        """The state where the first letter of a word is read (the successor of MONA's state 0)."""
        return self.edges[0][0][1]

    def word_states(self) -> set[int]:
        seen, stack = {self.word_start}, [self.word_start]
        while stack:
            q = stack.pop()
            for _, t in self.edges.get(q, []):
                if t not in seen:
                    seen.add(t)
                    stack.append(t)
        return seen


# LTLf2DFA has no W or T: they are spelled out (a W b = (a U b) | G a, a T b = F(a & X F b))
_LTLF2DFA_TEMPLATES = {
    Not: "!({0})", Next: "X({0})", WeakNext: "WX({0})", Eventually: "F({0})", Always: "G({0})",
    And: "({0}) & ({1})", Or: "({0}) | ({1})", Implies: "({0}) -> ({1})", Iff: "({0}) <-> ({1})",
    Until: "({0}) U ({1})", Release: "({0}) R ({1})", WeakUntil: "(({0}) U ({1})) | G({0})",
    Then: "F(({0}) & X(F({1})))",
}


def to_ltlf2dfa_text(formula: Formula, names: dict[str, str]) -> str:
    """Fully parenthesised text in LTLf2DFA's syntax (only its core operators), renaming propositions."""
    text: dict[int, str] = {}
    for node in subformulas(formula):
        c = [text[id(x)] for x in node.children()]
        if isinstance(node, Const):
            t = "true" if node.value else "false"
        elif isinstance(node, Prop):
            t = names[node.name]
        else:
            t = _LTLF2DFA_TEMPLATES[type(node)].format(*c)
        text[id(node)] = t
    return text[id(formula)]


def _program(formula: Formula, printed: bool) -> tuple[str, dict[str, str]]:
    from ltlf2dfa.base import MonaProgram
    from ltlf2dfa.parser.ltlf import LTLfParser

    if printed:  # our printer's ltlf2dfa dialect, as a user would hand it to LTLf2DFA
        from symlearn.logic.ltlf.printer import to_string

        names = {name: name for name in propositions(formula)}
        text = to_string(formula, "ltlf2dfa")
    else:
        names = {name: f"p{i}" for i, name in enumerate(sorted(propositions(formula)))}
        text = to_ltlf2dfa_text(formula, names)
    return MonaProgram(LTLfParser()(text)).mona_program(), names


def mona_dfa(formula: Formula, *, timeout: float = 120.0, printed: bool = False) -> MonaDFA:
    """Translate with LTLf2DFA + MONA; ``seconds`` is the wall time of the whole round trip.

    By default the formula reaches LTLf2DFA fully parenthesised with renamed propositions;
    ``printed=True`` sends ``to_string(formula, "ltlf2dfa")`` instead (plain lowercase names and
    LTLf2DFA's operators only), which tests that dialect against LTLf2DFA's own parser.
    """
    start = time.perf_counter()
    program, names = _program(formula, printed)
    upper = {v.upper(): k for k, v in names.items()}
    fd, path = tempfile.mkstemp(suffix=".mona")
    try:
        with os.fdopen(fd, "w") as handle:
            handle.write(program)
        result = subprocess.run(["mona", "-q", "-u", "-w", path], capture_output=True, text=True, timeout=timeout)
    finally:
        os.unlink(path)
    seconds = time.perf_counter() - start
    return _read_mona(result.stdout, upper, seconds)


def _read_mona(output: str, upper: dict[str, str], seconds: float) -> MonaDFA:
    free = re.search(r"DFA for formula with free variables:[ \t]*(.*)", output)
    count = re.search(r"Automaton has (\d+) states?", output)
    accepting = re.search(r"Accepting states:[ \t]*(.*)", output)
    if not (free and count and accepting):
        raise ModelError(f"could not read MONA's output: {output[:300]!r}")
    variables = [upper[v] for v in free.group(1).split()]
    edges: dict[int, list[tuple[Guard, int]]] = {}
    for m in re.finditer(r"^State (\d+):\s*([01X]*)\s*-> state (\d+)", output, re.MULTILINE):
        literals = {v: bit == "1" for v, bit in zip(variables, m.group(2)) if bit != "X"}
        edges.setdefault(int(m.group(1)), []).append((Guard.cube(literals), int(m.group(3))))
    return MonaDFA(int(count.group(1)), frozenset(int(s) for s in accepting.group(1).split()), edges, seconds)


def ltlf2dfa_dot(formula: Formula) -> tuple[str, float]:
    """LTLf2DFA's own end-to-end ``to_dfa`` (DOT text) and its wall time: the peer as users run it."""
    from ltlf2dfa.parser.ltlf import LTLfParser

    names = {name: f"p{i}" for i, name in enumerate(sorted(propositions(formula)))}
    start = time.perf_counter()
    dot = LTLfParser()(to_ltlf2dfa_text(formula, names)).to_dfa()
    return dot, time.perf_counter() - start
