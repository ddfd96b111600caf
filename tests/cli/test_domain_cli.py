"""``symlearn domain check``: a user's folder checked, and an edited rule file re-scored."""

import json

import warehouse_domain as wh
from cli_runner import run


def test_check_folder_and_edited_rules(capsys, tmp_path):
    folder = wh.write_warehouse(tmp_path / "warehouse")
    code, out, err = run(capsys, "domain", "check", folder, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert (doc["states"], doc["actions"]) == (len(wh.states()), len(wh.ACTIONS))
    assert doc["forbidden_by_truth"] == int(wh.truth_mask().sum())
    # the truth itself scores perfectly and forbids no demonstrated step
    wh.expert_demonstrations(10, seed=0).save(tmp_path / "demos.jsonl")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", folder / "truth.lp",
                         "--demos", tmp_path / "demos.jsonl", "--json")
    doc = json.loads(out)
    assert (doc["fpr"], doc["fnr"], doc["missed_truth_rules"], doc["demonstrated_steps_forbidden"]) == (0.0, 0.0, [], 0)
    # an edit that drops the alarm rule and forbids waiting in an alarm: both show up
    edited = tmp_path / "edited.lp"
    edited.write_text(":- move(V1), blocked(V1).\n:- alarm, wait.\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", edited, "--demos", tmp_path / "demos.jsonl")
    assert code == 0, err
    assert "misses (partly) the truth rule :- alarm, move(D)." in out
    assert "demonstrated steps the rules forbid: 0" not in out and "alarm" in out.split("first:")[1]


def test_check_errors_are_one_line(capsys, tmp_path):
    code, out, err = run(capsys, "domain", "check", tmp_path)
    assert code == 2 and "no domain.toml" in err and len(err.strip().splitlines()) == 1
    folder = wh.write_warehouse(tmp_path / "w")
    bad = tmp_path / "bad.lp"
    bad.write_text(":- alarm, move(D)\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", bad)
    assert code == 2 and "bad.lp:" in err and "Traceback" not in err


def test_scores_on_the_pairs_a_rule_abiding_agent_reaches(capsys, tmp_path):
    """A truth that makes some states unreachable: what a rule forbids there no rule-abiding
    demonstration can show, so the check scores the reachable pairs on a second line too."""
    folder = wh.write_warehouse(tmp_path / "warehouse")
    # the robot may not move once loaded: loaded states away from the pick station are unreachable
    (folder / "truth.lp").write_text(wh.TRUTH + ":- loaded, move(D).\n")
    rules = tmp_path / "rules.lp"
    rules.write_text(wh.TRUTH + ":- loaded, move(D).\n:- loaded, wait.\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules, "--json")
    assert code == 0, err
    doc = json.loads(out)
    # waiting loaded is forbidden in 10 cells x 2 alarm values (20 of 140 allowed pairs); only the pick
    # station's 2 are reachable (of 86 allowed pairs a rule-abiding agent meets)
    assert (doc["fpr"], doc["fnr"], doc["reach_fpr"], doc["reach_fnr"]) == (20 / 140, 0.0, 2 / 86, 0.0)
    assert (doc["reach_pairs"], doc["unreachable"]) == (122, 102) and doc["reach_pairs"] + doc["unreachable"] == doc["pairs"]
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules)
    assert "pairs an agent obeying the truth can reach from the model's start: FPR" in out
    # the plain warehouse reaches every state: no second line
    plain = wh.write_warehouse(tmp_path / "plain")
    code, out, err = run(capsys, "domain", "check", plain, "--rules", plain / "truth.lp", "--json")
    assert json.loads(out)["unreachable"] == 0
    code, out, err = run(capsys, "domain", "check", plain, "--rules", plain / "truth.lp")
    assert "can reach" not in out
