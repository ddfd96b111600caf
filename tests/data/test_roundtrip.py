"""Both file formats give back exactly what was saved (property-based)."""

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from symlearn.data import Demonstrations, Trajectory, load
from symlearn.errors import DataError

from demo_strategies import demonstrations

ROUND_TRIP = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@ROUND_TRIP
@given(demonstrations(kinds=("discrete", "vector", "features", "symbol")))
def test_jsonl_round_trip_is_exact(tmp_path, demos):
    path = tmp_path / "d.jsonl"
    demos.save(path)
    again = load(path)
    assert again == demos
    assert [t.states.dtype for t in again if hasattr(t.states, "dtype")] == \
           [t.states.dtype for t in demos if hasattr(t.states, "dtype")]


@ROUND_TRIP
@given(demonstrations())
def test_npz_round_trip_is_exact(tmp_path, demos):
    path = tmp_path / "d.npz"
    demos.save(path)
    assert load(path) == demos


@ROUND_TRIP
@given(demonstrations(kinds=("discrete", "vector", "symbol")))
def test_conversion_between_formats_keeps_everything(tmp_path, demos):
    demos.save(tmp_path / "a.jsonl")
    load(tmp_path / "a.jsonl").save(tmp_path / "b.npz")
    load(tmp_path / "b.npz").save(tmp_path / "c.jsonl")
    assert load(tmp_path / "c.jsonl") == demos


def test_float_bits_survive_jsonl(tmp_path):
    values = np.array([[0.1, 1 / 3], [np.nextafter(1.0, 2.0), -0.0]])
    demos = Demonstrations([Trajectory(values, actions=[0, 1])])
    demos.save(tmp_path / "f.jsonl")
    back = load(tmp_path / "f.jsonl")[0].states
    assert back.tobytes() == values.tobytes()


def test_images_are_refused_by_jsonl_with_a_hint(tmp_path):
    demos = Demonstrations([Trajectory(np.zeros((2, 4, 4), dtype=np.uint8))])
    with pytest.raises(DataError, match="npz"):
        demos.save(tmp_path / "img.jsonl")
    assert not (tmp_path / "img.jsonl").exists()


def test_jsonl_is_readable_text_with_a_versioned_header(tmp_path):
    demos = Demonstrations([Trajectory([0, 1], ["go(north)"], labels=[[], ["goal"]])], metadata={"env": "toy"})
    demos.save(tmp_path / "d.jsonl")
    lines = (tmp_path / "d.jsonl").read_text().splitlines()
    header = json.loads(lines[0])
    assert header["symlearn"] == "demonstrations" and header["format_version"] == 1
    assert header["metadata"] == {"env": "toy"}
    assert json.loads(lines[1]) == {"states": [0, 1], "actions": ["go(north)"], "labels": [[], ["goal"]]}


def test_npz_never_needs_pickle(tmp_path):
    demos = Demonstrations([Trajectory([{"x": 1.5, "mode": "fast"}, {"x": 2.0, "mode": "slow"}], [0],
                                       labels=[["a"], []], info={"k": [1, 2]})])
    demos.save(tmp_path / "d.npz")
    with np.load(tmp_path / "d.npz", allow_pickle=False) as archive:
        for name in archive.files:
            assert archive[name].dtype != object


def test_a_save_that_fails_midway_keeps_the_old_file(tmp_path, monkeypatch):
    import symlearn.data.jsonl_format as jsonl_format

    path = tmp_path / "d.jsonl"
    Demonstrations([Trajectory([0, 1], [1])]).save(path)
    before = path.read_bytes()
    real_dumps, calls = json.dumps, []

    def dumps_then_fail(*args, **kwargs):  # the header is written, then the disk "fills up"
        calls.append(1)
        if len(calls) > 1:
            raise OSError(28, "No space left on device")
        return real_dumps(*args, **kwargs)

    monkeypatch.setattr(jsonl_format.json, "dumps", dumps_then_fail)
    with pytest.raises(OSError):
        Demonstrations([Trajectory([5, 6, 7], [1, 2])]).save(path)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["d.jsonl"]  # no temporary file left behind


@pytest.mark.parametrize("suffix", [".jsonl", ".npz"])
@pytest.mark.parametrize("where, demos", [
    ("metadata['note']", Demonstrations([Trajectory(states=[0, 1], actions=["a"])], metadata={"note": "x\ud800"})),
    ("trajectory 0, actions[0]", Demonstrations([Trajectory(states=[0, 1], actions=["go\udcff"])])),
    ("trajectory 0, labels[1][0]", Demonstrations([Trajectory(states=[0, 1], actions=["a"], labels=[[], ["k\udc80"]])])),
    ("trajectory 0, info key", Demonstrations([Trajectory(states=[0, 1], actions=["a"], info={"w\udc80": 1})])),
])
def test_text_no_reader_takes_back_is_refused_before_writing(tmp_path, suffix, where, demos):
    """A lone surrogate (Python's reading of bytes that are not UTF-8) is refused by every reader;
    a save that wrote one would lose the data, so the writer refuses first, naming where it is,
    and an older file at the path stays as it was."""
    path = tmp_path / f"d{suffix}"
    old = Demonstrations([Trajectory(states=[0, 1], actions=["a"])])
    old.save(path)
    with pytest.raises(DataError, match="lone surrogate") as raised:
        demos.save(path)
    assert where in str(raised.value)
    assert load(path) == old
