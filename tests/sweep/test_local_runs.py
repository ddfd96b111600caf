"""``symlearn sweep run --local``: records, retries, crashes, timeouts, resuming, foreign folders."""

from __future__ import annotations

import json
from collections import Counter

from sweep_helpers import records


def test_run_records_every_cell_once_and_a_rerun_skips_them(write_sweep, cli, tmp_path):
    path = write_sweep("square", {"x": [1, 2, 3]}, seeds=2)
    out = tmp_path / "out"
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--local", "--workers", "2", "--json")
    assert code == 0
    doc = json.loads(stdout)
    assert (doc["cells"], doc["finished"], doc["skipped"], doc["failed"]) == (6, 6, 0, 0)
    first = records(out)
    assert sorted((r["params"]["x"], r["seed"]) for r in first) == [(x, s) for x in (1, 2, 3) for s in (0, 1)]
    assert all(r["status"] == "ok" and r["metrics"]["value"] == r["params"]["x"] ** 2 + r["seed"] for r in first)
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--local", "--json")
    doc = json.loads(stdout)
    assert (code, doc["finished"], doc["skipped"], doc["attempts"]) == (0, 0, 6, 0)
    assert records(out) == first  # nothing re-run, nothing appended


def test_cells_are_deterministic_and_global_generators_seeded(write_sweep, cli, tmp_path):
    path = write_sweep("global_random", {"x": [1, 2]}, seeds=2)
    for out in ("a", "b"):
        assert cli("sweep", "run", path, "--out", tmp_path / out, "--local", "--workers", "2")[0] == 0
    metrics = {out: {(r["params"]["x"], r["seed"]): r["metrics"] for r in records(tmp_path / out)} for out in "ab"}
    assert metrics["a"] == metrics["b"]
    # the same seed gives the same draws whatever the other parameters; another seed others
    assert metrics["a"][(1, 0)] == metrics["a"][(2, 0)]
    assert metrics["a"][(1, 0)]["python"] != metrics["a"][(1, 1)]["python"]


def test_a_raising_cell_is_recorded_with_its_traceback_and_retried(write_sweep, cli, tmp_path):
    path = write_sweep("sometimes_raises", {"x": [1, 3]}, seeds=1, extra="retries = 2")
    out = tmp_path / "out"
    code, stdout, stderr = cli("sweep", "run", path, "--out", out, "--local", "--workers", "1")
    assert code == 2
    assert "1 of 2 cells failed" in stderr
    assert "Traceback" not in stdout + stderr  # the traceback is in the store, not on the terminal
    bad = [r for r in records(out) if r["params"]["x"] == 3]
    assert [r["attempt"] for r in bad] == [1, 2, 3]
    assert all(r["status"] == "error" and r["error"]["type"] == "ValueError" for r in bad)
    assert "raise ValueError" in bad[0]["error"]["traceback"] and "cells.py" in bad[0]["error"]["traceback"]
    # --retries overrides the file; a re-run tries the failed cell again, not the finished one
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--local", "--retries", "0", "--json")
    doc = json.loads(stdout)
    assert (code, doc["skipped"], doc["attempts"], doc["failed"]) == (2, 1, 1, 1)
    assert [r["attempt"] for r in records(out) if r["params"]["x"] == 3][-1] == 4


def test_a_killed_worker_costs_one_attempt_and_no_record_is_lost_or_duplicated(write_sweep, cli, tmp_path):
    markers = tmp_path / "markers"
    markers.mkdir()
    path = write_sweep("dies_once", {"x": [1, 2, 3]}, fixed={"marker_dir": str(markers)}, seeds=2)
    out = tmp_path / "out"
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--local", "--workers", "2", "--json")
    assert code == 0 and json.loads(stdout)["retried"] == 6
    found = records(out)
    by_status = Counter(r["status"] for r in found)
    assert by_status == {"crash": 6, "ok": 6}
    ok = [r["cell"] for r in found if r["status"] == "ok"]
    assert len(ok) == len(set(ok)) == 6
    crash = next(r for r in found if r["status"] == "crash")
    assert "SIGKILL" in crash["error"]["message"] and crash["attempt"] == 1


def test_a_cell_past_its_time_limit_is_stopped_recorded_and_retried(write_sweep, cli, tmp_path):
    markers = tmp_path / "markers"
    markers.mkdir()
    path = write_sweep("hangs_once", {"x": [1]}, fixed={"marker_dir": str(markers)}, seeds=1,
                       extra="timeout = 1.0")
    out = tmp_path / "out"
    code, stdout, _ = cli("sweep", "run", path, "--out", out, "--local", "--json")
    doc = json.loads(stdout)
    assert code == 0 and doc["seconds"] < 30
    assert [r["status"] for r in records(out)] == ["timeout", "ok"]
    assert "time limit of 1 s" in records(out)[0]["error"]["message"]


def test_a_folder_of_another_sweep_is_refused_unless_forced(write_sweep, cli, tmp_path):
    out = tmp_path / "out"
    first = write_sweep("square", {"x": [1, 2]}, seeds=1, name="first.toml")
    assert cli("sweep", "run", first, "--out", out, "--local")[0] == 0
    other = write_sweep("square", {"x": [1, 2, 3]}, seeds=1, name="other.toml")
    code, stdout, stderr = cli("sweep", "run", other, "--out", out, "--local", "--json")
    assert code == 2
    assert "holds the results of another sweep" in stderr and "first.toml" in stderr
    assert json.loads(stdout)["error"]["hint"].count("--force") == 1
    assert len(records(out)) == 2
    # forced: the two cells the files share are kept, only x = 3 runs
    code, stdout, _ = cli("sweep", "run", other, "--out", out, "--local", "--force", "--json")
    doc = json.loads(stdout)
    assert (code, doc["skipped"], doc["finished"]) == (0, 2, 1)


def test_a_non_empty_folder_without_a_sweep_is_refused(write_sweep, cli, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    path = write_sweep("square", {"x": [1]}, seeds=1)
    code, _, stderr = cli("sweep", "run", path, "--out", out, "--local")
    assert code == 2 and "not empty" in stderr
    assert sorted(p.name for p in out.iterdir() if p.name != ".lock") == ["thesis.tex"]


def test_a_result_that_is_not_a_mapping_or_lacks_a_metric_is_an_error_record(write_sweep, cli, tmp_path):
    path = write_sweep("returns_text", {"x": [1]}, seeds=1, extra="retries = 0")
    assert cli("sweep", "run", path, "--out", tmp_path / "a", "--local")[0] == 2
    assert "not a mapping" in records(tmp_path / "a")[0]["error"]["message"]
    path = write_sweep("square", {"x": [1]}, seeds=1, extra='retries = 0\nmetrics = ["valeu"]', name="m.toml")
    assert cli("sweep", "run", path, "--out", tmp_path / "b", "--local")[0] == 2
    assert "no metric 'valeu'" in records(tmp_path / "b")[0]["error"]["message"]


def test_metrics_keep_only_the_named_keys(write_sweep, cli, tmp_path):
    path = write_sweep("square", {"x": [2]}, seeds=1, extra='metrics = ["value"]')
    assert cli("sweep", "run", path, "--out", tmp_path / "o", "--local")[0] == 0
    assert records(tmp_path / "o")[0]["metrics"] == {"value": 4}


def test_without_ray_the_error_says_to_install_the_sweep_extra(write_sweep, cli, tmp_path, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    path = write_sweep("square", {"x": [1]}, seeds=1)
    code, stdout, stderr = cli("sweep", "run", path, "--out", tmp_path / "o", "--json")
    assert code == 2
    assert "install the sweep extra" in stderr and "--local" in stderr
    assert json.loads(stdout)["error"]["kind"] == "MissingDependencyError"
    assert not (tmp_path / "o").exists()  # refused before anything was written


def test_bad_flags(write_sweep, cli, tmp_path):
    path = write_sweep("square", {"x": [1]}, seeds=1)
    code, _, stderr = cli("sweep", "run", path, "--local", "--workers", "0")
    assert code == 2 and "--workers must be at least 1" in stderr


def test_default_folder_is_beside_the_file(write_sweep, cli, tmp_path):
    path = write_sweep("square", {"x": [1]}, seeds=1, name="grid.toml")
    assert cli("sweep", "run", path, "--local")[0] == 0
    assert len(records(tmp_path / "grid-results")) == 1


def test_a_command_cell_reads_its_json_output(cli, tmp_path):
    path = tmp_path / "cmd.toml"
    path.write_text('[sweep]\ncommand = ["symlearn", "ltl", "parse", "{formula}", "--json"]\nseeds = 1\n'
                    'metrics = ["size", "propositions.0"]\n[grid]\nformula = ["F a", "a U (b & c)"]\n')
    out = tmp_path / "out"
    code, _, stderr = cli("sweep", "run", path, "--out", out, "--local", "--workers", "2")
    assert code == 0, stderr
    found = {r["params"]["formula"]: r["metrics"] for r in records(out)}
    assert found == {"F a": {"size": 2, "propositions.0": "a"}, "a U (b & c)": {"size": 5, "propositions.0": "a"}}


def test_a_failing_command_is_an_error_record_with_its_stderr(cli, tmp_path):
    path = tmp_path / "cmd.toml"
    path.write_text('[sweep]\ncommand = ["symlearn", "ltl", "parse", "{formula}", "--json"]\nseeds = 1\n'
                    'retries = 0\n[grid]\nformula = ["F (a"]\n')
    out = tmp_path / "out"
    assert cli("sweep", "run", path, "--out", out, "--local")[0] == 2
    error = records(out)[0]["error"]
    assert "exited with 2" in error["message"] and "symlearn: error" in error["message"]


def test_the_bar_counts_running_finished_and_failed_cells(write_sweep, tmp_path, capsys):
    from symlearn.sweep.runner import run_sweep
    from symlearn.sweep.spec import read_spec

    path = write_sweep("sometimes_raises", {"x": [1, 2, 3]}, seeds=1, extra="retries = 0")
    summary = run_sweep(read_spec(path), tmp_path / "out", backend="local", workers=1, progress=True)
    assert (summary.finished, summary.failed) == (2, 1)
    bar = capsys.readouterr().err.replace("\r", "\n")
    assert "0/3" in bar and "running 1" in bar and "finished 2, failed 1" in bar and "cell/s" in bar
