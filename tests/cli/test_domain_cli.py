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
