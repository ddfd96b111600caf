"""Answer set programming core: programs with source maps, the clingo adapter, hypotheses.

Only :mod:`symlearn.logic.asp.clingo_adapter` calls clingo.
"""

from symlearn.logic.asp.clingo_adapter import answer_sets, is_satisfiable, optimize, solve
from symlearn.logic.asp.hypothesis import Hypothesis, rule_length
from symlearn.logic.asp.program import Part, Program, as_program

__all__ = ["Hypothesis", "Part", "Program", "answer_sets", "as_program", "is_satisfiable", "optimize",
           "rule_length", "solve"]
