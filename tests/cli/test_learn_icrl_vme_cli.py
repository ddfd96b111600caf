"""``symlearn learn icrl --method vme-icrl``: a short run end to end writing a loadable cost."""

import json

import pytest

from cli_runner import run
from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations

MODULE = "symlearn.cli.learn_icrl_command"


@pytest.fixture(autouse=True)
def icrl_registered(monkeypatch):
    """The command until ``learn_command.LEARN_SUBCOMMANDS`` lists it."""
    from symlearn.cli import learn_command

    if MODULE not in learn_command.LEARN_SUBCOMMANDS:
        monkeypatch.setattr(learn_command, "LEARN_SUBCOMMANDS", (*learn_command.LEARN_SUBCOMMANDS, MODULE))


def test_vme_icrl_method_writes_a_two_feature_cost(capsys, tmp_path):
    demos, out = tmp_path / "expert.npz", tmp_path / "vme.safetensors"
    expert_demonstrations(2, seed=1).save(demos)
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--demos", demos, "--steps", 2048,
                            "--iterations", 1, "--method", "vme-icrl", "--cost-inputs", "x,y", "-o", out, "--json")
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["method"] == "vme-icrl" and doc["iterations"] == 1 and doc["lambda"] == [1.0, 0.0]
    assert {"prior_kl", "concentration"} <= set(doc["history"][0])
    from symlearn.learners.neural import NeuralCost

    assert NeuralCost.load(out, BlockedPoint()).phi.n_features == 2

