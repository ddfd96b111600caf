"""LTLf: formulas, parsing and printing in three dialects, semantics, progression, simplification
and translation to minimal DFAs.

>>> from symlearn.logic.ltlf import parse, holds, translate
>>> f = parse("G(!hole) & F goal")
>>> holds(f, [{"start"}, set(), {"goal"}])
True
>>> translate(f).n_states
3

Modules: ``ast`` (nodes), ``parser`` / ``printer`` (dialects ours, spot, ltlf2dfa; ``fast_parser``
reads well-formed formulas without lark),
``semantics`` (``holds``), ``vectorized`` (one formula on many traces), ``progression``,
``simplify``, ``to_dfa`` (LTLf -> minimal :class:`~symlearn.logic.automata.DFA`; ``conjunct_bound``, its
refusal before the work), ``mona`` (LTLf2DFA + MONA oracle adapter).
Heavy or optional pieces (numpy evaluation, sympy, MONA) load only when used.
"""

from symlearn.logic.ltlf.ast import (
    FALSE, TRUE, Always, And, Const, Eventually, Formula, Iff, Implies, Next, Not, Or, Prop, Release,
    Then, Until, WeakNext, WeakUntil, operator_count, propositions, size, temporal_depth,
)
from symlearn.logic.ltlf.parser import DIALECTS, parse
from symlearn.logic.ltlf.printer import to_latex, to_string
from symlearn.logic.ltlf.progression import holds_at_end, progress
from symlearn.logic.ltlf.semantics import holds
from symlearn.logic.ltlf.simplify import simplify
from symlearn.logic.ltlf.to_dfa import equivalent, to_dfa, translate

__all__ = [
    "Formula", "Const", "Prop", "Not", "And", "Or", "Implies", "Iff", "Next", "WeakNext", "Eventually",
    "Always", "Until", "Release", "WeakUntil", "Then", "TRUE", "FALSE", "size", "operator_count",
    "temporal_depth", "propositions", "DIALECTS", "parse", "to_string", "to_latex", "holds", "holds_at_end",
    "progress", "simplify", "translate", "to_dfa", "equivalent", "evaluate_many",
]


def evaluate_many(formula, traces):
    """Vectorised verdicts of ``formula`` on many traces (see :mod:`.vectorized`)."""
    from symlearn.logic.ltlf.vectorized import evaluate_many as _evaluate_many

    return _evaluate_many(formula, traces)
