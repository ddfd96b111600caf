"""What a sweep file may make symlearn run: the experiment it names, nothing else.

A sweep file names its cell function or command, and running it is the point; but a reference
such as ``logging:basicConfig``, ``numpy:savez`` or ``command = ["sh", "-c", ...]`` would let a
file received from someone else write files or run a shell. The rule (``docs/FORMATS.md``,
*Sweep files*), checked when the file is read, before any cell runs:

* ``file.py:function``: a Python file named by its path (relative to the sweep file's folder,
  or absolute), which must not lie inside the Python installation (the standard library and
  the installed packages: those are reached as modules, below);
* ``package.module:function``: a module of an installed package that is neither the standard
  library nor one of the libraries symlearn builds on (numpy, torch, ...), nor symlearn itself;
* ``command = [...]``: the first word must be ``symlearn`` (run as this environment's
  ``python -m symlearn``).
"""

from __future__ import annotations

import sys
import sysconfig
from pathlib import Path

__all__ = ["LIBRARIES", "function_refusal", "command_refusal"]

#: top-level packages a sweep may not name functions from besides the standard library: symlearn's
#: own dependencies, whose functions write files or run code when called with the right keywords
LIBRARIES = frozenset({
    "symlearn", "numpy", "scipy", "torch", "gymnasium", "gym", "safetensors", "clingo", "lark", "ray", "matplotlib",
    "pandas", "networkx", "sklearn", "PIL", "tqdm", "pytest", "_pytest", "pip", "setuptools", "pkg_resources",
    "importlib_metadata", "tomli", "yaml", "requests", "urllib3", "IPython", "jupyter", "duckdb", "hypothesis",
})


def _installation() -> list[Path]:
    paths = sysconfig.get_paths()
    folders = {paths[key] for key in ("stdlib", "platstdlib", "purelib", "platlib") if key in paths}
    folders |= {str(Path(p)) for p in sys.path if p and ("site-packages" in p or "dist-packages" in p)}
    return [Path(f).resolve() for f in folders]


def function_refusal(reference: str, base: Path) -> str | None:
    """Why ``reference`` (``module:function`` or ``file.py:function``) may not be run, or None."""
    where, _, _ = reference.rpartition(":")
    if where.endswith(".py"):
        path = (base / where).resolve()
        for folder in _installation():
            if path.is_relative_to(folder):
                return (f"{where} lies inside the Python installation ({folder}); a sweep runs functions from "
                        "its own files or from a named package")
        return None
    top = where.split(".", 1)[0]
    if top in sys.stdlib_module_names or top in sys.builtin_module_names:
        return f"{where!r} is part of Python's standard library; a sweep runs only an experiment's own functions"
    if top in LIBRARIES:
        return f"{where!r} belongs to {top}, a library symlearn builds on; a sweep runs only an experiment's own functions"
    return None


def command_refusal(command: list[str]) -> str | None:
    """Why ``command`` may not be run, or None: only ``symlearn`` commands are."""
    from symlearn.sweep.cell import SYMLEARN_WORDS

    if command and command[0] in SYMLEARN_WORDS:
        return None
    return (f"a sweep command must start with 'symlearn', not {command[0]!r}" if command
            else "a sweep command must start with 'symlearn'")
