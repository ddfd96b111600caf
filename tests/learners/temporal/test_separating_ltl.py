"""Separating-formula learning: bit-word semantics, optimality, anytime answers, bad input, CLI."""

import argparse
import io
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from symlearn.data.ltl_samples import load_sample, sample_from_traces, save_sample
from symlearn.errors import DataError, SymlearnError
from symlearn.learners.temporal.ltl_bitsets import BINARY, UNARY, Frame, apply, unpack
from symlearn.learners.temporal.separating_ltl import OPERATORS, learn_from_sample, learn_ltl
from symlearn.logic.ltlf import ast, holds, parse, size

PROPS = ("a", "b")
NODES = {"!": ast.Not, "X": ast.Next, "N": ast.WeakNext, "F": ast.Eventually, "G": ast.Always, "&": ast.And,
         "|": ast.Or, "->": ast.Implies, "U": ast.Until, "R": ast.Release, "W": ast.WeakUntil, "T": ast.Then}

label = st.frozensets(st.sampled_from(PROPS))
trace = st.lists(label, min_size=1, max_size=9).map(tuple)


def formulas(max_depth=3):
    leaves = st.sampled_from([ast.Prop(p) for p in PROPS])
    return st.recursive(leaves, lambda inner: st.one_of(
        st.builds(lambda op, f: NODES[op](f), st.sampled_from(UNARY), inner),
        st.builds(lambda op, f, g: NODES[op](f, g), st.sampled_from(BINARY), inner, inner)), max_leaves=4)


def bits_of(formula, frame):
    """Truth values of a formula by composing the bit-word operators, bottom-up."""
    if isinstance(formula, ast.Prop):
        return frame.propositions[formula.name]
    kids = [bits_of(k, frame) for k in formula.children()]
    op = next(o for o, node in NODES.items() if type(formula) is node)
    return apply(op, frame, *kids)


@settings(max_examples=150, deadline=None)
@given(formulas(), st.lists(trace, min_size=1, max_size=4))
def test_bit_words_agree_with_holds_at_every_position(formula, traces):
    frame = Frame.from_traces(traces, PROPS)
    values = unpack(bits_of(formula, frame), frame.length)
    for i, t in enumerate(traces):
        expected = [holds(formula, t[k:]) for k in range(len(t))]
        assert values[i, :len(t)].tolist() == expected
        assert not values[i, len(t):].any()  # padding stays false, so equal behaviour = equal bytes


@pytest.mark.parametrize("op", UNARY + BINARY)
def test_each_operator_on_long_traces_across_words(op):
    # traces longer than one 64-bit word exercise the carries between words
    rng = np.random.default_rng(len(op) * 7 + ord(op[0]))
    traces = [[frozenset(p for p in PROPS if rng.random() < q) for _ in range(n)]
              for n, q in ((150, 0.9), (70, 0.5), (1, 0.5), (129, 0.97))]
    frame = Frame.from_traces(traces, PROPS)
    a, b = ast.Prop("a"), ast.Prop("b")
    formula = NODES[op](a) if op in UNARY else NODES[op](a, b)
    values = unpack(bits_of(formula, frame), frame.length)
    for i, t in enumerate(traces):
        for k in range(0, len(t), 7):
            assert values[i, k] == holds(formula, t[k:]), (op, i, k)


def separates(formula, pos, neg):
    return all(holds(formula, t) for t in pos) and not any(holds(formula, t) for t in neg)


@settings(max_examples=40, deadline=None)
@given(st.lists(trace, min_size=1, max_size=6), st.lists(trace, min_size=1, max_size=6))
def test_learned_formula_separates_its_sample(pos, neg):
    neg = [t for t in neg if t not in pos]
    assume(neg)
    result = learn_ltl(pos, neg, propositions=PROPS, timeout=20, max_work=2e6)
    if result.formula is not None:
        assert separates(result.formula, pos, neg)
        assert size(result.formula) == result.size
        assert parse(str(result.formula)) == result.formula


@settings(max_examples=30, deadline=None)
@given(formulas(), st.lists(trace, min_size=6, max_size=14))
def test_size_at_most_planted_formula(planted, traces):
    pos = [t for t in traces if holds(planted, t)]
    neg = [t for t in traces if not holds(planted, t)]
    assume(pos and neg)
    result = learn_ltl(pos, neg, propositions=PROPS, operators=OPERATORS, timeout=30)
    assert result.formula is not None and separates(result.formula, pos, neg)
    assert result.size <= size(planted)
    assert result.optimal and result.method == "enumeration"


def test_smallest_formula_and_optimality_flag():
    pos = [[{"a"}, {"b"}], [set(), {"a"}, {"b"}], [{"a"}, {"a"}, {"b"}]]
    neg = [[{"b"}, {"a"}], [{"a"}], [set(), {"b"}]]
    result = learn_ltl(pos, neg)
    assert separates(result.formula, pos, neg) and result.size == 5 and result.optimal
    assert result.exhaustive_up_to == 4 and result.candidates_explored > 0 and result.seconds >= 0


def test_output_is_deterministic():
    rng = np.random.default_rng(3)
    traces = [tuple(frozenset(p for p in "abc" if rng.random() < 0.4) for _ in range(8)) for _ in range(40)]
    goal = parse("F(a & X F b) | G c")
    pos = [t for t in traces if holds(goal, t)]
    neg = [t for t in traces if not holds(goal, t)]
    first = learn_ltl(pos, neg, propositions="abc", max_work=3e6)
    second = learn_ltl(pos, neg, propositions="abc", max_work=3e6)
    assert str(first.formula) == str(second.formula) and first.candidates_explored == second.candidates_explored


def test_anytime_answer_when_exact_search_is_cut_short():
    # a conjunction of four eventualities is beyond a tiny work limit: the set cover still answers
    rng = np.random.default_rng(0)
    traces = {tuple(frozenset(p for p in "abcde" if rng.random() < 0.12) for _ in range(10)) for _ in range(120)}
    goal = parse("F a & F b & F c & F d")
    pos = [t for t in sorted(traces, key=str) if holds(goal, t)]
    neg = [t for t in sorted(traces, key=str) if not holds(goal, t)]
    assume_ok = pos and neg
    assert assume_ok
    result = learn_ltl(pos, neg, propositions="abcde", max_work=2e5)
    assert result.formula is not None and separates(result.formula, pos, neg)
    assert not result.optimal and result.method in ("set cover", "boolean search")
    assert result.exhaustive_up_to < result.size


def test_no_formula_up_to_size_k():
    pos, neg = [[{"a"}], [{"b"}]], [[set()], [set(), {"a"}]]  # needs a | b
    assert learn_ltl(pos, neg).size == 3
    result = learn_ltl(pos, neg, max_size=2)
    assert result.formula is None and result.optimal and result.size is None
    assert result.message == "no formula up to size 2 separates the sample"
    assert result.to_json()["formula"] is None


@pytest.mark.parametrize("pos, neg, props, message", [
    ([[{"a"}]], [[{"c"}]], ["a", "b"], "negative_traces[0][0]: unknown proposition 'c'"),
    ([], [[{"a"}]], None, "the sample has no positive traces"),
    ([[{"a"}]], [], None, "the sample has no negative traces"),
    ([[{"a"}, set()]], [[{"a"}, set()]], None, "contradictory sample"),
])
def test_bad_input_is_a_data_error(pos, neg, props, message):
    with pytest.raises(DataError, match=message.replace("[", r"\[").replace("]", r"\]")):
        learn_ltl(pos, neg, propositions=props)


def test_unknown_operator_is_refused():
    with pytest.raises(SymlearnError, match="unknown operator 'Y'"):
        learn_ltl([[{"a"}]], [[set()]], operators=("Y",))


# -- CLI ------------------------------------------------------------------------------------


def _cli(argv):
    """Run 'ltl learn' through a parser built like symlearn's (the lead wires it into 'ltl')."""
    from symlearn.cli.ltl_learn_command import add_learn_command
    from symlearn.cli.main import common_options
    from symlearn.cli.output import Output

    parser = argparse.ArgumentParser(prog="symlearn")
    parser.add_argument("--json", action="store_true")
    ltl = parser.add_subparsers(dest="command").add_parser("ltl").add_subparsers(dest="ltl_command")
    add_learn_command(ltl, common_options)
    args = parser.parse_args(["ltl", "learn", *map(str, argv)])
    stdout = io.StringIO()
    args.handler(args, Output(json_mode=getattr(args, "json", False), stdout=stdout, stderr=io.StringIO()))
    return stdout.getvalue()


def _sample_file(tmp_path, pos, neg, props=("a", "b")):
    path = tmp_path / "sample.json"
    save_sample(sample_from_traces(pos, neg, propositions=props), path)
    return path


def test_cli_json_document(tmp_path):
    path = _sample_file(tmp_path, [[{"a"}, {"b"}], [set(), {"a"}, {"b"}]], [[{"b"}, {"a"}], [{"a"}], [set(), {"b"}]])
    doc = json.loads(_cli([path, "--json", "--timeout", "5"]))
    assert doc["size"] == 5 and doc["optimal"] is True and isinstance(doc["seconds"], float)
    assert separates(parse(doc["formula"]), [[{"a"}, {"b"}], [set(), {"a"}, {"b"}]], [[{"b"}, {"a"}], [{"a"}], [set(), {"b"}]])
    assert doc["formula"] in _cli([path])


def test_cli_reports_no_formula_up_to_k(tmp_path):
    path = _sample_file(tmp_path, [[{"a"}], [{"b"}]], [[set()], [set(), {"a"}]])
    doc = json.loads(_cli([path, "--json", "--max-size", "2"]))
    assert doc["formula"] is None and doc["size"] is None
    assert "no formula up to size 2" in _cli([path, "--max-size", "2"])


@pytest.mark.parametrize("doc, message", [
    ({"atomic_propositions": ["a"], "positive_traces": [{"a": [1], "q": [1]}], "negative_traces": [{"a": [0]}]},
     "positive_traces[0].q: unknown proposition 'q'"),
    ({"atomic_propositions": ["a"], "positive_traces": [], "negative_traces": [{"a": [0]}]}, "no positive traces"),
    ({"atomic_propositions": ["a"], "positive_traces": [{"a": [1]}], "negative_traces": []}, "no negative traces"),
    ({"atomic_propositions": ["a"], "positive_traces": [{"a": [1]}], "negative_traces": [{"a": [1]}]},
     "contradictory sample"),
])
def test_cli_bad_input(tmp_path, doc, message):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(SymlearnError) as info:
        _cli([path, "--json"])
    assert message in str(info.value) and str(path) in str(info.value)


def test_cli_bad_options(tmp_path):
    path = _sample_file(tmp_path, [[{"a"}]], [[{"b"}]])
    with pytest.raises(SymlearnError, match="--max-size must be at least 1"):
        _cli([path, "--max-size", "0"])
    with pytest.raises(SymlearnError, match="unknown operator"):
        _cli([path, "--operators", "F,Q"])


BENCH = Path(__file__).resolve().parents[3].parent / "shared" / "benchmarks" / "ltlf_learning" / "dev"


@pytest.mark.skipif(not BENCH.exists(), reason="shared benchmarks absent")
@pytest.mark.parametrize("name", ["FixedFormulas/absence3_many_short_1.json",
                                  "OrderedSequence/trace_length=8number_atomic_propositions=3size_sequence=3"])
def test_benchmark_problems_reach_the_known_size(name):
    path = next(iter(sorted(BENCH.glob(name + "*"))))
    sample = load_sample(path)
    result = learn_from_sample(sample, timeout=20)
    known = sample.smallest_known_formula
    while known.count(")") > known.count("("):  # the OrderedSequence generator's surplus ')'
        known = known[: known.rindex(")")] + known[known.rindex(")") + 1:]
    assert result.optimal and result.size <= size(parse(known, dialect="spot"))
    assert separates(result.formula, sample.positive, sample.negative)


def _wired() -> bool:
    from symlearn.cli.main import build_parser

    parser = build_parser()
    groups = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    ltl = groups.get("ltl")
    if ltl is None:
        return False
    commands = next((a for a in ltl._actions if isinstance(a, argparse._SubParsersAction)), None)
    return commands is not None and "learn" in commands.choices


def test_cli_through_main_exit_codes(tmp_path, capsys):
    assert _wired(), "'ltl learn' must be registered in the ltl command group"
    from symlearn.cli.main import main

    good = _sample_file(tmp_path, [[{"a"}], [{"b"}]], [[set()], [set(), {"a"}]])
    assert main(["ltl", "learn", str(good), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["size"] == 3
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"atomic_propositions": ["a"], "positive_traces": [{"a": [1]}],
                               "negative_traces": [{"a": [1]}]}))
    assert main(["ltl", "learn", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"symlearn: error: {bad}: contradictory sample")
