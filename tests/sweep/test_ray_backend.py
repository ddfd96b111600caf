"""The Ray executor, on one Ray session for the whole module (starting Ray takes seconds); the
logic shared with ``--local`` is tested there."""

from __future__ import annotations

import json
from collections import Counter

import pytest

from sweep_helpers import records

ray = pytest.importorskip("ray")


@pytest.fixture(scope="module", autouse=True)
def ray_session():
    from symlearn.sweep.ray_pool import EMBEDDED_OBJECT_STORE_BYTES

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level="ERROR",
             object_store_memory=EMBEDDED_OBJECT_STORE_BYTES)
    yield
    ray.shutdown()


def test_ray_run_retries_a_killed_worker_records_errors_and_resumes(write_sweep, cli, tmp_path):
    markers = tmp_path / "markers"
    markers.mkdir()
    path = write_sweep("dies_once", {"x": [1, 2, 3]}, fixed={"marker_dir": str(markers)}, seeds=1)
    out = tmp_path / "out"
    code, stdout, stderr = cli("sweep", "run", path, "--out", out, "--workers", "2", "--json")
    assert code == 0, stderr
    doc = json.loads(stdout)
    assert (doc["backend"], doc["finished"], doc["retried"]) == ("ray", 3, 3)
    found = records(out)
    assert Counter(r["status"] for r in found) == {"crash": 3, "ok": 3}
    assert sorted(r["metrics"]["value"] for r in found if r["status"] == "ok") == [1, 2, 3]
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--json")
    assert (code, json.loads(stdout)["skipped"]) == (0, 3)
    assert len(records(out)) == 6


def test_ray_cancels_a_cell_past_its_time_limit(write_sweep, cli, tmp_path):
    markers = tmp_path / "markers"
    markers.mkdir()
    # 5 s: the retry must start a Ray worker and import the experiment within it, which took more
    # than 2 s on a saturated machine
    path = write_sweep("hangs_once", {"x": [1]}, fixed={"marker_dir": str(markers)}, seeds=1,
                       extra="timeout = 5.0")
    out = tmp_path / "out"
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--json")
    assert code == 0 and json.loads(stdout)["seconds"] < 40
    assert [r["status"] for r in records(out)] == ["timeout", "ok"]


def test_ray_raising_cell_has_its_traceback_in_the_store(write_sweep, cli, tmp_path):
    path = write_sweep("sometimes_raises", {"x": [3]}, seeds=1, extra="retries = 0")
    out = tmp_path / "out"
    code, stdout, stderr = cli("sweep", "run", path, "--out", out)
    assert code == 2 and "Traceback" not in stdout + stderr
    assert "raise ValueError" in records(out)[0]["error"]["traceback"]
