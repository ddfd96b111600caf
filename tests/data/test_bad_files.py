"""Malformed demonstration files are refused with file, line and column."""

import io
import json
import zipfile

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory, load
from symlearn.errors import DataError, ParseError, SymlearnError

HEADER = json.dumps({"symlearn": "demonstrations", "format_version": 1, "state_kind": "discrete",
                     "state_dtype": "int64", "action_kind": "discrete", "action_dtype": "int64", "metadata": {}})


def write(tmp_path, text, name="d.jsonl"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    "body, line, column, message",
    [
        ('{"states": [0, 1], "actions": [1}', 2, 33, "invalid JSON"),
        ('{"states": [0, 1], "action": [1]}', 2, 20, "unknown key 'action'"),
        ('{"actions": [1]}', 2, 1, "no 'states'"),
        ('[0, 1]', 2, 1, "must be a JSON object"),
        ('{"states": [0, 1], "actions": [1, 1, 1]}', 2, 20, "mismatched lengths: 3 actions for 2 states"),
        ('{"states": [0.5, 1], "actions": [1]}', 2, 2, "integer ids"),
        ('{"states": [0, 1], "rewards": [NaN]}', 2, 32, "non-finite number NaN"),
        ('{"states": 3}', 2, 2, "'states' must be a list"),
        ('{"states": [0, 1], "labels": ["a", "b"]}', 2, 20, "labels at step 0"),
        ('{"states": [0, 1]}\n{"states": [0, 1], "actions": [0], "rewards": [1, 2]}', 3, 36, "2 rewards"),
    ],
)
def test_jsonl_errors_name_line_and_column(tmp_path, body, line, column, message):
    path = write(tmp_path, HEADER + "\n" + body + "\n")
    with pytest.raises(SymlearnError, match=message) as info:
        load(path)
    err = info.value
    assert (err.file, err.line, err.column) == (str(path), line, column)
    assert str(err).startswith(f"{path}:{line}:{column}: ")


def test_jsonl_header_problems(tmp_path):
    with pytest.raises(DataError, match="file is empty") as info:
        load(write(tmp_path, "\n\n"))
    assert info.value.file
    with pytest.raises(DataError, match="missing header") as info:
        load(write(tmp_path, '{"states": [0]}\n'))
    assert (info.value.line, info.value.column) == (1, 1)
    newer = HEADER.replace('"format_version": 1', '"format_version": 7')
    with pytest.raises(DataError, match="newer than this symlearn"):
        load(write(tmp_path, newer + "\n" + '{"states": [0]}\n'))
    with pytest.raises(DataError, match="unknown state_kind 'pixels'"):
        load(write(tmp_path, HEADER.replace('"state_kind": "discrete"', '"state_kind": "pixels"') + "\n"))
    with pytest.raises(DataError, match="no trajectories after the header"):
        load(write(tmp_path, HEADER + "\n"))
    with pytest.raises(ParseError, match="invalid JSON") as info:
        load(write(tmp_path, "{oops\n"))
    assert (info.value.line, info.value.column) == (1, 2)


def test_jsonl_inconsistent_trajectories_name_the_file(tmp_path):
    text = HEADER + "\n" + '{"states": [0, 1], "actions": [0]}\n{"states": [0, 1]}\n'
    with pytest.raises(DataError, match="trajectory 1 has no actions") as info:
        load(write(tmp_path, text))
    assert info.value.file == str(tmp_path / "d.jsonl")


def test_jsonl_kind_must_match_header(tmp_path):
    text = HEADER + "\n" + '{"states": ["a", "b"], "actions": [0]}\n'
    with pytest.raises(DataError, match="must be numbers for discrete states") as info:
        load(write(tmp_path, text))
    assert info.value.line == 2


def test_not_utf8(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_bytes(b"\xff\xfe\x00bad")
    with pytest.raises(ParseError, match="not UTF-8"):
        load(path)


def test_unknown_suffix_missing_file_and_directory(tmp_path):
    with pytest.raises(DataError, match="unknown demonstrations format '.csv'"):
        load(tmp_path / "x.csv")
    with pytest.raises(DataError, match="no such file"):
        load(tmp_path / "missing.jsonl")
    (tmp_path / "dir.npz").mkdir()
    with pytest.raises(DataError, match="is a directory"):
        load(tmp_path / "dir.npz")


def _npz(tmp_path, **arrays):
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    path = tmp_path / "d.npz"
    path.write_bytes(buffer.getvalue())
    return path


def test_npz_errors(tmp_path):
    path = tmp_path / "d.npz"
    path.write_text("not a zip")
    with pytest.raises(DataError, match="not a readable NPZ file"):
        load(path)
    with pytest.raises(DataError, match="lacks member '__meta__'"):
        load(_npz(tmp_path, lengths=np.array([1])))
    with pytest.raises(DataError, match="bad __meta__"):
        load(_npz(tmp_path, __meta__=np.asarray('{"hello": 1}')))
    with pytest.raises(DataError, match="dtype '\\|O'"):  # object arrays need pickle: refused from the header
        load(_npz(tmp_path, __meta__=np.array([{"a": 1}], dtype=object)))


def test_npz_truncated_member_is_reported(tmp_path):
    demos = Demonstrations([Trajectory([0, 1, 2], [1, 1])])
    demos.save(tmp_path / "good.npz")
    with np.load(tmp_path / "good.npz", allow_pickle=False) as archive:
        arrays = {k: archive[k] for k in archive.files}
    arrays["states"] = arrays["states"][:2]
    with pytest.raises(DataError, match="member 'states' has 2 rows, expected 3"):
        load(_npz(tmp_path, **arrays))
    arrays = {**arrays, "states": np.array([0, 1, 2]), "lengths": np.array([0])}
    with pytest.raises(DataError, match="'lengths' must be positive"):
        load(_npz(tmp_path, **arrays))


def test_npz_pickled_payload_is_never_unpickled(tmp_path):
    path = tmp_path / "evil.npz"
    with zipfile.ZipFile(path, "w") as archive:
        buffer = io.BytesIO()
        np.save(buffer, np.array([object()], dtype=object), allow_pickle=True)
        archive.writestr("__meta__.npy", buffer.getvalue())
    with pytest.raises(DataError):
        load(path)
