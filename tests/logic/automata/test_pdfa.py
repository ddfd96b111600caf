"""PDFA: probabilities, most probable accepted word, sampling, normalisation checks."""

import math

import numpy as np
import pytest

from symlearn.errors import LimitExceededError, ModelError
from symlearn.logic.automata import DFA, PDFA
from symlearn.logic.guards import Guard

a, b = Guard.var("a"), Guard.var("b")
T = Guard.true()


def coin():
    # state 0: 'a' (0.5) -> 1, '!a' (0.3) -> 0, stop 0.2 (not accepting: a stop there is a reject)
    return PDFA({"a"}, 2, 0, {0: [(a, 1, 0.5), (~a, 0, 0.3)], 1: [(T, 1, 0.4)]}, [0.2, 0.6], accepting=[1])


def test_word_probabilities():
    p = coin()
    assert p.probability([{"a"}]) == pytest.approx(0.5 * 0.6)
    assert p.probability([set(), {"a"}, {"a", "x"}]) == pytest.approx(0.3 * 0.5 * 0.4 * 0.6)
    assert p.probability([]) == pytest.approx(0.2)
    assert p.log_probability([{"a"}]) == pytest.approx(math.log(0.3))
    # per-label: guard 'true' over {a} has 2 labels
    assert p.probability([{"a"}, set()], per_label=True) == pytest.approx(0.5 * 0.4 / 2 * 0.6)


def test_probabilities_sum_to_one_over_guard_sequences():
    # enumerate all edge sequences up to length 30 (labels: one representative per guard)
    p = coin()
    total, frontier = 0.0, [(0, 1.0)]
    for _ in range(60):
        nxt = []
        for q, mass in frontier:
            total += mass * p.termination[q]
            nxt += [(t, mass * pr) for _, t, pr in p.successors(q)]
        frontier = nxt
    assert total == pytest.approx(1.0, abs=1e-9)


def test_most_probable_accepted_word():
    p = PDFA({"a", "b"}, 3, 0, {
        0: [(a & ~b, 1, 0.6), (b, 2, 0.4)],
        1: [(T, 2, 0.9)],
        2: [(T, 2, 0.5)],
    }, [0.0, 0.1, 0.5], accepting=[1, 2])
    word, prob = p.most_probable_accepted()
    # candidates: [a] 0.06, [b] 0.2, [a, x] .6*.9*.5=.27 -> best
    assert word == [frozenset({"a"}), frozenset()] and prob == pytest.approx(0.27)
    assert p.probability(word) == pytest.approx(prob)


def test_most_probable_accepted_none_when_no_accepting_stop():
    p = PDFA({"a"}, 1, 0, {0: [(T, 0, 0.5)]}, [0.5], accepting=[])
    assert p.most_probable_accepted() is None


def test_sampling_matches_probabilities():
    p = coin()
    rng = np.random.default_rng(3)
    samples = [tuple(p.sample(rng, label_choice="minimal")) for _ in range(4000)]
    for word in ([], [frozenset({"a"})], [frozenset(), frozenset({"a"})]):
        frequency = sum(s == tuple(word) for s in samples) / len(samples)
        assert frequency == pytest.approx(p.probability(word), abs=0.025)
    uniform = [p.sample(rng) for _ in range(500)]
    assert all(p.dfa.run(w) for w in uniform)
    assert {frozenset()} | {frozenset({"a"})} >= {lab for w in uniform for lab in w[1:]}


def test_sampling_limit():
    p = PDFA({"a"}, 1, 0, {0: [(T, 0, 1.0)]}, [0.0])
    with pytest.raises(LimitExceededError, match="exceeded 50 letters"):
        p.sample(np.random.default_rng(0), max_length=50)


def test_from_dfa_samples_only_accepted_words():
    d = DFA({"a", "b"}, 3, 0, [1], {0: [(~a, 0), (a & ~b, 1), (a & b, 2)], 1: [(T, 1)], 2: [(T, 2)]})
    p = PDFA.from_dfa(d, termination=0.3)
    assert p.n_states == 2  # the dead state is dropped
    rng = np.random.default_rng(0)
    for _ in range(200):
        assert d.accepts(p.sample(rng))


@pytest.mark.parametrize("kwargs, message", [
    (dict(termination=[0.2, 0.5]), "state 1: outgoing probabilities plus termination sum to 0.9, not 1"),
    (dict(termination=[0.3, 0.6]), "state 0: outgoing probabilities plus termination sum to 1.1"),
    (dict(termination=[0.2]), "1 termination probabilities for 2 states"),
    (dict(termination=[-0.2, 1.4]), "must be a number in [0, 1]"),
    (dict(transitions={0: [(a, 1, 0.5), (a | b, 0, 0.3)], 1: [(T, 1, 0.4)]}), "not deterministic"),
    (dict(transitions={0: [(a, 1, 0.5), (~a, 0, "0.3")], 1: [(T, 1, 0.4)]}), "must be a number"),
    (dict(transitions={0: [(Guard.false(), 1, 0.8)], 1: [(T, 1, 0.4)]}), "its guard is false"),
])
def test_bad_probabilities_raise_model_error(kwargs, message):
    args = dict(alphabet={"a", "b"}, n_states=2, initial=0,
                transitions={0: [(a, 1, 0.5), (~a, 0, 0.3)], 1: [(T, 1, 0.4)]}, termination=[0.2, 0.6])
    args.update(kwargs)
    with pytest.raises(ModelError) as info:
        PDFA(**args)
    assert message in str(info.value)


def test_dot_shows_probabilities():
    dot = coin().to_dot()
    assert 'label="a / 0.5"' in dot and "stop 0.6" in dot
