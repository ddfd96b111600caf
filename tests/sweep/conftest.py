from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # cells, sweep_helpers, cli_harness

from sweep_helpers import sweep_text  # noqa: E402


@pytest.fixture
def write_sweep(tmp_path):
    """``write_sweep(function, grid, ...)``: a sweep file in ``tmp_path`` (see ``sweep_text``)."""
    def write(*args, name: str = "s.toml", **kwargs) -> Path:
        path = tmp_path / name
        path.write_text(sweep_text(*args, **kwargs))
        return path

    return write


@pytest.fixture
def cli(capsys):
    """``symlearn ARGS`` in-process: (exit code, stdout, stderr)."""
    from cli_harness import main

    def run(*args):
        code = main([str(a) for a in args])
        captured = capsys.readouterr()
        return code, captured.out, captured.err

    return run
