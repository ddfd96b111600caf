"""LTLf from positive examples only, after Roy, Gaglione, Baharisangari, Neider, Xu and Topcu (AAAI 2023).

With only positive traces, ``true`` is always consistent; Roy et al. therefore ask for a formula
of size at most ``n`` that holds on every positive trace and whose language is *minimal*: no
other consistent formula of size at most ``n`` has a strictly smaller language. They search with
a SAT solver and counterexample words. This module searches the same space with our LTLf core,
by enumeration instead of SAT:

1. *Universe.* A finite set ``R`` of traces stands in for "all traces": every sequence of the
   letters seen in the positives (label sets) of length 1 .. the longest positive, or, when
   that is more than ``universe_limit`` traces, a seeded random sample of them (then the result
   is minimal on the sample only, and says so). Roy et al.'s language is over every letter;
   ``letters`` widens ``R`` to letters the positives never show (say, the labels a world can
   produce), so that excluding what the positives never do (``G !n``) makes a formula more
   specific. With only the positives' letters, such a conjunct changes nothing on ``R``.
2. *Candidates.* Every formula up to ``max_size`` over the operators is enumerated bottom-up
   (:class:`~symlearn.learners.temporal.ltl_enumeration.Enumerator`) on positives + ``R``, one
   per distinct truth-value vector, so two kept candidates differ on some trace of ``R``.
3. *Minimal language.* Among candidates true on every positive, the one accepting the fewest
   traces of ``R`` is inclusion-minimal on ``R`` (a consistent formula whose language is a
   strict subset would accept fewer); ties go to the smaller formula, then to the one found first.

The chosen formula's language is exact (its automaton is :func:`~symlearn.logic.ltlf.translate`),
so how it compares with a true language can be decided (the sub-goal benchmark does).

>>> traces = [[{"a"}, {"b"}], [{"a"}, {"a"}, {"b"}]]
>>> result = learn_positive_only(traces, ["a", "b"], max_size=4)
>>> str(result.formula), result.minimal_on_all_traces
('a & F b', True)
"""

from __future__ import annotations

import itertools
import os
import time
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.temporal.ltl_bitsets import Frame
from symlearn.learners.temporal.ltl_enumeration import Enumerator
from symlearn.logic.ltlf import ast

DEFAULT_OPERATORS = ("!", "X", "F", "G", "&", "|", "U")
_NODES = {"!": ast.Not, "X": ast.Next, "N": ast.WeakNext, "F": ast.Eventually, "G": ast.Always,
          "&": ast.And, "|": ast.Or, "->": ast.Implies, "U": ast.Until, "R": ast.Release,
          "W": ast.WeakUntil, "T": ast.Then}


@dataclass(frozen=True)
class PositiveOnlyResult:
    formula: ast.Formula
    size: int
    accepted_in_universe: int  # traces of the universe the formula holds on
    universe: int  # traces in the universe
    minimal_on_all_traces: bool  # the universe was every trace up to the longest positive
    candidates: int  # distinct formulas enumerated
    complete_up_to: int  # every formula up to this size was enumerated
    seconds: float
    stopped_by: str = "max_size"  # the enumeration's stop: "max_size", "candidate limit", "deadline", ...
    letters: int = 0  # distinct letters the universe is made of

    def as_dict(self) -> dict:
        d = asdict(self)
        d["formula"] = str(self.formula)
        return d


def learn_positive_only(positive: Sequence[Sequence[Iterable[str]]], propositions: Sequence[str], *,
                        max_size: int = 5, operators: Sequence[str] = DEFAULT_OPERATORS,
                        universe_limit: int = 4000, max_candidates: int = 500_000, seed: int = 0,
                        timeout: float | None = None,
                        letters: Iterable[Iterable[str]] | None = None) -> PositiveOnlyResult:
    """The most specific formula of size <= ``max_size`` holding on every positive trace (module doc).

    ``letters``: label sets the universe's traces are made of besides those the positives show
    (default: none). ``timeout`` (seconds) and ``max_candidates`` stop the enumeration early: the
    result is then the best among the formulas enumerated so far (``stopped_by`` says which limit,
    ``complete_up_to`` up to which size the search is exhaustive)."""
    started = time.monotonic()
    positive = [[frozenset(label) for label in trace] for trace in positive]
    if not positive or any(not trace for trace in positive):
        raise DataError("positive-only LTLf learning needs at least one trace, and no empty trace")
    unknown = sorted({p for trace in positive for label in trace for p in label} - set(propositions))
    if unknown:
        raise DataError(f"proposition {unknown[0]!r} is not declared", hint="declared: " + ", ".join(propositions))
    if max_size < 1:
        raise DataError(f"max_size must be at least 1, got {max_size}")
    extra = [frozenset(label) for label in letters or ()]
    undeclared = sorted({p for label in extra for p in label} - set(propositions))
    if undeclared:
        raise DataError(f"letter proposition {undeclared[0]!r} is not declared",
                        hint="declared: " + ", ".join(propositions))
    letters = sorted({label for trace in positive for label in trace} | set(extra), key=lambda s: sorted(s))
    longest = max(len(t) for t in positive)
    total = sum(len(letters) ** n for n in range(1, longest + 1))
    complete = total <= universe_limit
    if complete:
        universe = [list(w) for n in range(1, longest + 1) for w in itertools.product(letters, repeat=n)]
    else:
        rng = np.random.default_rng(seed)
        lengths = rng.integers(1, longest + 1, universe_limit)
        universe = [[letters[i] for i in rng.integers(len(letters), size=n)] for n in lengths]
    frame = Frame.from_traces(positive + universe, propositions)
    atoms = [(name, frame.propositions[name], 1) for name in propositions]
    deadline = None if timeout is None else started + timeout
    search = Enumerator(frame, atoms, operators, lambda v: np.zeros(len(v), dtype=bool),
                        max_candidates=max_candidates, deadline=deadline)
    outcome = search.run(max_size)
    ids, sizes, values = search.all_candidates(first_only=True)
    n_pos = len(positive)
    consistent = values[:, :n_pos].all(axis=1)
    if not consistent.any():  # cannot happen: "true"-like formulas (a | !a) need size 4
        raise DataError(f"no formula of size <= {max_size} holds on every positive trace",
                        hint="raise max_size")
    accepted = values[:, n_pos:].sum(axis=1)
    order = np.lexsort((np.arange(len(ids)), sizes, np.where(consistent, accepted, np.iinfo(np.int64).max)))
    best = int(order[0])
    formula = search.build(int(ids[best]), ast.Prop, lambda op, *kids: _NODES[op](*kids))
    return PositiveOnlyResult(formula, int(sizes[best]), int(accepted[best]), len(universe), complete,
                              outcome.candidates, outcome.complete_up_to, time.monotonic() - started,
                              outcome.stopped_by, len(letters))


class PositiveOnlyLtlLearner(Learner):
    """Roy et al.'s positive-only LTLf as a learner (see the module doc).

    ``fit(sample)``: an :class:`~symlearn.data.ltl_samples.LtlSample` (or its file; negatives, if
    any, are ignored: the method sees positives only), or a list of traces (label sets) with
    ``propositions`` passed as the second argument. Results: ``formula_``, ``search_`` (the
    :class:`PositiveOnlyResult`), ``result_``; ``save(path.ltl)`` writes the formula.
    """

    artefact_suffix = ".ltl"

    def __init__(self, *, max_size: int = 5, operators: Sequence[str] = DEFAULT_OPERATORS,
                 universe_limit: int = 4000, random_state: int = 0, timeout: float | None = None,
                 letters: Sequence[Iterable[str]] | None = None, max_candidates: int = 500_000) -> None:
        self.max_size = max_size
        self.operators = operators
        self.universe_limit = universe_limit
        self.random_state = random_state
        self.timeout = timeout
        self.letters = letters
        self.max_candidates = max_candidates

    @renamed_arguments(sample="demonstrations", propositions="world")
    def fit(self, demonstrations: Any, world: Sequence[str] | None = None) -> PositiveOnlyLtlLearner:
        """Learn from ``demonstrations``: an :class:`LtlSample` (or its path; its positives are used)
        or traces (sequences of label sets); ``world`` names the propositions of traces (default:
        those they show)."""
        from symlearn.data.ltl_samples import LtlSample

        sample, propositions = demonstrations, world
        if isinstance(sample, (str, os.PathLike)):
            from symlearn.data.ltl_samples import load_sample

            sample = load_sample(sample)
        if isinstance(sample, LtlSample):
            traces, propositions = list(sample.positive), list(sample.propositions)
        else:
            traces = list(sample)
            if propositions is None:
                propositions = sorted({p for trace in traces for label in trace for p in label})
        search = learn_positive_only(traces, list(propositions), max_size=self.max_size,
                                     operators=tuple(self.operators), universe_limit=self.universe_limit,
                                     seed=self.random_state, timeout=self.timeout, letters=self.letters,
                                     max_candidates=self.max_candidates)
        self.search_ = search
        self.formula_ = search.formula
        metrics = {k: v for k, v in search.as_dict().items() if k not in ("formula", "seconds")}
        self._set_result(search.formula, str(search.formula) + "\n", metrics=metrics,
                         timings={"total": max(search.seconds, 1e-9)})
        return self
