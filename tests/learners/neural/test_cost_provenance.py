"""A learned neural cost's file says where its demonstrations came from (their
``metadata["source"]``), as the DNF file's header does; files without it still load."""

import json

import pytest

from symlearn.data import Demonstrations
from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
from symlearn.learners.neural import NeuralCost, NeuralGACL, NeuralMCEICRL, NeuralMEICRL

TINY = dict(n_iterations=1, nominal_steps=256, policy_steps=256, n_policy_episodes=2, obs_dims=[0, 1],
            hidden_sizes=(8,), select_inputs=0)


@pytest.mark.parametrize("method, extra", [(NeuralMCEICRL, {"n_features": 1, "pretrain_epochs": 1}),
                                           (NeuralMEICRL, {"backward_epochs": 1}), (NeuralGACL, {})])
def test_the_saved_cost_names_the_demonstrations_source(tmp_path, method, extra):
    recorded = expert_demonstrations(2, seed=0)
    demos = Demonstrations(recorded, metadata={**recorded.metadata, "source": "2 expert episodes of\nblocked-point"})
    learner = method(**TINY, **extra).fit(demos, BlockedPoint)
    assert learner.cost_.learned_from == "2 expert episodes of blocked-point"  # one line
    path = learner.save(tmp_path / "cost.safetensors")
    provenance = json.loads(path.with_suffix(".json").read_text())["config"]["provenance"]
    assert provenance["demonstrations"] == "2 expert episodes of blocked-point"
    assert provenance["learner"] == method.__name__ and "parameters" in provenance
    assert NeuralCost.load(path, BlockedPoint()).learned_from == "2 expert episodes of blocked-point"


def test_demonstrations_that_do_not_say_and_older_files(tmp_path):
    learner = NeuralGACL(**TINY).fit(expert_demonstrations(2, seed=0), BlockedPoint)
    assert learner.cost_.learned_from is None and "demonstrations" not in learner.cost_.provenance
    path = learner.save(tmp_path / "cost.safetensors")
    # a file written before the provenance named the demonstrations (or with none at all) still loads
    document = json.loads(path.with_suffix(".json").read_text())
    document["config"].pop("provenance")
    path.with_suffix(".json").write_text(json.dumps(document))
    assert NeuralCost.load(path, BlockedPoint()).learned_from is None


@pytest.mark.parametrize("method, extra", [(NeuralMCEICRL, {"n_features": 1, "pretrain_epochs": 1}),
                                           (NeuralMEICRL, {"backward_epochs": 1}), (NeuralGACL, {})])
def test_the_saved_cost_records_what_it_charges_its_demonstrations(tmp_path, method, extra):
    """The expert's level -- the default budget of an agent trained on the cost -- is the mean of
    the cost's undiscounted sums over the demonstration episodes, as the cost itself computes them."""
    import numpy as np

    demos = expert_demonstrations(3, seed=0)
    learner = method(**TINY, **extra).fit(demos, BlockedPoint)
    record = learner.cost_.provenance["expert_cost"]
    sums = [float(learner.cost_(np.asarray(ep.states[:len(ep.actions)]), np.asarray(ep.actions)).sum())
            for ep in demos]
    assert record["episodes"] == 3 and record["mean"] == pytest.approx(np.mean(sums), rel=1e-6)
    assert record["min"] <= record["mean"] <= record["max"] and record["mean"] > 0   # a sigmoid charges everything
    path = learner.save(tmp_path / "cost.safetensors")
    assert NeuralCost.load(path, BlockedPoint()).expert_level == pytest.approx(record["mean"])


def test_an_expert_level_that_is_no_number_is_refused_on_load(tmp_path):
    from symlearn.errors import ModelError

    learner = NeuralGACL(**TINY).fit(expert_demonstrations(2, seed=0), BlockedPoint)
    path = learner.save(tmp_path / "cost.safetensors")
    document = json.loads(path.with_suffix(".json").read_text())
    for bad in (-1.0, "7", None, True):
        document["config"]["provenance"]["expert_cost"] = {"mean": bad}
        path.with_suffix(".json").write_text(json.dumps(document))
        with pytest.raises(ModelError, match="expert_cost.mean") as caught:
            NeuralCost.load(path, BlockedPoint())
        assert caught.value.file == str(path)
    document["config"]["provenance"].pop("expert_cost")   # older files: no level, still loaded
    path.with_suffix(".json").write_text(json.dumps(document))
    assert NeuralCost.load(path, BlockedPoint()).expert_level is None
