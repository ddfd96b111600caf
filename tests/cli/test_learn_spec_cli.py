"""``symlearn learn spec`` end to end (in-process through main())."""

import json

from cli_runner import run
from symlearn.data import Demonstrations, Trajectory
from symlearn.grounding.labeling import Labeling
from symlearn.rendering import dot_available




def test_json_document_and_files(capsys, tmp_path):
    out_file = tmp_path / "spec.ltl"
    code, out, err = run(capsys, "learn", "spec", "--env", "office-1", "--n-demos", 15, "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert {"formula", "propositions", "success_rate", "entropy", "iterations", "seconds"} <= set(doc)
    assert doc["success_rate"] == 1.0 and doc["iterations"] >= 1
    assert out_file.read_text().strip() == doc["formula"]
    labeling = Labeling.load(tmp_path / "spec.labeling.json")
    assert "g" in labeling.propositions
    assert "digraph" in (tmp_path / "spec.dot").read_text()
    if dot_available():
        assert "<svg" in (tmp_path / "spec.svg").read_text()
    assert "iteration 1:" in err  # progress per iteration on stderr


def test_learned_propositions_from_a_demonstrations_file(capsys, tmp_path):
    from symlearn.envs.spec_experts import expert_demonstrations

    path = tmp_path / "demos.jsonl"
    expert_demonstrations("office-1", 15, seed=3).save(path)
    code, out, err = run(capsys, "learn", "spec", "--env", "office-1", "--demos", path, "--props", "learn", "-q")
    assert code == 0, err
    assert "formula: " in out and "agent in cell" in out and "success rate on the ground-truth task" in out


def test_unknown_environment(capsys):
    code, out, err = run(capsys, "learn", "spec", "--env", "kitchen-1")
    assert code == 2 and out == ""
    assert err.startswith("symlearn: error: unknown environment/task 'kitchen-1'") and "office-1" in err


def test_demonstrations_outside_the_environment(capsys, tmp_path):
    path = tmp_path / "bad.jsonl"
    Demonstrations([Trajectory([13, 14, 4000])]).save(path)
    code, _, err = run(capsys, "learn", "spec", "--env", "office-1", "--demos", path)
    assert code == 2
    # located: the trajectory's line and the column of the value 4000
    assert f"symlearn: error: {path}:2:21: demonstration 0: states: step 2: state 4000 is outside" in err


def test_unknown_proposition_in_a_labeling_file(capsys, tmp_path):
    path = tmp_path / "lab.json"
    Labeling({13: {"x"}, 4000: {"y"}}).save(path)
    code, _, err = run(capsys, "learn", "spec", "--env", "office-1", "--labeling", path, "--n-demos", 3)
    assert code == 2 and "labels state 4000" in err


def test_group_without_subcommand_prints_help(capsys):
    code, _, err = run(capsys, "learn")
    assert code == 2 and "spec" in err
