"""The ``train --algo dqrm|dqn`` handler for the rendered block tasks (wired into train_command by the lead)."""

import argparse
import io
import json

import pytest

from symlearn.cli.output import Output
from symlearn.cli.train_rm import train_blocks
from symlearn.errors import DataError


def _args(**kw):
    base = {"env": "blockworld-stack2", "algo": "dqrm", "machine": "truth", "steps": 12, "output": None, "seed": 0}
    return argparse.Namespace(**{**base, **kw})


def test_short_dqrm_run_writes_json_and_networks(tmp_path):
    stream = io.StringIO()
    train_blocks(_args(output=str(tmp_path / "agent.safetensors")), Output(json_mode=True, stdout=stream))
    doc = json.loads(stream.getvalue())
    assert doc["method"] == "dqrm" and doc["episodes"] == 4 and len(doc["curve"]) == 1
    assert 0 <= doc["success"] <= 1 and doc["machine"] == "ground truth"
    assert (tmp_path / "agent.safetensors").exists() and (tmp_path / "agent.json").exists()


def test_dqn_on_a_learned_machine_file(tmp_path, capsys, monkeypatch):
    from cli_runner import run

    from symlearn.cli import learn_command

    module = "symlearn.cli.learn_rm_command"
    if module not in learn_command.LEARN_SUBCOMMANDS:  # until main's list has it
        monkeypatch.setattr(learn_command, "LEARN_SUBCOMMANDS", (*learn_command.LEARN_SUBCOMMANDS, module))
    code, _, err = run(capsys, "learn", "rm", "--env", "blockworld-stack2", "-o", tmp_path / "m.json")
    assert code == 0, err
    stream = io.StringIO()
    train_blocks(_args(algo="dqn", machine=str(tmp_path / "m.json"), steps=6, reward="sparse"),
                 Output(stdout=stream))
    assert "dqn-sparse on " in stream.getvalue() and "m.json" in stream.getvalue()


@pytest.mark.parametrize("changes, message", [
    ({"env": "toy-navigation"}, "'toy-navigation' is no rendered block task"),
    ({"steps": 0}, "--steps must be at least 1"),
    ({"output": "agent.pt"}, "-o must name a .safetensors file"),
    ({"reward": "dense"}, "--reward must be shaped or sparse"),
])
def test_bad_arguments(changes, message):
    with pytest.raises(DataError, match=message):
        train_blocks(_args(**changes), Output(stdout=io.StringIO()))
