"""Killing the driver: the store stays valid, the re-run skips the finished cells."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest

from symlearn.errors import DataError
from symlearn.sweep.store import ResultsStore, read_records
from sweep_helpers import HERE, records


def _wait_for(condition, seconds: float = 60.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError("timed out waiting")
        time.sleep(0.05)


def _lines(path: Path) -> list[str]:
    return path.read_text().splitlines() if path.exists() else []


def test_driver_killed_halfway_then_resumed_runs_only_the_rest(write_sweep, tmp_path):
    log = tmp_path / "executions.log"
    path = write_sweep("logged", {"x": list(range(8))}, fixed={"log": str(log), "delay": 0.3}, seeds=2)
    out = tmp_path / "out"
    command = [sys.executable, str(HERE / "cli_harness.py"), "sweep", "run", str(path), "--out", str(out),
               "--local", "--workers", "2", "--quiet"]
    driver = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        _wait_for(lambda: len(_lines(out / "results.jsonl")) >= 5)
        driver.send_signal(signal.SIGKILL)
        driver.wait(timeout=30)
    finally:
        if driver.poll() is None:
            driver.kill()
    # the workers notice and end: the executions log stops growing
    time.sleep(1.5)
    settled = len(_lines(log))
    time.sleep(1.0)
    assert len(_lines(log)) == settled
    before = read_records(out)  # every line whole JSON (a torn last line would be skipped)
    assert all(json.loads(line) for line in _lines(out / "results.jsonl"))
    finished_before = {(r["params"]["x"], r["seed"]) for r in before if r["status"] == "ok"}
    assert 5 <= len(finished_before) < 16
    ran_before = len(_lines(log))

    done = subprocess.run(command[:-1] + ["--json"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    summary = json.loads(done.stdout)
    assert summary["skipped"] == len(finished_before)
    assert summary["finished"] == 16 - len(finished_before)
    # no finished cell ran again; every cell has exactly one ok record
    rerun = [tuple(map(int, line.split())) for line in _lines(log)[ran_before:]]
    assert not set(rerun) & finished_before
    assert len(rerun) == 16 - len(finished_before)
    ok = Counter((r["params"]["x"], r["seed"]) for r in records(out) if r["status"] == "ok")
    assert len(ok) == 16 and set(ok.values()) == {1}


def test_a_torn_last_line_is_skipped_and_cut_before_the_next_append(tmp_path):
    out = tmp_path / "out"
    with ResultsStore(out, "f" * 64, {"spec": {}}) as store:
        store.append({"cell": "a", "status": "ok", "metrics": {"v": 1}})
    with open(out / "results.jsonl", "ab") as handle:
        handle.write(b'{"cell": "b", "status": "o')  # the driver died in this write
    assert [r["cell"] for r in read_records(out)] == ["a"]
    with ResultsStore(out, "f" * 64, {"spec": {}}) as store:
        assert store.finished() == {"a"}
        store.append({"cell": "c", "status": "ok", "metrics": {"v": 3}})
    assert [json.loads(line)["cell"] for line in _lines(out / "results.jsonl")] == ["a", "c"]


def test_a_damaged_line_in_the_middle_is_located(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.jsonl").write_text('{"cell": "a", "status": "ok"}\n{"cell": \n{"cell": "b", "status": "ok"}\n')
    with pytest.raises(DataError) as error:
        read_records(out)
    assert error.value.line == 2


def test_two_drivers_cannot_write_one_folder(tmp_path):
    out = tmp_path / "out"
    with ResultsStore(out, "f" * 64, {"spec": {}}):
        with pytest.raises(DataError, match="another 'symlearn sweep run' is writing"):
            ResultsStore(out, "f" * 64, {"spec": {}})
    ResultsStore(out, "f" * 64, {"spec": {}}).close()  # released with the first


def test_appended_records_survive_as_strict_json(tmp_path):
    out = tmp_path / "out"
    with ResultsStore(out, "f" * 64, {"spec": {}}) as store:
        with pytest.raises(ValueError):
            store.append({"cell": "a", "status": "ok", "metrics": {"v": float("nan")}})
    assert os.path.getsize(out / "results.jsonl") == 0


def test_leftovers_of_a_killed_embedded_ray_are_ended_and_nothing_else(tmp_path):
    """Ray's agents outlive a SIGKILLed driver; the next run ends the processes that carry the
    recorded node id in their environment, and leaves every other process alone."""
    from symlearn.sweep.ray_pool import NODE_FILE, _start_time, end_leftovers

    gone = subprocess.Popen(["sleep", "60"])
    gone_start = _start_time(gone.pid)
    gone.kill()
    gone.wait()  # the "driver": dead (its pid may be another process's by now: the start time tells)
    leftover = subprocess.Popen(["sleep", "60"], env={**os.environ, "RAY_NODE_ID": "feedbeef"})
    bystander = subprocess.Popen(["sleep", "60"], env={**os.environ, "RAY_NODE_ID": "other"})
    try:
        (tmp_path / NODE_FILE).write_text(json.dumps({"node_id": "feedbeef", "driver": gone.pid,
                                                      "driver_start": gone_start}))
        assert end_leftovers(tmp_path) == [leftover.pid]
        assert leftover.wait(timeout=10) == -signal.SIGKILL
        assert bystander.poll() is None
        assert not (tmp_path / NODE_FILE).exists()
        # a record of a driver that is still running is left alone
        (tmp_path / NODE_FILE).write_text(json.dumps({"node_id": "other", "driver": bystander.pid,
                                                      "driver_start": _start_time(bystander.pid)}))
        assert end_leftovers(tmp_path) == [] and bystander.poll() is None
        # a driver's pid now held by another process (pids are reused) counts as ended
        (tmp_path / NODE_FILE).write_text(json.dumps({"node_id": "nobody", "driver": bystander.pid,
                                                      "driver_start": _start_time(bystander.pid) - 1}))
        assert end_leftovers(tmp_path) == [] and not (tmp_path / NODE_FILE).exists()
        assert bystander.poll() is None
    finally:
        for process in (leftover, bystander):
            if process.poll() is None:
                process.kill()
                process.wait()


def test_ctrl_c_loses_only_the_cells_in_flight(write_sweep, tmp_path):
    log = tmp_path / "executions.log"
    # 16 cells of 0.4 s on 2 workers: the driver cannot finish before the interrupt even when a
    # loaded machine polls the results file late (with 6 cells it did once, and exited 0)
    path = write_sweep("logged", {"x": list(range(16))}, fixed={"log": str(log), "delay": 0.4}, seeds=1)
    out = tmp_path / "out"
    command = [sys.executable, str(HERE / "cli_harness.py"), "sweep", "run", str(path), "--out", str(out),
               "--local", "--workers", "2", "--quiet"]
    # SIGINT at its default in the driver: a pytest-xdist worker ignores it, and a child inherits
    # an ignored SIGINT (Python then installs no KeyboardInterrupt handler and the run completes)
    driver = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                              preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        _wait_for(lambda: len(_lines(out / "results.jsonl")) >= 2)
        driver.send_signal(signal.SIGINT)
        assert driver.wait(timeout=30) == 130
    finally:
        if driver.poll() is None:
            driver.kill()
    assert "interrupted" in driver.stderr.read()
    finished = {r["params"]["x"] for r in read_records(out) if r["status"] == "ok"}
    started = {int(line.split()[0]) for line in _lines(log)}
    assert len(started - finished) <= 2  # at most the two cells in flight were lost
    time.sleep(1.0)
    assert {int(line.split()[0]) for line in _lines(log)} == started  # the workers were stopped
