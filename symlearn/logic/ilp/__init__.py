"""Inductive logic programming: ILASP-compatible task files, mode bias, hypothesis spaces, learner.

>>> from symlearn.logic.ilp import parse_task, learn
>>> task = parse_task("#pos(a, {}, {}, {p(1).}). #neg(b, {}, {}, {p(2).}). #modeb(1, p(const(n))). #constant(n, 2).")
>>> learn(task).hypothesis.rules
[':- p(2).']
"""

from symlearn.logic.ilp.learner import Diagnostics, LearningResult, coverage_matrix, learn, score
from symlearn.logic.ilp.parser import load_task, parse_task
from symlearn.logic.ilp.space import Candidate, HypothesisSpace, generate_space
from symlearn.logic.ilp.task import Example, ILPTask

__all__ = ["Candidate", "Diagnostics", "Example", "HypothesisSpace", "ILPTask", "LearningResult", "coverage_matrix",
           "generate_space", "learn", "load_task", "parse_task", "score"]
