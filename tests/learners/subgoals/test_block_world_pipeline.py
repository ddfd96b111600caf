"""The chapter-6 pipeline on the block world, scored against the demonstrator's ground truth:
language equivalence, probabilities within 3 binomial standard errors, greedy plan = preferred
ordering, and replanning to acceptance when a block is hidden."""

import numpy as np
import pytest

from symlearn.backends.subgoal_plan import execute, greedy_plan
from symlearn.envs.block_world import BlockWorld, Demonstrator, place_task, stack_task
from symlearn.learners.subgoals import SubgoalPDFALearner
from symlearn.learners.subgoals.scoring import edge_deviations, renamed


def learn(task, n, seed, **kw):
    runs, orders = Demonstrator(task, seed=seed, **kw).demonstrations(n)
    learner = SubgoalPDFALearner(subsets=task.subsets()).fit(runs, task.feature_names())
    truth = task.truth_subgoals()
    mapping = learner.subgoals_.match(truth, tolerance=0.01)
    return learner, mapping, orders


@pytest.fixture(scope="module")
def place4_1000():
    return (place_task(4),) + learn(place_task(4), 1000, seed=11)


@pytest.mark.parametrize("task, n", [(place_task(3), 200), (stack_task(2), 40)])
def test_language_equals_the_truth_when_every_ordering_is_observed(task, n):
    learner, mapping, orders = learn(task, n, seed=5)
    assert len(mapping) == len(task.placements) == len(learner.subgoals_)
    truth = task.truth_pdfa()
    assert len({tuple(o) for o in orders}) == sum(1 for _ in _orderings(truth))  # every ordering was shown
    same, witness = renamed(learner.pdfa_, mapping).equivalent(truth.dfa)
    assert same, witness
    # every word is the demonstrator's ordering, noise and dropped detections notwithstanding
    names = [task.subgoal_name(j) for j in range(len(task.placements))]
    assert [tuple(mapping[s] for s in w) for w in learner.words_] == [tuple(names[j] for j in o) for o in orders]


def _orderings(pdfa):
    stack = [(pdfa.initial, 0)]
    while stack:
        q, depth = stack.pop()
        if not pdfa.successors(q):
            yield q
        stack += [(t, depth + 1) for _, t, _ in pdfa.successors(q)]


def test_probabilities_within_three_standard_errors_at_1000_words(place4_1000):
    task, learner, mapping, _ = place4_1000
    assert learner.counts_.n_words == 1000
    deviations = edge_deviations(learner.pdfa_, learner.counts_, task.truth_pdfa(), mapping)
    assert len(deviations) == 32  # every transition of the 16-state truth
    assert max(d.standard_errors for d in deviations) <= 3.0, max(deviations, key=lambda d: d.standard_errors)


def test_centres_within_a_centimetre_and_greedy_plan_is_the_preferred_ordering(place4_1000):
    task, learner, mapping, _ = place4_1000
    truth = task.truth_subgoals()
    for goal in learner.subgoals_:
        assert np.linalg.norm(np.subtract(goal.centre, truth[mapping[goal.name]].centre)) < 0.01
    preferred = [task.subgoal_name(j) for j in task.preferred_order()]
    assert [mapping[s] for s in learner.plan_] == preferred
    assert [mapping[s] for s in greedy_plan(learner.pdfa_).subgoals] == preferred


def test_a_non_trivial_preference_is_recovered():
    task = place_task(3, preferred=[2, 0, 1])
    learner, mapping, _ = learn(task, 150, seed=2)
    assert [mapping[s] for s in learner.plan_] == ["blue_at_0", "red_at_0", "green_at_0"]


def test_replanning_reaches_acceptance_with_a_hidden_block(place4_1000):
    task, learner, mapping, _ = place4_1000
    successes = []
    rng = np.random.default_rng(0)
    for trial in range(20):
        block = int(rng.integers(4))
        world = BlockWorld(task, hidden={block: int(rng.integers(1, 4))}, seed=trial)
        report = execute(learner.pdfa_, world.controller(learner.subgoals_),
                         reachable=world.reachable(learner.subgoals_))
        successes.append(report.success and world.task_done())
        if block == 0:  # the preferred first block was hidden: the plan changed around it
            assert report.replans and report.achieved[0] != learner.plan_[0]
    assert all(successes)


def test_a_permanently_unreachable_subgoal_is_avoided_when_another_accepted_set_exists():
    # demonstrations complete either {red, green} or {red, blue}
    from symlearn.learners.subgoals import pdfa_from_words

    pdfa = pdfa_from_words([("red", "green")] * 5 + [("red", "blue")] * 2)
    done = []

    def controller(symbol):
        done.append(symbol)
        return symbol != "green"

    report = execute(pdfa, controller, reachable=lambda s: s != "green")
    assert report.success and report.achieved == ("red", "blue") and "green" not in done
    assert report.initial_plan == ("red", "green") and report.replans[0].excluded == ("green",)
