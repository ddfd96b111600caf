"""Diagnostics for an edited rule file (issue #25 section 4): ``ilp check`` and ``domain check``
name predicates defined nowhere, explain uncovered examples, put a missing '.' where the rule
ends and name unsafe variables."""

from __future__ import annotations

import json

import pytest
import warehouse_domain as wh
from cli_runner import run

from symlearn.errors import ParseError
from symlearn.logic.asp import Hypothesis
from symlearn.logic.asp.predicates import undefined_predicates
from symlearn.logic.asp.program import Program

TASK = """dir(north;south;east;west).
#pos(p1, {}, {}, { wall(north). go(south). }).
#pos(p2, {}, {}, { go(east). }).
#neg(n1, {}, {}, { wall(north). go(north). }).
#neg(n2, {}, {}, { wall(east). go(east). }).
#modeb(1, wall(var(d))).
#modeb(1, go(var(d))).
#maxv(1).
"""


@pytest.fixture
def task(tmp_path):
    path = tmp_path / "walls.las"
    path.write_text(TASK)
    return path


def check(capsys, task, tmp_path, text, *extra):
    rules = tmp_path / "edited.lp"
    rules.write_text(text)
    code, out, err = run(capsys, "ilp", "check", task, rules, *extra)
    return code, out, err, rules


def test_a_misspelt_predicate_is_named_with_a_suggestion(capsys, task, tmp_path):
    code, out, err, rules = check(capsys, task, tmp_path, "% edited\n:- wal(V1), go(V1).\n", "--json")
    doc = json.loads(out)
    assert code == 2 and doc["warnings"] == [{
        "predicate": "wal/1", "file": str(rules), "line": 2, "column": 4, "did_you_mean": "wall/1",
        "message": "predicate wal/1 is defined nowhere (no head, fact or context has it), so the atom is always "
                   "false; did you mean wall/1?"}]
    code, out, err, rules = check(capsys, task, tmp_path, "% edited\n:- wal(V1), go(V1).\n")
    assert f"warning: {rules}:2:4: predicate wal/1 is defined nowhere" in out
    # correct names, a wrong number of arguments, and a head the file defines itself
    code, out, err, _ = check(capsys, task, tmp_path, ":- wall(V1), go(V1).\n", "--json")
    assert code == 0 and json.loads(out)["warnings"] == []
    found = undefined_predicates(Program.from_text("h(X) :- wall(X, Y), dir(Y).\n:- h(north), zzz.", source="r.lp"),
                                 {("wall", 1), ("dir", 1)})
    assert [(u.name, u.arity, u.suggestion, u.line) for u in found] == [("wall", 2, "wall/1", 1), ("zzz", 0, None, 2)]


def test_uncovered_examples_name_polarity_context_and_the_rule(capsys, task, tmp_path):
    code, out, err, _ = check(capsys, task, tmp_path, ":- go(south).\n:- go(north).\n", "--coverage", "--json")
    doc = json.loads(out)
    assert code == 2
    by_id = {u["id"]: u for u in doc["uncovered"]}
    assert set(by_id) == {"p1", "n2"}
    assert by_id["p1"]["polarity"] == "positive" and by_id["p1"]["line"] == 2
    assert by_id["p1"]["context"] == "wall(north). go(south)." and by_id["p1"]["excluded_by"] == [":- go(south)."]
    assert by_id["n2"]["polarity"] == "negative" and by_id["n2"]["excluded_by"] == []
    code, out, err, _ = check(capsys, task, tmp_path, ":- go(south).\n:- go(north).\n", "--coverage")
    assert "uncovered: p1 (positive, task line 2) context: wall(north). go(south). -- excluded by :- go(south)." in out
    assert "uncovered: n2 (negative, task line 5) context: wall(east). go(east). -- no rule excludes it" in out
    # without --coverage: polarity and context, no rule analysis
    code, out, err, _ = check(capsys, task, tmp_path, ":- go(north).\n")
    assert "uncovered: n2 (negative, task line 5) context: wall(east). go(east)." in out and "--" not in out


@pytest.mark.parametrize("text, line, column", [
    (":- wall(V1), go(V1)\n\n:- go(north).\n", 1, 20),
    (":- wall(V1), go(V1) % a comment\n% another\n:- go(north).\n", 1, 20),
    (":- go(north).\n:- wall(V1), go(V1)", 2, 20),  # the end of the file
])
def test_a_missing_dot_is_reported_where_the_rule_ends(capsys, task, tmp_path, text, line, column):
    code, out, err, rules = check(capsys, task, tmp_path, text)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert f"{rules}:{line}:{column}: syntax error: the rule ending here has no '.'" in err


def test_a_syntax_error_inside_a_rule_stays_where_it_is(tmp_path):
    path = tmp_path / "r.lp"
    path.write_text(":- go(north).\n:- wall(V1) go(V1).\n")
    with pytest.raises(ParseError) as info:
        Hypothesis.from_lp(path)
    assert (info.value.line, info.value.column) == (2, 13) and "no '.'" not in info.value.message


def test_an_unsafe_variable_is_named(capsys, task, tmp_path):
    code, out, err, rules = check(capsys, task, tmp_path, ":- wall(V1), go(V2), V3 < V1.\n")
    assert code == 2 and err.startswith(f"symlearn: error: {rules}:1:")
    assert "unsafe variable V3: a variable must occur in a positive body atom" in err
    assert "add a positive atom that binds V3" in err and "check the ASP syntax" not in err


def test_domain_check_names_undefined_predicates_and_the_forbidding_rule(capsys, tmp_path):
    folder = wh.write_warehouse(tmp_path / "warehouse")
    demos = tmp_path / "demos.jsonl"
    wh.expert_demonstrations(5, seed=0).save(demos)
    rules = tmp_path / "rules.lp"
    rules.write_text(":- alarm, move(V1).\n:- move(V1), blocekd(V1).\n:- wait.\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules, "--demos", demos, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert [(w["predicate"], w["line"], w["did_you_mean"]) for w in doc["warnings"]] == [("blocekd/1", 2, "blocked/1")]
    assert doc["first_forbidden_step"]["rules"] == [":- wait."]
    code, out, err = run(capsys, "domain", "check", folder, "--rules", rules, "--demos", demos)
    assert "forbidden by :- wait." in out and f"warning: {rules}:2:14: predicate blocekd/1" in out
