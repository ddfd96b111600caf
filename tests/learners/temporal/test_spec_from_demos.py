"""Specification learning from demonstrations: template scoring, the learner, bad input."""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.spec_experts import expert_demonstrations
from symlearn.envs.spec_tasks import get_task
from symlearn.errors import DataError, ModelError
from symlearn.learners.base import NotFittedError
from symlearn.learners.temporal.spec_from_demos import SpecLearner, _SpecFit, _without_reproductions
from symlearn.learners.temporal.spec_templates import (
    TEMPLATES, TraceBounds, best_candidate, information_gain, instantiate, novelty_depth,
)
from symlearn.grounding.labeling import Labeling
from symlearn.logic.ltlf import holds, parse
from symlearn.logic.ltlf.vectorized import evaluate_many

NAMES = ("p", "q", "r")


def task_env(name):
    """A fresh environment of a specification task (the learner takes an environment, not a name)."""
    return get_task(name).make_env()


# --- templates ---------------------------------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(st.integers(0, 4), min_size=1, max_size=7), min_size=1, max_size=6),
       st.integers(0, 2 ** 15 - 1))
def test_bounds_agree_with_the_core_semantics(traces, bits):
    # 5 states, 3 atoms: a random labeling drawn from `bits`
    atoms = np.array([[(bits >> (3 * s + p)) & 1 for p in range(3)] for s in range(5)], dtype=bool)
    bounds = TraceBounds.from_traces([np.array(t) for t in traces], atoms)
    words = [[{NAMES[p] for p in range(3) if atoms[s, p]} for s in t] for t in traces]
    for template in TEMPLATES:
        pairs = [(p, q) for p in range(3) for q in range(3) if p != q] if template == "T" else [(p,) for p in range(3)]
        for args in pairs:
            ours = bounds.satisfies(template, *args)
            for negated in (False, True):
                formula = instantiate(template, [NAMES[i] for i in args], negated)
                expected = evaluate_many(formula, words)
                assert (ours ^ negated).tolist() == expected.tolist(), (formula, words)
                assert expected.tolist() == [holds(formula, w) for w in words]
        counts = bounds.counts(template)
        if template == "T":
            assert counts[0, 1] == bounds.satisfies("T", 0, 1).sum()
        else:
            assert counts.tolist() == [bounds.satisfies(template, p).sum() for p in range(3)]


def test_negations_read_naturally():
    assert str(instantiate("F", ["n"], True)) == "G !n"
    assert str(instantiate("G", ["n"], True)) == "F !n"
    assert str(instantiate("T", ["f", "g"], False)) == "f T g"
    assert str(instantiate("T", ["f", "g"], True)) == "!(f T g)"


def test_information_gain_values():
    gain = information_gain(np.array([10, 0, 5, 10]), np.array([0, 10, 5, 10]), 10, 10)
    assert gain.tolist() == pytest.approx([1.0, 1.0, 0.0, 0.0])
    # unequal split: 10 of 10 experts and 3 of 10 nominal satisfy
    p_sat = 13 / 20
    h = -(10 / 13) * np.log2(10 / 13) - (3 / 13) * np.log2(3 / 13)
    assert information_gain(np.array([10]), np.array([3]), 10, 10)[0] == pytest.approx(1 - p_sat * h)


def test_best_candidate_keeps_expert_polarity_and_prefers_simple_templates():
    # states: 0 start, 1 goal (g), 2 trap (n); experts reach g, nominal fall into n
    atoms = np.array([[0, 0], [1, 0], [0, 1]], dtype=bool)
    experts = TraceBounds.from_traces([np.array([0, 1])] * 4, atoms)
    nominal = TraceBounds.from_traces([np.array([0, 2])] * 4, atoms)
    choice = best_candidate(experts, nominal)
    assert choice.gain == pytest.approx(1.0)
    assert choice.template in ("F", "G") and choice.expert_rate == 1.0 and choice.nominal_rate == 0.0
    formula = instantiate(choice.template, [("g", "n")[i] for i in choice.atoms], choice.negated)
    assert str(formula) in ("F g", "G !n")
    # excluding what was chosen moves on to the other one
    other = best_candidate(experts, nominal, exclude={(choice.template, choice.atoms, choice.negated)})
    assert (other.template, other.atoms) != (choice.template, choice.atoms) and other.gain == pytest.approx(1.0)


def test_novelty_depth_prefers_places_far_from_nominal_behaviour():
    atoms = np.eye(6, dtype=bool)
    covered = np.array([1, 1, 0, 0, 0, 0], dtype=bool)
    depth = novelty_depth([np.array([0, 1, 2, 3, 4, 5])], atoms, covered)
    assert depth.tolist() == [0, 0, 1, 2, 3, 4]


# --- the learner -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def office1_demos():
    return expert_demonstrations("office-1", 30, seed=0)


def test_given_propositions_office1(office1_demos):
    learner = SpecLearner(random_state=0).fit(office1_demos, task_env("office-1"))
    assert learner.success_rate("(f T g) & G !n") == 1.0
    assert "g" in str(learner.formula_) and "G !n" in str(learner.formula_)
    added = [h for h in learner.history_ if h["added"]]
    assert learner.iterations_ == len(added) >= 1
    assert all(h["gain"] >= 0.2 for h in added)
    last = learner.history_[-1]
    assert not last["added"] and last["gain"] < 0.2  # the formula below the threshold is not added
    assert {"template", "gain", "seconds", "nominal_success"} <= set(last.as_dict())
    assert learner.dfa_.accepts([{"g"}]) == learner.dfa_.accepts([set(), {"g"}])
    assert 0 <= learner.entropy_ <= 1 and learner.length_ <= 7
    assert learner.labeling_.propositions == ("a", "b", "c", "d", "e", "f", "g", "n")


def test_learned_propositions_office1(office1_demos, tmp_path):
    env = task_env("office-1")
    learner = SpecLearner(propositions="learn", random_state=0).fit(office1_demos, env)
    assert learner.success_rate("(f T g) & G !n") == 1.0
    props = learner.labeling_.propositions
    assert props and all(p.startswith("p") for p in props)
    numbers = [int(p[1:]) for p in props]
    assert numbers == sorted(numbers)  # named in order of discovery
    for p in props:
        (state,) = learner.labeling_.states_where(p)
        assert learner.labeling_.meanings[p] == f"agent in cell {env.cell_of(state)}"
    learner.labeling_.save(tmp_path / "lab.json")
    assert Labeling.load(tmp_path / "lab.json") == learner.labeling_
    assert json.loads((tmp_path / "lab.json").read_text())["symlearn"] == "labeling"


def _outcome(learner):
    return (str(learner.formula_), [{k: v for k, v in h.as_dict().items() if k != "seconds"} for h in learner.history_],
            learner.pruned_, learner.entropy_, learner.labeling_.propositions, learner.stopped_because_)


def test_two_fits_on_one_learner_share_nothing(office1_demos):
    # a fit's working state lives in an object of its own (spec_from_demos._SpecFit): a second
    # fit on the same learner gives what a fresh learner gives, and a fit that fails part-way
    # leaves the previous results whole
    office2 = expert_demonstrations("office-2", 10, seed=1)
    learner = SpecLearner(random_state=0, max_iterations=3)
    learner.fit(office1_demos[:10], task_env("office-1"))
    first = _outcome(learner)
    learner.fit(office2, task_env("office-2"))
    assert _outcome(learner) == _outcome(SpecLearner(random_state=0, max_iterations=3).fit(office2, task_env("office-2")))
    learner.fit(office1_demos[:10], task_env("office-1"))
    assert _outcome(learner) == first
    model = learner.model_
    with pytest.raises(DataError, match="unknown proposition"):
        learner.set_params(propositions=["nowhere"]).fit(office2, task_env("office-2"))
    assert learner.model_ is model and _outcome(learner) == first
    assert not [k for k in vars(learner) if k.startswith("_")]


def test_without_policy_updates_the_nominal_stays_random(office1_demos):
    learner = SpecLearner(policy_updates=False, max_iterations=3, prune=False, random_state=0)
    learner.fit(office1_demos[:10], task_env("office-1"))
    # a random walk never satisfies the growing spec, so every chosen conjunct keeps a high gain
    assert all(h["nominal_success"] <= 0.2 for h in learner.history_[1:])
    assert learner.iterations_ == 3


def test_reproduced_demonstrations_leave_the_nominal_side():
    experts = [np.array([0, 1, 2]), np.array([0, 3, 2])]
    nominal = [np.array([0, 1, 2]), np.array([0, 4, 2]), np.array([0, 1]), np.array([0, 3, 2])]
    assert [t.tolist() for t in _without_reproductions(nominal, experts)] == [[0, 4, 2], [0, 1]]
    # Why: 50 experts go 0-1-2 or 0-3-2; the nominal agent does the same two thirds of the time
    # and cuts through state 4 otherwise. "G !4" holds for every expert and every reproduction,
    # but only after the reproductions leave does its gain reach the threshold.
    atoms = np.eye(5, dtype=bool)
    experts = [np.array([0, 1, 2])] * 25 + [np.array([0, 3, 2])] * 25
    nominal = [np.array([0, 1, 2])] * 17 + [np.array([0, 3, 2])] * 17 + [np.array([0, 4, 2])] * 16
    full = best_candidate(TraceBounds.from_traces(experts, atoms), TraceBounds.from_traces(nominal, atoms),
                          min_expert_rate=0.9)
    reduced = best_candidate(TraceBounds.from_traces(experts, atoms),
                             TraceBounds.from_traces(_without_reproductions(nominal, experts), atoms),
                             min_expert_rate=0.9)
    assert (full.template, full.atoms, full.negated) == (reduced.template, reduced.atoms, reduced.negated) == \
        ("F", (4,), True)
    assert full.gain < 0.2 <= reduced.gain


def test_learned_propositions_office2_close_the_undemonstrated_route():
    # Two equally short routes satisfy "mail, then g, avoiding the decorations the experts
    # avoid"; only the bottom one is demonstrated. The top corridor crosses decorations, so the
    # learner has to forbid it without ever seeing the experts avoid it (threshold stays 0.2).
    demos = expert_demonstrations("office-2", 50, seed=0)
    for seed in (0, 1):
        env = task_env("office-2")
        learner = SpecLearner(propositions="learn", random_state=seed).fit(demos, env)
        assert learner.threshold == 0.2
        assert learner.success_rate("(e T g) & G !n") == 1.0
        assert all(h["gain"] >= 0.2 for h in learner.history_ if h["added"])
        assert learner.stopped_because_ in ("gain below threshold", "nominal reproduces the demonstrations")
        cells = [env.cell_of(s) for p in learner.labeling_.propositions
                 for s in learner.labeling_.states_where(p)]
        assert any(x >= 3 and y <= 2 for x, y in cells)  # a cell of the top corridor is forbidden
        assert any(h["nominal_reproduced"] > 0 for h in learner.history_)


def test_pruning_drops_implied_conjuncts(office1_demos):
    env = task_env("office-1")
    learner = SpecLearner(random_state=0).fit(office1_demos[:10], env)
    labeling = env.labeling
    run = _SpecFit(np.random.default_rng(0), learner.model_, None)  # the working state of one fit
    kept = learner._pruned(run, [(parse("F f"), ("F", ("f",))), (parse("f T g"), ("T", ("f", "g")))], labeling)
    assert [str(f) for f, _ in kept] == ["f T g"]
    assert run.pruned == ["F f"]


# --- bad input ---------------------------------------------------------------------------------
def test_states_outside_the_environment():
    demos = Demonstrations([Trajectory([13, 14, 500])])
    with pytest.raises(DataError, match=r"step 2: state 500 is outside the environment \(0\.\.107\)"):
        SpecLearner().fit(demos, task_env("office-1"))


def test_empty_demonstrations():
    with pytest.raises(DataError, match="no demonstrations"):
        SpecLearner().fit([], task_env("office-1"))


def test_non_integer_states():
    with pytest.raises(DataError, match="integer state ids"):
        SpecLearner().fit([[0.5, 1.5]], task_env("office-1"))


def test_unknown_environment_name():
    with pytest.raises(DataError, match="unknown environment/task 'office-7'"):
        task_env("office-7")


def test_unknown_proposition_in_given_labeling():
    with pytest.raises(DataError, match="unknown proposition 'z'") as info:
        SpecLearner(propositions=["f", "z"]).fit([[13, 14]], task_env("office-1"))
    assert "known propositions: a, b" in info.value.hint


def test_labeling_of_states_outside_the_environment():
    labeling = Labeling({3: {"x"}, 999: {"y"}})
    with pytest.raises(DataError, match="labels state 999"):
        SpecLearner(labeling=labeling).fit([[13, 14]], task_env("office-1"))


def test_bad_parameters():
    with pytest.raises(ModelError, match="threshold"):
        SpecLearner(threshold=2).fit([[13]], task_env("office-1"))
    with pytest.raises(ModelError, match="propositions"):
        SpecLearner(propositions="maybe").fit([[13]], task_env("office-1"))
    with pytest.raises(NotFittedError, match="not fitted"):
        SpecLearner().success_rate("F g")


def test_min_expert_rate_rejects_details_only_some_experts_show():
    # 3 of 5 experts pass state 1 (a chance detour), none of the nominal; all experts reach state 2
    atoms = np.eye(3, dtype=bool)
    experts = TraceBounds.from_traces([np.array([0, 1, 2])] * 3 + [np.array([0, 2])] * 2, atoms)
    nominal = TraceBounds.from_traces([np.array([0, 2])] * 3 + [np.array([0])] * 2, atoms)
    loose = best_candidate(experts, nominal)
    assert loose.expert_rate < 1.0  # the chance detour wins on gain alone
    strict = best_candidate(experts, nominal, min_expert_rate=0.9)
    assert strict.expert_rate == 1.0 and strict.atoms == (2,) and strict.template == "F"
