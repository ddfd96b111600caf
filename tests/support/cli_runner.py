"""Run the symlearn CLI in-process and capture what it printed."""

from symlearn.cli.main import main


def run(capsys, *args):
    """``(exit code, stdout, stderr)`` of ``symlearn ARGS`` (arguments are turned into strings)."""
    code = main([str(a) for a in args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err
