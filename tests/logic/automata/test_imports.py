"""Import of MONA / LTLf2DFA DOT and of the reward-machines text format."""

import shutil
import subprocess
from pathlib import Path

import pytest

from symlearn.errors import ModelError, ParseError
from symlearn.logic.automata import DFA, RewardMachine, parse_mona_dot, parse_rm_text, read_mona_dot, read_rm_text
from symlearn.logic.guards import Guard

DATA = Path(__file__).parent / "data"
a, b, c = Guard.var("a"), Guard.var("b"), Guard.var("c")
T = Guard.true()


# -- LTLf2DFA DOT ------------------------------------------------------------------------------
def test_ltlf2dfa_dot_f_a_and_g_b():
    d = read_mona_dot(DATA / "ltlf2dfa_fa_and_gb.dot")
    expected = DFA({"a", "b"}, 2, 0, [1], {0: [(b & ~a, 0), (a & b, 1)], 1: [(b, 1)]})
    assert d.equivalent(expected) == (True, None)
    assert d.state_names == ("1", "2", "3") and d.initial == 0  # MONA state 1 is the initial state


def test_ltlf2dfa_dot_strong_next():
    d = read_mona_dot(DATA / "ltlf2dfa_g_a_implies_xb.dot")
    assert d.accepts([set(), {"a"}, {"b"}]) and not d.accepts([{"a"}]) and not d.accepts([{"a"}, set()])
    assert d.minimize().n_states == 3


def test_ltlf2dfa_dot_parenthesised_guards_and_false():
    d = read_mona_dot(DATA / "ltlf2dfa_a_until_bc.dot")
    assert d.accepts([{"a"}, {"a", "c"}, {"b", "c"}]) and not d.accepts([{"a"}, {"b"}])
    never = read_mona_dot(DATA / "ltlf2dfa_false.dot")
    assert never.is_empty()


# -- raw MONA DOT --------------------------------------------------------------------------------
def test_raw_mona_dot_drops_the_extra_initial_state():
    d = read_mona_dot(DATA / "mona_raw_a_implies_b_or_c.dot", variables=["a", "b", "c"])
    assert d.n_states == 3 and d.state_names == ("1", "2", "3")
    assert d.accepts([{"a", "b"}, set(), {"c", "a"}]) and not d.accepts([{"b"}, {"a"}])
    assert not d.accepts([])  # MONA marks state 1 "don't care" (box): read as rejecting


def test_raw_mona_default_variable_names():
    d = read_mona_dot(DATA / "mona_raw_a_implies_b_or_c.dot")
    assert d.alphabet == {"v1", "v2", "v3"}


@pytest.mark.oracle
@pytest.mark.skipif(shutil.which("mona") is None, reason="mona is not installed")
def test_raw_mona_live(tmp_path):
    program = tmp_path / "p.mona"
    program.write_text("m2l-str; var2 a, b; ex1 p: p in a & p+1 in b;")
    out = subprocess.run(["mona", "-gw", str(program)], capture_output=True, text=True, timeout=60).stdout
    d = parse_mona_dot(out[out.index("digraph"):], variables=["a", "b"])
    assert d.accepts([{"a"}, {"b"}]) and d.accepts([set(), {"a"}, {"a", "b"}, set()])
    assert not d.accepts([{"a"}, set()]) and not d.accepts([{"b"}, {"a"}]) and not d.accepts([{"a"}])


@pytest.mark.parametrize("text, line, message", [
    ("graph X {\n}", 1, "expected 'digraph NAME {'"),
    ("digraph M {\n init -> 1;\n 1 -> 2 [label=\"a &\"];\n}", 3, "edge label: unexpected end"),
    ("digraph M {\n init -> 1;\n 1 => 2;\n}", 3, "expected an edge"),
    ("digraph M {\n init -> 1;\n 1 -> 1 [label=\"true\"];\n", 3, "ends before the closing"),
    ("digraph M {\n 1 -> 1 [label=\"true\"];\n}", None, "initial state is unknown"),
    ("digraph M {\n init -> 1;\n init -> 2;\n}", 3, "second 'init ->'"),
    ("digraph M {\n}\n}", 3, "after the closing"),
    ("", 1, "empty DOT text"),
])
def test_malformed_mona_dot(text, line, message):
    with pytest.raises(ParseError) as info:
        parse_mona_dot(text, source="x.dot")
    assert message in info.value.message
    assert info.value.line == line and info.value.file == "x.dot"


def test_mona_dot_guard_error_column():
    with pytest.raises(ParseError) as info:
        parse_mona_dot('digraph M {\n init -> 1;\n 1 -> 2 [label="a & $"];\n}')
    assert (info.value.line, info.value.column) == (3, 21)


def test_nondeterministic_mona_dot_is_model_error():
    with pytest.raises(ModelError, match="not deterministic"):
        parse_mona_dot('digraph M {\n node [shape = circle]; 1; 2;\n init -> 1;\n 1 -> 2 [label="a"];\n'
                       ' 1 -> 1 [label="true"];\n}', source="f.dot")


# -- reward-machine text ---------------------------------------------------------------------------
OFFICE = """0      # initial state
[2]    # terminal state
(0,0,'!e&!n',ConstantRewardFunction(0))
(0,1,'e&!g&!n',ConstantRewardFunction(0))
(0,2,'e&g&!n',ConstantRewardFunction(1))
(1,1,'!g&!n',ConstantRewardFunction(0))
(1,2,'g&!n',ConstantRewardFunction(1))
"""


def test_rm_text_office_example():
    rm = parse_rm_text(OFFICE)
    assert rm.alphabet == {"e", "g", "n"} and rm.initial == 0
    assert rm.step(0, {"e"}) == (1, 0.0) and rm.step(1, {"g"}) == (2, 1.0)
    assert rm.step(0, {"e", "g"}) == (2, 1.0)
    fail, reward = rm.step(0, {"n"})  # as the public code: unmatched -> terminal failure state
    assert reward == 0.0 and fail in rm.terminal and rm.state_names[fail] == "fail"
    assert parse_rm_text(OFFICE, unmatched="stay").step(0, {"n"}) == (0, 0.0)


def test_rm_text_without_terminal_line_negative_ids_and_true(tmp_path):
    text = "5\n(5,5,'!a',ConstantRewardFunction(0))\n(5,-1,'a',ConstantRewardFunction(2.5))\n" \
           "(-1,-1,'True',ConstantRewardFunction(0))\n"
    path = tmp_path / "rm.txt"
    path.write_text(text)
    rm = read_rm_text(path)
    assert rm.state_names == ("-1", "5") and rm.initial == 1
    assert rm.terminal == {0}  # only a True self-loop with reward 0
    assert rm.run([set(), {"a"}]) == ([1, 1, 0], [0.0, 2.5])


@pytest.mark.parametrize("text, line, column, message", [
    ("", 1, 1, "empty reward machine file"),
    ("x\n[1]\n", 1, 1, "expected a state number"),
    ("0\n[1, 2\n", 2, 6, "expected ',' or ']'"),
    ("0\n[1]\n(0,1,'a',ConstantRewardFunction(1)\n", 3, 35, "expected ')' but the line ended"),
    ("0\n[1]\n(0,1,'a & ',ConstantRewardFunction(1))\n", 3, 11, "unexpected end"),
    ("0\n[1]\n(0,1,'a',RewardControl())\n", 3, 10, "only ConstantRewardFunction"),
    ("0\n[1]\n(0,1,a,ConstantRewardFunction(1))\n", 3, 6, "expected a quoted guard"),
    ("0\n[1]\n(0,1.5,'a',ConstantRewardFunction(1))\n", 3, 4, "must be an integer"),
    ("0\n[1]\n(0,1,'a',ConstantRewardFunction(1)) extra\n", 3, 37, "after the end"),
    ("0\n[1]\n(0,1,'a',ConstantRewardFunction(1))\n(0,0,'a|b',ConstantRewardFunction(0))\n", 4, 6, "overlaps"),
    ("0\n[1]\n(0,1,'a',ConstantRewardFunction(1)) ; \n", 3, 37, "unexpected character"),
])
def test_malformed_rm_text(text, line, column, message):
    with pytest.raises((ParseError, ModelError)) as info:
        parse_rm_text(text, source="rm.txt")
    assert message in info.value.message
    assert (info.value.file, info.value.line, info.value.column) == ("rm.txt", line, column)


def test_rm_text_never_evaluates_python():
    with pytest.raises(ParseError):
        parse_rm_text("__import__('os').system('false')\n[]\n")


# -- cross-check of our operations against automata built independently by LTLf2DFA/MONA --------
def _ltlf2dfa(name):
    return read_mona_dot(DATA / f"ltlf2dfa_{name}.dot")


def test_products_and_complement_agree_with_mona():
    fa, gb = _ltlf2dfa("fa"), _ltlf2dfa("gb")
    assert (fa & gb).equivalent(_ltlf2dfa("fa_and_gb")) == (True, None)
    assert (fa | gb).equivalent(_ltlf2dfa("fa_or_gb")) == (True, None)
    assert fa.complement().equivalent(_ltlf2dfa("not_fa")) == (True, None)
    same, witness = fa.equivalent(gb)
    assert not same and fa.accepts(witness) != gb.accepts(witness)


def test_minimize_keeps_mona_minimal_sizes():
    # MONA's DFAs are minimal; ours must have the same number of states after minimising
    for name in ("fa", "gb", "fa_and_gb", "fa_or_gb", "a_until_b", "ga_implies_fb", "g_a_implies_xb"):
        d = _ltlf2dfa(name)
        assert d.is_complete() and d.minimize().n_states == d.n_states, name


@pytest.mark.parametrize("text", ["F a", "F a & G !b", "a U b", "G(a -> X b)", "(a T b) & F c", "true", "false"])
def test_the_dot_symlearn_writes_reads_back(text):
    # `automaton convert X.dot Y.json` refused our own drawing ('__start', one statement per
    # state; held-out pass): the language comes back, over the propositions the guards mention
    from symlearn.logic.automata.mona_dot_import import parse_mona_dot
    from symlearn.logic.ltlf import parse, translate

    dfa = translate(parse(text))
    back = parse_mona_dot(dfa.to_dot(title=text), source="<dot>")
    assert back.n_states == dfa.n_states
    alphabet = dfa.alphabet | back.alphabet
    assert dfa.with_alphabet(alphabet).equivalent(back.with_alphabet(alphabet))[0]
