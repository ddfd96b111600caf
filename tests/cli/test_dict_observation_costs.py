"""A DNF learned from a Dict-observing environment's demonstrations constrains training there.

``record`` stores a ``Dict(floor=Discrete, door=Discrete)`` observation as the named values
``{floor: 2, door: 0}``, so ``learn dnf`` learns rules over ``floor`` and ``door``; the policy sees
the one-hot flattening (4 + 2 columns). Before, ``train --cost`` said the environment "names no
features", and ``--features floor,door`` was refused for 6 columns."""

import json

import pytest

from cli_runner import run
from dict_lift_env import DICT_ROBOT

pytest.importorskip("gymnasium")


def test_dnf_of_dict_observations_trains_there(capsys, tmp_path, monkeypatch):
    import gymnasium

    (tmp_path / "lift_lab.py").write_text(DICT_ROBOT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import lift_lab  # noqa: F401 -- registers DictLift-v0

    from symlearn.data import record

    plan = iter([1, 1, 1, 0] * 6)
    record(gymnasium.make("DictLift-v0"), lambda obs: next(plan), 6, seed=0).save(tmp_path / "lift.jsonl")
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
