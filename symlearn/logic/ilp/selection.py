"""The single-grounding path for integrity constraints over examples with one answer set each.

When H contains only integrity constraints, the answer sets of B ∪ H ∪ C are the answer sets of
B ∪ C in which no rule body of H holds. If every context C_e determines a single answer set A_e
(checked: the union of all tagged copies must have exactly one answer set), then

* a positive e is accepted iff A_e extends e and no chosen rule fires on A_e;
* a negative e is accepted iff A_e extends e and no chosen rule fires on A_e.

So learning is a weighted set cover: choose rules firing on every (extending) negative and on no
(extending) positive, minimising the total cost. The steps each take one clingo call:

1. :func:`single_worlds` solves the tagged union of B ∪ C_e for all examples (at most 2 models);
2. :func:`firing_matrix` grounds the model as facts together with one rule per candidate,
   ``fires__(E, r) :- <body of r, tagged with E>``, which grounding alone decides;
3. :func:`select_rules` solves the cover as a clingo optimisation.

Candidates with identical firing rows are interchangeable for the task; only the cheapest (the
first in space order on ties) is kept -- rules that differ only by a renaming never reach this
point, but rules that are different and *behave* differently (e.g. ``V1 < V2`` vs ``V2 < V1``)
have different rows and are both kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.encoding import ACTIVE, examples_program, firing_rows
from symlearn.logic.ilp.general import SearchOutcome
from symlearn.logic.ilp.space import HypothesisSpace
from symlearn.logic.ilp.task import Example, ILPTask


@dataclass
class Worlds:
    """The answer set of B ∪ C_e per example (tagged atoms), and whether it extends the example."""

    atoms: list[cl.Symbol]
    extends: dict[int, bool]
    empty: list[int] = field(default_factory=list)  # examples whose B ∪ C_e has no answer set


def _extends(example: Example, tag: int, present: set[cl.Symbol]) -> bool:
    from symlearn.logic.ilp.encoding import tag_symbol

    return all(tag_symbol(s, tag) in present for s in example.inclusions) and \
        not any(tag_symbol(s, tag) in present for s in example.exclusions)


def single_worlds(task: ILPTask, *, timeout: float | None = None) -> Worlds | None:
    """Answer sets of all B ∪ C_e at once; None when some context has several answer sets."""
    indexed = list(enumerate(task.examples))
    facts = "\n".join(f"{ACTIVE}({i})." for i, _ in indexed)
    program = examples_program(task, indexed, accept=False) + Program.from_text(facts, source="<examples>")
    outcome = cl.solve(program, max_models=2, timeout=timeout)
    if len(outcome.models) > 1:
        return None
    if outcome.models and not outcome.complete:  # uniqueness not established in time
        raise cl.LimitExceededError("checking that every context has one answer set did not finish in time",
                                    hint="raise the timeout")
    if not outcome.models:
        if not outcome.complete and outcome.satisfiable is None:
            raise cl.LimitExceededError("solving the example contexts did not finish in time",
                                        hint="raise the timeout")
        return _worlds_one_by_one(task, timeout)
    atoms = outcome.models[0]
    present = set(atoms)
    return Worlds(atoms, {i: _extends(e, i, present) for i, e in indexed})


def _worlds_one_by_one(task: ILPTask, timeout: float | None) -> Worlds | None:
    """Some B ∪ C_e has no answer set: find which, solving the others together."""
    atoms: list[cl.Symbol] = []
    extends: dict[int, bool] = {}
    empty = []
    for i, e in enumerate(task.examples):
        program = examples_program(task, [(i, e)], accept=False) + f"{ACTIVE}({i})."
        outcome = cl.solve(program, max_models=2, timeout=timeout)
        if len(outcome.models) > 1:
            return None
        if not outcome.models:
            empty.append(i)
            extends[i] = False
            continue
        atoms.extend(outcome.models[0])
        extends[i] = _extends(e, i, set(outcome.models[0]))
    return Worlds(atoms, extends, empty)


def firing_matrix(task: ILPTask, space: HypothesisSpace, worlds: Worlds, examples: list[int]) -> dict[int, set[int]]:
    """For every candidate: the examples (indices among ``examples``) whose answer set it fires on."""
    return firing_rows(space.candidates, worlds.atoms, examples)


def select_rules(task: ILPTask, space: HypothesisSpace, fires: dict[int, set[int]], *, noise: bool,
                 hard_pos: set[int], soft_pos: dict[int, int], hard_neg: set[int], soft_neg: dict[int, int],
                 timeout: float | None) -> SearchOutcome:
    """Weighted set cover in clingo; candidate rows already exclude rules firing on hard positives."""
    best: dict[tuple, tuple[int, int]] = {}
    for c in space.candidates:
        row = fires.get(c.index, set())
        if row & hard_pos:
            continue
        useful = (row & hard_neg) or (row & set(soft_neg))
        if not useful:
            continue
        signature = (frozenset(row & (hard_neg | set(soft_neg))), frozenset(row & set(soft_pos)))
        if signature not in best or (c.cost, c.index) < best[signature]:
            best[signature] = (c.cost, c.index)
    kept = sorted(index for _cost, index in best.values())
    by_index = {c.index: c for c in space.candidates}
    lines = [f"cand({r},{by_index[r].cost})." for r in kept]
    for r in kept:
        row = fires.get(r, set())
        lines.extend(f"f({r},{e})." for e in sorted(row & (hard_neg | set(soft_neg) | set(soft_pos))))
    lines += [f"hneg({e})." for e in sorted(hard_neg)]
    lines += [f"sneg({e},{p})." for e, p in sorted(soft_neg.items())]
    lines += [f"spos({e},{p})." for e, p in sorted(soft_pos.items())]
    lines += [
        "{ sel(R) : cand(R,_) }.",
        "cov(E) :- sel(R), f(R,E).",
        ":- hneg(E), not cov(E).",
        "#minimize { C,r,R : sel(R), cand(R,C) ; P,e,E : sneg(E,P), not cov(E) ; P,e,E : spos(E,P), cov(E) }.",
        "#show sel/1. #show cov/1.",
    ]
    if noise and task.max_penalty is not None:
        lines.append(f":- #sum {{ P,E : sneg(E,P), not cov(E) ; P,E : spos(E,P), cov(E) }} > {task.max_penalty}.")
    outcome = cl.optimize(Program.from_text("\n".join(lines), source="<rule selection>"), timeout=timeout)
    result = SearchOutcome(None, notes=[f"{len(kept)} of {len(space)} candidates after removing rules that "
                                        "exclude a positive and merging rules with identical coverage"])
    if not outcome.models:
        if not outcome.complete and outcome.satisfiable is None:
            result.notes.append("time limit reached before a hypothesis was found")
            result.timed_out = True
        return result
    model = outcome.models[-1]
    chosen = sorted(s.arguments[0].number for s in model if s.name == "sel")
    covered = {s.arguments[0].number for s in model if s.name == "cov"}
    result.selected = chosen
    result.cost = sum(by_index[r].cost for r in chosen)
    uncovered = [e for e in soft_neg if e not in covered] + [e for e in soft_pos if e in covered]
    result.penalty = sum(soft_neg[e] for e in soft_neg if e not in covered) + \
        sum(soft_pos[e] for e in soft_pos if e in covered)
    result.uncovered = [task.examples[e].id for e in sorted(uncovered)]
    result.optimal = outcome.complete
    result.timed_out = not outcome.complete
    return result
