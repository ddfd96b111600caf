"""Algorithm 6.2 and the probabilities of eqs. 6.2/6.3 against hand-computed automata."""

import math

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.learners.subgoals.ordering_automaton import (
    count_orderings, letter_guards, ordering_pdfa, pdfa_from_words,
)
from symlearn.logic.automata.operations import equivalent
from symlearn.logic.automata.dfa import DFA

WORDS = [("a", "b")] * 6 + [("b", "a")] * 2 + [("a",)] * 2


def test_states_are_sets_of_completed_subgoals():
    counts = count_orderings(WORDS, ["a", "b"])
    assert counts.n_states == 4  # {}, {a}, {a,b}, {b}
    names = sorted(counts.state_name(q) for q in range(counts.n_states))
    assert names == ["{a,b}", "{a}", "{b}", "{}"]
    # both orders end in the same state: the one of the set {a, b}
    ab = next(q for q in range(4) if counts.state_name(q) == "{a,b}")
    assert counts.end_counts[ab] == 8 and counts.accepting == {ab, next(q for q in range(4)
                                                                      if counts.state_name(q) == "{a}")}
    assert counts.total_length == 6 * 2 + 2 * 2 + 2 and counts.n_words == 10


def test_consistent_probabilities_are_the_empirical_frequencies():
    pdfa = pdfa_from_words(WORDS)
    a, b = (letter_guards(["a", "b"])[s].satisfying_label() for s in "ab")
    assert pdfa.probability([a, b]) == pytest.approx(0.6)
    assert pdfa.probability([b, a]) == pytest.approx(0.2)
    assert pdfa.probability([a]) == pytest.approx(0.2)
    assert pdfa.probability([b]) == 0.0
    for q in pdfa.states:  # a valid PDFA: every state sums to 1
        assert sum(p for _, _, p in pdfa.successors(q)) + pdfa.termination[q] == pytest.approx(1.0)
    word, p = pdfa.most_probable_accepted()
    assert word == [a, b] and p == pytest.approx(0.6)
    rng = np.random.default_rng(0)
    samples = [tuple(sorted(x) for x in pdfa.sample(rng, label_choice="minimal")) for _ in range(2000)]
    assert samples.count(([ "a"], ["b"])) / 2000 == pytest.approx(0.6, abs=0.04)


def test_thesis_probabilities_follow_eqs_6_2_and_6_3():
    counts = count_orderings(WORDS, ["a", "b"])
    pdfa = ordering_pdfa(counts, "thesis")
    state = {counts.state_name(q): q for q in range(counts.n_states)}
    edges = {(pdfa.name(s), pdfa.name(t)): p for s, _, t, p in pdfa.edges()}
    # eq. 6.2: per state over the edges only: from {} 8 words go to {a}, 2 to {b}
    assert edges[("{}", "{a}")] == pytest.approx(0.8) and edges[("{}", "{b}")] == pytest.approx(0.2)
    assert edges[("{a}", "{a,b}")] == pytest.approx(1.0)  # the 2 words stopping at {a} do not count
    # eq. 6.3: entries into accepting states: {a} entered 8 times, {a,b} 8 times
    assert pdfa.termination[state["{a}"]] == pytest.approx(0.5)
    assert pdfa.termination[state["{a,b}"]] == pytest.approx(0.5)
    # eq. 6.1 with these numbers
    a, b = (letter_guards(["a", "b"])[s].satisfying_label() for s in "ab")
    assert pdfa.probability([a, b]) == pytest.approx(0.8 * 1.0 * 0.5)


def test_thesis_and_consistent_agree_when_every_word_completes_the_same_set():
    words = [("a", "b", "c")] * 5 + [("c", "a", "b")] * 3 + [("b", "c", "a")]
    thesis, consistent = pdfa_from_words(words, probabilities="thesis"), pdfa_from_words(words)
    assert [p for *_, p in thesis.edges()] == pytest.approx([p for *_, p in consistent.edges()])
    assert thesis.termination == pytest.approx(consistent.termination)


def test_language_is_exactly_the_observed_orderings_closed_under_sets():
    words = [("a", "b"), ("b", "a"), ("a", "c")]
    dfa = pdfa_from_words(words).dfa
    guards = letter_guards(["a", "b", "c"])
    truth = DFA(["a", "b", "c"], 5, 0, [3, 4], {0: [(guards["a"], 1), (guards["b"], 2)],
                                                 1: [(guards["b"], 3), (guards["c"], 4)], 2: [(guards["a"], 3)]})
    assert equivalent(dfa, truth) == (True, None)
    # one ordering fewer is another language, and the witness is that ordering
    same, witness = equivalent(pdfa_from_words(words[:2]).dfa, truth)
    assert not same and [sorted(x) for x in witness] == [["a"], ["c"]]


def test_construction_is_one_pass_over_words():
    words = (tuple("abcd") for _ in range(1000))  # a generator is read once
    counts = count_orderings(words)
    assert counts.n_words == 1000 and counts.total_length == 4000 and counts.n_states == 5


@pytest.mark.parametrize("words, alphabet, message", [
    ([("a", "a")], None, "repeats sub-goal 'a'"),
    ([("a", "z")], ["a", "b"], "symbol 'z' is not a sub-goal"),
    (["ab"], None, "is a string"),
    ([], None, "no words"),
    ([("a",)], ["a", "a"], "named twice"),
    ([("not a name",)], None, "identifiers"),
])
def test_bad_words_are_refused(words, alphabet, message):
    with pytest.raises(DataError) as info:
        count_orderings(words, alphabet)
    assert message in str(info.value)


def test_empty_words_make_the_initial_state_accepting():
    pdfa = pdfa_from_words([(), ("a",), ("a",), ("a",)])
    assert pdfa.initial in pdfa.accepting and pdfa.termination[pdfa.initial] == pytest.approx(0.25)
    assert math.isclose(pdfa.probability([]), 0.25)


def test_the_language_generalises_over_orders_within_a_set():
    pdfa = pdfa_from_words([("a", "b", "c"), ("b", "a", "d")])
    g = letter_guards(["a", "b", "c", "d"])
    word = lambda *s: [g[x].satisfying_label() for x in s]  # noqa: E731
    assert pdfa.probability(word("a", "b", "d")) > 0 and pdfa.probability(word("b", "a", "c")) > 0
    assert pdfa.probability(word("a", "b")) == 0 and pdfa.n_states == 6
