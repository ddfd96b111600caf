import json

import pytest

from symlearn import __version__
from symlearn.cli import main as cli_main
from symlearn.data import Demonstrations, Trajectory


def test_help_and_version(run_cli):
    top = run_cli("--help")
    assert top.returncode == 0 and "demo" in top.stdout and "data" in top.stdout
    version = run_cli("--version")
    assert version.returncode == 0 and version.stdout.strip() == f"symlearn {__version__}"
    for args in (("demo", "--help"), ("data", "--help"), ("data", "info", "--help")):
        result = run_cli(*args)
        assert result.returncode == 0, args
        assert "--json" in result.stdout or args == ("data", "--help")


def test_no_command_prints_help_and_exits_2(run_cli):
    result = run_cli()
    assert result.returncode == 2 and "usage: symlearn" in result.stderr


@pytest.fixture
def demos_file(tmp_path):
    path = tmp_path / "demos.jsonl"
    Demonstrations([Trajectory([0, 1, 2], [1, 1], [0.0, 1.0], [[], [], ["goal"]])]).save(path)
    return path


def test_data_info_text_and_json(run_cli, demos_file):
    text = run_cli("data", "info", demos_file)
    assert text.returncode == 0 and "1 trajectories, 3 steps" in text.stdout
    js = run_cli("data", "info", demos_file, "--json")
    assert js.returncode == 0
    doc = json.loads(js.stdout)  # exactly one JSON document, nothing else on stdout
    assert doc["summary"]["n_steps"] == 3 and doc["summary"]["label_counts"] == {"goal": 1}
    before = run_cli("--json", "data", "info", demos_file)
    assert json.loads(before.stdout) == doc


def test_data_convert_and_validate(run_cli, demos_file, tmp_path):
    target = tmp_path / "demos.npz"
    assert run_cli("data", "convert", demos_file, target, "--quiet").returncode == 0
    result = run_cli("data", "validate", target)
    assert result.returncode == 0 and "valid" in result.stdout


def test_bad_input_is_one_line_with_location_and_exit_2(run_cli, tmp_path, demos_file):
    bad = tmp_path / "bad.jsonl"
    lines = demos_file.read_text().splitlines()
    bad.write_text(lines[0] + "\n" + '{"states": [0, 1], "actions": [1, 1, 1]}\n')
    result = run_cli("data", "validate", bad)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.strip().splitlines() == [
        f"symlearn: error: {bad}:2:20: mismatched lengths: 3 actions for 2 states "
        "(hint: give one action per state, or one fewer when the last state is final)"
    ]
    missing = run_cli("data", "info", tmp_path / "nope.jsonl")
    assert missing.returncode == 2 and "no such file" in missing.stderr and "Traceback" not in missing.stderr


def test_debug_shows_the_traceback(run_cli, tmp_path):
    result = run_cli("--debug", "data", "info", tmp_path / "nope.jsonl")
    assert result.returncode == 2 and "Traceback" in result.stderr


def test_usage_errors_exit_2(run_cli):
    result = run_cli("data", "info")
    assert result.returncode == 2 and "required" in result.stderr
    assert run_cli("no-such-command").returncode == 2


def test_internal_failure_exits_1(monkeypatch, capsys, demos_file):
    from symlearn.cli import data_command

    def broken(args, out):
        raise RuntimeError("boom")

    monkeypatch.setattr(data_command, "_info", broken)
    code = cli_main.main(["data", "info", str(demos_file)])
    err = capsys.readouterr().err
    assert code == 1 and "internal error: RuntimeError: boom" in err and "--debug" in err


def test_one_grammar_no_abbreviations_and_did_you_mean(run_cli):
    """A misspelt or shortened flag is refused in one line that names the flag meant."""
    for args, meant in ((("learn", "dnf", "--demoz", "x"), "did you mean --demos?"),
                        (("learn", "dnf", "--env-kw", "{}"), "did you mean --env-kwargs?"),
                        (("learn", "icrl", "--env", "x", "--method", "mce-icr"), "did you mean 'mce-icrl'?"),
                        (("lern",), "did you mean 'learn'?")):
        result = run_cli(*args)
        assert result.returncode == 2 and meant in result.stderr, result.stderr
        assert len(result.stderr.strip().splitlines()) == 1 and "usage:" not in result.stderr
    result = run_cli("learn", "dnf", "--max-dep", "3", "--demos", "x")
    assert result.returncode == 2 and "unrecognized arguments: --max-dep" in result.stderr  # never taken as --max-depth


def test_a_stray_warning_is_one_line_without_a_source_path(capsys, monkeypatch):
    """A warning no command turned into a note prints as one 'warning:' line (no path:line of
    symlearn's source); code recording warnings still records them."""
    import sys
    import warnings

    from symlearn.cli.main import _one_line_warnings

    # displayed as Python displays an unrecorded warning (pytest records them all otherwise)
    monkeypatch.setattr(warnings, "showwarning", lambda message, category, filename, lineno, file=None, line=None:
                        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line)))
    with _one_line_warnings(debug=False):
        warnings.warn_explicit("the expert\n   looks odd", UserWarning, "/x/learner.py", 261)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            warnings.warn("recorded", UserWarning)
    err = capsys.readouterr().err
    assert err == "warning: the expert looks odd\n"
    assert [str(w.message) for w in caught] == ["recorded"]
