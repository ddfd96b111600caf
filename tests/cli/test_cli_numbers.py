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
