"""benchmarks/safety_gym_{record,crosscheck}.py without Safety-Gymnasium (a peer, never imported here).

The recorder runs under a separate Python 3.10 and cannot import the symlearn package, so it loads
SafeNav's lidar module from the checkout by path; these tests check that it computes exactly the
library's lidar that way, and that the driver skips cleanly when the peer interpreter is missing.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

from symlearn.envs.safenav.lidar import pseudo_lidar

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _load(name: str, monkeypatch):
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, name, module)  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


def test_recorder_lidar_is_safenav_lidar(monkeypatch):
    recorder = _load("safety_gym_record", monkeypatch)  # numpy only at import time: safety_gymnasium is imported in record()
    rng = np.random.default_rng(0)
    for _ in range(200):
        x, y = rng.uniform(-2, 2, size=2)
        heading = rng.uniform(-4, 4)
        hazards = rng.uniform(-2, 2, size=(8, 2))
        expected = pseudo_lidar(x, y, heading, hazards, 0.2)
        assert np.array_equal(recorder.pseudo_lidar(x, y, heading, hazards, 0.2), expected)


def test_crosscheck_skips_without_the_peer(tmp_path, capsys, monkeypatch):
    crosscheck = _load("safety_gym_crosscheck", monkeypatch)
    out = tmp_path / "result.json"
    assert crosscheck.main(["--python", str(tmp_path / "no-python"), "--json", str(out)]) == 0
    assert "skipped" in capsys.readouterr().out
    assert not out.exists()
