import json

import numpy as np
import pytest

from cli_runner import run




def test_parse_prints_canonical_form_and_size(capsys):
    code, out, _ = run(capsys, "ltl", "parse", "F  F a&(b|b)", "--simplify")
    assert code == 0
    assert out.splitlines()[0] == "F F a & (b | b)"
    assert "size 7" in out and "simplified: F a & b" in out
    code, out, _ = run(capsys, "ltl", "parse", "X a -> b <-> c", "--dialect", "spot", "--to", "ours", "--json")
    doc = json.loads(out)
    assert doc["formula"] == "WX a -> (b <-> c)" and doc["size"] == 6 and doc["propositions"] == ["a", "b", "c"]


def test_parse_error_is_one_located_message(capsys):
    code, out, err = run(capsys, "ltl", "parse", "a => b")
    assert code == 2 and out == ""
    assert err.startswith("symlearn: error: 1:3: unexpected character '='")
    assert "hint: write '->' for implication" in err and "    ^" in err


def test_eval_prints_verdicts_in_trace_order(tmp_path, capsys):
    traces = tmp_path / "t.jsonl"
    traces.write_text('[["a"], [], ["b"]]\n\n[["b"]]\n[["a"], ["b"]]\n')
    code, out, _ = run(capsys, "ltl", "eval", "a T b", "--traces", traces, "--json")
    assert code == 0 and json.loads(out) == {"results": [True, False, True]}
    code, out, _ = run(capsys, "ltl", "eval", "a T b", "--traces", traces)
    assert "trace 2: fails" in out and "2 of 3 traces" in out


@pytest.mark.parametrize("line, where, message", [
    ('[["a"], "b"]', "1:9", "step 1 must be a list"),
    ('[["a"], [3]]', "1:10", "non-empty string"),
    ('[["a"],', "1:8", "not valid JSON"),
    ('{"a": 1}', "1:1", "must be a JSON list"),
])
def test_eval_reports_malformed_trace_files_with_file_line_col(tmp_path, capsys, line, where, message):
    traces = tmp_path / "bad.jsonl"
    traces.write_text('[["a"]]\n' + line + "\n")
    line_no, col = where.split(":")
    code, _, err = run(capsys, "ltl", "eval", "a", "--traces", traces)
    assert code == 2
    assert f"{traces}:{int(line_no) + 1}:{col}: " in err and message in err


def test_dfa_single_formula_writes_files(tmp_path, capsys):
    dot, svg, js = tmp_path / "a.dot", tmp_path / "a.svg", tmp_path / "a.json"
    args = ["ltl", "dfa", "G(!hole) & (key T door)", "--dot", dot, "--save", js]
    from symlearn.rendering import dot_available

    if dot_available():
        args += ["--svg", svg]
    code, out, _ = run(capsys, *args)
    assert code == 0
    assert out.startswith("minimal DFA: 4 states, 9 edges")
    assert dot.read_text().startswith("digraph")
    from symlearn.logic.automata.dfa import DFA

    loaded = DFA.load(js)
    assert loaded.n_states == 4 and loaded.accepts([{"key"}, {"door"}])
    if dot_available():
        assert svg.read_text().lstrip().startswith("<?xml")


def test_dfa_batch_file(tmp_path, capsys):
    specs = tmp_path / "f.txt"
    specs.write_text("# comment\nF(var0)\n\nX[!] a && X b\nG(var1 -> G(var0))\n")
    code, out, _ = run(capsys, "ltl", "dfa", "--file", specs, "--dialect", "spot", "--json")
    rows = json.loads(out)
    assert [r["formula"] for r in rows] == ["F(var0)", "X[!] a && X b", "G(var1 -> G(var0))"]
    assert [r["states"] for r in rows] == [2, 4, 3]  # X[!] a && X b = X[!](a & b)
    assert all(set(r) == {"formula", "states", "edges", "seconds"} for r in rows)


def test_dfa_batch_errors_are_located(tmp_path, capsys):
    specs = tmp_path / "f.txt"
    specs.write_text("F a\nF a &&& b\n")
    code, _, err = run(capsys, "ltl", "dfa", "--file", specs)
    assert code == 2 and f"{specs}:2:7: unexpected '&'" in err and "'&' or '&&'" in err
    specs.write_text(" & ".join(f"F p{i}" for i in range(10)) + "\n")
    code, _, err = run(capsys, "ltl", "dfa", "--file", specs, "--max-states", "50")
    assert code == 2 and f"{specs}:1: " in err and "more than 50 states" in err
    code, _, err = run(capsys, "ltl", "dfa")
    assert code == 2 and "give one of a FORMULA, --file" in err


def test_dfa_text_lists_the_first_states_of_a_large_automaton_and_json_lists_all(capsys):
    # a 1,029-state DFA printed thousands of lines, most of the run spent writing guards nobody reads
    formula = " & ".join(f"F q{i}" for i in range(7))  # 128 states
    code, out, _ = run(capsys, "ltl", "dfa", formula)
    assert code == 0
    listed = [line for line in out.splitlines() if line.lstrip(" *").split(":")[0].isdigit()]
    assert len(listed) == 50
    assert "... and 78 more states (--json lists every state's transitions" in out
    code, out, _ = run(capsys, "ltl", "dfa", formula, "--json")
    doc = json.loads(out)
    assert doc["states"] == 128 and len(doc["transitions"]) == 128
    code, out, _ = run(capsys, "ltl", "dfa", "a U b")
    assert "more states" not in out and len(out.splitlines()) == 4


def test_eval_rechecks_a_spec_file_against_labelled_demonstrations(tmp_path, capsys):
    from symlearn.data import Demonstrations, Trajectory

    # an edited SPEC.ltl (a '# why' comment above its formula) against the demonstrations' label
    # words: the guide did this in Python only
    demos = Demonstrations([Trajectory(states=np.zeros((3, 1)), labels=[["charger"], [], ["dock"]]),
                            Trajectory(states=np.zeros((2, 1)), labels=[["dock"], ["charger"]])])
    demos.save(tmp_path / "tour.jsonl")
    spec = tmp_path / "tour.ltl"
    spec.write_text("# charger first\nF charger & (!dock U charger) & F dock\n")
    code, out, _ = run(capsys, "ltl", "eval", "--file", spec, "--demos", tmp_path / "tour.jsonl")
    assert code == 0
    assert "demonstration 1: holds" in out and "demonstration 2: fails" in out
    assert "1 of 2 demonstrations satisfy F charger & (!dock U charger) & F dock" in out
    code, out, _ = run(capsys, "ltl", "eval", "F dock", "--demos", tmp_path / "tour.jsonl", "--json")
    assert json.loads(out) == {"results": [True, True]}
    Demonstrations([Trajectory(states=np.zeros((2, 1)))]).save(tmp_path / "plain.jsonl")
    code, _, err = run(capsys, "ltl", "eval", "F dock", "--demos", tmp_path / "plain.jsonl")
    assert code != 0 and "have no labels" in err and "labeler" in err
    (tmp_path / "two.ltl").write_text("F a\nG b\n")
    code, _, err = run(capsys, "ltl", "eval", "--file", tmp_path / "two.ltl", "--demos", tmp_path / "tour.jsonl")
    assert code != 0 and "holds 2 formulas" in err
    code, _, err = run(capsys, "ltl", "eval", "F dock", "--traces", spec, "--demos", tmp_path / "tour.jsonl")
    assert code != 0 and "give one of --traces" in err
