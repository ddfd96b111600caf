"""``coverage_matrix`` decides most (rule, example) pairs from one witness answer set per example
(symlearn/logic/ilp/coverage.py); its answers must be those of one clingo call per rule
(B ∪ {rule} for each rule alone, as before issue 26's ninth round), for every kind of rule and
for backgrounds with one and with several answer sets per example."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from symlearn.errors import LimitExceededError
from symlearn.logic.asp import Hypothesis
from symlearn.logic.ilp import coverage, coverage_matrix, load_task, parse_task
from symlearn.logic.ilp.encoding import accepted_by

KB = Path(__file__).resolve().parents[3] / "background_kb"

HANOI_RULES = [  # every branch: constraints that fire or not, fresh heads, heads B reads, choices, odd loops
    ":- move(D, P), D > {k}.",
    ":- move(D, P), at(E, P, _), E > D, D < {k}.",
    ":- on(D1, D2), D1 < D2, D2 != {k}.",
    "c{i}(D) :- moved(D), D >= {k}.",
    "c{i}(D) :- disk(D), not c{i}(D), D = {k}.",
    "moved(D) :- disk(D), D = {k}.",
    "-moved(D) :- disk(D), D = {k}.",
    "{{ moved(D) }} :- disk(D), D > {k}.",
    "{{ w{i}(D) : disk(D) }} 0 :- move(D, _), D > {k}.",
    "1 {{ w{i}(D) : disk(D), D > {k} }} :- move(_, _).",
    "v{i}(1;2) :- move(_, P), P > {k}.",
    ":- move(D, P), #count {{ E : at(E, P, _) }} > {k}.",
    "after(D, 9, 9) :- move(D, _), D = {k}.",
    ":- not moved({k}).",
    "s{i} :- on(D1, D2), D1 = D2 + {k}.",
]

CHOICES = """
b(1..3).
{ a(X) } :- b(X).
d :- a(1), a(2).
#pos(p1, {a(1)}, {}, {}).
#pos(p2, {}, {a(2)}, {}).
#pos(p3, {d}, {}, { b(4). }).
#pos(p4, {a(4)}, {}, {}).
#neg(n1, {a(3)}, {a(1)}, {}).
#neg(n2, {}, {}, { :- a(2). }).
#neg(n3, {c}, {}, {}).
#modeb(1, a(var(t))).
"""
CHOICE_RULES = [":- a(1).", ":- a(2), a(3).", ":- d.", "c :- a(1).", "c(X) :- a(X).", "a(4) :- b(1).",
                "a(4) :- a(1), not a(2).", "e :- not e, a(3).", ":- not a(1).", "{ c } :- d.", "d.",
                "-a(1) :- b(1).", "c :- not a(3).", "f(X) :- a(X).", "g :- not a(1)."]


def one_call_per_rule(task, rules):
    return {rule: accepted_by(task, [rule], task.examples, timeout=60) for rule in rules}


def matrix_expected(task, rules):
    return {rule: {e.id: (ok[e.id] if e.positive else not ok[e.id]) for e in task.examples}
            for rule, ok in one_call_per_rule(task, rules).items()}


def hanoi_rules(n: int, seed: int) -> list[str]:
    pick = random.Random(seed)
    return [pick.choice(HANOI_RULES).format(i=i, k=pick.randrange(4)) for i in range(n)]


@pytest.mark.parametrize("seed", [0, 1])
def test_hanoi_rules_alone_as_one_call_per_rule(seed, monkeypatch):
    monkeypatch.setattr(coverage, "PAIRS_PER_CALL", 37)  # several exact calls, one cut inside a rule's pairs
    task = load_task(KB / "hanoi" / "tasks" / "hanoi.las")
    task.examples = task.examples[::7]  # both polarities, fewer copies for the one-call-per-rule oracle
    rules = hanoi_rules(30, seed)
    hypothesis = Hypothesis(rules, background=task.background)
    assert coverage_matrix(task, hypothesis) == matrix_expected(task, hypothesis.rules)


def test_several_answer_sets_per_example_inclusions_exclusions_and_contexts():
    task = parse_task(CHOICES)
    hypothesis = Hypothesis(CHOICE_RULES, background=task.background)
    assert coverage_matrix(task, hypothesis) == matrix_expected(task, hypothesis.rules)


def test_traffic_rules_with_a_fact_and_duplicates():
    task = load_task(KB / "traffic" / "tasks" / "priority.las")
    task.examples = task.examples[::10]
    rules = [":- go(north).", ":- go(D), onRoad(D), not carOnTheRight.", "onRoad(east) :- at(1, 1).",
             "seen(D) :- go(D).", ":- go(north).", "carOnTheRight.", ":- at(X, Y), X = Y."]
    hypothesis = Hypothesis(rules, background=task.background)
    matrix = coverage_matrix(task, hypothesis)
    assert list(matrix) == list(dict.fromkeys(hypothesis.rules))
    assert matrix == matrix_expected(task, hypothesis.rules)


def test_columns_for_some_examples_only():
    task = parse_task(CHOICES)
    hypothesis = Hypothesis(CHOICE_RULES, background=task.background)
    wanted = [e for e in task.examples if e.id in ("p4", "n1")]
    expected = matrix_expected(task, hypothesis.rules)
    assert coverage_matrix(task, hypothesis, examples=wanted) == {
        rule: {e.id: row[e.id] for e in wanted} for rule, row in expected.items()}


def test_one_budget_for_the_whole_matrix():
    task = parse_task(CHOICES)
    hypothesis = Hypothesis(CHOICE_RULES, background=task.background)
    with pytest.raises(LimitExceededError) as caught:
        coverage_matrix(task, hypothesis, timeout=0)
    assert caught.value.message == "checking each of the 15 rules alone did not finish within 0 s"
