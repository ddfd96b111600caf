"""Every learner follows one contract (symlearn/learners/base.py), checked on small real fits."""

from __future__ import annotations

import inspect

import pytest
from sklearn.base import clone

from symlearn.learners.base import Learner, LearnerResult, NotFittedError, record_dict


def _ilp():
    from symlearn.learners.constraints.ilp_learner import ILPLearner
    from symlearn.logic.ilp import parse_task

    task = parse_task("dir(n; s).\n#modeb(1, go(var(dir))). #modeb(1, blocked(var(dir))).\n"
                      "#pos(p1, {}, {}, { go(n). blocked(s). }).\n#neg(n1, {}, {}, { go(s). blocked(s). }).\n")
    return ILPLearner(timeout=10), (task,), ":- go(V1), blocked(V1)."


def _separating():
    from symlearn.data.ltl_samples import sample_from_traces
    from symlearn.learners.temporal.separating_ltl import SeparatingLtlLearner

    sample = sample_from_traces([[["a"], ["b"]], [["b"]]], [[["a"]], [[]]], propositions=["a", "b"])
    return SeparatingLtlLearner(timeout=5), (sample,), "F b"


def _gridworld(cls, **kw):
    def build():
        from symlearn.data import record
        from symlearn.envs.gridworld import StochasticGridworld

        env = StochasticGridworld(0.0)
        policy = env.expert_policy()
        demos = record(env, lambda s: int(policy[s]), 3, seed=0, max_steps=200)
        return cls(**kw), (demos, env.to_tabular()), "symlearn-constraints"
    return build


def _ml():
    from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference

    return _gridworld(MLConstraintInference, horizon=30)()


def _mce():
    from symlearn.learners.constraints.mce_icrl import MCEICRL

    return _gridworld(MCEICRL, n_iterations=50)()


def _me():
    from symlearn.learners.constraints.mce_icrl import MEICRL

    return _gridworld(MEICRL, n_iterations=50)()


def _logic():
    from symlearn.envs.logic_mdp import logic_mdp
    from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference

    lm = logic_mdp("hanoi")
    return LogicConstraintInference(iterations=3), (lm.expert_demonstrations(10, seed=0), lm.domain), "V1 < V2"


def _spec():
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task
    from symlearn.learners.temporal.spec_from_demos import SpecLearner

    return (SpecLearner(random_state=0, max_iterations=3),
            (expert_demonstrations("office-1", 10, seed=0), get_task("office-1").make_env()), "")


def _one_class_tree():
    import numpy as np

    from symlearn.learners.trees import OneClassTreeConstraint

    rng = np.random.default_rng(0)
    bottom = np.column_stack([rng.uniform(0.1, 0.7, 300), rng.uniform(0.1, 0.3, 300)])
    right = np.column_stack([rng.uniform(0.7, 0.9, 400), rng.uniform(0.1, 0.9, 400)])
    return OneClassTreeConstraint(max_depth=3), (np.vstack([bottom, right]), ["x", "y"]), "x < 0.1"


def _subgoal_pdfa():
    from symlearn.envs.block_world import Demonstrator, place_task
    from symlearn.learners.subgoals import SubgoalPDFALearner

    task = place_task(2)
    runs, _ = Demonstrator(task, seed=0).demonstrations(20)
    return SubgoalPDFALearner(subsets=task.subsets()), (runs, task.feature_names()), '"kind": "pdfa"'


def _positive_only_ltl():
    from symlearn.learners.temporal.positive_only_ltl import PositiveOnlyLtlLearner

    traces = [[{"a"}, {"b"}], [{"a"}, {"a"}, {"b"}]]
    return PositiveOnlyLtlLearner(max_size=4), (traces, ["a", "b"]), "a & F b"


def _reward_machine():
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations
    from symlearn.learners.reward_machines.rm_inference import RewardMachineInference

    return RewardMachineInference(), (demonstrations("stack-2", seed=0).front,), '"reward_machine"'


def _neural(name):
    def build():
        from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
        from symlearn.learners import neural

        learner = getattr(neural, name)(n_iterations=1, nominal_steps=1024, policy_steps=1024, n_policy_episodes=4,
                                        obs_dims=[0, 1], hidden_sizes=(16,))
        return learner, (expert_demonstrations(3, seed=0), BlockedPoint), "neural-icrl-cost"
    return build


BUILDERS = {"ilp": _ilp, "separating-ltl": _separating, "ml": _ml, "mce-icrl": _mce, "logic": _logic,
            "me-icrl": _me, "spec": _spec, "one-class-tree": _one_class_tree, "subgoal-pdfa": _subgoal_pdfa,
            "positive-only-ltl": _positive_only_ltl, "neural-mce-icrl": _neural("NeuralMCEICRL"),
            "neural-me-icrl": _neural("NeuralMEICRL"), "neural-gacl": _neural("NeuralGACL"),
            "neural-vme-icrl": _neural("NeuralVMEICRL"),
            "reward-machine": _reward_machine}


@pytest.mark.parametrize("name", sorted(BUILDERS))
def test_learner_contract(name, tmp_path):
    learner, data, expected_text = BUILDERS[name]()
    assert isinstance(learner, Learner)
    # __init__ stores hyper-parameters under their names and nothing else
    init_names = [p for p in inspect.signature(type(learner).__init__).parameters if p != "self"]
    assert set(learner.get_params()) == set(init_names)
    assert set(vars(learner)) == set(init_names)
    twin = clone(learner)
    assert twin.get_params() == learner.get_params()
    with pytest.raises(NotFittedError):
        learner.save(tmp_path / "early")
    before = dict(learner.get_params())
    assert learner.fit(*data) is learner
    assert learner.get_params() == before
    result = learner.result_
    assert isinstance(result, LearnerResult) and result.learner == type(learner).__name__
    assert result.timings["total"] > 0
    for record in result.history:
        assert isinstance(record_dict(record), dict)
    assert isinstance(result.as_dict()["metrics"], dict)
    path = learner.save(tmp_path / f"out{learner.artefact_suffix}")
    text = path.with_suffix(".json").read_text() if path.suffix == ".safetensors" else path.read_text()
    assert expected_text in text
    assert not twin.__dict__.keys() & {k for k in vars(learner) if k.endswith("_")}  # clones are unfitted


def _learner_classes() -> dict[str, type]:
    """Every concrete Learner subclass defined under symlearn.learners, by qualified name."""
    import importlib
    import pkgutil

    import symlearn.learners as package

    found: dict[str, type] = {}
    for module_info in pkgutil.walk_packages(package.__path__, "symlearn.learners."):
        module = importlib.import_module(module_info.name)
        for name, cls in inspect.getmembers(module, inspect.isclass):
            if issubclass(cls, Learner) and cls is not Learner and cls.__module__ == module.__name__ \
                    and not inspect.isabstract(cls):
                found[f"{cls.__module__}.{name}"] = cls
    return found


def test_every_learner_is_under_the_contract_test():
    # a learner added without a builder above fails here instead of escaping the contract
    covered = set()
    for build in BUILDERS.values():
        learner = build()[0]
        covered.add(f"{type(learner).__module__}.{type(learner).__name__}")
    missing = sorted(set(_learner_classes()) - covered)
    assert not missing, f"learners without a contract builder in tests/learners/test_contract.py: {missing}"
