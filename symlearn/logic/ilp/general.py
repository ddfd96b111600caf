"""The general search: full answer-set semantics for any hypothesis space.

One optimisation program holds a copy of B ∪ context per positive example (see
:mod:`~symlearn.logic.ilp.encoding`), every candidate rule guarded by a choice atom ``use__(r)``,
and ``#minimize`` over rule costs (plus penalties of dropped soft positives). Its optimum is the
cheapest hypothesis accepting all positives. Negatives need "no answer set extends it", which is
not expressible in the same program, so the search is iterative (generate and test, with
counterexamples as in ILASP):

1. optimise -> H = N ∪ C (N: rules with heads, C: integrity constraints);
2. check every negative against H in one clingo call, keeping a witness answer set A for each
   negative that H wrongly accepts;
3. for each witness: any H' with the same normal rules N still has A as an answer set unless one
   of its constraints fires on A -- so add the cut "N' = N implies some chosen constraint fires on
   A" (firing of every constraint candidate on A is decided in one grounding). For a hard
   negative the cut is an integrity constraint; a soft negative pays its penalty when the cut's
   condition holds;
4. repeat until the optimum accepts no negative it does not pay for.

Each cut only removes hypotheses that really accept the negative, so the optimiser's costs are
lower bounds and the first hypothesis that passes is optimal. With normal rules in the space a
cut is specific to one set N, so tasks with many negatives and many normal rules need many
rounds; the single-grounding path (:mod:`~symlearn.logic.ilp.selection`) is the fast one.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.encoding import ACTIVE, examples_program, firing_rows, witnesses
from symlearn.logic.ilp.space import HypothesisSpace
from symlearn.logic.ilp.task import ILPTask


@dataclass
class SearchOutcome:
    selected: list[int] | None  # candidate indices; None when no hypothesis exists / was found
    cost: int | None = None
    penalty: int = 0
    optimal: bool = False
    uncovered: list[str] = field(default_factory=list)
    rounds: int = 0
    notes: list[str] = field(default_factory=list)
    timed_out: bool = False  # the time limit cut the search


def _soft(example, noise: bool) -> bool:
    return noise and example.penalty is not None


def search_general(task: ILPTask, space: HypothesisSpace, *, noise: bool, deadline: float) -> SearchOutcome:
    positives = [(i, e) for i, e in enumerate(task.examples) if e.positive]
    negatives = [e for e in task.examples if not e.positive]
    lines = []
    for i, e in positives:
        if _soft(e, noise):
            lines.append(f"{{ ignored__({i}) }}.")
            lines.append(f"{ACTIVE}({i}) :- not ignored__({i}).")
        else:
            lines.append(f"{ACTIVE}({i}).")
    for c in space.candidates:
        lines.append(f"{{ use__({c.index}) }}.")
        lines.append(c.tagged_rule("E__", (f"{ACTIVE}(E__)", f"use__({c.index})")))
    weights = [f"{c.cost},r,{c.index} : use__({c.index})" for c in space.candidates if c.cost]
    weights += [f"{e.penalty},e,{i} : ignored__({i})" for i, e in positives if _soft(e, noise)]
    if weights:
        lines.append("#minimize { " + " ; ".join(weights) + " }.")
    if task.max_penalty is not None and noise:
        soft = [f"{e.penalty},{i} : ignored__({i})" for i, e in positives if _soft(e, noise)]
        if soft:
            lines.append(f":- #sum {{ {' ; '.join(soft)} }} > {task.max_penalty}.")
    lines.append("#show use__/1. #show ignored__/1. #show accepts__/1.")
    lines.append("#defined accepts__/1.")
    program = examples_program(task, positives) + Program.from_text("\n".join(lines), source="<search>")
    optimizer = cl.IncrementalOptimizer(program)
    by_index = {c.index: c for c in space.candidates}
    outcome = SearchOutcome(None)
    constraints = [c for c in space.candidates if c.is_constraint]
    normal = [c for c in space.candidates if not c.is_constraint]
    n_cuts = 0
    while True:
        outcome.rounds += 1
        remaining = deadline - time.perf_counter()
        if remaining <= 0:
            outcome.notes.append("time limit reached before a hypothesis was verified")
            outcome.timed_out = True
            return outcome
        solved = optimizer.optimize(timeout=remaining)
        if not solved.models:
            if solved.complete or solved.satisfiable is False:
                outcome.notes.append("no hypothesis in the space covers the examples")
            else:
                outcome.notes.append("time limit reached before a hypothesis was found")
                outcome.timed_out = True
            return outcome
        model = solved.models[-1]
        chosen = sorted(s.arguments[0].number for s in model if s.name == "use__")
        dropped = [task.examples[s.arguments[0].number] for s in model if s.name == "ignored__"]
        charged = {s.arguments[0].number for s in model if s.name == "accepts__"}
        rules = [by_index[r].text for r in chosen]
        left = deadline - time.perf_counter()
        try:
            found = witnesses(task, rules, negatives, timeout=max(left, 0.001)) if negatives else {}
        except cl.LimitExceededError:
            outcome.notes.append("time limit reached while checking the negative examples")
            outcome.timed_out = True
            return outcome
        wrong = [(j, e) for j, e in enumerate(negatives) if found.get(e.id) is not None]
        unpaid = [(j, e) for j, e in wrong if not _soft(e, noise) or j not in charged]
        if not unpaid:
            outcome.selected = chosen
            outcome.cost = sum(by_index[r].cost for r in chosen)
            outcome.penalty = sum(e.penalty for e in dropped) + sum(e.penalty for _j, e in wrong)
            outcome.uncovered = [e.id for e in dropped] + [e.id for _j, e in wrong]
            outcome.optimal = solved.complete
            outcome.notes.append(f"{outcome.rounds} rounds, {n_cuts} counterexample cuts")
            if not solved.complete:
                outcome.timed_out = True
                outcome.notes.append("time limit reached: best hypothesis found so far, not proven optimal")
            return outcome
        chosen_set = set(chosen)
        same_normal = [f"use__({c.index})" if c.index in chosen_set else f"not use__({c.index})" for c in normal]
        atoms = [a for j, e in unpaid for a in found[e.id]]
        rows = firing_rows(constraints, atoms, [j for j, _e in unpaid])
        fired_on: dict[int, list[int]] = {}
        for r, tags in rows.items():
            for t in tags:
                fired_on.setdefault(t, []).append(r)
        cuts = []
        for j, e in unpaid:
            n_cuts += 1
            body = same_normal + [f"not use__({r})" for r in sorted(fired_on.get(j, []))]
            condition = ", ".join(body) if body else "#true"
            if _soft(e, noise):
                cuts.append(f"accepts__({j}) :- {condition}.")
                cuts.append(f"#minimize {{ {e.penalty},n,{j} : accepts__({j}) }}.")
            else:
                cuts.append(f":- {condition}.")
        optimizer.add("\n".join(cuts))
