"""Feature maps, feature-defined and callable labelings, fact groundings: values, files, errors."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.errors import DataError, ParseError, SymlearnError
from symlearn.grounding import (CallableLabeling, FactGrounding, FeatureLabeling, FeatureMap, Labeling,
                                load_labeling, parse_condition, read_labeling)

DOC = {"symlearn": "labeling", "format_version": 1, "kind": "features",
       "features": {"symlearn": "feature-map", "format_version": 1, "names": ["x", "y", "speed"]},
       "propositions": [{"name": "near_goal", "meaning": "within 0.5 of the goal", "when": "x > 4.5 & y > 4.5"},
                        {"name": "fast", "meaning": "", "when": "speed >= 2 | speed <= -2"}]}


def test_documented_feature_labeling_loads(tmp_path):
    path = tmp_path / "lab.json"
    path.write_text(json.dumps(DOC))
    lab = load_labeling(path)
    assert isinstance(lab, FeatureLabeling)
    assert lab.label([5, 5, 0]) == {"near_goal"}
    assert lab.label({"x": 0, "y": 0, "speed": -3}) == {"fast"}
    lab.save(tmp_path / "again.json")
    assert load_labeling(tmp_path / "again.json") == lab


def test_table_labeling_still_loads_without_kind(tmp_path):
    path = tmp_path / "old.json"
    path.write_text(json.dumps({"symlearn": "labeling", "format_version": 1,
                                "propositions": [{"name": "a", "meaning": ""}], "table": [[1, ["a"]]]}))
    assert load_labeling(path) == Labeling({1: {"a"}})
    with pytest.raises(DataError, match="not a table"):
        Labeling.from_json(json.dumps(DOC))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(-10, 10, allow_nan=False), st.floats(-10, 10, allow_nan=False),
                          st.floats(-10, 10, allow_nan=False)), min_size=1, max_size=20))
def test_label_matrix_agrees_with_label(rows):
    lab = FeatureLabeling.from_document(DOC)
    features = np.array(rows)
    matrix = lab.label_matrix(features)
    for row, flags in zip(rows, matrix):
        assert {p for p, f in zip(lab.propositions, flags) if f} == lab.label(list(row))


@given(st.lists(st.tuples(st.sampled_from(["x", "y_2", "speed"]), st.sampled_from(["<", "<=", ">", ">="]),
                          st.floats(-1e6, 1e6, allow_nan=False)), min_size=1, max_size=4), st.integers(1, 3))
def test_condition_print_parse_round_trip(atoms, n_disjuncts):
    from symlearn.logic.dnf import DNF

    cond = DNF.of(*[[(f, o, float(v)) for f, o, v in atoms]] * n_disjuncts)
    assert parse_condition(cond.to_string(one_line=True)) == cond


def test_condition_errors_name_the_column():
    """The column is the condition's, said in the message with a caret: as a location it read as
    a line of the labeling file, or alone ("6: lava: ...") as nothing."""
    with pytest.raises(ParseError, match="p, column 11 of its condition: unexpected character") as info:
        parse_condition("x > 1 & y = 2", where="p")
    assert info.value.column is None and str(info.value).endswith("  x > 1 & y = 2\n            ^ (hint: < <= > >= "
                                                                   "== != compare a feature with a number (== for "
                                                                   "equality))")
    with pytest.raises(ParseError) as info:
        read_labeling('{"lava": "cell = 12"}', feature_names=["cell"])
    assert str(info.value).startswith("--labeling: proposition 'lava', column 6 of its condition: unexpected "
                                      "character '='")
    assert read_labeling('{"lava": "cell == 12", "dry": "cell != 12"}', feature_names=["cell"]).label_word(
        [[11], [12], [13]]) == (frozenset({"dry"}), frozenset({"lava"}), frozenset({"dry"}))
    with pytest.raises(ParseError, match="empty"):
        parse_condition("  ")
    with pytest.raises(DataError, match="unknown feature 'z'"):
        FeatureLabeling(["x"], {"p": "z < 1"})


def test_callable_labeling_checks_its_propositions():
    lab = CallableLabeling(lambda s: {"hot"} if s > 30 else {"cold"} if s < 0 else set(), ["hot", "cold"])
    assert lab.label_word([40, 10, -5]) == (frozenset({"hot"}), frozenset(), frozenset({"cold"}))
    bad = CallableLabeling(lambda s: {"warm"}, ["hot"])
    with pytest.raises(DataError, match="undeclared proposition 'warm'"):
        bad.label(1)
    with pytest.raises(SymlearnError, match="cannot be saved"):
        lab.to_json()


def test_feature_map_forms_and_errors(tmp_path):
    table = FeatureMap(["a", "b"], table=np.array([[0.0, 1.0], [2.0, 3.0]]))
    assert table.features(1).tolist() == [2.0, 3.0]
    table.save(tmp_path / "fm.json")
    assert FeatureMap.load(tmp_path / "fm.json") == table
    assert table.as_dict(0) == {"a": 0.0, "b": 1.0}
    with pytest.raises(DataError, match="not a state id"):
        table.features(5)
    fm = FeatureMap(["a", "b"], function=lambda s: [s, 2 * s])
    assert fm.matrix([1, 2]).tolist() == [[1.0, 2.0], [2.0, 4.0]]
    with pytest.raises(SymlearnError, match="cannot be saved"):
        fm.to_json()
    with pytest.raises(DataError, match="finite"):
        FeatureMap(["a"]).features([float("nan")])
    with pytest.raises(DataError, match="no feature 'b'"):
        FeatureMap(["a", "b"]).features({"a": 1})
    with pytest.raises(DataError, match="repeat"):
        FeatureMap(["a", "a"])


def test_fact_grounding_files_and_errors(tmp_path):
    g = FactGrounding(["at(0,0). loaded.", ""], ["move(north)", "wait"])
    g.save_jsonl(tmp_path / "s.jsonl", tmp_path / "a.jsonl")
    assert FactGrounding.from_jsonl(tmp_path / "s.jsonl", tmp_path / "a.jsonl") == g
    assert g.facts(0, 0) == ("at(0,0).", "loaded.", "move(north).")
    assert g.action_index("move( north )") == 0
    (tmp_path / "s.jsonl").write_text('{"id": 0, "facts": "a."}\n{"id": 2, "facts": "b."}\n')
    with pytest.raises(DataError, match="id 1 is missing"):
        FactGrounding.from_jsonl(tmp_path / "s.jsonl", tmp_path / "a.jsonl")
    (tmp_path / "s.jsonl").write_text('{"id": 0, "facts": "a."}\n{"id": 0, "facts": "b."}\n')
    with pytest.raises(DataError, match="appears twice") as info:
        FactGrounding.from_jsonl(tmp_path / "s.jsonl", tmp_path / "a.jsonl")
    assert info.value.line == 2
    with pytest.raises(ParseError, match="not a ground fact"):
        FactGrounding(["p(X)."], ["go"])
    # facts given as ready-made tuples are checked too, and a choice or directive is no fact
    for bad in [("p(X).",), ("{ c }.",), ("#const n = 1.",), ("a :- b.",)]:
        with pytest.raises(ParseError, match="not a ground fact"):
            FactGrounding([bad], ["go"])
    with pytest.raises(ParseError, match="not a ground fact"):
        FactGrounding(["a."], ["go"], pair_facts={(0, 0): ("a.", "{ b }.")})
    assert FactGrounding([("at(1, 2).", "-p(a).")], ["go"]).facts(0, 0) == ("at(1,2).", "-p(a).", "go.")
    with pytest.raises(DataError, match="names two actions"):
        FactGrounding([""], ["go", "go"])
