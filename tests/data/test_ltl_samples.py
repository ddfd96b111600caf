"""Loading and writing labelled trace samples (benchmark JSON schema)."""

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symlearn.data.ltl_samples import load_sample, parse_sample, sample_from_traces, sample_to_document, save_sample
from symlearn.errors import DataError

BENCH = Path(__file__).resolve().parents[2].parent / "shared" / "benchmarks" / "ltlf_learning"


def _doc(**changes):
    doc = {"atomic_propositions": ["a", "b"],
           "positive_traces": [{"a": [1, 0], "b": [0, 1]}],
           "negative_traces": [{"a": [0], "b": [1]}],
           "smallest_known_formula": "a"}
    doc.update(changes)
    return doc


def _write(tmp_path, doc) -> Path:
    path = tmp_path / "s.json"
    path.write_text(json.dumps(doc) if not isinstance(doc, str) else doc)
    return path


def test_parse_reads_traces_as_label_sets():
    s = parse_sample(_doc())
    assert s.positive == ((frozenset({"a"}), frozenset({"b"})),)
    assert s.negative == ((frozenset({"b"}),),)
    assert s.smallest_known_formula == "a" and s.propositions == ("a", "b") and s.max_length == 2


def test_string_bits_are_accepted():
    s = parse_sample(_doc(positive_traces=[{"a": ["1", "0"], "b": ["0", "1"]}]))
    assert s.positive[0][0] == frozenset({"a"})


@pytest.mark.parametrize("change, message", [
    ({"positive_traces": [{"a": [1], "c": [0]}]}, "positive_traces[0].c: unknown proposition 'c'"),
    ({"positive_traces": []}, "positive_traces: the sample has no positive traces"),
    ({"negative_traces": []}, "negative_traces: the sample has no negative traces"),
    ({"negative_traces": [{"a": [1, 0], "b": [0, 1]}]}, "contradictory sample: positive_traces[0] and negative_traces[0]"),
    ({"positive_traces": [{"a": [1, 0], "b": [0]}]}, "positive_traces[0].b: 1 values where the other propositions have 2"),
    ({"positive_traces": [{"a": [1, 2], "b": [0, 1]}]}, "positive_traces[0].a[1]: expected 0 or 1, found 2"),
    ({"negative_traces": [{"a": [], "b": []}]}, "negative_traces[0]: empty trace"),
    ({"negative_traces": [{"a": [1]}]}, "negative_traces[0]: no values for proposition 'b'"),
    ({"positive_traces": "x"}, "positive_traces: expected a list of traces"),
])
def test_bad_documents_name_file_and_json_path(tmp_path, change, message):
    path = _write(tmp_path, _doc(**change))
    with pytest.raises(DataError) as info:
        load_sample(path)
    assert message in str(info.value)
    assert str(info.value).startswith(str(path))


def test_a_bad_value_is_located_at_its_line_and_column(tmp_path):
    path = _write(tmp_path, json.dumps(_doc(negative_traces=[{"a": [1, 0], "b": [0, "x"]}]), indent=1))
    with pytest.raises(DataError) as info:
        load_sample(path)
    lines = path.read_text().splitlines()
    line, column = info.value.line, info.value.column
    assert lines[line - 1][column - 1:].startswith('"x"'), (line, column)
    assert str(info.value).startswith(f"{path}:{line}:{column}: negative_traces[0].b[1]: expected 0 or 1")


def test_missing_key_and_bad_json(tmp_path):
    doc = _doc()
    del doc["negative_traces"]
    with pytest.raises(DataError, match="missing key 'negative_traces'"):
        load_sample(_write(tmp_path, doc))
    with pytest.raises(DataError) as info:
        load_sample(_write(tmp_path, '{"atomic_propositions": [}'))
    assert "not valid JSON" in str(info.value) and info.value.line == 1


def test_in_memory_samples_are_validated_too():
    with pytest.raises(DataError, match="unknown proposition 'z'"):
        sample_from_traces([[{"z"}]], [[set()]], propositions=["a"])
    with pytest.raises(DataError, match="contradictory"):
        sample_from_traces([[{"a"}]], [[{"a"}]])
    with pytest.raises(DataError, match="no negative traces"):
        sample_from_traces([[{"a"}]], [])


traces = st.lists(st.lists(st.frozensets(st.sampled_from("abc")), min_size=1, max_size=5), min_size=1, max_size=4)


@settings(max_examples=40, deadline=None)
@given(traces, traces)
def test_write_then_load_is_identity(tmp_path_factory, pos, neg):
    neg = [t for t in neg if t not in pos]
    if not neg:
        return
    s = sample_from_traces(pos, neg, propositions=["a", "b", "c"], metadata={"name": "x"})
    path = tmp_path_factory.mktemp("s") / "s.json"
    save_sample(s, path)
    again = load_sample(path)
    assert again == s and again.metadata["name"] == "x"
    assert json.loads(path.read_text())["number_traces"] == len(pos) + len(neg)


@pytest.mark.skipif(not BENCH.exists(), reason="shared benchmarks absent")
def test_benchmark_files_load():
    files = sorted((BENCH / "dev").glob("*/*.json"))[::25]
    assert files
    for path in files:
        s = load_sample(path)
        doc = json.loads(path.read_text())
        assert len(s.positive) == len(doc["positive_traces"]) and s.propositions == tuple(doc["atomic_propositions"])
        assert sample_to_document(s)["positive_traces"] == [{p: [int(v) for v in t[p]] for p in s.propositions}
                                                             for t in doc["positive_traces"]]


def test_a_sample_of_infinite_traces_is_refused_not_learned_as_finite():
    import pytest as _pytest

    from symlearn.data.ltl_samples import parse_sample
    from symlearn.errors import DataError as _DataError

    document = {"atomic_propositions": ["a"], "positive_traces": [{"a": [1]}], "negative_traces": [{"a": [0]}],
                "trace_type": "infinite"}
    with _pytest.raises(_DataError, match='trace_type: "infinite" traces are not read'):
        parse_sample(document)
    assert parse_sample({**document, "trace_type": "finite"}).positive == ((frozenset({"a"}),),)


def test_traces_written_as_lists_of_steps_and_their_propositions_inferred(tmp_path):
    """The form symlearn's traces files and ``automaton explain --trace`` use: each trace a list of
    steps, each step the propositions true there; ``atomic_propositions`` is then optional."""
    doc = {"positive_traces": [[["a"], ["b"]], [["a", "c"], []]], "negative_traces": [[["b"]]]}
    s = load_sample(_write(tmp_path, doc))
    assert s.propositions == ("a", "b", "c")
    assert s.positive == ((frozenset({"a"}), frozenset({"b"})), (frozenset({"a", "c"}), frozenset()))
    # the two forms mix once the names are declared
    mixed = parse_sample(_doc(negative_traces=[[["b"]], {"a": [0, 1], "b": [1, 1]}]))
    assert mixed.negative == ((frozenset({"b"}),), (frozenset({"b"}), frozenset({"a", "b"})))


@pytest.mark.parametrize("doc, message, needle", [
    ({"atomic_propositions": ["a"], "positive_traces": [[["a"], ["c"]]], "negative_traces": [[[]]]},
     "positive_traces[0][1][0]: unknown proposition 'c'", '"c"'),
    ({"positive_traces": [[["a"], "b"]], "negative_traces": [[[]]]},
     "positive_traces[0][1]: expected a list of the propositions true at this step", '"b"'),
    ({"positive_traces": [[["a"]]], "negative_traces": [[]]}, "negative_traces[0]: empty trace", "[]]"),
    ({"positive_traces": [{"a": [1]}], "negative_traces": [[["a"]]]}, "missing key 'atomic_propositions'", "{"),
])
def test_bad_step_lists_are_located(tmp_path, doc, message, needle):
    path = _write(tmp_path, json.dumps(doc))
    with pytest.raises(DataError) as info:
        load_sample(path)
    assert message in str(info.value)
    text = path.read_text()
    assert text[info.value.column - 1:].startswith(needle), (info.value.column, text)
