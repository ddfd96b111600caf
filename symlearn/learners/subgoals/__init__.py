"""Sub-goals and their preferred orderings from demonstrations (thesis, chapter 6)."""

from symlearn.learners.subgoals.ordering_automaton import count_orderings, ordering_pdfa, pdfa_from_words
from symlearn.learners.subgoals.pdfa_learner import SubgoalPDFALearner

__all__ = ["SubgoalPDFALearner", "count_orderings", "ordering_pdfa", "pdfa_from_words"]
