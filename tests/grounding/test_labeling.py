import pytest

from symlearn.errors import DataError, ParseError
from symlearn.grounding.labeling import Labeling


def test_labels_and_growth():
    lab = Labeling({0: ["coffee"], (1, 2): ["mail", "coffee"]}, meanings={"coffee": "coffee machine"})
    assert lab.label(0) == {"coffee"} and lab.label((1, 2)) == {"mail", "coffee"} and lab.label(9) == frozenset()
    grown = lab.with_proposition("p0", [9, 0], "cell 9 or 0")
    assert grown.label(9) == {"p0"} and grown.label(0) == {"coffee", "p0"}
    assert grown.propositions[-1] == "p0" and grown.meanings["p0"] == "cell 9 or 0"
    assert lab.label(9) == frozenset()  # the original is untouched
    with pytest.raises(DataError, match="already exists"):
        grown.with_proposition("p0", [1])
    assert lab.label_word([0, 9]) == (frozenset({"coffee"}), frozenset())


def test_json_round_trip(tmp_path):
    lab = Labeling({0: ["a"], (3, 4): ["b"], "s": ["a", "b"]}, meanings={"a": "first"}, propositions=["b", "a"])
    lab.save(tmp_path / "lab.json")
    again = Labeling.load(tmp_path / "lab.json")
    assert again == lab and again.propositions == ("b", "a") and again.label((3, 4)) == {"b"}


def test_bad_labeling_files(tmp_path):
    path = tmp_path / "lab.json"
    path.write_text('{"symlearn": "labeling", "format_version": 1,\n "propositions": [}')
    with pytest.raises(ParseError, match="invalid JSON") as info:
        Labeling.load(path)
    assert info.value.line == 2
    path.write_text('{"symlearn": "labeling", "format_version": 1, "propositions": [{"nom": "a"}], "table": []}')
    with pytest.raises(DataError, match=r'propositions\[0\]: expected an object with a "name"') as info:
        Labeling.load(path)
    assert (info.value.line, info.value.column) == (1, 64)  # the object that lacks the name
    path.write_text('{"format_version": 1}')
    with pytest.raises(DataError, match="not a symlearn labeling"):
        Labeling.load(path)
    with pytest.raises(DataError, match="not a proposition name"):
        Labeling({0: [""]})


def test_items_and_restrict():
    lab = Labeling({0: ["a", "b"], 1: ["b"], 2: ["c"]}, meanings={"a": "A", "b": "B"}, propositions=["c", "b", "a"])
    assert dict(lab.items()) == {0: {"a", "b"}, 1: {"b"}, 2: {"c"}}
    cut = lab.restrict(["a", "c"])
    assert cut.propositions == ("c", "a") and cut.label(0) == {"a"} and cut.label(1) == frozenset()
    assert cut.meanings == {"c": "", "a": "A"}
    with pytest.raises(DataError, match="unknown proposition 'z'"):
        lab.restrict(["z"])
