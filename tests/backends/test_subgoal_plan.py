"""Plans from sub-goal PDFAs: greedy (thesis), best (Dijkstra), execution with replanning."""

import pytest

from symlearn.backends.subgoal_plan import best_plan, execute, greedy_plan, step
from symlearn.errors import DataError
from symlearn.learners.subgoals import pdfa_from_words

# greedy takes a (0.6) then c (1.0): 0.6 * 1 * ... ; the single most probable word is b,a
WORDS = [("a", "c")] * 3 + [("a", "d")] * 3 + [("b", "e")] * 4


def test_greedy_follows_the_most_probable_edge_and_best_finds_the_most_probable_word():
    pdfa = pdfa_from_words(WORDS)
    greedy = greedy_plan(pdfa)
    assert greedy.subgoals == ("a", "c") and greedy.accepted and greedy.probability == pytest.approx(0.3)
    best = best_plan(pdfa)
    assert best.subgoals == ("b", "e") and best.probability == pytest.approx(0.4)
    word, p = pdfa.most_probable_accepted()
    assert [sorted(x)[0] for x in word] == list(best.subgoals) and p == pytest.approx(best.probability)


def test_greedy_stops_where_stopping_beats_going_on():
    pdfa = pdfa_from_words([("a",)] * 3 + [("a", "b")])
    assert greedy_plan(pdfa).subgoals == ("a",)
    assert greedy_plan(pdfa, excluded={"a"}).accepted is False


def test_excluded_subgoals_must_exist_and_states_must_be_valid():
    pdfa = pdfa_from_words(WORDS)
    with pytest.raises(DataError, match="'z' is not a symbol of the automaton"):
        greedy_plan(pdfa, excluded={"z"})
    with pytest.raises(DataError, match="not a state"):
        best_plan(pdfa, state=99)
    with pytest.raises(DataError, match="no transition"):
        step(pdfa, pdfa.initial, "c")


def test_execution_retries_a_failing_controller_then_gives_up():
    pdfa = pdfa_from_words([("a", "b")])
    calls = []
    report = execute(pdfa, lambda s: calls.append(s) or s == "a", max_attempts=5)
    assert not report.success and report.achieved == ("a",) and len(calls) == 5
    assert report.failures[-1] == (report.states[-1], "b")


def test_execution_postpones_an_unreachable_subgoal():
    pdfa = pdfa_from_words([("a", "b", "c")] * 5 + [("b", "a", "c"), ("c", "a", "b")])
    visible = {"a": False}

    def controller(symbol):
        visible["a"] = True  # a shows up once anything has been done
        return True

    report = execute(pdfa, controller, reachable=lambda s: visible.get(s, True))
    assert report.success and report.achieved[0] != "a" and set(report.achieved) == {"a", "b", "c"}
    assert report.replans[0].reason.startswith("without a") or "postponed" in report.replans[0].reason


def test_a_stubborn_subgoal_does_not_starve_one_that_failed_by_chance():
    pdfa = pdfa_from_words([("a", "b")] * 5 + [("b", "a")])
    done, tries = [], {"b": 0}

    def controller(symbol):
        if symbol == "a":
            ok = "b" in done  # a is only possible once b is done
        else:
            tries["b"] += 1
            ok = tries["b"] > 1  # b fails once, by chance
        if ok:
            done.append(symbol)
        return ok

    report = execute(pdfa, controller, max_attempts=10)
    assert report.success and report.achieved == ("b", "a") and report.attempts <= 5
