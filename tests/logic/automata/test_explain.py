"""Explaining failing traces: where they fail and a minimum-edit fix."""

import itertools

from automata_strategies import a_then_b_avoid_c, dfas, words
from hypothesis import given, settings

from symlearn.logic.automata import DFA, explain
from symlearn.logic.automata.explain import shortest_fix
from symlearn.logic.guards import Guard

a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")
T = Guard.true()


def test_accepted_trace():
    report = explain(a_then_b_avoid_c(), [{"a"}, {"b"}])
    assert report.accepted and report.reason == "accepted" and report.edits == []


def test_incomplete_trace_gets_an_insertion():
    report = explain(a_then_b_avoid_c(), [set(), {"a"}])
    assert report.reason == "incomplete" and report.failure_step == 2
    assert [str(e) for e in report.edits] == ["append {b} at the end"]   # there is no step 2 to be before
    assert report.edits[0].to_dict() == {"kind": "insert", "position": 2, "old": None, "new": ["b"]}
    assert report.fixed_trace == [frozenset(), frozenset({"a"}), frozenset({"b"})]


def test_stuck_trace_is_repaired_with_the_closest_label():
    report = explain(a_then_b_avoid_c(), [{"a"}, {"b", "c"}])
    assert report.reason == "stuck" and report.failure_step == 1
    assert [e.kind for e in report.edits] == ["substitute"]
    assert report.edits[0].new == frozenset({"b"})  # only c flipped
    assert a_then_b_avoid_c().accepts(report.fixed_trace)
    assert "no transition matches" in report.summary()


def test_dead_state_failure_step():
    d = a_then_b_avoid_c().complete()
    report = explain(d, [{"a"}, {"c"}, {"b"}])
    assert report.reason == "dead" and report.failure_step == 1
    assert len(report.edits) == 1 and d.accepts(report.fixed_trace)


def test_empty_language():
    never = DFA({"a"}, 1, 0, [], {0: [(T, 0)]})
    report = explain(never, [{"a"}])
    assert report.reason == "empty-language" and report.fixed_trace is None
    assert "no fix" in report.summary()


def _edit_distance_brute_force(dfa, trace, max_extra=2):
    """Smallest Levenshtein distance from trace to an accepted word over the letters."""
    letters = [frozenset(s) for r in range(len(dfa.alphabet) + 1)
               for s in itertools.combinations(sorted(dfa.alphabet), r)]

    def lev(u, v):
        row = list(range(len(v) + 1))
        for i, x in enumerate(u, 1):
            prev, row[0] = row[0], i
            for j, y in enumerate(v, 1):
                prev, row[j] = row[j], min(row[j] + 1, row[j - 1] + 1, prev + (x != y))
        return row[-1]

    best = None
    for length in range(0, len(trace) + max_extra + 1):
        for word in itertools.product(letters, repeat=length):
            if dfa.accepts(list(word)):
                d = lev(trace, list(word))
                best = d if best is None else min(best, d)
    return best


@settings(max_examples=25, deadline=None)
@given(dfas(("a", "b"), max_states=3), words(("a", "b"), max_size=3))
def test_shortest_fix_is_minimal(d, trace):
    trace = [frozenset(s) for s in trace]
    if d.initial not in d.live_states():
        return
    edits, fixed = shortest_fix(d, trace)
    assert d.accepts(fixed)
    # a fix never needs more than the trace length + shortest word, so brute force is bounded
    brute = _edit_distance_brute_force(d, trace, max_extra=3)
    assert brute is not None and len(edits) == brute
