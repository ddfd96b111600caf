"""A researcher's own domain folders (blocks with arity-2 atoms and named states, an elevator with
CRLF files), used through the CLI as documented: what they learn at the defaults, and where every
mistake in their files (rules, bias, --known, demonstrations) is reported."""

from __future__ import annotations

import json

import blocks_domain as bd
import pytest
from cli_runner import run


@pytest.fixture
def blocks(tmp_path):
    folder = bd.write_domain(bd.BLOCKS, tmp_path / "blocks")
    demos = tmp_path / "blocks_demos.jsonl"
    bd.expert_demonstrations(bd.BLOCKS, 40, seed=0, by_name=True, path=demos)
    return folder, demos


@pytest.fixture
def elevator(tmp_path):
    folder = bd.write_domain(bd.ELEVATOR, tmp_path / "elevator")
    demos = tmp_path / "elevator_demos.jsonl"
    bd.expert_demonstrations(bd.ELEVATOR, 40, seed=0, path=demos)
    return folder, demos


# --- what is learned at the defaults ------------------------------------------------------------
def test_blocks_by_name_learn_the_weight_rule(capsys, blocks, tmp_path):
    folder, demos = blocks
    out_file = tmp_path / "rules.lp"
    # the expert's optimal plans never needed the weight rule (the planner fitted to them at rationality
    # ~42 never stacks a heavier block either): at the defaults nothing is learned, and the file says why
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-o", out_file,
                         "--json", "-q")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["rules"] == [] and doc["stop_reason"] == "min_evidence" and doc["fpr"] == 0.0
    assert len(doc["warnings"]) == 1 and doc["warnings"][0].startswith("no rule learned: the demonstrations never")
    assert "% No rules learned" in out_file.read_text() and "--known" in out_file.read_text()
    # without the evidence test the refitted planner still finds it, weakly supported
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-o", out_file,
                         "--json", "-q", "--min-evidence", "0")
    assert code == 0, err
    doc = json.loads(out)
    assert ":- stack(V1,V2), heavier(V1,V2)." in doc["rules"] and doc["fnr"] == 0.0
    assert doc["stop_reason"] in {"converged", "no_candidates", "min_visitation"} and doc["iterations"] < 20
    assert doc["warnings"] == []
    assert any(":- stack(V1,V2), heavier(V1,V2). is weakly supported" in n for n in doc["notes"])
    code, out, err = run(capsys, "domain", "check", folder, "--rules", out_file, "--demos", demos)
    assert code == 0 and "demonstrated steps the rules forbid: 0" in out


def test_crlf_elevator_learns_both_door_rules(capsys, elevator):
    folder, demos = elevator
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "--json", "-q")
    assert code == 0, err
    doc = json.loads(out)
    assert {":- door_open, up.", ":- door_open, down."} <= set(doc["rules"]) and doc["fnr"] == 0.0


# --- rule files -------------------------------------------------------------------------------
def test_an_unsafe_variable_is_located_in_the_rule_file(capsys, elevator, tmp_path):
    folder, _ = elevator
    rules = tmp_path / "edited.lp"
    rules.write_text(":- door_open, up.\n\n   :- door_open, down, not floor(F).\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules)
    assert code == 2 and "Traceback" not in err
    assert err.startswith(f"symlearn: error: {rules}:3:4: unsafe variable F"), err


def test_a_rule_with_a_head_is_located(capsys, elevator, tmp_path):
    folder, _ = elevator
    rules = tmp_path / "edited.lp"
    rules.write_text(":- door_open, up.\nstuck :- door_open.\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules)
    assert code == 2 and f"{rules}:2:1: rule 'stuck :- door_open.' has a head" in err


# --- the bias -----------------------------------------------------------------------------------
def test_a_missing_full_stop_in_the_bias_names_the_unfinished_declaration(capsys, blocks):
    folder, _ = blocks
    unfinished = "#modeb(1, stack(var(block), var(block)))"
    (folder / "bias.las").write_text(unfinished + "  % a comment\n\n#maxv(2).\n")
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2
    # located just after the declaration's last character, where the '.' belongs
    assert (f"{folder / 'bias.las'}:1:{len(unfinished) + 1}: the #modeb declaration starting at line 1 does not "
            "end with '.' (the next declaration, '#maxv', starts on line 3)" in err), err


def test_mode_declarations_that_can_never_fire_are_warned_about(capsys, blocks):
    folder, demos = blocks
    (folder / "bias.las").write_text("#modeb(1, stak(var(block), var(block)), (positive)).\n"
                                     "#modeb(1, heavier(var(block), var(block)), (positive)).\n"
                                     "#modeb(1, on_table(const(blk))).\n#maxv(2).\n")
    bias = folder / "bias.las"
    code, out, err = run(capsys, "domain", "check", folder, "--json")
    assert code == 0
    warnings = json.loads(out)["bias_warnings"]
    assert [(w["line"], w["column"]) for w in warnings] == [(1, 1), (3, 1)]
    assert "predicate stak/2 is defined nowhere" in warnings[0]["message"] and "did you mean stack/2?" in \
        warnings[0]["message"]
    assert "const(blk) has no #constant(blk, ...)" in warnings[1]["message"]
    code, out, err = run(capsys, "domain", "check", folder)
    assert f"warning: {bias}:1:1: #modeb(stak(var(block),var(block))): predicate stak/2" in out
    # learning with it finds nothing, and says why
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q")
    assert code == 0 and "rules: (none induced)" in out and f"warning: {bias}:1:1:" in out


def test_a_misspelt_known_rule_is_warned_about(capsys, blocks, tmp_path):
    folder, demos = blocks
    known = tmp_path / "known.lp"
    known.write_text(":- stack(X, Y), havier(X, Y).\n")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "--known", known,
                         "-q", "--json")
    assert code == 0, err
    assert any(w.startswith(f"{known}:1:17: --known: predicate havier/2 is defined nowhere")
               for w in json.loads(out)["warnings"])


# --- demonstrations -----------------------------------------------------------------------------
def _edit_demo(demos, index, key, step, value):
    lines = demos.read_text(encoding="utf-8").splitlines()
    record = json.loads(lines[index + 1])
    record[key][step] = value
    lines[index + 1] = json.dumps(record, ensure_ascii=False)
    demos.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return lines[index + 1]


@pytest.mark.parametrize("command", ["learn", "check"])
def test_an_unknown_state_name_is_located_in_the_demonstrations(capsys, blocks, command):
    folder, demos = blocks
    line = _edit_demo(demos, 3, "states", 1, "a▸b  · c")
    column = line.index('"a▸b  · c"') + 1
    args = (["learn", "constraints", "--domain", folder, "--demos", demos, "--validation", "0.5"]
            if command == "learn" else ["domain", "check", folder, "--rules", folder / "truth.lp", "--demos", demos])
    code, out, err = run(capsys, *args)
    assert code == 2 and "Traceback" not in err
    assert err.startswith(f"symlearn: error: {demos}:5:{column}: demonstration 3: states: unknown state "
                          "'a▸b  · c' (step 1)"), err


def test_action_atoms_are_matched_as_asp_reads_them(capsys, blocks):
    folder, demos = blocks
    text = demos.read_text(encoding="utf-8")
    demos.write_text(text.replace("stack(b,a)", "stack(b, a)"), encoding="utf-8")
    assert "stack(b, a)" in demos.read_text(encoding="utf-8")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q")
    assert code == 0, err
    code, out, err = run(capsys, "domain", "check", folder, "--rules", folder / "truth.lp", "--demos", demos)
    assert code == 0 and "demonstrated steps the rules forbid: 0" in out
    # a wrong atom is still an error, located at the step
    line = _edit_demo(demos, 0, "actions", 0, "stak(b,a)")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q")
    assert code == 2 and f"{demos}:2:{line.index('stak') }: demonstration 0: actions: unknown action" in err


def test_a_step_breaking_known_rules_is_named_where_it_is(capsys, blocks, tmp_path):
    folder, demos = blocks
    known = tmp_path / "known.lp"
    known.write_text(":- unstack(c).\n")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "--known", known,
                         "--validation", "0.5")
    assert code == 2 and "--noise" in err and "/ unstack(c) breaks the given constraints" in err
    assert err.startswith(f"symlearn: error: {demos}:"), err
    index = int(err.split("demonstration ")[1].split(",")[0])
    line_number = int(err.split(f"{demos}:")[1].split(":")[0])
    assert line_number == index + 2  # the file's own numbering, not the training split's
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "--known", known,
                         "--noise", "-q", "--json")
    assert code == 0 and any("treated as noise" in w for w in json.loads(out)["warnings"])


def test_iterations_below_one_are_refused(capsys, blocks):
    folder, demos = blocks
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "--iterations", 0)
    assert code == 2 and "--iterations must be at least 1, got 0" in err


def test_no_rules_to_write_says_why(capsys, blocks, tmp_path):
    folder, demos = blocks
    (folder / "bias.las").write_text("#modeb(1, stak(var(block), var(block)), (positive)).\n#maxv(2).\n")
    target = tmp_path / "rules.lp"
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q", "-o", target)
    assert code == 2 and not target.exists()
    assert ("no rules were induced (no undemonstrated pair the bias can forbid (with rules of at most 3 body "
            "literals, --max-body) is left)") in err
    assert f"{folder / 'bias.las'}:1:1: #modeb(stak(var(block),var(block)))" in err and "did you mean stack/2?" in err


def test_a_feature_table_one_row_short_is_refused(capsys, blocks):
    folder, _ = blocks
    doc = json.loads((folder / "features.json").read_text())
    doc["table"] = doc["table"][:-1]
    (folder / "features.json").write_text(json.dumps(doc))
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'features.json'}: state 12 of 13 has no features" in err


# --- states.jsonl / actions.jsonl ---------------------------------------------------------------
def _edit_line(path, number, old, new):
    lines = path.read_text(encoding="utf-8").splitlines()
    assert old in lines[number - 1]
    lines[number - 1] = lines[number - 1].replace(old, new, 1)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return lines[number - 1]


@pytest.mark.parametrize("fact, mistake, hint", [
    ("temp(21.5). ", ".5", "ASP has no decimal numbers"),
    ("Temp(21). ", "(21", "Temp starts with a capital letter"),
])
def test_a_syntax_error_in_a_states_facts_is_located_in_the_line(capsys, blocks, fact, mistake, hint):
    folder, _ = blocks
    line = _edit_line(folder / "states.jsonl", 5, '"facts": "', '"facts": "on_table(a).  ' + fact)
    code, out, err = run(capsys, "domain", "check", folder)
    column = line.index(fact) + fact.index(mistake) + 1
    assert code == 2 and err.startswith(f"symlearn: error: {folder / 'states.jsonl'}:5:{column}: clingo: syntax "
                                        "error"), err
    assert hint in err


def test_a_repeated_action_atom_or_state_name_is_named_in_its_own_file(capsys, blocks, elevator):
    folder, _ = elevator
    _edit_line(folder / "actions.jsonl", 5, '"atom": "wait"', '"atom": "up"')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'actions.jsonl'}:5: action atom 'up' of id 4 is already that of id 0" in err
    folder, _ = blocks
    first = json.loads((folder / "states.jsonl").read_text(encoding="utf-8").splitlines()[0])["name"]
    _edit_line(folder / "states.jsonl", 3, '"name": "', f'"name": "{first}", "old": "')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'states.jsonl'}:3: state name '{first}' of id 2 is already that of id 0" in err


def test_a_gap_in_the_ids_points_at_the_largest_id(capsys, blocks):
    folder, _ = blocks
    _edit_line(folder / "states.jsonl", 8, '"id": 7,', '"id": 77,')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'states.jsonl'}:8: ids must be 0..77 without gaps; id 7 is missing" in err


def test_the_rule_files_recheck_command_can_be_pasted(capsys, blocks, tmp_path):
    import shlex

    folder, demos = blocks
    target = tmp_path / "my rules.lp"
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q", "-o", target)
    assert code == 0, err
    line = next(x for x in target.read_text().splitlines() if "re-check with:" in x)
    command = shlex.split(line.split("re-check with: ", 1)[1])
    assert command[:3] == ["symlearn", "domain", "check"] and str(target) in command
    code, out, err = run(capsys, *command[1:])
    assert code == 0 and "demonstrated steps the rules forbid: 0" in out


def test_learn_dnf_reads_states_by_name_through_the_feature_map(capsys, blocks):
    folder, demos = blocks
    code, out, err = run(capsys, "learn", "dnf", "--domain", folder, "--demos", demos, "-q", "--json")
    assert code == 0, err
    assert "height" in out and "stacks" in out
    _edit_demo(demos, 0, "states", 0, "no such state")
    code, out, err = run(capsys, "learn", "dnf", "--domain", folder, "--demos", demos, "-q")
    assert code == 2 and f"{demos}:2:" in err and "unknown state 'no such state'" in err


def test_domain_check_reads_demonstrations_without_rules(capsys, blocks):
    folder, demos = blocks
    code, out, err = run(capsys, "domain", "check", folder, "--demos", demos, "--json")
    assert code == 0, err
    report = json.loads(out)["demonstrations"]
    assert report["episodes"] == 40 and report["impossible_steps"] == 0 and 0 < report["pairs"] <= 24
    # a step the model cannot make is counted and shown (the expert was put where it was not)
    lines = demos.read_text(encoding="utf-8").splitlines()
    index = next(i for i, line in enumerate(lines[1:]) if len(json.loads(line)["actions"]) == 1)
    record = json.loads(lines[index + 1])
    record["states"][1] = record["states"][0]  # the one move, and the expert stays where it was
    lines[index + 1] = json.dumps(record, ensure_ascii=False)
    demos.write_text("\n".join(lines) + "\n", encoding="utf-8")
    code, out, err = run(capsys, "domain", "check", folder, "--demos", demos)
    assert code == 0, err
    assert f"warning: 1 step(s) have probability zero under the model (first: demonstration {index}, step 0" in out
    assert "Traceback" not in err and "UserWarning" not in err


def test_a_misspelt_truth_rule_is_warned_about(capsys, blocks):
    folder, demos = blocks
    (folder / "truth.lp").write_text("% truth\n:- stak(X, Y), heavier(X, Y).\n")
    code, out, err = run(capsys, "domain", "check", folder, "--json")
    assert code == 0 and json.loads(out)["truth_warnings"][0]["did_you_mean"] == "stack/2"
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", demos, "-q")
    assert code == 0 and f"warning: {folder / 'truth.lp'}:2:4: truth: predicate stak/2 is defined nowhere" in out


def test_a_capitalised_constant_in_a_states_facts_is_named_where_it_is(capsys, blocks):
    # item(Glass) parses (Glass is a variable) but is no ground fact: the column is the variable's
    # and the hint names it, as for a capitalised predicate
    folder, _ = blocks
    line = _edit_line(folder / "states.jsonl", 5, '"facts": "', '"facts": "colour(Red).  ')
    code, out, err = run(capsys, "domain", "check", folder)
    column = line.index("Red)") + 1
    assert code == 2 and err.startswith(f"symlearn: error: {folder / 'states.jsonl'}:5:{column}: 'colour(Red).' is "
                                        "not a ground fact"), err
    assert "Red starts with a capital letter" in err
