"""Every learner follows one contract (symlearn/learners/base.py), checked on small real fits.

The learners are found, not listed: every public concrete ``Learner`` subclass defined under
``symlearn.learners`` is a case. ``FIXTURES`` says what data each one fits on (and the few
hyper-parameters that keep the fit small); a learner without an entry fails its case, so a new
learner cannot escape the contract by being forgotten here."""

from __future__ import annotations

import inspect

import pytest
from sklearn.base import clone

from learner_classes import learner_classes
from symlearn.learners.base import Learner, LearnerResult, NotFittedError, record_dict


def _ilp():
    from symlearn.logic.ilp import parse_task

    task = parse_task("dir(n; s).\n#modeb(1, go(var(dir))). #modeb(1, blocked(var(dir))).\n"
                      "#pos(p1, {}, {}, { go(n). blocked(s). }).\n#neg(n1, {}, {}, { go(s). blocked(s). }).\n")
    return {"timeout": 10}, task, None, ":- go(V1), blocked(V1)."


def _separating():
    from symlearn.data.ltl_samples import sample_from_traces

    sample = sample_from_traces([[["a"], ["b"]], [["b"]]], [[["a"]], [[]]], propositions=["a", "b"])
    return {"timeout": 5}, sample, None, "F b"


def _gridworld(**params):
    def build():
        from symlearn.data import record
        from symlearn.envs.gridworld import StochasticGridworld

        env = StochasticGridworld(0.0)
        policy = env.expert_policy()
        demos = record(env, lambda s: int(policy[s]), 3, seed=0, max_steps=200)
        return params, demos, env.to_tabular(), "symlearn-constraints"
    return build


def _logic():
    from symlearn.envs.logic_mdp import logic_mdp

    lm = logic_mdp("hanoi")
    return {"iterations": 3}, lm.expert_demonstrations(10, seed=0), lm.domain, "V1 < V2"


def _spec():
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task

    return ({"random_state": 0, "max_iterations": 3}, expert_demonstrations("office-1", 10, seed=0),
            get_task("office-1").make_env(), "")


def _one_class_tree():
    import numpy as np

    rng = np.random.default_rng(0)
    bottom = np.column_stack([rng.uniform(0.1, 0.7, 300), rng.uniform(0.1, 0.3, 300)])
    right = np.column_stack([rng.uniform(0.7, 0.9, 400), rng.uniform(0.1, 0.9, 400)])
    return {"max_depth": 3}, np.vstack([bottom, right]), ["x", "y"], "x < 0.1"


def _subgoal_pdfa():
    from symlearn.envs.block_world import Demonstrator, place_task

    task = place_task(2)
    runs, _ = Demonstrator(task, seed=0).demonstrations(20)
    return {"subsets": task.subsets()}, runs, task.feature_names(), '"kind": "pdfa"'


def _positive_only_ltl():
    traces = [[{"a"}, {"b"}], [{"a"}, {"a"}, {"b"}]]
    return {"max_size": 4}, traces, ["a", "b"], "a & F b"


def _reward_machine():
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations

    return {}, demonstrations("stack-2", seed=0).front, None, '"reward_machine"'


def _neural():
    from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations

    params = {"n_iterations": 1, "nominal_steps": 1024, "policy_steps": 1024, "n_policy_episodes": 4,
              "obs_dims": [0, 1], "hidden_sizes": (16,)}
    return params, expert_demonstrations(3, seed=0), BlockedPoint, "neural-icrl-cost"


LEARNERS = learner_classes()

#: qualified class name -> () -> (hyper-parameters, demonstrations, world, text the saved file contains)
FIXTURES = {
    "symlearn.learners.constraints.ilp_learner.ILPLearner": _ilp,
    "symlearn.learners.constraints.logic_constraint_inference.LogicConstraintInference": _logic,
    "symlearn.learners.constraints.mce_icrl.MCEICRL": _gridworld(n_iterations=50),
    "symlearn.learners.constraints.mce_icrl.MEICRL": _gridworld(n_iterations=50),
    "symlearn.learners.constraints.ml_constraint_inference.MLConstraintInference": _gridworld(horizon=30),
    "symlearn.learners.neural.gacl.NeuralGACL": _neural,
    "symlearn.learners.neural.mce_icrl.NeuralMCEICRL": _neural,
    "symlearn.learners.neural.me_icrl.NeuralMEICRL": _neural,
    "symlearn.learners.neural.vme_icrl.NeuralVMEICRL": _neural,
    "symlearn.learners.reward_machines.rm_inference.RewardMachineInference": _reward_machine,
    "symlearn.learners.subgoals.pdfa_learner.SubgoalPDFALearner": _subgoal_pdfa,
    "symlearn.learners.temporal.positive_only_ltl.PositiveOnlyLtlLearner": _positive_only_ltl,
    "symlearn.learners.temporal.separating_ltl.SeparatingLtlLearner": _separating,
    "symlearn.learners.temporal.spec_from_demos.SpecLearner": _spec,
    "symlearn.learners.trees.one_class_tree.OneClassTreeConstraint": _one_class_tree,
}


def test_learners_are_found():
    # the discovery itself: a walk that found nothing would make every other case vacuous
    assert "symlearn.learners.constraints.mce_icrl.MEICRL" in LEARNERS
    assert len(LEARNERS) >= len(FIXTURES)
    stale = sorted(set(FIXTURES) - set(LEARNERS))
    assert not stale, f"fixtures for learners that no longer exist: {stale}"


@pytest.mark.parametrize("name", sorted(LEARNERS))
def test_learner_contract(name, tmp_path):
    cls = LEARNERS[name]
    if name not in FIXTURES:
        pytest.fail(f"{name} has no entry in FIXTURES of tests/learners/test_contract.py: say what data it fits on")
    # every hyper-parameter has a default, so the learner constructs with none given
    assert isinstance(cls(), Learner)
    # fit is spelt alike everywhere, so a generic caller may pass both arguments by keyword
    fit_parameters = list(inspect.signature(cls.fit).parameters.values())
    assert [p.name for p in fit_parameters[:3]] == ["self", "demonstrations", "world"]
    assert fit_parameters[2].default is None
    params, demonstrations, world, expected_text = FIXTURES[name]()
    learner = cls(**params)
    # __init__ stores hyper-parameters under their names and nothing else
    init_names = [p for p in inspect.signature(cls.__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(init_names)
    assert set(vars(learner)) == set(init_names)
    twin = clone(learner)
    assert twin.get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early")
    before = dict(learner.get_params())
    assert learner.fit(demonstrations=demonstrations, world=world) is learner
    assert learner.get_params() == before
    # what a fit leaves on the learner is results (named with a trailing _), never working state
    working = sorted(k for k in set(vars(learner)) - set(init_names) if not k.endswith("_"))
    assert not working, f"fit left working state on the learner: {working}"
    result = learner.result_
    assert isinstance(result, LearnerResult) and result.learner == cls.__name__
    assert result.timings["total"] > 0
    for record in result.history:
        assert isinstance(record_dict(record), dict)
    assert isinstance(result.as_dict()["metrics"], dict)
    path = learner.save(tmp_path / f"out{learner.artefact_suffix}")
    text = path.with_suffix(".json").read_text() if path.suffix == ".safetensors" else path.read_text()
    assert expected_text in text
    assert not twin.__dict__.keys() & {k for k in vars(learner) if k.endswith("_")}  # clones are unfitted


def test_old_fit_keywords_still_work_with_a_warning():
    from symlearn.learners.temporal.positive_only_ltl import PositiveOnlyLtlLearner

    traces = [[{"a"}, {"b"}], [{"a"}, {"a"}, {"b"}]]
    with pytest.warns(FutureWarning, match=r"fit\(propositions=\.\.\.\) is deprecated.*world="):
        old = PositiveOnlyLtlLearner(max_size=4).fit(sample=traces, propositions=["a", "b"])
    assert old.formula_ == PositiveOnlyLtlLearner(max_size=4).fit(traces, ["a", "b"]).formula_
    with pytest.raises(TypeError, match="both propositions= and world="):
        PositiveOnlyLtlLearner().fit(traces, propositions=["a"], world=["a"])
