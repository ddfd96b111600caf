"""``symlearn sweep report``: aggregation over seeds, tables, figures."""

from __future__ import annotations

import json
import math

import pytest

from symlearn.errors import DataError
from symlearn.sweep.statistics import bootstrap_interval, mean_se, summarize, summarize_curves


def test_mean_and_standard_error():
    mean, se = mean_se([1.0, 2.0, 3.0, 6.0])
    assert mean == 3.0
    assert se == pytest.approx(math.sqrt(((4 + 1 + 0 + 9) / 3) / 4))
    assert mean_se([5.0]) == (5.0, None)


def test_bootstrap_interval_is_seeded_and_brackets_the_mean():
    values = [0.1, 0.4, 0.35, 0.8, 0.2, 0.55]
    low, high = bootstrap_interval(values)
    assert low < sum(values) / len(values) < high
    assert bootstrap_interval(values) == (low, high)
    assert bootstrap_interval([1.0]) is None
    narrow = bootstrap_interval([v / 10 for v in values])
    assert narrow[1] - narrow[0] < high - low


def test_curves_are_cut_to_the_shortest():
    summary = summarize_curves([[1, 2, 3], [3, 4]])
    assert summary["mean"] == [2, 3] and summary["cut"] and summary["length"] == 2
    assert summarize([2.0, 4.0], interval="se")["low"] == pytest.approx(2.0)


@pytest.fixture
def finished(write_sweep, cli, tmp_path):
    """A finished local sweep over x (numeric) and delay (two values) with 3 seeds."""
    text = "[report]\nx = \"x\"\n[report.labels]\nx = \"input x (units)\"\nvalue = \"x squared plus seed\"\n"
    path = write_sweep("square", {"x": [1, 2, 3], "delay": [0.0, 0.001]}, seeds=3)
    path.write_text(path.read_text() + text)
    out = tmp_path / "out"
    assert cli("sweep", "run", path, "--out", out, "--local", "--workers", "2")[0] == 0
    return out


def test_report_tables_figures_and_summary(finished, cli):
    code, stdout, _ = cli("sweep", "report", finished)
    assert code == 0
    markdown = (finished / "report" / "report.md").read_text()
    # x = 2: values 4, 5, 6 over seeds 0..2: mean 5, standard error 1/sqrt(3)
    assert f"| 2 | 0.0 | 3 | 5.000 ± {1 / math.sqrt(3):.3f} |" in markdown
    assert "| input x (units) | delay | seeds | x squared plus seed |" in markdown
    assert "## x squared plus seed" in markdown  # the pivot: x down, delay across
    assert "| input x (units) | 0.0 | 0.001 |" in markdown
    figures = sorted(p.name for p in (finished / "report" / "figures").iterdir())
    assert figures == ["curve_curve.png", "curve_curve.svg", "value_vs_x.png", "value_vs_x.svg"]
    png = (finished / "report" / "figures" / "value_vs_x.png").read_bytes()
    svg = (finished / "report" / "figures" / "value_vs_x.svg").read_text()
    assert png.startswith(b"\x89PNG") and "input x (units)" in svg and "x squared plus seed" in svg
    assert "standard error" in svg  # the band is named on the figure
    summary = json.loads((finished / "report" / "summary.json").read_text())
    assert summary["finished"] == 18 and summary["varying"] == ["x", "delay"]
    assert summary["curves"] == ["curve"] and summary["metrics"] == ["value"]
    assert "written:" in stdout


def test_bootstrap_report_json(finished, cli):
    code, stdout, _ = cli("sweep", "report", finished, "--interval", "bootstrap", "--no-plots", "--json")
    assert code == 0
    doc = json.loads(stdout)
    row = next(r for r in doc["rows"] if r["params"] == {"x": 2, "delay": 0.0})
    stats = row["metrics"]["value"]
    assert stats["mean"] == 5.0 and 4.0 <= stats["low"] < 5.0 < stats["high"] <= 6.0
    assert doc["figures"] == [] and "markdown" not in doc


def test_bars_for_categorical_parameters_and_failed_cells_listed(write_sweep, cli, tmp_path):
    path = write_sweep("sometimes_raises", {"x": [1, 2, 3]}, fixed={}, seeds=2, extra="retries = 0")
    text = path.read_text().replace("x = [1, 2, 3]", "x = [1, 2, 3]\nbad = [3, 4]")
    path.write_text(text)
    out = tmp_path / "out"
    assert cli("sweep", "run", path, "--out", out, "--local")[0] == 2
    assert cli("sweep", "report", out)[0] == 0
    markdown = (out / "report" / "report.md").read_text()
    assert "10 of 12 cells finished, 2 failed" in markdown
    assert "x = 3 is the bad value" in markdown
    assert (out / "report" / "figures" / "value_vs_x.png").exists()


def test_report_of_a_folder_without_a_sweep(cli, tmp_path):
    code, _, stderr = cli("sweep", "report", tmp_path)
    assert code == 2 and "no sweep results folder" in stderr
    with pytest.raises(DataError):
        from symlearn.sweep.report import write_report

        write_report(tmp_path)


def test_report_plot_selects_the_figures(write_sweep, cli, tmp_path):
    path = write_sweep("square", {"x": [1, 2]}, seeds=2)
    path.write_text(path.read_text() + '[report]\nplot = ["curve"]\ncurve_x = { curve = "step (units)" }\n')
    out = tmp_path / "out"
    assert cli("sweep", "run", path, "--out", out, "--local")[0] == 0
    assert cli("sweep", "report", out)[0] == 0
    assert sorted(p.name for p in (out / "report" / "figures").iterdir()) == ["curve_curve.png", "curve_curve.svg"]
    assert "step (units)" in (out / "report" / "figures" / "curve_curve.svg").read_text()


def test_report_of_the_sweep_file_reads_its_default_results_folder(write_sweep, cli, tmp_path):
    """``sweep run FILE.toml`` writes ``FILE-results``; ``sweep report FILE.toml`` reads it (a user
    naturally gives the report the file they ran), and says so when nothing ran yet."""
    path = write_sweep("square", {"x": [1, 2]}, seeds=2)
    code, _, stderr = cli("sweep", "report", path)
    assert code == 2 and "holds no results yet" in stderr and f"sweep run {path}" in stderr
    assert cli("sweep", "run", path, "--local")[0] == 0
    code, stdout, _ = cli("sweep", "report", path, "--no-plots")
    assert code == 0 and "written:" in stdout
    assert (path.with_name(path.stem + "-results") / "report" / "report.md").is_file()
