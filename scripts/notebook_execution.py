"""Execute a freshly built notebook and write it with its outputs (scripts/make_notebook_1*.py).

The notebook runs in a temporary folder, as tests/test_notebooks.py runs it, so nothing it writes
lands in the checkout; a failing cell stops the script before anything is written.
"""

import tempfile
from pathlib import Path

import nbclient
import nbformat
from nbformat.v4 import new_code_cell

#: the first code cell of the guide's notebooks: imports, QUICK, the guide's module on the path
GUIDE_SETUP = r"""import os
import sys
import tempfile
from pathlib import Path

import gymnasium as gym
import matplotlib.pyplot as plt
import numpy as np

import symlearn

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"  # the test suite asks for small settings
GUIDE = Path(symlearn.__file__).resolve().parent.parent / "docs" / "guide"
sys.path.insert(0, str(GUIDE))  # what `cd docs/guide` does for the command line
import guide_robot  # registers GuideRobot-v0 and GuideTour-v0

workspace = tempfile.TemporaryDirectory(prefix="symlearn-guide-")
os.chdir(workspace.name)  # every file this notebook writes goes here"""


def guide_setup_cell(*lines: str):
    """:data:`GUIDE_SETUP` followed by a notebook's own settings (``lines``)."""
    return new_code_cell(GUIDE_SETUP + "\n\n" + "\n".join(lines))


def execute_and_write(nb, path: Path, timeout: int = 900) -> None:
    for number, cell in enumerate(nb.cells):  # stable ids: regenerating changes only what changed
        cell.id = f"cell-{number:02d}"
    with tempfile.TemporaryDirectory(prefix="symlearn-notebook-") as folder:
        nbclient.NotebookClient(nb, timeout=timeout, kernel_name="python3",
                                resources={"metadata": {"path": folder}}).execute()
    for cell in nb.cells:  # wall-clock stamps would change on every run; the outputs are what matters
        cell.get("metadata", {}).pop("execution", None)
    nbformat.write(nb, str(path))
    print("wrote", path)
