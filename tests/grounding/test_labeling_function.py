"""The labelings a user brings: saved JSON, a plain {proposition: condition} object, FILE.py:function."""

from __future__ import annotations

import json

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.grounding import FeatureLabeling, FunctionLabeling, Labeling, load_labeling_function, read_labeling
from symlearn.grounding.labeling_function import as_observation_labeler


def test_three_forms(tmp_path):
    table = tmp_path / "table.json"
    Labeling({3: {"goal"}}).save(table)
    assert read_labeling(str(table)).label(3) == {"goal"}

    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps({"near_goal": "x > 0.8 & y > 0.8"}))
    features = read_labeling(str(plain), feature_names=["x", "y"])
    assert isinstance(features, FeatureLabeling)
    assert features.label(np.array([0.9, 0.9])) == {"near_goal"} and features.label([0.9, 0.1]) == frozenset()

    module = tmp_path / "labels.py"
    module.write_text("PROPOSITIONS = ['far']\nMEANINGS = {'far': 'beyond 10'}\n"
                      "def label(obs, info):\n    return ['far'] if info.get('distance', 0) > 10 else []\n")
    function = read_labeling(f"{module}:label")
    assert isinstance(function, FunctionLabeling) and function.propositions == ("far",)
    assert function.meanings == {"far": "beyond 10"}
    assert function(None, {"distance": 11}) == {"far"} and function(None, {}) == frozenset()


def test_declared_by_attribute_and_discovered(tmp_path):
    module = tmp_path / "labels.py"
    module.write_text("def tagged(obs, info):\n    return ['b', 'a']\ntagged.propositions = ['a', 'b']\n"
                      "def free(obs, info):\n    return ['z'] if obs else ['y']\n")
    assert load_labeling_function(f"{module}:tagged").propositions == ("a", "b")
    free = load_labeling_function(f"{module}:free")
    assert not free.declared and free.propositions == ()
    free(0, {}), free(1, {})
    assert free.propositions == ("y", "z")  # in the order first returned


def test_feature_labeling_needs_names(tmp_path):
    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps({"near_goal": "x > 0.8"}))
    with pytest.raises(DataError, match="needs the observation's feature names"):
        read_labeling(str(plain))
    plain.write_text("[1, 2]")
    with pytest.raises(DataError, match="proposition: condition"):
        read_labeling(str(plain), feature_names=["x"])


def test_not_file_function(tmp_path):
    with pytest.raises(DataError, match="is not FILE.py:function"):
        load_labeling_function("labels.py")


def test_three_argument_function_gets_the_environment():
    lab = FunctionLabeling(lambda obs, info, env: {env}, ["here"])
    assert lab.label(0, {}, env="here") == {"here"}
    with pytest.raises(DataError, match="needs the environment"):
        lab.label(0, {})


def test_observation_labeler_of_each_form():
    table = as_observation_labeler(Labeling({2: {"goal"}}))
    assert table(2, {"ignored": 1}) == {"goal"}
    one_argument = as_observation_labeler(lambda obs: ["odd"] if obs % 2 else [])
    assert one_argument(3, {}) == {"odd"}
    with pytest.raises(DataError, match="is not a labeling"):
        as_observation_labeler(42)
