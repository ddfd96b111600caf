"""A DNF learned from a Dict-observing environment's demonstrations constrains training there.

``record`` stores a ``Dict(floor=Discrete, door=Discrete)`` observation as the named values
``{floor: 2, door: 0}``, so ``learn dnf`` learns rules over ``floor`` and ``door``; the policy sees
the one-hot flattening (4 + 2 columns). Before, ``train --cost`` said the environment "names no
features", and ``--features floor,door`` was refused for 6 columns."""

import json

import pytest

from cli_runner import run
from dict_lift_env import lift_demonstrations

pytest.importorskip("gymnasium")


def test_dnf_of_dict_observations_trains_there(capsys, tmp_path, monkeypatch):
    lift_demonstrations(tmp_path, monkeypatch, 6)
    code, out, err = run(capsys, "learn", "dnf", "--env", "lift_lab:DictLift-v0", "--demos", "lift.jsonl",
                         "-o", "lift.dnf", "--json")
    assert code == 0, err
    features = set(json.loads(out)["features"]) if "features" in json.loads(out) else None
    text = (tmp_path / "lift.dnf").read_text()
    assert "floor" in text or "door" in text, text
    code, out, err = run(capsys, "train", "--env", "lift_lab:DictLift-v0", "--algo", "ppo-lag", "--cost", "lift.dnf",
                         "--steps", 1024, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_kind"] == "dnf" and doc["multipliers"], doc
    assert doc["cost"] is None  # the environment reports no info["cost"]: n/a, never 0
    assert features is None or features <= {"floor", "door"}


def test_dnf_of_vector_dict_observations_trains_there(capsys, tmp_path, monkeypatch):
    """A Dict of vectors (pos, vel) is recorded as named columns (pos[0], ..., as Minari's reader
    names them) and train --cost reads the same names from the live observation."""
    from dict_lift_env import rover_demonstrations

    demos = rover_demonstrations(tmp_path, monkeypatch, 8)
    code, out, err = run(capsys, "learn", "dnf", "--demos", demos, "--inputs", "pos[0],pos[1]", "-o", "rover.dnf",
                         "--json")
    assert code == 0, err
    text = (tmp_path / "rover.dnf").read_text()
    assert '"pos[0]"' in text and "vel" not in text.split("\n", 3)[-1], text
    code, out, err = run(capsys, "train", "--env", "vector_rover:VectorRover-v0", "--algo", "ppo-lag",
                         "--cost", "rover.dnf", "--steps", 1024, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_kind"] == "dnf" and doc["multipliers"], doc
    assert doc["cost"] is not None   # the environment's own info["cost"] is reported beside it


def test_learn_icrl_reads_named_columns_of_a_dict_environment(capsys, tmp_path, monkeypatch):
    """Recorded columns (moving as one integer) are rebuilt into the policy's view (moving
    one-hot): before, 'observations have shape (5,), the space's is (6,)'."""
    from dict_lift_env import rover_demonstrations

    demos = rover_demonstrations(tmp_path, monkeypatch, 4)
    code, out, err = run(capsys, "learn", "icrl", "--env", "vector_rover:VectorRover-v0", "--demos", demos,
                         "--steps", 2048, "--iterations", 1, "--json")
    assert code == 0, err
    inputs = json.loads(out)["cost_inputs"]
    # the view's entries are named (pos[0], moving=1, ...), not numbered
    assert inputs["names"] and all(isinstance(n, str) for n in inputs["names"]), inputs
    assert set(inputs["names"]) <= {"moving=0", "moving=1", "pos[0]", "pos[1]", "vel[0]", "vel[1]"}
