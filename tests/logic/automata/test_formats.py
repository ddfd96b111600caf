"""DOT, JSON and HOA exports of automata; JSON round trip and malformed files."""

import json
import re

import pytest
from automata_strategies import dfas
from hypothesis import given, settings

from symlearn.errors import ModelError, ParseError
from symlearn.logic.automata import DFA, PDFA, RewardMachine, load_automaton
from symlearn.logic.guards import Guard
from symlearn.rendering import dot_available

a, b = Guard.var("a"), Guard.var("b")


def example():
    return DFA({"a", "b"}, 3, 0, [1], {0: [(~a & ~b, 0), (a & ~b, 1), (b, 2)], 1: [(~b, 1), (b, 2)],
                                       2: [(Guard.true(), 2)]}, ["start", "goal", "broken"])


def test_dot_has_initial_arrow_double_circles_and_readable_guards():
    dot = example().to_dot(title="demo")
    assert "__start -> 0;" in dot
    assert re.search(r'1 \[label="goal", shape=doublecircle\]', dot)
    assert 'label="a & !b"' in dot and 'label="!a & !b"' in dot
    assert re.search(r'2 \[label="broken", color=gray50', dot)  # dead state greyed
    assert 'label="demo"' in dot


@pytest.mark.skipif(not dot_available(), reason="graphviz dot not installed")
def test_render_svg_and_repr(tmp_path):
    path = example().render(tmp_path / "x.svg")
    assert path.read_text().lstrip().startswith("<?xml") or "<svg" in path.read_text()
    assert "<svg" in example()._repr_svg_()


def test_json_round_trip_exact_for_all_kinds():
    d = example()
    assert DFA.from_json(d.to_json()) == d
    p = PDFA({"a"}, 2, 0, {0: [(a, 1, 0.3), (~a, 0, 0.7)], 1: [(a, 1, 0.1)]}, [0.0, 0.9])
    assert PDFA.from_json(p.to_json()) == p
    rm = RewardMachine.from_dfa(d, shaping=True, gamma=0.9)
    back = RewardMachine.from_json(rm.to_json())
    assert back == rm and back.potential == rm.potential


@settings(max_examples=50, deadline=None)
@given(dfas(("a", "b", "c"), max_states=5))
def test_json_round_trip_property(d):
    assert DFA.from_json(d.to_json()) == d
    assert DFA.from_json(json.loads(d.to_json())) == d


def test_load_automaton_dispatches_on_kind(tmp_path):
    example().save(tmp_path / "d.json")
    RewardMachine.from_dfa(example()).save(tmp_path / "r.json")
    assert isinstance(load_automaton(tmp_path / "d.json"), DFA)
    assert isinstance(load_automaton(tmp_path / "r.json"), RewardMachine)
    assert DFA.load(tmp_path / "d.json") == example()


def _document():
    return json.loads(example().to_json())


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d.update(format="other"), "format: expected 'symlearn-automaton'"),
    (lambda d: d.update(version=7), "version: unsupported version 7"),
    (lambda d: d.update(kind="nfa"), "kind: unknown automaton kind"),
    (lambda d: d.pop("states"), "states: missing field"),
    (lambda d: d.update(initial="0"), "initial: expected an integer, got text"),
    (lambda d: d.update(alphabet=["a", 3]), "alphabet[1]: expected text"),
    (lambda d: d["transitions"][2].update(guard="a &"), "transitions[2].guard: unexpected end"),
    (lambda d: d["transitions"][1].pop("target"), "transitions[1].target: missing field"),
    (lambda d: d["transitions"].__setitem__(0, 5), "transitions[0]: expected an object"),
    (lambda d: d.update(accepting=[9]), "accepting state 9 is not a state"),
])
def test_malformed_json_names_the_field(tmp_path, mutate, message):
    document = _document()
    mutate(document)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(document))
    with pytest.raises((ParseError, ModelError)) as info:
        load_automaton(path)
    assert message in str(info.value)
    assert info.value.file == str(path)


def test_json_syntax_error_has_line_and_column(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"format": "symlearn-automaton",\n  "version": 1,,\n}')
    with pytest.raises(ParseError) as info:
        load_automaton(path)
    assert (info.value.line, info.value.column) == (2, 16)
    assert "not valid JSON" in info.value.message


def test_nondeterministic_json_is_a_model_error(tmp_path):
    document = _document()
    document["transitions"].append({"source": 0, "target": 1, "guard": "b"})
    with pytest.raises(ModelError, match="not deterministic"):
        DFA.from_json(json.dumps(document))


def test_hoa_export_structure():
    hoa = example().to_hoa(name="spec", encoding="final-marks")
    lines = hoa.splitlines()
    assert lines[0] == "HOA: v1" and lines[1].startswith('name: "spec (finite words: marked states are FINAL')
    assert "States: 3" in lines and "Start: 0" in lines and 'AP: 2 "a" "b"' in lines
    assert 'State: 1 "goal" {0}' in lines and 'State: 0 "start"' in lines
    assert "[0&!1] 1" in lines and "[!0&!1] 0" in lines and "[1] 2" in lines and "[t] 2" in lines
    assert lines[-1] == "--END--"


def test_hoa_export_encodes_finite_words_with_alive_by_default():
    """HOA has no finite-word acceptance: the default is Spot's from_ltlf encoding, said in the header."""
    hoa = example().to_hoa(name="spec")
    lines = hoa.splitlines()
    assert "alive" in lines[1] and 'AP: 3 "a" "b" "alive"' in lines and "States: 4" in lines
    assert any(line.startswith("/*") and "from_ltlf" in line for line in lines)
    assert 'State: 1 "goal"' in lines and "[0&!1&2] 1" in lines and "[!2] 3" in lines  # final -> end on !alive
    assert 'State: 3 "end" {0}' in lines and lines[-2] == "[!2] 3"


def test_hoa_labels_encode_the_guards_exactly():
    from symlearn.logic.automata.hoa_export import hoa_label

    g = (a & ~b) | (~a & b)
    text = hoa_label(g, {"a": 0, "b": 1})
    back = Guard.parse(text.replace("0", "a").replace("1", "b"))
    assert back == g


@settings(max_examples=40, deadline=None)
@given(dfas(("a", "b"), max_states=4))
def test_pdfa_and_reward_machine_round_trips(d):
    rm = RewardMachine.from_dfa(d, shaping=True, gamma=0.95)
    assert RewardMachine.from_json(rm.to_json()) == rm
    back = RewardMachine.from_text(rm.to_text(), unmatched="stay")
    for word in ([], [{"a"}], [{"a", "b"}, set(), {"b"}]):
        assert back.run(word) == rm.run(word)
    if d.trim().accepting:
        p = PDFA.from_dfa(d, termination=0.25)
        assert PDFA.from_json(p.to_json()) == p


def test_copy_goes_through_json():
    import copy

    d = example()
    assert copy.deepcopy(d) == d and copy.copy(RewardMachine.from_dfa(d)) == RewardMachine.from_dfa(d)
