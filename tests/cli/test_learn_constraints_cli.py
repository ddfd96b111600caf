"""``symlearn learn constraints`` and ``symlearn envs`` end to end (in-process through main())."""

import json

import pytest

from cli_runner import run
from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.logic_mdp import logic_mdp
from symlearn.logic.asp import Hypothesis




def test_hanoi_rules_json_and_editable_file(capsys, tmp_path):
    out_file = tmp_path / "hanoi.lp"
    code, out, err = run(capsys, "learn", "constraints", "--env", "hanoi", "--n-demos", 10, "--iterations", 4,
                         "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert {"rules", "constraints", "fpr", "fnr", "accuracy", "iterations", "seconds"} <= set(doc)
    assert doc["rules"] == [":- on(V1,V2), V1 < V2."]
    assert doc["fnr"] == 0.0 and doc["constraints"] == 102
    assert Hypothesis.from_lp(out_file).rules == doc["rules"]
    assert "iteration 1: inferred" in err and "induction" in err


def test_ml_on_a_junction_from_a_demonstrations_file_with_state_names(capsys, tmp_path):
    lm = logic_mdp("junction-priority")
    demos = lm.expert_demonstrations(20, seed=1)
    named = Demonstrations([Trajectory(states=[lm.mdp.state_names[s] for s in t.states],
                                       actions=[lm.mdp.action_names[a] for a in t.actions]) for t in demos])
    path = tmp_path / "demos.jsonl"
    named.save(path)
    out_file = tmp_path / "pairs.json"
    code, out, err = run(capsys, "learn", "constraints", "--env", "junction-priority", "--demos", path,
                         "--method", "ml", "--iterations", 30, "-o", out_file, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["rules"] is None and 0 < doc["constraints"] <= 30 * 5
    saved = json.loads(out_file.read_text())
    assert saved["format"] == "symlearn-constraints" and len(saved["forbidden"]) == doc["constraints"]


def test_state_outside_the_environment_names_the_file(capsys, tmp_path):
    path = tmp_path / "bad.jsonl"
    Demonstrations([Trajectory(states=[0, 999], actions=[0])]).save(path)
    code, _, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--demos", path)
    assert code == 2
    assert str(path) in err and "999 is outside the environment" in err


def test_unavailable_action_is_a_clear_error(capsys, tmp_path):
    lm = logic_mdp("hanoi")
    s, a = map(int, next(iter(zip(*((lm.unavailable & ~lm.mdp.terminal[:, None]).nonzero())))))
    path = tmp_path / "bad.jsonl"
    Demonstrations([Trajectory(states=[s, s], actions=[a])]).save(path)
    code, _, err = run(capsys, "learn", "constraints", "--env", "hanoi", "--demos", path)
    assert code == 2 and "is not available in state" in err


def test_demonstrations_breaking_known_rules(capsys, tmp_path):
    lm = logic_mdp("junction-lights")
    demos = lm.expert_demonstrations(5, seed=0)
    path = tmp_path / "demos.jsonl"
    demos.save(path)
    known = tmp_path / "known.lp"
    known.write_text(":- go(north).\n")  # some expert drive goes north
    code, _, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--demos", path,
                       "--method", "ml", "--known", known)
    assert code == 2 and "breaks the given constraints" in err
    # the noise is counted in the result's warnings (text and JSON), not as a Python warning on stderr
    code, out, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--demos", path,
                         "--method", "ml", "--known", known, "--noise", "--iterations", 5)
    assert code == 0, err
    assert "warning: " in out and "break the given constraints (treated as noise)" in out


def test_method_needing_facts_or_reward_is_refused(capsys):
    code, _, err = run(capsys, "learn", "constraints", "--env", "gridworld", "--method", "logic")
    assert code == 2 and "no ASP facts" in err
    code, _, err = run(capsys, "learn", "constraints", "--env", "hanoi", "--method", "mce-icrl", "--reward", "given")
    assert code == 2 and "defines no reward" in err


def test_mce_icrl_without_a_reward_heads_for_where_demonstrations_end(capsys):
    code, out, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--method", "mce-icrl",
                         "--n-demos", 20, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["constraints"] > 0 and doc["fnr"] < 0.5  # most true constraints found, at a cost in FPR


def test_envs_lists_both_kinds(capsys):
    code, out, err = run(capsys, "envs", "--json")
    assert code == 0, err
    doc = json.loads(out)
    names = {r["name"] for r in doc["constraints"]}
    assert {"hanoi", "junction-lights", "junction-priority", "junction-combined", "gridworld"} <= names
    assert "office-1" in {r["name"] for r in doc["specs"]}


def test_sumo_driven_demonstrations(capsys):
    pytest.importorskip("sumo")
    pytest.importorskip("traci")
    code, out, err = run(capsys, "learn", "constraints", "--env", "junction-priority", "--expert", "sumo",
                         "--n-demos", 15, "--iterations", 6, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["rules"] and doc["iterations"] >= 1


def test_sumo_refuses_other_environments(capsys):
    code, _, err = run(capsys, "learn", "constraints", "--env", "hanoi", "--expert", "sumo", "--n-demos", 3)
    assert code == 2 and "SUMO drives only" in err


def test_inconsistent_goal_label(capsys, tmp_path):
    lm = logic_mdp("junction-lights")
    demo = lm.expert_demonstrations(1, seed=0)[0]
    wrong = lm.mdp.state_names[int(demo.states[0])]
    path = tmp_path / "bad.jsonl"
    Demonstrations([Trajectory(states=list(demo.states), actions=list(demo.actions), info={"goal": wrong})]).save(path)
    code, _, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--demos", path, "--method", "ml")
    assert code == 2 and "labelled with goal" in err and str(path) in err
    right = lm.mdp.state_names[int(demo.states[-1])]
    Demonstrations([Trajectory(states=list(demo.states), actions=list(demo.actions), info={"goal": right})]).save(path)
    code, _, err = run(capsys, "learn", "constraints", "--env", "junction-lights", "--demos", path, "--method", "ml",
                       "--iterations", 3)
    assert code == 0, err
