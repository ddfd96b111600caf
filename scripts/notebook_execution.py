"""Execute a freshly built notebook and write it with its outputs (scripts/make_notebook_1*.py).

The notebook runs in a temporary folder, as tests/test_notebooks.py runs it, so nothing it writes
lands in the checkout; a failing cell stops the script before anything is written.
"""

import tempfile
from pathlib import Path

import nbclient
import nbformat


def execute_and_write(nb, path: Path, timeout: int = 900) -> None:
    with tempfile.TemporaryDirectory(prefix="symlearn-notebook-") as folder:
        nbclient.NotebookClient(nb, timeout=timeout, kernel_name="python3",
                                resources={"metadata": {"path": folder}}).execute()
    for cell in nb.cells:  # wall-clock stamps would change on every run; the outputs are what matters
        cell.get("metadata", {}).pop("execution", None)
    nbformat.write(nb, str(path))
    print("wrote", path)
