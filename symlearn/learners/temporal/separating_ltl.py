"""Learn a small LTLf formula that every positive trace satisfies and no negative trace does.

:func:`learn_ltl` works in phases, all on truth values packed as bit words
(:mod:`~symlearn.learners.temporal.ltl_bitsets`), all keeping one candidate per distinct behaviour:

1. **Exact search** (:class:`~symlearn.learners.temporal.ltl_enumeration.Enumerator`): all formulas by
   increasing size over the chosen operators, each represented by its truth values at every
   position of every trace. The first size with a separating candidate gives a smallest formula
   (``optimal=True``).
2. **Narrow search** (when the exact search hits its work limit): the same over ``F X &`` only,
   which reaches deeper on the same budget (sequences like ``F(a & X F(b & X F c))``).
3. **Boolean combination** (anytime): the candidates of both searches only matter at position 0
   of each trace now, so each becomes one bit per trace. Greedy set covers (a conjunction of
   candidates true on every positive that together reject every negative, the dual disjunction,
   and greedy disjunctions of conjunctions and their duals; ``X..X p`` literals make sure traces
   that differ late can still be told apart) give a first answer; then a second size-ordered
   search combines a pool of candidates with ``!``, ``&``, ``|``, ``->`` over those per-trace
   bits, looking for a smaller one. Answers of phases 2 and 3 are flagged ``optimal=False``
   unless the exact phase already proved nothing smaller exists.

Size is the number of nodes of the syntax tree (:func:`symlearn.logic.ltlf.ast.size`:
propositions, constants and every operator count 1, ``a -> b`` is 3), the measure under which
the benchmarks' ``smallest_known_formula`` is compared.

Time: the phases stop by at most 30 %, 55 % and 80 % of ``timeout`` and the set cover by 95 %,
so an answer comes back within the timeout. The result is deterministic as long as the work
limits (``max_work``, ``max_candidates``: they count work, not time) bind before those
deadlines, which is the case on an unloaded machine with the defaults; on a heavily loaded
machine a deadline may cut a phase at a different point.

>>> pos = [[{"a"}, {"b"}], [set(), {"a"}, {"b"}]]
>>> neg = [[{"b"}, {"a"}], [{"a"}], [set(), {"b"}]]
>>> result = learn_ltl(pos, neg)
>>> str(result.formula), result.size, result.optimal
('F(a & F b)', 5, True)
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.data.ltl_samples import LtlSample, sample_from_traces
from symlearn.errors import SymlearnError
from symlearn.learners.base import Learner
from symlearn.learners.fit_arguments import renamed_arguments
from symlearn.learners.temporal.ltl_bitsets import BINARY, UNARY, Frame, _pack, first_bits, unpack
from symlearn.learners.temporal.ltl_enumeration import Enumerator
from symlearn.logic.ltlf import ast

__all__ = ["learn_ltl", "learn_from_sample", "LearnResult", "SeparatingLtlLearner", "DEFAULT_OPERATORS", "OPERATORS"]

OPERATORS = UNARY + BINARY
#: the operators of the public benchmarks' formulas (``X`` is the strong next)
DEFAULT_OPERATORS = ("!", "X", "F", "G", "&", "|", "->", "U")
_BOOLEAN = ("!", "&", "|", "->")
_FRAGMENT = ("F", "X", "&")

_NODES = {"!": ast.Not, "X": ast.Next, "N": ast.WeakNext, "F": ast.Eventually, "G": ast.Always,
          "&": ast.And, "|": ast.Or, "->": ast.Implies, "U": ast.Until, "R": ast.Release,
          "W": ast.WeakUntil, "T": ast.Then}


@dataclass(frozen=True)
class LearnResult:
    """What :func:`learn_ltl` found.

    ``formula`` is ``None`` when no separating formula was found within ``max_size`` and the
    limits; ``optimal`` is True when no smaller formula over the operators exists (for a
    ``None`` formula: when it is proven that none of size ``<= max_size`` exists).
    """

    formula: ast.Formula | None
    size: int | None
    optimal: bool
    seconds: float
    candidates_explored: int
    max_size: int
    exhaustive_up_to: int  # every formula of at most this size was checked
    stopped_by: str
    method: str  # "enumeration", "set cover", "boolean search" or "none"

    @property
    def message(self) -> str:
        if self.formula is not None:
            kind = "smallest" if self.optimal else "not proven smallest"
            return f"{self.formula} (size {self.size}, {kind}, {self.seconds:.2f} s)"
        if self.optimal:
            return f"no formula up to size {self.max_size} separates the sample"
        return (f"no formula found within the limits (every formula up to size {self.exhaustive_up_to} was "
                f"checked; stopped by {self.stopped_by})")

    def to_json(self) -> dict:
        return {"formula": None if self.formula is None else str(self.formula), "size": self.size,
                "optimal": self.optimal, "seconds": round(self.seconds, 4),
                "candidates_explored": self.candidates_explored, "exhaustive_up_to": self.exhaustive_up_to,
                "method": self.method, "message": self.message}


def learn_ltl(positive_traces: Iterable[Iterable[Iterable[str]]], negative_traces: Iterable[Iterable[Iterable[str]]],
              *, propositions: Sequence[str] | None = None, max_size: int = 40, timeout: float = 10.0,
              operators: Sequence[str] = DEFAULT_OPERATORS, max_work: float = 3e7,
              max_candidates: int = 400_000, pool_size: int = 600) -> LearnResult:
    """A formula true on every positive and false on every negative trace, as small as found.

    Traces are sequences of label sets (the propositions true at each step). ``max_work``
    bounds the exact phase (words evaluated, about 30 ns each), ``max_candidates`` its memory
    (``candidates x traces x ceil(length/64) x 8`` bytes), ``pool_size`` the candidates the
    Boolean phase combines. Raises :class:`~symlearn.errors.DataError` for an empty class, a
    contradictory sample or (with ``propositions``) an unknown proposition.
    """
    sample = sample_from_traces(positive_traces, negative_traces, propositions=propositions)
    return learn_from_sample(sample, max_size=max_size, timeout=timeout, operators=operators, max_work=max_work,
                             max_candidates=max_candidates, pool_size=pool_size)


def learn_from_sample(sample: LtlSample, *, max_size: int = 40, timeout: float = 10.0,
                      operators: Sequence[str] = DEFAULT_OPERATORS, max_work: float = 3e7,
                      max_candidates: int = 400_000, pool_size: int = 600) -> LearnResult:
    """:func:`learn_ltl` on a loaded :class:`~symlearn.data.ltl_samples.LtlSample`."""
    unknown = [op for op in operators if op not in OPERATORS]
    if unknown:
        raise SymlearnError(f"unknown operator {unknown[0]!r}", hint=f"choose among {' '.join(OPERATORS)}")
    if max_size < 1:
        raise SymlearnError(f"max_size must be at least 1, not {max_size}")
    start = time.monotonic()
    deadline = start + 0.8 * timeout
    traces = list(sample.positive) + list(sample.negative)
    n_pos = len(sample.positive)
    frame = Frame.from_traces(traces, sample.propositions)
    target = np.zeros(len(traces), dtype=bool)
    target[:n_pos] = True

    def separates(values: np.ndarray) -> np.ndarray:
        return (first_bits(values) == target).all(axis=1)

    atoms = [(name, frame.propositions[name], 1) for name in sample.propositions]
    exact = Enumerator(frame, atoms, operators, separates, max_candidates=max_candidates, max_work=max_work,
                       deadline=start + 0.3 * timeout)
    outcome = exact.run(max_size)

    def finish(formula, size, method, explored, stopped_by):
        optimal = size is not None and size <= outcome.complete_up_to + 1
        if formula is None:
            optimal = outcome.complete_up_to >= max_size
        return LearnResult(formula, size, optimal, time.monotonic() - start, explored, max_size,
                           outcome.complete_up_to, stopped_by, method)

    sources = [exact]

    def build(cid: int) -> ast.Formula:
        if cid < 0:
            return extras[-cid - 1][0]
        for search in sources:
            if cid < search.stored:
                return search.build(cid, ast.Prop, lambda op, *kids: _NODES[op](*kids))
            cid -= search.stored
        raise IndexError(cid)

    if outcome.solution is not None:
        return finish(build(outcome.solution), outcome.solution_size, "enumeration", outcome.evaluated, "solution")
    if outcome.stopped_by == "max_size":
        return finish(None, None, "none", outcome.evaluated, "max_size")
    explored = outcome.evaluated

    # A narrower operator set reaches deeper (sequences such as F(a & X F(b & X F c))) on the same budget.
    found = None
    fragment = tuple(op for op in _FRAGMENT if op in operators)
    if len(fragment) >= 2 and len(fragment) < len(operators):
        narrow = Enumerator(frame, atoms, fragment, separates, max_candidates=max_candidates, max_work=max_work,
                            deadline=start + 0.55 * timeout)
        narrow_outcome = narrow.run(max_size)
        explored += narrow_outcome.evaluated
        if narrow_outcome.solution is not None:
            found = narrow.build(narrow_outcome.solution, ast.Prop, lambda op, *kids: _NODES[op](*kids))
        sources.append(narrow)

    extras = _positional_literals(frame, sample.propositions, outcome.complete_up_to)
    limit = max_size if found is None else ast.size(found) - 1  # the combination must beat the narrow answer
    best = _combine(sources, extras, target, limit, pool_size, deadline, max_work, start + 0.95 * timeout)
    explored += best.explored
    if best.formula_ids is None:
        if found is not None:
            return finish(found, ast.size(found), "enumeration (F, X, &)", explored, outcome.stopped_by)
        return finish(None, None, "none", explored, outcome.stopped_by)
    formula = best.formula_ids(build)
    return finish(formula, ast.size(formula), best.method, explored, outcome.stopped_by)


@dataclass
class _Combination:
    formula_ids: object  # callable(build) -> Formula, or None
    size: int | None
    method: str
    explored: int


def _positional_literals(frame: Frame, propositions: Sequence[str], complete_up_to: int):
    """``X X ... X p`` and ``X ... X !p`` with their first-position values, for every step and proposition.

    The exact phase covers those no larger than ``complete_up_to``; the longer ones let the
    set cover tell apart traces that differ only late (at the price of a large formula).
    """
    extras = []
    valid = unpack(frame.mask, frame.length)
    for step in range(frame.length):
        for name in propositions:
            at_step = unpack(frame.propositions[name], frame.length)[:, step]
            for negated in (False, True):
                size = step + 1 + negated
                if size <= complete_up_to:
                    continue
                formula: ast.Formula = ast.Prop(name)
                formula = ast.Not(formula) if negated else formula
                for _ in range(step):
                    formula = ast.Next(formula)
                extras.append((formula, (at_step != negated) & valid[:, step], size))
    return extras


def _combine(sources: list[Enumerator], extras: list, target: np.ndarray, max_size: int, pool_size: int,
             deadline: float, max_work: float, hard_deadline: float) -> _Combination:
    """Phase 2: Boolean combinations of the exact phases' candidates, judged at position 0 only.

    Candidate ids run through the sources one after the other; extras get negative ids.
    """
    parts, offset = [], 0
    for search in sources:
        ids, sizes, first = search.all_candidates(first_only=True)  # first: (k, n) values at position 0
        parts.append((ids + offset, sizes, first))
        offset += search.stored
    if extras:
        parts.append((-1 - np.arange(len(extras)), np.array([size for _, _, size in extras]),
                      np.stack([bits for _, bits, _ in extras])))
    ids, sizes, first = (np.concatenate(column) for column in zip(*parts))
    by_size = np.argsort(sizes, kind="stable")
    ids, sizes, first = ids[by_size], sizes[by_size], first[by_size]
    # one candidate per distinct first-position behaviour (the smallest: candidates come in size order)
    _, keep = np.unique(np.packbits(first, axis=1), axis=0, return_index=True)
    keep.sort()
    constant = first[keep].all(axis=1) | ~first[keep].any(axis=1)
    keep = keep[~constant]
    ids, sizes, first = ids[keep], sizes[keep], first[keep]
    pos, neg = target, ~target
    best = _Combination(None, None, "none", 0)

    for groups, outer, inner in ((_greedy_cover(first, sizes, pos, neg, conjunction=True), ast.And, ast.And),
                                 (_greedy_cover(first, sizes, pos, neg, conjunction=False), ast.Or, ast.Or),
                                 (_greedy_two_level(first, sizes, pos, neg, hard_deadline), ast.Or, ast.And),
                                 (_greedy_two_level(~first, sizes, neg, pos, hard_deadline), ast.And, ast.Or)):
        if groups is None:
            continue
        size = sum(int(sizes[c].sum()) + len(c) - 1 for c in groups) + len(groups) - 1
        if size <= max_size and (best.size is None or size < best.size):
            nested = [[int(ids[c]) for c in group] for group in groups]
            best = _Combination(_nested(nested, outer, inner), size, "set cover", 0)

    bound = max_size if best.size is None else best.size - 1
    smallest_atom = int(sizes.min()) if len(sizes) else bound + 1
    if bound <= smallest_atom or time.monotonic() > deadline:
        return best
    pool = _choose_pool(first, sizes, pos, neg, pool_size)
    frame = Frame.from_columns(len(target))
    padded = np.zeros((len(pool), frame.shape[1] * 64), dtype=bool)
    padded[:, :len(target)] = first[pool]
    bits = _pack(padded).reshape(len(pool), 1, -1)
    goal_bits = np.zeros((1, frame.shape[1] * 64), dtype=bool)
    goal_bits[0, :len(target)] = target
    goal = _pack(goal_bits)

    def solves(batch: np.ndarray) -> np.ndarray:
        return (batch == goal).all(axis=(1, 2))

    atoms = [(int(ids[p]), bits[i], int(sizes[p])) for i, p in enumerate(pool)]
    search = Enumerator(frame, atoms, _BOOLEAN, solves, max_candidates=300_000, max_work=max_work / 2,
                        deadline=deadline)
    outcome = search.run(bound)
    best.explored = outcome.evaluated
    if outcome.solution is not None:
        solution = outcome.solution

        def rebuild(build):
            return search.build(solution, build, lambda op, *kids: _NODES[op](*kids))

        return _Combination(rebuild, outcome.solution_size, "boolean search", outcome.evaluated)
    return best


def _nested(groups: list[list[int]], outer, inner):
    """``outer`` over groups of ``inner`` over candidates, e.g. a disjunction of conjunctions."""

    def rebuild(build):
        def join(node, parts):
            formula = parts[0]
            for part in parts[1:]:
                formula = node(formula, part)
            return formula

        return join(outer, [join(inner, [build(c) for c in group]) for group in groups])

    return rebuild


def _greedy_cover(first: np.ndarray, sizes: np.ndarray, pos: np.ndarray, neg: np.ndarray, *,
                  conjunction: bool) -> list[list[int]] | None:
    """Candidates whose conjunction (disjunction) separates: greedy weighted set cover.

    For a conjunction every chosen candidate must hold on all positives, and together they must
    reject every negative; the greedy step picks the most newly rejected negatives per node.
    """
    keep_class, cover_class = (pos, neg) if conjunction else (neg, pos)
    truth = first if conjunction else ~first
    usable = np.flatnonzero(truth[:, keep_class].all(axis=1))
    if not len(usable):
        return None
    covers = ~truth[usable][:, cover_class]  # which traces of the other class each candidate settles
    uncovered = np.ones(covers.shape[1], dtype=bool)
    chosen: list[int] = []
    while uncovered.any():
        gain = (covers & uncovered).sum(axis=1)
        score = gain / sizes[usable]
        pick = int(np.argmax(score))
        if gain[pick] == 0:
            return None
        chosen.append(int(usable[pick]))
        uncovered &= ~covers[pick]
    return [chosen] if conjunction else [[c] for c in chosen]


def _greedy_two_level(first: np.ndarray, sizes: np.ndarray, pos: np.ndarray, neg: np.ndarray,
                      deadline: float) -> list[list[int]] | None:
    """A disjunction of conjunctions of candidates that separates, built greedily.

    Each term starts from the positives not yet covered and adds the candidate that rejects the
    most remaining negatives times the positives it keeps, per node, until no negative is left;
    the positives it keeps are then covered. (Called with ``~first`` and the classes swapped, it
    gives the dual conjunction of disjunctions.)
    """
    # packed bits and popcounts: the loop below scores every candidate once per step
    on_pos = np.packbits(first[:, pos], axis=1)
    on_neg = np.packbits(first[:, neg], axis=1)
    off_neg = np.packbits(~first[:, neg], axis=1)
    uncovered = np.packbits(np.ones(int(pos.sum()), dtype=bool))
    all_neg = np.packbits(np.ones(int(neg.sum()), dtype=bool))
    terms: list[list[int]] = []
    while uncovered.any():
        kept, left = uncovered.copy(), all_neg.copy()
        term: list[int] = []
        while left.any():
            if time.monotonic() > deadline:
                return None
            keeps = np.bitwise_count(on_pos & kept).sum(axis=1, dtype=np.int64)
            rejects = np.bitwise_count(off_neg & left).sum(axis=1, dtype=np.int64)
            score = keeps * keeps * rejects / sizes
            pick = int(np.argmax(score))
            if score[pick] == 0:
                return None
            term.append(pick)
            kept &= on_pos[pick]
            left &= on_neg[pick]
        terms.append(term)
        uncovered &= ~kept
    return terms


def _choose_pool(first: np.ndarray, sizes: np.ndarray, pos: np.ndarray, neg: np.ndarray, limit: int) -> np.ndarray:
    """At most ``limit`` candidates for the Boolean search: one-sided ones first, then by size."""
    one_sided = first[:, pos].all(axis=1) | ~first[:, neg].any(axis=1)
    order = np.lexsort((np.arange(len(sizes)), sizes, ~one_sided))
    half = np.flatnonzero(one_sided[order]).size
    primary = order[:min(half, limit // 2)]
    rest = order[half:][: limit - len(primary)]
    pool = np.concatenate([primary, rest])
    return pool[np.lexsort((pool, sizes[pool]))]


class SeparatingLtlLearner(Learner):
    """``SeparatingLtlLearner(timeout=5).fit(sample).formula_``: the learner-contract form of
    :func:`learn_from_sample` (the functions stay as one-call conveniences).

    ``fit(sample)``: an :class:`~symlearn.data.ltl_samples.LtlSample` or the path of a sample file.
    Results: ``formula_``, ``optimal_`` (no smaller separating formula exists), ``search_`` (the
    :class:`LearnResult` with sizes and counts), ``result_``; ``save(path)`` writes the formula.
    """

    artefact_suffix = ".ltl"

    def __init__(self, *, max_size: int = 40, timeout: float = 10.0, operators: Sequence[str] = DEFAULT_OPERATORS,
                 max_work: float = 3e7) -> None:
        self.max_size = max_size
        self.timeout = timeout
        self.operators = operators
        self.max_work = max_work

    @renamed_arguments(sample="demonstrations", domain="world")
    def fit(self, demonstrations: LtlSample | str | os.PathLike, world: Any = None) -> SeparatingLtlLearner:
        """Learn from ``demonstrations``, an :class:`LtlSample` or the path of one; ``world`` is not
        used: the sample carries its propositions."""
        sample = demonstrations
        if not isinstance(sample, LtlSample):
            from symlearn.data.ltl_samples import load_sample

            sample = load_sample(sample)
        search = learn_from_sample(sample, max_size=self.max_size, timeout=self.timeout,
                                   operators=tuple(self.operators), max_work=self.max_work)
        self.search_ = search
        self.formula_ = search.formula
        self.optimal_ = search.optimal
        metrics = {k: v for k, v in search.to_json().items() if k not in ("formula", "seconds")}
        self._set_result(search.formula, "" if search.formula is None else str(search.formula) + "\n",
                         metrics=metrics, timings={"total": search.seconds})
        return self
