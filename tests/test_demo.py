import json

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


def test_every_registered_pipeline_runs_quickly(tmp_path):
    names = [p.name for p in pipelines()]
    summary = run_demo(tmp_path, quick=True)
    assert [p["name"] for p in summary["pipelines"]] == names
    for entry in summary["pipelines"]:
        assert entry["files"], f"{entry['name']} wrote no files"
        for name in entry["files"]:
            assert (tmp_path / name).exists()
