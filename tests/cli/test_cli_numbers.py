"""``--n-demos`` of every learn command: a whole number from 1 to 100,000, refused in one usage line
before anything is recorded (10^9 ran on, unrefused, past a minute and 1 GB)."""

import pytest

from cli_runner import run

COMMANDS = [("spec", "office-1"), ("constraints", "hanoi"), ("dnf", "toy-navigation"), ("icrl", "blocked-point"),
            ("pdfa", "blocks-place-2")]


@pytest.mark.parametrize("command, env", COMMANDS)
@pytest.mark.parametrize("value, words", [("0", "got 0"), ("1000000000", "got 1,000,000,000"),
                                          (str(10**40), "between 1 and 100,000"), ("2.5", "invalid int value")])
def test_n_demos_out_of_range_is_one_usage_line(capsys, command, env, value, words):
    try:
        code, out, err = run(capsys, "learn", command, "--env", env, "--n-demos", value)
    except SystemExit as stop:  # argparse's usage error ends main() itself
        captured = capsys.readouterr()
        code, out, err = stop.code, captured.out, captured.err
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "--n-demos" in lines[0] and words in lines[0], err


@pytest.mark.parametrize("value", ["0", "-1"])
def test_ltl_dfa_max_states_below_one_is_refused(capsys, value):
    code, out, err = run(capsys, "ltl", "dfa", "F a", "--max-states", value)
    assert code == 2 and err.strip() == f"symlearn: error: --max-states must be at least 1, got {value}"


def test_saving_onto_a_directory_names_the_directory(capsys, tmp_path):
    # the atomic writer's temporary sibling was named in the message instead of the user's path
    (tmp_path / "outd").mkdir()
    code, out, err = run(capsys, "ltl", "dfa", "F a", "--save", str(tmp_path / "outd"))
    assert code == 2 and "outd: Is a directory" in err and ".tmp" not in err and len(err.strip().splitlines()) == 1
