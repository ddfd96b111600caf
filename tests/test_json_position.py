"""symlearn.json_position: a path of keys and indexes back to the line and column of JSON text."""

import json

import pytest

from symlearn.json_position import JsonPathError, locate, located

TEXT = '''{"a": "x]}\\\\\\"{[",
 "list": [1, -2.5e3, true, null, {"k": [7, "]"]}],
 "nested": {"deep": [[], [{"b": 0}]]}}'''


def test_the_text_is_json():
    assert json.loads(TEXT)["nested"]["deep"][1][0]["b"] == 0


@pytest.mark.parametrize("path, where", [
    ((), (1, 1)),
    (("a",), (1, 7)),
    (("list",), (2, 10)),
    (("list", 1), (2, 14)),
    (("list", 3), (2, 28)),
    (("list", 4, "k", 1), (2, 44)),
    (("nested", "deep", 1, 0, "b"), (3, 33)),
])
def test_a_path_is_located(path, where):
    assert locate(TEXT, path) == where


@pytest.mark.parametrize("path", [("missing",), ("list", 9), ("a", 0), ("list", "k"), (0,), ("list", True)])
def test_a_path_that_is_not_there_is_none(path):
    assert locate(TEXT, path) is None


def test_text_json_would_refuse_gives_none_not_a_guess():
    assert locate('{"a": [1, 2', ("a", 5)) is None
    assert locate('{"a" 1}', ("b",)) is None


def test_deep_nesting_is_scanned_without_recursion():
    depth = 50_000
    text = "[" * depth + "1" + "]" * depth
    assert locate(text, (0,) * depth) == (1, depth + 1)
    assert locate('[' + text + ', 2]', (1,)) == (1, 2 * depth + 5)


def test_the_message_starts_with_the_path():
    assert str(JsonPathError("bad", path=())) == "$: bad"
    assert str(JsonPathError("bad", path=("traces", 0, "a", 2))) == "traces[0].a[2]: bad"
    assert str(copied(JsonPathError("bad", path=("k",), file="f.json"))) == "f.json: k: bad"


def copied(error):
    import copy

    return copy.copy(error)   # through __reduce__, as between processes


def test_located_fills_in_line_and_column_once():
    error = located(JsonPathError("bad", path=("list", 1), file="f.json"), TEXT)
    assert (error.line, error.column) == (2, 14) and str(error).startswith("f.json:2:14: list[1]: bad")
    kept = located(JsonPathError("x", path=("list",), line=9, column=1), TEXT)
    assert (kept.line, kept.column) == (9, 1)


@pytest.mark.parametrize("text, line, column", [
    ('# my demonstrations\n{"a": 1}\n', 1, 1),
    ('{"a": 1, // the speed\n"b": 2}', 1, 10),
    ('[1, /* two */ 2]', 1, 5),
])
def test_a_comment_in_json_is_named_as_one(text, line, column):
    """JSON has no comments; hand-written files have them more often than any other mistake."""
    from symlearn.errors import ParseError
    from symlearn.input_limits import load_json

    with pytest.raises(ParseError) as info:
        load_json(text, source="f.json")
    assert (info.value.line, info.value.column) == (line, column)
    assert "JSON has no comments" in (info.value.hint or "")
    with pytest.raises(ParseError) as info:
        load_json('{"a": 1,}', source="f.json")
    assert "comments" not in (info.value.hint or "")
