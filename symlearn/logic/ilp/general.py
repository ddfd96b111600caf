"""The general search: full answer-set semantics for any hypothesis space.

One optimisation program holds a copy of B ∪ context per positive example (see
:mod:`~symlearn.logic.ilp.encoding`), every candidate rule guarded by a choice atom ``use__(r)``,
and ``#minimize`` over rule costs (plus penalties of dropped soft positives). Its optimum is the
cheapest hypothesis accepting all positives. Negatives need "no answer set extends it", which is
not expressible in the same program, so the search is iterative (generate and test):

1. optimise -> H;  2. check every negative against H in one clingo call;
3. if H accepts a hard negative, forbid exactly this choice of rules (a nogood over ``use__``);
   a soft negative instead adds its penalty whenever exactly this H is chosen;
4. repeat until the optimum accepts no unpaid negative.

Every cost the optimiser sees is a lower bound of the true cost, and the returned hypothesis'
cost is exact, so the first hypothesis that passes is optimal. Nogoods block exactly one
hypothesis each; tasks with many negatives and large spaces need many rounds -- the
single-grounding path (:mod:`~symlearn.logic.ilp.selection`) is the fast one for constraints.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.encoding import ACTIVE, accepted_by, examples_program, tagged_rules
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
        rule = tagged_rules([c.text], guard=[f"use__({c.index})"])
        lines.append(rule)
    weights = [f"{c.cost},r,{c.index} : use__({c.index})" for c in space.candidates if c.cost]
    weights += [f"{e.penalty},e,{i} : ignored__({i})" for i, e in positives if _soft(e, noise)]
    if weights:
        lines.append("#minimize { " + " ; ".join(weights) + " }.")
    if task.max_penalty is not None and noise:
        soft = [f"{e.penalty},{i} : ignored__({i})" for i, e in positives if _soft(e, noise)]
        if soft:
            lines.append(f":- #sum {{ {' ; '.join(soft)} }} > {task.max_penalty}.")
    lines.append("#show use__/1. #show ignored__/1.")
    program = examples_program(task, positives) + Program.from_text("\n".join(lines), source="<search>")
    optimizer = cl.IncrementalOptimizer(program)
    by_index = {c.index: c for c in space.candidates}
    outcome = SearchOutcome(None)
    paid: dict[frozenset[int], set[str]] = {}  # soft negatives already charged to a hypothesis
    while True:
        outcome.rounds += 1
        remaining = deadline - time.perf_counter()
        if remaining <= 0:
            outcome.notes.append("time limit reached before a hypothesis was verified")
            return outcome
        solved = optimizer.optimize(timeout=remaining)
        if not solved.models:
            if solved.complete or solved.satisfiable is False:
                outcome.notes.append("no hypothesis in the space covers the examples")
            else:
                outcome.notes.append("time limit reached before a hypothesis was found")
            return outcome
        model = solved.models[-1]
        chosen = sorted(s.arguments[0].number for s in model if s.name == "use__")
        dropped = [task.examples[s.arguments[0].number] for s in model if s.name == "ignored__"]
        key = frozenset(chosen)
        rules = [by_index[r].text for r in chosen]
        left = deadline - time.perf_counter()
        verdict = accepted_by(task, rules, negatives, timeout=max(left, 0.001)) if negatives else {}
        wrong = [e for e in negatives if verdict.get(e.id)]
        charged = paid.setdefault(key, set())
        unpaid = [e for e in wrong if not _soft(e, noise) or e.id not in charged]
        if not unpaid:
            outcome.selected = chosen
            outcome.cost = sum(by_index[r].cost for r in chosen)
            outcome.penalty = sum(e.penalty for e in dropped) + sum(e.penalty for e in wrong)
            outcome.uncovered = [e.id for e in dropped] + [e.id for e in wrong]
            outcome.optimal = solved.complete
            if not solved.complete:
                outcome.notes.append("time limit reached: best hypothesis found so far, not proven optimal")
            return outcome
        exact = ", ".join([f"use__({r})" for r in chosen] +
                          [f"not use__({c.index})" for c in space.candidates if c.index not in key])
        if any(not _soft(e, noise) for e in unpaid):
            optimizer.add(f":- {exact}." if exact else ":- #true.")
        else:
            tag = outcome.rounds
            terms = " ; ".join(f"{e.penalty},n,{tag},{j} : {exact}" if exact else f"{e.penalty},n,{tag},{j}"
                               for j, e in enumerate(unpaid))
            optimizer.add(f"#minimize {{ {terms} }}.")
            charged.update(e.id for e in unpaid)
