"""``learn(task)``: the cheapest hypothesis covering the examples, with diagnostics when none does.

>>> from symlearn.logic.ilp import parse_task
>>> task = parse_task('''
... #pos(p1, {}, {}, { on(1,2). }).
... #neg(n1, {}, {}, { on(2,1). }).
... #modeb(1, on(var(disk), var(disk))).
... #modeb(1, var(disk) < var(disk)).
... ''')
>>> learn(task).hypothesis.rules
[':- on(V1,V2), V2 < V1.']

Two search paths (``method``):

* ``"single"`` -- integrity constraints only and one answer set per context: firing of every
  candidate on every example decided in one grounding, then a set-cover optimisation
  (:mod:`~symlearn.logic.ilp.selection`);
* ``"general"`` -- full ASP semantics by generate-and-test (:mod:`~symlearn.logic.ilp.general`).

``"auto"`` (default) takes the single-grounding path whenever its conditions hold (checked).
"""

from __future__ import annotations

import math
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from symlearn.errors import DataError, LimitExceededError, SymlearnError
from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.hypothesis import Hypothesis
from symlearn.logic.ilp.coverage import rule_acceptance
from symlearn.logic.ilp.encoding import accepted_by
from symlearn.logic.ilp.general import SearchOutcome, search_general
from symlearn.logic.ilp.selection import firing_matrix, select_rules, single_worlds
from symlearn.logic.ilp.settled import unaffected_examples
from symlearn.logic.ilp.space import HypothesisSpace, generate_space
from symlearn.logic.ilp.task import Example, ILPTask

METHODS = ("auto", "single", "general")


@dataclass
class Diagnostics:
    """Why learning failed (or what it had to give up), for people and for JSON."""

    space_size: int = 0
    uncoverable_positives: list[str] = field(default_factory=list)
    # negative -> the positives that every candidate excluding it also excludes (the blockers:
    # each alone makes the negative unexcludable); empty when no single positive does that
    unexcludable_negatives: dict[str, list[str]] = field(default_factory=dict)
    # negative -> positives most often excluded with it, when no single positive blocks every candidate
    frequent_blockers: dict[str, list[str]] = field(default_factory=dict)
    conflicts: list[tuple[str, str]] = field(default_factory=list)  # (positive, negative) indistinguishable
    # hard negatives that every hypothesis of the space accepts (no rule of it can affect them)
    unaffected_negatives: list[str] = field(default_factory=list)
    hints: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    timed_out: bool = False  # the time limit cut the search (the result may not be the best)

    def to_dict(self) -> dict[str, Any]:
        return {"space_size": self.space_size, "uncoverable_positives": self.uncoverable_positives,
                "unexcludable_negatives": self.unexcludable_negatives,
                "frequent_blockers": self.frequent_blockers,
                "conflicts": [list(c) for c in self.conflicts], "unaffected_negatives": self.unaffected_negatives,
                "hints": self.hints, "notes": self.notes,
                "timed_out": self.timed_out}

    def render(self) -> str:
        lines = [f"hypothesis space: {self.space_size} rules"]
        if self.uncoverable_positives:
            lines.append("positives no hypothesis can accept (background + context alone already rejects them): "
                         + ", ".join(self.uncoverable_positives))
        for neg, blockers in self.unexcludable_negatives.items():
            if blockers:
                why = f" (every candidate that excludes it also excludes {_listing(blockers)})"
            elif self.frequent_blockers.get(neg):
                why = (" (every candidate that excludes it also excludes some positive; most often "
                       f"{_listing(self.frequent_blockers[neg])})")
            else:
                why = " (no candidate fires on it)"
            lines.append(f"negative {neg} cannot be excluded{why}")
        if self.unaffected_negatives:
            lines.append("negatives every hypothesis of the space accepts (no rule of it can exclude them): "
                         + _listing(self.unaffected_negatives))
        for pos, neg in self.conflicts:
            lines.append(f"examples {pos} and {neg} conflict: same answer set, one positive, one negative")
        lines += [f"note: {n}" for n in self.notes]
        lines += [f"hint: {h}" for h in self.hints]
        return "\n".join(lines)


def _listing(ids: list[str], shown: int = 5) -> str:
    if len(ids) <= shown:
        return ", ".join(ids)
    return ", ".join(ids[:shown]) + f" and {len(ids) - shown} more"


@dataclass
class LearningResult:
    """What :func:`learn` found. ``hypothesis`` is None when no hypothesis covers the examples."""

    hypothesis: Hypothesis | None
    score: int | None
    optimal: bool
    seconds: float
    space_size: int
    coverage: dict[str, bool]
    diagnostics: Diagnostics
    method: str = "general"
    penalty: int = 0

    @property
    def found(self) -> bool:
        return self.hypothesis is not None

    @property
    def timed_out(self) -> bool:
        """The time limit cut the search: without a hypothesis, time ran out (the bias may be
        fine); with one, it is the best found so far."""
        return self.diagnostics.timed_out

    def to_dict(self) -> dict[str, Any]:
        return {"rules": list(self.hypothesis.rules) if self.hypothesis else [], "score": self.score,
                "optimal": self.optimal, "seconds": round(self.seconds, 4), "space_size": self.space_size,
                "method": self.method, "penalty": self.penalty, "coverage": self.coverage,
                "diagnostics": self.diagnostics.to_dict()}


def _check_examples(task: ILPTask) -> None:
    if not task.examples:
        raise DataError("the task has no examples (#pos/#neg)", file=task.source,
                        hint="add at least one #pos or #neg example")


def learn(task: ILPTask, timeout: float = 30.0, noise: bool = False, *, method: str = "auto",
          max_body: int | None = None, space: HypothesisSpace | None = None) -> LearningResult:
    """Find a minimum-cost hypothesis (see module docstring). Deterministic for the same input.

    ``noise``: examples with a ``@penalty`` may be left uncovered at that cost (bounded by
    ``#max_penalty``); examples without one must be covered. On timeout the best hypothesis
    found so far is returned with ``optimal=False``.
    """
    if method not in METHODS:
        raise SymlearnError(f"unknown method {method!r}", hint=f"use one of {', '.join(METHODS)}")
    start = time.perf_counter()
    deadline = start + _budget(timeout)
    _check_examples(task)
    if space is None:
        space = generate_space(task, max_body=max_body, timeout=deadline - time.perf_counter())
    diagnostics = Diagnostics(space_size=len(space), notes=list(space.notes))
    if len(space) == 0:
        diagnostics.hints.append("the mode bias generates no rule: check that every variable can be bound by a "
                                 "positive body literal, raise #maxv or the recalls, or declare #constant values")
        raise SymlearnError("the mode bias makes the hypothesis space empty"
                            + (f" ({'; '.join(space.notes)})" if space.notes else ""),
                            file=task.source, hint=diagnostics.hints[-1])
    chosen_method = method
    outcome: SearchOutcome | None = None
    if method in ("auto", "single"):
        if not task.constraints_only or not all(c.is_constraint for c in space.candidates):
            if method == "single":
                raise SymlearnError("the single-grounding path needs a space of integrity constraints (no #modeh)")
        else:
            try:
                worlds = single_worlds(task, timeout=max(deadline - time.perf_counter(), 0.001))
            except LimitExceededError:
                diagnostics.notes.append("time limit reached while solving the example contexts")
                diagnostics.timed_out = True
                return LearningResult(None, None, False, time.perf_counter() - start, len(space), {},
                                      diagnostics, "single")
            if worlds is None:
                if method == "single":
                    raise SymlearnError("the single-grounding path needs one answer set per example context; "
                                        "some context has several", hint="use method='general'")
                diagnostics.notes.append("some context has several answer sets: using the general search")
            else:
                chosen_method = "single"
                outcome = _single(task, space, worlds, noise, deadline, diagnostics)
    if outcome is None:
        chosen_method = "general"
        outcome = _settled_outcome(task, space, noise, deadline, diagnostics)
    if outcome is None:
        outcome = search_general(task, space, noise=noise, deadline=deadline)
        if outcome.selected is None and outcome.notes and "no hypothesis" in outcome.notes[-1]:
            _general_diagnostics(task, diagnostics)
    diagnostics.notes.extend(outcome.notes)
    diagnostics.timed_out = diagnostics.timed_out or outcome.timed_out
    seconds = time.perf_counter() - start
    if outcome.selected is None:
        if diagnostics.timed_out:
            diagnostics.hints[:] = ["time ran out before a hypothesis was found: raise the timeout"
                                    + _enumeration_warning(task, space, noise, chosen_method)]
        elif not diagnostics.hints:
            diagnostics.hints.append(_relax_hint(task))
        return LearningResult(None, None, False, seconds, len(space), {}, diagnostics, chosen_method)
    by_index = {c.index: c for c in space.candidates}
    rules = [by_index[r].text for r in outcome.selected]
    hypothesis = Hypothesis(rules, background=task.background, cost=outcome.cost,
                            provenance={"task": task.source, "method": chosen_method, "noise": noise,
                                        "space_size": len(space), "optimal": outcome.optimal})
    uncovered = set(outcome.uncovered)
    coverage = {e.id: e.id not in uncovered for e in task.examples}
    return LearningResult(hypothesis, outcome.cost + outcome.penalty, outcome.optimal, seconds, len(space),
                          coverage, diagnostics, chosen_method, outcome.penalty)


def _single(task: ILPTask, space: HypothesisSpace, worlds, noise: bool, deadline: float,
            diagnostics: Diagnostics) -> SearchOutcome:
    def soft(e) -> bool:
        return noise and e.penalty is not None

    hard_pos, hard_neg = set(), set()
    soft_pos, soft_neg = {}, {}
    extra_penalty = 0
    uncovered_upfront = []
    for i, e in enumerate(task.examples):
        if e.positive:
            if not worlds.extends[i]:
                if soft(e):
                    extra_penalty += e.penalty
                    uncovered_upfront.append(e.id)
                else:
                    diagnostics.uncoverable_positives.append(e.id)
                continue
            (soft_pos.__setitem__(i, e.penalty) if soft(e) else hard_pos.add(i))
        elif worlds.extends[i]:
            (soft_neg.__setitem__(i, e.penalty) if soft(e) else hard_neg.add(i))
    relevant = sorted(hard_pos | hard_neg | set(soft_pos) | set(soft_neg))
    fires = firing_matrix(task, space, worlds, relevant)
    if diagnostics.uncoverable_positives:
        _single_diagnostics(task, space, worlds, fires, hard_pos, hard_neg, diagnostics)
        return SearchOutcome(None, notes=["no hypothesis in the space covers the examples"])
    if time.perf_counter() >= deadline:
        return SearchOutcome(None, notes=["time limit reached before the rule selection"], timed_out=True)
    outcome = select_rules(task, space, fires, noise=noise, hard_pos=hard_pos, soft_pos=soft_pos,
                           hard_neg=hard_neg, soft_neg=soft_neg,
                           timeout=max(deadline - time.perf_counter(), 0.001))
    if outcome.selected is None and outcome.timed_out:
        return outcome
    if outcome.selected is None:
        _single_diagnostics(task, space, worlds, fires, hard_pos, hard_neg, diagnostics)
        return outcome
    outcome.penalty += extra_penalty
    outcome.uncovered = uncovered_upfront + outcome.uncovered
    return outcome


def _single_diagnostics(task, space, worlds, fires, hard_pos, hard_neg, diagnostics: Diagnostics) -> None:
    by_example: dict[int, set[int]] = {}
    for r, row in fires.items():
        for e in row:
            by_example.setdefault(e, set()).add(r)
    for n in sorted(hard_neg):
        rules = by_example.get(n, set())
        if any(not (fires[r] & hard_pos) for r in rules):
            continue
        name = task.examples[n].id
        # the blockers: positives excluded by *every* candidate that excludes n (one of them
        # mislabelled, or lacking the facts that tell it apart, is the usual cause)
        common = set.intersection(*(fires[r] & hard_pos for r in rules)) if rules else set()
        diagnostics.unexcludable_negatives[name] = [task.examples[p].id for p in sorted(common)]
        if rules and not common:
            counts = Counter(p for r in rules for p in fires[r] & hard_pos)
            ranked = sorted(counts, key=lambda p: (-counts[p], p))
            diagnostics.frequent_blockers[name] = [f"{task.examples[p].id} ({counts[p]} of {len(rules)} candidates)"
                                                   for p in ranked[:5]]
    # positives and negatives whose answer sets coincide can never be separated by constraints
    signature: dict[frozenset, list[int]] = {}
    for atom in worlds.atoms:
        signature.setdefault(atom.arguments[0].number, [])
    atoms_of: dict[int, set[str]] = {}
    for atom in worlds.atoms:
        if atom.arguments:
            tag = atom.arguments[0]
            if tag.type == cl.SymbolType.Number:
                atoms_of.setdefault(tag.number, set()).add(f"{atom.name}/{[str(a) for a in atom.arguments[1:]]}")
    groups: dict[frozenset, list[int]] = {}
    for e in sorted(hard_pos | hard_neg):
        groups.setdefault(frozenset(atoms_of.get(e, set())), []).append(e)
    for members in groups.values():
        pos = [e for e in members if e in hard_pos]
        neg = [e for e in members if e in hard_neg]
        for p in pos[:3]:
            for n in neg[:3]:
                diagnostics.conflicts.append((task.examples[p].id, task.examples[n].id))
    blockers = sorted({p for names in diagnostics.unexcludable_negatives.values() for p in names})
    if diagnostics.conflicts:
        diagnostics.hints.append("conflicting examples have the same answer set: fix their labels, add the "
                                 "facts that tell them apart to the contexts, or learn with noise=True and penalties")
    elif blockers:
        negatives = [n for n, names in diagnostics.unexcludable_negatives.items() if names]
        diagnostics.hints.append(f"no rule in the space excludes {_listing(negatives)} without excluding "
                                 f"{_listing(blockers)}: if the labels are right, {_relax_bias(task)} so that a rule "
                                 "can tell them apart; if a label is wrong, fix it or learn with noise=True and "
                                 "penalties")
    elif diagnostics.uncoverable_positives:
        diagnostics.hints.append("a positive example is rejected by the background knowledge and its context alone; "
                                 "check its inclusions/exclusions and the background")
    elif diagnostics.unexcludable_negatives:
        diagnostics.hints.append(_relax_hint(task))


def _settled_outcome(task: ILPTask, space: HypothesisSpace, noise: bool, deadline: float,
                     diagnostics: Diagnostics) -> SearchOutcome | None:
    """A failed outcome when some hard example is accepted or rejected alike by every hypothesis
    of the space, against its label (:mod:`~symlearn.logic.ilp.settled`); else None. Without
    this the general search would enumerate every set of normal rules until the time limit."""
    hard = [e for e in task.examples if not (noise and e.penalty is not None)]
    fixed = unaffected_examples(task, space, hard)
    if not fixed:
        return None
    try:
        verdict = accepted_by(task, [], fixed, timeout=max(deadline - time.perf_counter(), 0.001))
    except SymlearnError:  # undecided in time: let the search (and its time limit) answer
        return None
    negatives = [e.id for e in fixed if not e.positive and verdict[e.id]]
    positives = [e.id for e in fixed if e.positive and not verdict[e.id]]
    if not negatives and not positives:
        return None
    diagnostics.uncoverable_positives.extend(positives)
    diagnostics.unaffected_negatives.extend(negatives)
    named = negatives + positives
    diagnostics.hints.append(f"no rule of the space can change whether {_listing(named)} "
                             f"{'is' if len(named) == 1 else 'are'} accepted: it holds no constraint (a bias "
                             "with #modeh learns normal rules only) and its head predicates occur nowhere in the "
                             "background, these contexts or their inclusions/exclusions; drop #modeh to learn "
                             "constraints, use the heads in the background or the examples, or fix the labels")
    return SearchOutcome(None, notes=["no hypothesis in the space covers the examples"])


def _enumeration_warning(task: ILPTask, space: HypothesisSpace, noise: bool, method: str) -> str:
    """Why raising the timeout may not help: without a constraint in the space, the general search
    rules out one set of normal rules per wrongly accepted negative, up to 2^(rules) rounds."""
    if method != "general" or any(c.is_constraint for c in space.candidates):
        return ""
    hard = [e.id for e in task.negatives if not (noise and e.penalty is not None)]
    if not hard:
        return ""
    return (f"; but the space holds no constraint, so the search rules out one subset of its {len(space)} normal "
            f"rules per round (2^{len(space)} in all): it may hold no hypothesis that excludes {_listing(hard)} "
            "(normal rules exclude a negative only through the background, e.g. a constraint on their head, or "
            "the example's exclusions)")


def _general_diagnostics(task: ILPTask, diagnostics: Diagnostics) -> None:
    """Which positives the background rejects even before any rule (cheap: one call)."""
    try:
        verdict = accepted_by(task, [], task.positives, timeout=10.0)
    except SymlearnError:
        return
    if task.constraints_only:
        diagnostics.uncoverable_positives = [e for e, ok in verdict.items() if not ok]


def _budget(timeout: float | None) -> float:
    """Seconds for a search: None, ``inf`` and huge values mean no limit; NaN is refused."""
    if timeout is None:
        return math.inf
    timeout = float(timeout)
    if math.isnan(timeout):
        raise SymlearnError("timeout must be a number of seconds, not NaN",
                            hint="give a positive number of seconds (None or inf: no limit)")
    return max(timeout, 0.0)


def _relax_bias(task: ILPTask) -> str:
    return (f"relax the bias (raise #maxv (now {task.n_variables}), the recall of #modeb declarations or "
            f"max_body (now {task.max_body}), add modes or #constant values)")


def _relax_hint(task: ILPTask) -> str:
    return f"{_relax_bias(task)}; or use noise=True with penalties"


def score(task: ILPTask, hypothesis: Hypothesis, *, timeout: float | None = 60.0) -> dict[str, Any]:
    """Coverage of each example by ``hypothesis`` (full ASP semantics) and its cost."""
    _check_examples(task)
    accepted = accepted_by(task, hypothesis.program(), task.examples, timeout=timeout)
    coverage = {e.id: (accepted[e.id] if e.positive else not accepted[e.id]) for e in task.examples}
    penalty = sum((e.penalty or 0) for e in task.examples if not coverage[e.id])
    hard_misses = [e.id for e in task.examples if not coverage[e.id] and e.penalty is None]
    return {"coverage": coverage, "covered": sum(coverage.values()), "total": len(coverage),
            "cost": hypothesis.cost, "penalty": penalty, "uncovered_without_penalty": hard_misses,
            "score": None if hard_misses else hypothesis.cost + penalty}


def coverage_matrix(task: ILPTask, hypothesis: Hypothesis, *, timeout: float | None = 60.0,
                    examples: Sequence[Example] | None = None) -> dict[str, dict[str, bool]]:
    """For each rule alone: which examples B ∪ {rule} covers (rows: rules, columns: example ids;
    ``examples``: only those columns). ``timeout``: one budget for the whole matrix."""
    _check_examples(task)
    examples = task.examples if examples is None else list(examples)
    rows = rule_acceptance(task, hypothesis, examples, seconds=_budget(timeout))
    matrix: dict[str, dict[str, bool]] = {}
    for rule, row in zip(hypothesis.rules, rows):
        matrix.setdefault(rule, {e.id: (ok if e.positive else not ok) for e, ok in zip(examples, row)})
    return matrix
