"""``symlearn automaton show|explain|convert`` end to end (in-process through main())."""

import json
from pathlib import Path

import pytest

from cli_runner import run
from symlearn.logic.automata import DFA, RewardMachine, load_automaton
from symlearn.logic.guards import Guard
from symlearn.rendering import dot_available

DATA = Path(__file__).parent.parent / "logic" / "automata" / "data"
a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")


@pytest.fixture
def spec(tmp_path):
    d = DFA({"a", "b", "c"}, 3, 0, [2], {0: [(~a & ~c, 0), (a & ~c, 1)], 1: [(~b & ~c, 1), (b & ~c, 2)],
                                         2: [(~c, 2)]}, ["wait_a", "wait_b", "done"])
    return d.save(tmp_path / "spec.json")




def test_show_text_and_drawings(capsys, spec, tmp_path):
    argv = ["automaton", "show", spec, "--dot", tmp_path / "s.dot"]
    if dot_available():
        argv += ["--svg", tmp_path / "s.svg"]
    code, out, _ = run(capsys, *argv)
    assert code == 0
    assert "dfa, 3 states, 5 edges, alphabet {a, b, c}" in out
    assert "wait_a --[a & !c]--> wait_b" in out and "minimal complete DFA: 4 states" in out
    assert "doublecircle" in (tmp_path / "s.dot").read_text()
    if dot_available():
        assert "<svg" in (tmp_path / "s.svg").read_text()


def test_show_json(capsys, spec):
    code, out, _ = run(capsys, "automaton", "show", spec, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["kind"] == "dfa" and doc["states"] == 3 and doc["complete"] is False
    assert {"source": 0, "target": 1, "guard": "a & !c"} in doc["transitions"]


def test_show_reward_machine_text_and_mona_dot(capsys, tmp_path):
    path = tmp_path / "rm.txt"
    path.write_text("0\n[1]\n(0,0,'!a',ConstantRewardFunction(0))\n(0,1,'a',ConstantRewardFunction(1))\n")
    code, out, _ = run(capsys, "automaton", "show", path)
    assert code == 0 and "reward_machine" in out and "0 --[a / r=1]--> 1" in out and "terminal: 1" in out
    code, out, _ = run(capsys, "automaton", "show", DATA / "ltlf2dfa_fa_and_gb.dot", "--json")
    assert code == 0 and json.loads(out)["states"] == 3


def test_explain_failing_trace(capsys, spec):
    code, out, _ = run(capsys, "automaton", "explain", spec, "--trace", '[["a"], ["c"], ["b"]]')
    assert code == 0
    assert "REJECTED" in out and "at step 1 no transition matches" in out
    assert "fixed: {a} {} {b}" in out


def test_explain_json_and_trace_file(capsys, spec, tmp_path):
    trace = tmp_path / "t.json"
    trace.write_text('[["a"], []]')
    code, out, _ = run(capsys, "automaton", "explain", spec, "--trace", trace, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["accepted"] is False and doc["reason"] == "incomplete"
    assert len(doc["edits"]) == 1 and doc["edits"][0]["new"] == ["b"]
    assert DFA.load(spec).accepts(doc["fixed_trace"]) and doc["state_names"] == ["wait_a", "wait_b", "wait_b"]


def test_explain_accepted(capsys, spec):
    code, out, _ = run(capsys, "automaton", "explain", spec, "--trace", '[["a"], ["b"]]')
    assert code == 0 and "ACCEPTED" in out


@pytest.mark.parametrize("trace, message", [
    ('[["a"], ["b"]', "--trace:1:14: the trace is not valid JSON"),   # not a bare "1:14:"
    ('{"a": 1}', "--trace: a trace must be a JSON list of steps"),
    ('[["a"], "b"]', "--trace: trace step 1 must be a list of proposition names"),
    ("missing.json", "--trace: 'missing.json' is neither a trace file nor a JSON trace"),   # was "1:1: not valid JSON"
])
def test_explain_bad_trace(capsys, spec, trace, message):
    code, _, err = run(capsys, "automaton", "explain", spec, "--trace", trace)
    assert code == 2 and message in err and err.startswith("symlearn: error:")
    assert len(err.strip().splitlines()) == 1


def test_bad_automaton_file(capsys, tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a"], '
                    '"states": 2, "initial": 0, "accepting": [1], "transitions": [{"source": 0, "target": 1}]}')
    code, _, err = run(capsys, "automaton", "show", path)
    # located at the transition that lacks the field (line 1, column 143)
    assert code == 2 and f"{path}:1:143: transitions[0].guard: missing field" in err
    code, _, err = run(capsys, "automaton", "show", tmp_path / "x.yaml")
    assert code == 2 and "cannot tell the format" in err
    code, _, err = run(capsys, "automaton", "show", tmp_path / "missing.json")
    assert code == 2


def test_convert_between_formats(capsys, spec, tmp_path):
    for suffix in ("hoa", "dot", "txt", "json"):
        code, out, _ = run(capsys, "automaton", "convert", spec, tmp_path / f"out.{suffix}")
        assert code == 0 and "wrote" in out
    assert (tmp_path / "out.hoa").read_text().startswith("HOA: v1")
    rm = load_automaton(tmp_path / "out.json")
    assert isinstance(rm, DFA) and rm == DFA.load(spec)
    code, _, _ = run(capsys, "automaton", "convert", tmp_path / "out.txt", tmp_path / "rm.json")
    assert code == 0 and isinstance(load_automaton(tmp_path / "rm.json"), RewardMachine)
    code, _, _ = run(capsys, "automaton", "convert", DATA / "mona_raw_a_implies_b_or_c.dot", tmp_path / "m.json",
                     "--variables", "a,b,c")
    assert code == 0 and load_automaton(tmp_path / "m.json").alphabet == {"a", "b", "c"}
