import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
SHARED = REPO.parent / "shared"

# Tests never draw progress bars, whatever terminal runs them.
os.environ.setdefault("SYMLEARN_QUIET", "1")


@pytest.fixture
def run_cli():
    """Run ``symlearn`` in a subprocess; returns CompletedProcess with text output."""
    import subprocess

    def run(*args, input=None, cwd=None):
        return subprocess.run([sys.executable, "-m", "symlearn", *map(str, args)], capture_output=True,
                              text=True, input=input, cwd=cwd, timeout=300)

    return run
