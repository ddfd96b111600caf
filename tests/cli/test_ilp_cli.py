"""``symlearn ilp learn|check|space`` end to end, including bad input."""

import json

import pytest

TASK = """
dir(north;south;east;west).
#pos(p1, {}, {}, { wall(north). go(south). }).
#pos(p2, {}, {}, { go(east). }).
#neg(n1, {}, {}, { wall(north). go(north). }).
#neg(n2, {}, {}, { wall(east). go(east). }).
#modeb(1, wall(var(d))).
#modeb(1, go(var(d))).
#maxv(1).
"""


@pytest.fixture
def task_file(tmp_path):
    path = tmp_path / "walls.las"
    path.write_text(TASK)
    return path


def test_learn_prints_rules_and_writes_an_editable_file(run_cli, task_file, tmp_path):
    out = tmp_path / "learned.lp"
    result = run_cli("ilp", "learn", task_file, "-o", out)
    assert result.returncode == 0, result.stderr
    assert ":- wall(V1), go(V1)." in result.stdout and "score 2 (optimal)" in result.stdout
    text = out.read_text()
    assert text.startswith("% learned by symlearn ilp learn") and ":- wall(V1), go(V1)." in text
    # the header's re-check line names this task and this file, ready to paste
    assert f"% edit the rules below; re-check with: symlearn ilp check {task_file} {out}\n" in text
    again = run_cli("ilp", "check", task_file, out)
    assert again.returncode == 0 and "4/4 examples covered" in again.stdout


def test_learn_json_keys(run_cli, task_file):
    result = run_cli("ilp", "learn", task_file, "--json", "--timeout", "20")
    doc = json.loads(result.stdout)
    assert {"rules", "score", "optimal", "seconds"} <= set(doc)
    assert doc["rules"] == [":- wall(V1), go(V1)."] and doc["score"] == 2 and doc["optimal"] is True


def test_check_rescores_an_edited_file(run_cli, task_file, tmp_path):
    hyp = tmp_path / "edited.lp"
    hyp.write_text("% my edit: only forbid going north\n:- go(north).\n")
    result = run_cli("ilp", "check", task_file, hyp, "--json")
    doc = json.loads(result.stdout)
    # an uncovered example without a penalty fails the check (exit 2, one line on stderr), so CI notices
    assert result.returncode == 2 and doc["passed"] is False
    assert result.stderr.strip().splitlines() == [f"symlearn: error: {hyp}: 1 example without a penalty not "
                                                   "covered: n2"]
    assert doc["coverage"] == {"p1": True, "p2": True, "n1": True, "n2": False}
    assert doc["score"] is None and doc["uncovered_without_penalty"] == ["n2"]
    text = run_cli("ilp", "check", task_file, hyp).stdout
    assert "3/4 examples covered" in text and "uncovered: n2" in text
    hyp.write_text(":- wall(V1), go(V1).\n")
    passed = run_cli("ilp", "check", task_file, hyp, "--json")
    assert passed.returncode == 0 and json.loads(passed.stdout)["passed"] is True and passed.stderr == ""


def test_space_prints_size_and_sample(run_cli, task_file):
    result = run_cli("ilp", "space", task_file, "--sample", "3")
    assert result.returncode == 0 and "candidate rules" in result.stdout
    doc = json.loads(run_cli("ilp", "space", task_file, "--json", "--dialect", "fastlas").stdout)
    assert doc["size"] == 3 and {r["rule"] for r in doc["sample"]} == {":- wall(V1).", ":- go(V1).",
                                                                       ":- wall(V1), go(V1)."}
    ilasp = json.loads(run_cli("ilp", "space", task_file, "--json").stdout)  # negated body atoms too
    assert ilasp["size"] > doc["size"]


def test_extra_background_file(run_cli, tmp_path):
    task = tmp_path / "t.las"
    task.write_text("#pos(p, {}, {}, { a. }).\n#neg(n, {}, {}, { c. }).\n#modeb(1, b).\n")
    bk = tmp_path / "bk.lp"
    bk.write_text("b :- c.\n")
    doc = json.loads(run_cli("ilp", "learn", task, "--bk", bk, "--json").stdout)
    assert doc["rules"] == [":- b."]


@pytest.mark.parametrize("content, message", [
    ("#modeb(1, p(var(t)).\n", "t.las:1:"),
    ("#pos(a, {}, {}, {}).\nbad(.\n#modeb(1, p).\n", "t.las:2:"),
    ("#modeo(a).\n", "unsupported feature #modeo at line 1"),
    ("#modeb(1, p).\n", "no examples"),
    ("#pos(a, {}, {}, {}).\n#modeb(1, p(const(c))).\n", "hypothesis space empty"),
])
def test_bad_input_is_one_line_and_exit_2(run_cli, tmp_path, content, message):
    task = tmp_path / "t.las"
    task.write_text(content)
    result = run_cli("ilp", "learn", task)
    assert result.returncode == 2 and message in result.stderr
    assert result.stderr.startswith("symlearn: error:") and "Traceback" not in result.stderr


def test_no_solution_prints_diagnostics_and_exits_2(run_cli, tmp_path):
    task = tmp_path / "t.las"
    task.write_text("#pos(p, {}, {}, { go(n). }).\n#neg(q, {}, {}, { go(n). }).\n#modeb(1, go(var(d))).\n")
    result = run_cli("ilp", "learn", task)
    assert result.returncode == 2
    assert "no hypothesis found" in result.stdout and "p and q conflict" in result.stdout


GREENHOUSE = """
bed(0).
onBed :- at(X), bed(X).
#modeh(bad).
#modeb(1, rain, (positive)). #modeb(1, water, (positive)).
#modeb(1, onBed, (positive)). #modeb(1, wet, (positive)).
#maxv(1).
#pos(p1, {}, {}, {at(-2). water.}).
#pos(p2, {}, {}, {at(0). rest.}).
#neg(n1, {}, {}, {at(-1). rain. water.}).
#neg(n2, {}, {}, {at(0). water.}).
"""


def test_a_space_that_cannot_exclude_the_negatives_answers_without_waiting(run_cli, tmp_path):
    # only normal rules whose head nothing reads: it used to search until --timeout, then say "raise --timeout"
    task = tmp_path / "gh.las"
    task.write_text(GREENHOUSE)
    result = run_cli("ilp", "learn", task, "--timeout", "60")
    assert result.returncode == 2, result.stderr
    assert "no hypothesis found" in result.stdout
    assert "no rule of the space can change whether n1, n2 are accepted" in result.stdout
    # where the background reads the head, the search runs; its time-out says the space may hold none
    task.write_text("ok :- bad.\n" + GREENHOUSE)
    # 5 s, not 1: on a loaded machine 1 s ran out while grounding, before the search it is about
    result = run_cli("ilp", "learn", task, "--timeout", "5")
    assert result.returncode == 2
    assert "(hint: raise --timeout; but the space holds no constraint" in result.stderr
    assert "may hold no hypothesis that excludes n1, n2" in result.stderr


def test_noise_flag_and_coverage_matrix(run_cli, tmp_path):
    task = tmp_path / "noisy.las"
    task.write_text(TASK + "#pos(p3@4, {}, {}, { wall(south). go(south). }).\n")  # mislabelled
    assert run_cli("ilp", "learn", task).returncode == 2
    result = run_cli("ilp", "learn", task, "--noise", "--coverage", "--json")
    doc = json.loads(result.stdout)
    assert result.returncode == 0 and doc["rules"] == [":- wall(V1), go(V1)."]
    assert doc["penalty"] == 4 and doc["score"] == 6 and doc["coverage"]["p3"] is False
    assert doc["matrix"][":- wall(V1), go(V1)."]["n2"] is True


# -- issue 15 ---------------------------------------------------------------------------------------

def test_check_help_documents_its_arguments(capsys):
    from symlearn.cli.main import main

    with pytest.raises(SystemExit):
        main(["ilp", "check", "--help"])
    text = capsys.readouterr().out
    for words in ("TASK.las", "the task file the rules are checked", "HYP.lp", "rules (.lp)", "--bk F.lp",
                  "--timeout S", "--max-memory MB", "Exit 0 when every example without a penalty is covered"):
        assert words in " ".join(text.split()), words


def test_hints_speak_in_flags_not_api_names(capsys, tmp_path):
    from cli_runner import run

    task = tmp_path / "t.las"
    task.write_text("#pos(p, {}, {}, { go(n). }).\n#neg(q, {}, {}, { go(s). }).\n"
                    "#modeb(1, go(var(d)), (positive)).\n#maxv(1).\n")
    code, out, _err = run(capsys, "ilp", "learn", task)
    assert code == 2 and "excludes p)" in out
    assert "--noise" in out and "--max-body" in out and "noise=True" not in out and "max_body" not in out


@pytest.mark.parametrize("command", ["learn", "check", "space"])
def test_timeout_values_on_every_ilp_command(capsys, task_file, tmp_path, command):
    from cli_runner import run

    hyp = tmp_path / "h.lp"
    hyp.write_text(":- wall(V1), go(V1).\n")
    args = ["ilp", command, task_file] + ([hyp] if command == "check" else [])
    for value in ("inf", "1e10", "1e308"):  # no limit, no overflow into "already expired"
        code, out, err = run(capsys, *args, "--timeout", value, "--json")
        assert code == 0, err
        doc = json.loads(out)
        assert doc.get("optimal", True) is True and doc.get("passed", True) is True
    for value in ("0", "-1", "nan"):
        code, out, err = run(capsys, *args, "--timeout", value)
        assert code == 2 and out == ""
        assert err.splitlines() == [f"symlearn: error: --timeout must be a positive number of seconds, not {value} "
                                    "(hint: give a positive number of seconds ('inf' for no limit))"]
