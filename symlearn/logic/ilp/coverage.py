"""Which examples each rule of a hypothesis covers on its own: does B ∪ {rule} accept the example?

Asking clingo once per rule grounds the background once per rule (issue 26: 1,000 rules took
over 100 s). Most (rule, example) pairs are decided without that, from an answer set A of
B ∪ context extending the example (its *witness*, one clingo call for all examples):

* A satisfies the rule: A is still an answer set of B ∪ {rule} (A is a model of the larger
  reduct, and a smaller model of it would be a smaller model of B's reduct), so accepted;
* a constraint only removes answer sets: when B alone rejects the example, or A is the only
  answer set extending it and the constraint fires on A, the example is rejected;
* a normal rule whose head predicate occurs nowhere else (not in B, a context, an example or
  its own body) sits on top of B (splitting set theorem): every answer set of B ∪ {rule} is one
  of B plus the heads the rule derives from it, so accepted exactly when B alone accepts.

Which rules each witness satisfies is decided for all rules in one grounding (the witnesses as
facts). The pairs left (a rule with a head that B reads, or a constraint on an example with
several answer sets) are checked exactly, many per clingo call (:class:`PairCheck`).
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Sequence
from dataclasses import dataclass

from symlearn.errors import LimitExceededError
from symlearn.logic.asp import clingo_adapter as cl
from symlearn.logic.asp.hypothesis import Hypothesis
from symlearn.logic.asp.program import Program
from symlearn.logic.ilp.encoding import ACTIVE, PairCheck, examples_program, tagged_rules, witnesses
from symlearn.logic.ilp.task import Example, ILPTask

ASTType = cl.clingo.ast.ASTType
# every predicate name matches; so may other words (a constant, part of a variable): that only
# makes a head look less fresh, which costs an exact check, never a wrong answer
_NAME = re.compile(r"_*[a-z][A-Za-z0-9_']*")
PAIRS_PER_CALL = 200  # exact checks: copies of the background in one clingo call (bounds its memory)


@dataclass
class _Rule:
    """What the shortcuts need to know of one rule."""

    index: int
    kind: str  # "constraint", "atom" (one plain atom as head) or "other" (choice, disjunction, ...)
    # ``viol__(index) :- ...``: false on an answer set only if the rule holds there (exactly when it
    # is violated for a constraint or an "atom" rule; when its body holds, for the others)
    violation: str
    fresh: bool  # an "atom" rule whose head predicate occurs nowhere else


class _Clock:
    """One budget for the whole matrix: each clingo call gets what is left of it."""

    def __init__(self, seconds: float, what: str) -> None:
        self.seconds, self.what = seconds, what
        self.deadline = time.monotonic() + seconds

    def left(self) -> float | None:
        if math.isinf(self.seconds):
            return None
        left = self.deadline - time.monotonic()
        if left <= 0:
            raise self.exceeded()
        return left

    def exceeded(self) -> LimitExceededError:
        return LimitExceededError(f"{self.what} did not finish within {self.seconds:g} s", hint="raise the timeout")


def rule_acceptance(task: ILPTask, hypothesis: Hypothesis, examples: Sequence[Example], *,
                    seconds: float = math.inf) -> list[list[bool]]:
    """``rows[j][i]``: does B ∪ {hypothesis.rules[j]} accept ``examples[i]`` (an answer set
    extending it)? LimitExceededError when ``seconds`` (one budget for all) run out."""
    examples = list(examples)
    if not examples:  # ``ilp check --coverage`` with no uncovered positive
        return [[] for _rule in hypothesis.rules]
    clock = _Clock(seconds, f"checking each of the {len(hypothesis.rules)} rules alone")
    try:
        return _acceptance(task, hypothesis, examples, clock)
    except LimitExceededError:
        raise clock.exceeded() from None


def _acceptance(task: ILPTask, hypothesis: Hypothesis, examples: list[Example], clock: _Clock) -> list[list[bool]]:
    found = witnesses(task, [], examples, timeout=clock.left())
    answer_sets = [found[e.id] for e in examples]  # atoms tagged with the example's position
    base = [a is not None for a in answer_sets]
    known = _names_outside(task)
    rules = [_rule(j, statement, known) for j, statement in enumerate(hypothesis.asts)]
    violated = _violations([r for r in rules if not r.fresh], answer_sets)
    unique = _unique(task, examples, base, {i for j, i in violated if rules[j].kind == "constraint"}, clock)
    rows: list[list[bool | None]] = []
    for rule in rules:
        rows.append([_shortcut(rule, base[i], (rule.index, i) in violated, i in unique)
                     for i in range(len(examples))])
    _check_the_rest(task, hypothesis, examples, rows, clock)
    return rows  # type: ignore[return-value]  # every None replaced by _check_the_rest


def _shortcut(rule: _Rule, accepted: bool, violated: bool, unique: bool) -> bool | None:
    """The answer for (rule, example) without asking clingo, None when there is none: ``accepted``
    whether B alone accepts the example, ``violated`` whether the rule fails on its witness,
    ``unique`` whether that witness is its only answer set extending it."""
    if rule.fresh:
        return accepted
    if accepted and not violated:
        return True
    if rule.kind == "constraint" and (not accepted or unique):
        return False
    return None


def _names_outside(task: ILPTask) -> set[str]:
    """Every name the background, the contexts and the examples' atoms use (a superset)."""
    texts = [task.background.text]
    for example in task.examples:
        texts.append(example.context.text)
        texts.extend(str(a) for a in (*example.inclusions, *example.exclusions))
    return set(_NAME.findall("\n".join(texts)))


def _rule(index: int, statement, known: set[str]) -> _Rule:
    """A rule's kind, its violation rule and whether its head is fresh (see the module)."""
    body = "; ".join(str(b) for b in statement.body)
    head = statement.head
    plain = (head.ast_type == ASTType.Literal and head.sign == cl.clingo.ast.Sign.NoSign
             and head.atom.ast_type == ASTType.SymbolicAtom)
    if head.ast_type == ASTType.Literal and head.atom.ast_type == ASTType.BooleanConstant and not head.atom.value:
        kind, condition = "constraint", body
    elif plain:
        kind, condition = "atom", "; ".join(c for c in (body, f"not {head}") if c)
    else:  # only "the body holds nowhere" shows that such a rule is satisfied
        kind, condition = "other", body
    violation = f"viol__({index}) :- {condition}." if condition else f"viol__({index})."
    fresh = kind == "atom" and not set(_NAME.findall(str(head))) & (known | set(_NAME.findall(body)))
    return _Rule(index, kind, violation, fresh)


def _violations(rules: list[_Rule], answer_sets: list[list[cl.Symbol] | None]) -> set[tuple[int, int]]:
    """(rule index, example position) for every rule violated by that example's witness; one
    grounding of a stratified program (the witnesses as facts, one ``viol__`` rule a rule)."""
    tags = [i for i, atoms in enumerate(answer_sets) if atoms is not None]
    if not rules or not tags:
        return set()
    facts = [f"{a}." for i in tags for a in answer_sets[i]] + [f"{ACTIVE}({i})." for i in tags]
    checks = Program.from_text("\n".join(r.violation for r in rules), source="<rule checks>")
    program = Program.from_text("\n".join(facts), source="<answer sets>") + tagged_rules(checks)
    return {(a.arguments[1].number, a.arguments[0].number) for a in cl.ground_atoms(program, [("viol__", 2)])}


def _unique(task: ILPTask, examples: list[Example], base: list[bool], wanted: set[int],
            clock: _Clock) -> set[int]:
    """Of the ``wanted`` examples that B accepts, those with exactly one answer set extending
    them: brave and cautious consequences agree (copies are independent, so per copy too)."""
    tags = sorted(i for i in wanted if base[i])
    if not tags:
        return set()
    program = examples_program(task, [(i, examples[i]) for i in tags]) + Program.from_text(
        "\n".join(f"{ACTIVE}({i})." for i in tags), source="<coverage check>")
    found = cl.consequences(program, timeout=clock.left())
    if found is None:  # cannot happen: B accepts each of them
        return set()
    brave, cautious = found
    return set(tags) - {a.arguments[0].number for a in set(brave) - set(cautious)
                               if a.arguments and a.arguments[0].type == cl.SymbolType.Number}


def _check_the_rest(task: ILPTask, hypothesis: Hypothesis, examples: list[Example],
                    rows: list[list[bool | None]], clock: _Clock) -> None:
    """Ask clingo about every pair no shortcut decided, :data:`PAIRS_PER_CALL` pairs a call."""
    open_pairs = [(j, i) for j, row in enumerate(rows) for i, value in enumerate(row) if value is None]
    if not open_pairs:
        return
    check = PairCheck(task, _one_program_a_rule(hypothesis), examples)
    for start in range(0, len(open_pairs), PAIRS_PER_CALL):
        chunk = open_pairs[start:start + PAIRS_PER_CALL]
        for (j, i), answer in zip(chunk, check.accepted(chunk, timeout=clock.left())):
            rows[j][i] = answer


def _one_program_a_rule(hypothesis: Hypothesis) -> list[Program]:
    """Each rule as a program of its own, located in the user's file when read from one."""
    parts = hypothesis.program().parts
    if len(parts) == len(hypothesis.rules):
        return [Program((part,)) for part in parts]
    return [Program.from_text(rule, source="<hypothesis>") for rule in hypothesis.rules]
