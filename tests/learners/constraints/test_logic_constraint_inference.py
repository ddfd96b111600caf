"""Logic constraint inference (ML inference + ILP induction) on the bundled logic domains."""

import copy

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.logic_mdp import logic_mdp
from symlearn.errors import DataError, SymlearnError
from symlearn.learners.base import NotFittedError
from symlearn.learners.constraints.constraint_metrics import constraint_metrics, reachable_pairs
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference, LogicIteration


@pytest.fixture(scope="module")
def hanoi():
    return logic_mdp("hanoi")


@pytest.fixture(scope="module")
def hanoi_fit(hanoi):
    return LogicConstraintInference(iterations=3).fit(hanoi.expert_demonstrations(10, seed=0), hanoi)


@pytest.fixture(scope="module")
def priority():
    return logic_mdp("junction-priority")


@pytest.fixture(scope="module")
def priority_fit(priority):
    return LogicConstraintInference(iterations=10).fit(priority.expert_demonstrations(30, seed=0), priority)


# --- Hanoi: exactly the thesis' rule ------------------------------------------------------------
def test_hanoi_learns_no_larger_disk_on_a_smaller_one(hanoi, hanoi_fit):
    assert hanoi_fit.rules_ == [":- on(V1,V2), V1 < V2."]
    # the meaning, not the spelling: the rule forbids exactly the pairs the truth forbids
    np.testing.assert_array_equal(hanoi.rule_mask(hanoi_fit.rules_), hanoi.truth_forbidden)
    np.testing.assert_array_equal(hanoi_fit.rule_constraints_, hanoi.truth_forbidden)
    assert hanoi_fit.score() == {"fpr": 0.0, "fnr": 0.0, "accuracy": 1.0,
                                 "forbidden": int(hanoi.truth_forbidden.sum())}
    # the closed constraint set contains the rules' pairs and never a demonstrated one
    assert (hanoi_fit.constraints_ >= hanoi_fit.rule_constraints_).all()
    assert not (hanoi_fit.constraints_ & hanoi_fit.demonstrated_).any()
    assert hanoi_fit.score(of="constraints")["fnr"] == 0.0
    assert hanoi_fit.hypothesis_ is not None and list(hanoi_fit.hypothesis_.rules) == hanoi_fit.rules_


@pytest.mark.parametrize("start", ["demonstrations", 0.5, "uniform"])
def test_hanoi_rule_by_start(hanoi, start):
    """Every start learns the rule. A pure uniform start used not to (started from every state,
    the most visited undemonstrated pairs are allowed moves far from the demonstrated path, e.g.
    onto an empty peg, and 3 iterations went to them); no rule of the bias forbids those without
    forbidding a demonstrated move, so inference now passes them over and reports them."""
    learner = LogicConstraintInference(iterations=3, start=start).fit(hanoi.expert_demonstrations(10, seed=0), hanoi)
    assert learner.rules_ == [":- on(V1,V2), V1 < V2."]
    if start == "uniform":
        assert learner.unexplained_


def test_history_records_every_iteration(hanoi_fit):
    history = hanoi_fit.history_
    assert 1 <= len(history) <= 3
    assert [h.iteration for h in history] == list(range(1, len(history) + 1))
    for h in history:
        assert isinstance(h, LogicIteration)
        assert h.inference_seconds >= 0 and h.induction_seconds > 0
        assert h.n_positive > 0 and h.n_negative >= 1 and h.visitation > 0
        assert " / " in h.inferred and isinstance(h.rules, tuple)
        record = h.as_dict()
        assert {"inference_seconds", "induction_seconds", "rules", "constraints"} <= set(record)
    assert history[-1].rules == tuple(hanoi_fit.rules_)
    # negatives only grow: every inferred pair stays a negative example
    assert all(a.n_negative <= b.n_negative for a, b in zip(history, history[1:]))
    assert hanoi_fit.inferred_.sum() == len(history)
    assert hanoi_fit.seconds_ >= sum(h.induction_seconds for h in history)


def test_rules_can_be_written_as_lp(hanoi_fit, tmp_path):
    path = hanoi_fit.to_lp(tmp_path / "hanoi.lp")
    text = path.read_text() if hasattr(path, "read_text") else (tmp_path / "hanoi.lp").read_text()
    assert ":- on(V1,V2), V1 < V2." in text


# --- traffic junction with priority to the right --------------------------------------------------
def test_priority_rules_match_the_truth_where_a_rule_abiding_driver_goes(priority, priority_fit):
    learned = priority.rule_mask(priority_fit.rules_)
    np.testing.assert_array_equal(learned, priority_fit.rule_constraints_)
    truth = priority.truth_forbidden
    space = reachable_pairs(priority.mdp, truth) & ~priority.unavailable
    assert space.sum() > 50  # every road cell with both observations, all 5 actions
    assert (learned[space] == truth[space]).all(), priority.pairs_of(space & (learned != truth))
    assert constraint_metrics(learned, truth, space)["accuracy"] == 1.0
    # stay on the road and priority to the right are among the rules
    assert ":- not onRoad(V1) : dir(V1)." in priority_fit.rules_
    assert ":- carOnTheRight, not go(zero)." in priority_fit.rules_
    # with the default start, over the whole space too: the 7 thesis rules, exactly the truth
    assert len(priority_fit.rules_) == 7
    np.testing.assert_array_equal(priority_fit.rule_constraints_, truth)
    assert priority_fit.score() == {"fpr": 0.0, "fnr": 0.0, "accuracy": 1.0, "forbidden": int(truth.sum())}


def test_lights_junction_learns_the_off_road_rule_and_exactly_the_truth():
    """With the default start (a 0.1 uniform share) the off-road cells keep nominal visitation
    after the 8 sideways rules are learned, so the off-road rule is induced too: the 13 thesis
    rules (about 30 s). With start="demonstrations" the loop stops at 12 rules, full-space FNR
    0.816."""
    lights = logic_mdp("junction-lights")
    learner = LogicConstraintInference(iterations=13).fit(lights.expert_demonstrations(100, seed=0), lights)
    assert ":- not onRoad(V1) : dir(V1)." in learner.rules_
    assert len(learner.rules_) == 13
    np.testing.assert_array_equal(learner.rule_constraints_, lights.truth_forbidden)
    assert learner.score() == {"fpr": 0.0, "fnr": 0.0, "accuracy": 1.0,
                               "forbidden": int(lights.truth_forbidden.sum())}


def test_start_is_passed_to_the_inference_and_checked(hanoi):
    with pytest.raises(SymlearnError, match="unknown start"):
        LogicConstraintInference(iterations=1, start="anywhere").fit(hanoi.expert_demonstrations(2, seed=0), hanoi)
    with pytest.raises(SymlearnError, match=r"\[0, 1\]"):
        LogicConstraintInference(iterations=1, start=1.5).fit(hanoi.expert_demonstrations(2, seed=0), hanoi)


def test_reachable_pairs_follow_the_allowed_moves(priority):
    everything = reachable_pairs(priority.mdp, np.zeros_like(priority.truth_forbidden))
    truth_space = reachable_pairs(priority.mdp, priority.truth_forbidden)
    assert (truth_space <= everything).all() and truth_space.sum() < everything.sum()
    assert not truth_space[priority.mdp.terminal].any()
    starts = priority.mdp.initial > 0
    assert truth_space[starts].all()
    # no off-road cell is reachable when the truth is obeyed
    for s in np.flatnonzero(truth_space[:, 0]):
        assert priority.logic.model.road_of(priority.states[s].cell) is not None


# --- bad input ----------------------------------------------------------------------------------
def test_state_outside_the_mdp_is_a_data_error(hanoi):
    demos = Demonstrations([Trajectory(states=[0, hanoi.mdp.n_states + 5], actions=[0])])
    with pytest.raises(DataError):
        LogicConstraintInference(iterations=1).fit(demos, hanoi)


def _empty_peg_move(hanoi):
    """A move from an empty peg: no pair of the domain at all."""
    bad = np.argwhere(hanoi.unavailable & ~hanoi.mdp.terminal[:, None])
    s, a = map(int, bad[0])
    assert hanoi.mdp.transitions[s, a, s] == 1.0  # it stays put
    return s, a


@pytest.mark.parametrize("noise", [False, True])
def test_a_move_that_does_not_exist_is_a_data_error_even_with_noise(hanoi, noise):
    s, a = _empty_peg_move(hanoi)
    good = list(hanoi.expert_demonstrations(3, seed=1))
    bad = Trajectory(states=[s, s], actions=[a])
    with pytest.raises(DataError, match="not available"):
        LogicConstraintInference(iterations=1, noise=noise).fit(Demonstrations(good + [bad]), hanoi)


def _known_broken(hanoi, demos):
    """A known constraint that the first demonstrated step breaks."""
    first = demos[0]
    known = np.zeros_like(hanoi.unavailable)
    known[int(first.states[0]), int(first.actions[0])] = True
    return known


def test_breaking_a_known_constraint_is_a_data_error(hanoi):
    demos = hanoi.expert_demonstrations(3, seed=1)
    known = _known_broken(hanoi, demos)
    with pytest.raises(DataError, match="breaks the given constraints"):
        LogicConstraintInference(iterations=1, known=known).fit(demos, hanoi)


def test_noise_turns_the_error_into_a_warning(hanoi):
    demos = hanoi.expert_demonstrations(5, seed=1)
    known = _known_broken(hanoi, demos)
    with pytest.warns(UserWarning, match="break the given constraints"):
        learner = LogicConstraintInference(iterations=1, noise=True, known=known).fit(demos, hanoi)
    assert len(learner.history_) == 1
    s, a = int(demos[0].states[0]), int(demos[0].actions[0])
    assert not learner.constraints_[s, a]  # the noisy pair stays allowed


@pytest.mark.parametrize("iterations", [0, -2])
def test_iterations_must_be_positive(hanoi, iterations):
    with pytest.raises(SymlearnError, match="iterations"):
        LogicConstraintInference(iterations=iterations).fit(hanoi.expert_demonstrations(2, seed=0), hanoi)


def test_to_lp_without_rules_is_an_error(hanoi_fit):
    learner = copy.copy(hanoi_fit)  # a fitted learner (an unfitted one fails earlier, NotFittedError)
    learner.hypothesis_ = None
    with pytest.raises(SymlearnError, match="no rules were induced"):
        learner.to_lp("unused.lp")


def test_results_before_fit_are_a_not_fitted_error():
    with pytest.raises(NotFittedError):
        LogicConstraintInference(iterations=1).to_lp("unused.lp")


def test_known_rules_are_given_not_learned_again(hanoi):
    # the known rule's pairs are no examples for induction: it is neither relearned nor judged by
    # rule support, and the rule file lists it apart from the learned rules
    learner = LogicConstraintInference(iterations=3, known=":- on(1,2).").fit(hanoi.expert_demonstrations(10, seed=0),
                                                                            hanoi)
    assert learner.rules_ == [":- on(V1,V2), V1 < V2."]
    assert learner.known_rules_ == [":- on(1,2)."]
    assert [r.rule for r in learner.rule_support_] == learner.rules_
    header, _, body = learner._lp_text().partition("\n\n")
    assert "Given in advance (known, not learned; not among the rules below):\n%   :- on(1,2)." in header
    assert body.split() == [":-", "on(V1,V2),", "V1", "<", "V2."]


def test_a_known_truth_leaves_nothing_to_learn(hanoi):
    learner = LogicConstraintInference(iterations=3, known=[":- on(V1,V2), V1 < V2."]).fit(
        hanoi.expert_demonstrations(10, seed=0), hanoi)
    assert learner.rules_ == [] and learner.known_rules_ == [":- on(V1,V2), V1 < V2."]
    # a mask is still accepted: no rules to list then
    mask = hanoi.rule_mask([":- on(V1,V2), V1 < V2."])
    assert LogicConstraintInference(iterations=1, known=mask).fit(hanoi.expert_demonstrations(10, seed=0),
                                                                  hanoi).known_rules_ == []
