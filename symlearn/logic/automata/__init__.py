"""Automata over proposition alphabets: DFA, PDFA, reward machines, and their file formats.

>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.guards import Guard
>>> DFA({"a"}, 1, 0, [0], {0: [(Guard.var("a"), 0)]}).accepts([{"a"}, {"a"}])
True
"""

from symlearn.logic.automata.dfa import DFA

__all__ = ["DFA"]
