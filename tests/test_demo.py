import json
from pathlib import Path

from symlearn.demo import run_demo
from symlearn.demo.registry import pipelines


def test_demo_command_writes_a_report(run_cli, tmp_path):
    out = tmp_path / "report"
    result = run_cli("demo", "--quick", "--out", out, "--only", "demonstrations", "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert (out / "summary.md").is_file() and (out / "summary.json").is_file()
    entry = summary["pipelines"][0]
    assert entry["name"] == "demonstrations"
    figures = entry["figures"]
    assert figures["round_trip_exact"] is True
    assert figures["expert_success_rate"] > figures["random_success_rate"]
    for name in entry["files"]:
        assert (out / name).is_file(), name
    assert "digraph" in (out / "frozenlake_visits.dot").read_text()
    assert "FrozenLake" in (out / "summary.md").read_text()


def test_demo_rejects_unknown_pipeline(run_cli, tmp_path):
    result = run_cli("demo", "--only", "nonsense", "--out", tmp_path)
    assert result.returncode == 2 and "unknown demo pipeline 'nonsense'" in result.stderr


#: pipelines run (in their quick setting) by a test module of their own, tests/demo/test_<name>_pipeline.py
OWN_TESTS = {path.stem[len("test_"):-len("_pipeline")] for path in (Path(__file__).parent / "demo").glob("test_*_pipeline.py")}


def test_every_registered_pipeline_runs_quickly(tmp_path):
    """The runner on every pipeline that no test module of its own runs (those are run there, not
    twice): sections, files and summary for each."""
    names = [p.name for p in pipelines()]
    assert OWN_TESTS <= set(names), f"tests/demo names pipelines that do not exist: {OWN_TESTS - set(names)}"
    rest = [name for name in names if name not in OWN_TESTS]
    assert rest, "every pipeline has its own test module: run one of them here so the runner is covered"
    summary = run_demo(tmp_path, only=rest, quick=True)
    assert [p["name"] for p in summary["pipelines"]] == rest
    for entry in summary["pipelines"]:
        assert entry["files"], f"{entry['name']} wrote no files"
        for name in entry["files"]:
            assert (tmp_path / name).exists()
    assert json.loads((tmp_path / "summary.json").read_text())["pipelines"] == summary["pipelines"]
