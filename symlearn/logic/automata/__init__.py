"""Automata over proposition alphabets: DFA, PDFA, reward machines, and their file formats.

>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.guards import Guard
>>> DFA({"a"}, 1, 0, [0], {0: [(Guard.var("a"), 0)]}).accepts([{"a"}, {"a"}])
True

Modules: ``dfa`` (the DFA class), ``operations`` (completion, minimisation, products, shortest
words, equivalence), ``transition_diagram`` (symbolic transitions: one shared decision diagram
per automaton, successor states as leaves), ``pdfa``, ``reward_machine``, ``explain`` (why a
trace fails, shortest fix), ``dot_export``, ``json_format`` (versioned JSON,
``load_automaton``), ``hoa_export``, ``mona_dot_import`` (DOT from MONA/LTLf2DFA) and
``rm_text_import`` (reward-machines text).

The names below are imported on first use, so ``import symlearn.logic.automata.dfa`` (what the
LTLf translation and the CLI need) does not load the readers, PDFAs and reward machines.
"""

import importlib

# eager: the function shares its name with its module, and a lazy attribute would be shadowed
# by the module once anything imports symlearn.logic.automata.explain (a light module)
from symlearn.logic.automata.explain import Explanation, explain

_EXPORTS = {
    "DFA": "dfa", "PDFA": "pdfa", "RewardMachine": "reward_machine", "explain": "explain",
    "Explanation": "explain", "load_automaton": "json_format", "parse_mona_dot": "mona_dot_import",
    "read_mona_dot": "mona_dot_import", "parse_rm_text": "rm_text_import", "read_rm_text": "rm_text_import",
}

__all__ = ["DFA", "PDFA", "RewardMachine", "explain", "Explanation", "load_automaton", "parse_mona_dot",
           "read_mona_dot", "parse_rm_text", "read_rm_text"]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'symlearn.logic.automata' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"symlearn.logic.automata.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
