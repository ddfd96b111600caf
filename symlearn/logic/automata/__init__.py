"""Automata over proposition alphabets: DFA, PDFA, reward machines, and their file formats.

>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.guards import Guard
>>> DFA({"a"}, 1, 0, [0], {0: [(Guard.var("a"), 0)]}).accepts([{"a"}, {"a"}])
True

Modules: ``dfa`` (the DFA class), ``operations`` (completion, minimisation, products, shortest
words, equivalence), ``pdfa``, ``reward_machine``, ``explain`` (why a trace fails, shortest
fix), ``dot_export``, ``json_format`` (versioned JSON, ``load_automaton``), ``hoa_export``,
``mona_dot_import`` (DOT from MONA/LTLf2DFA) and ``rm_text_import`` (reward-machines text).
"""

from symlearn.logic.automata.dfa import DFA
from symlearn.logic.automata.explain import Explanation, explain
from symlearn.logic.automata.json_format import load_automaton
from symlearn.logic.automata.mona_dot_import import parse_mona_dot, read_mona_dot
from symlearn.logic.automata.pdfa import PDFA
from symlearn.logic.automata.reward_machine import RewardMachine
from symlearn.logic.automata.rm_text_import import parse_rm_text, read_rm_text

__all__ = ["DFA", "PDFA", "RewardMachine", "explain", "Explanation", "load_automaton", "parse_mona_dot",
           "read_mona_dot", "parse_rm_text", "read_rm_text"]
