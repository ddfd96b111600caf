"""What a sweep file may make symlearn run: the experiment it names, nothing else.

A sweep file names its cell function or command, and running it is the point; but a reference
such as ``logging:basicConfig``, ``numpy:savez`` or ``command = ["sh", "-c", ...]`` would let a
file received from someone else write files or run a shell. The rule (``docs/FORMATS.md``,
*Sweep files*), checked when the file is read, before any cell runs:

* ``file.py:function``: a Python file named by its path (relative to the sweep file's folder,
  or absolute), which must not lie inside the Python installation (the standard library and
  the installed packages: those are reached as modules, below);
* ``package.module:function``: a module of the user's own, found outside the Python installation
  (the current folder, ``PYTHONPATH``, an editable install); never the standard library, one of
  the libraries symlearn builds on (numpy, torch, ...) or symlearn itself. A package installed
  into the environment is refused too unless the *user* allows it by name (``sweep run
  --allow-package NAME``): any installed library may hold a function that evaluates its
  argument (``sympy:simplify`` runs a string given as ``expr``), so a list of the dangerous ones
  can never be complete, and the permission cannot come from the file being checked;
* ``command = [...]``: the first word must be ``symlearn`` (run as this environment's
  ``python -m symlearn``).

Files stay where the user put the experiment: a ``file.py`` function, and every word of a
command that names a path by climbing out (absolute, ``~``, or a ``..`` step), must lie inside the
sweep file's folder or the folder the command is run from -- the two places the person running it
chose. A file received from someone else cannot then run a Python file lying elsewhere on the
machine, or make a ``symlearn`` command write (``-o /elsewhere/f``) or read outside them; ``sweep run
--allow-outside`` lifts this for a file one trusts (the same rule and flag as domain folders).
A relative word without ``..`` stays inside the sweep file's folder, where commands run.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import sysconfig
from collections.abc import Iterable
from pathlib import Path

__all__ = ["LIBRARIES", "function_refusal", "command_refusal", "outside_refusal", "sweep_roots"]

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


def _installed_at(top: str) -> Path | None:
    """The folder of the installation that holds the top-level module ``top``, or None when it is
    found elsewhere or not at all (found as the cell workers will: ``sys.path`` plus the current
    folder; nothing is imported)."""
    extra = os.getcwd() not in sys.path
    if extra:
        sys.path.append(os.getcwd())
    try:
        spec = importlib.util.find_spec(top)
    except (ImportError, ValueError):
        return None
    finally:
        if extra:
            sys.path.remove(os.getcwd())
    if spec is None:
        return None
    places = [spec.origin] if spec.origin not in (None, "built-in", "frozen") else []
    places += list(spec.submodule_search_locations or ())
    for place in places:
        try:
            folder = _installation_folder(Path(place).resolve())
        except (OSError, RuntimeError):
            continue
        if folder is not None:
            return folder
    return None


def _installation_folder(path: Path) -> Path | None:
    """The innermost folder of the Python installation holding the resolved ``path`` (site-packages
    rather than the lib folder around it), or None."""
    return max((f for f in _installation() if path.is_relative_to(f)), key=lambda f: len(f.parts), default=None)


def function_refusal(reference: str, base: Path, allowed: Iterable[str] = (), *,
                     allow_outside: bool = False) -> str | None:
    """Why ``reference`` (``module:function`` or ``file.py:function``) may not be run, or None;
    ``allowed``: installed packages the user allows by name (never the standard library or the
    libraries in :data:`LIBRARIES`); ``allow_outside``: a ``file.py`` may lie outside the sweep
    file's folder and the current folder."""
    where, _, _ = reference.rpartition(":")
    if where.endswith(".py"):
        folder = _installation_folder(_resolved(base / where))
        if folder is not None:
            return (f"{where} lies inside the Python installation ({folder}); a sweep runs functions from "
                    "its own files or from a named package")
        return None if allow_outside else outside_refusal(where, base)
    top = where.split(".", 1)[0]
    if top in sys.stdlib_module_names or top in sys.builtin_module_names:
        return f"{where!r} is part of Python's standard library; a sweep runs only an experiment's own functions"
    if top in LIBRARIES:
        return f"{where!r} belongs to {top}, a library symlearn builds on; a sweep runs only an experiment's own functions"
    if top in set(allowed):
        return None
    folder = _installed_at(top)
    if folder is not None:
        return (f"{where!r} belongs to {top}, a package installed in {folder}; a sweep runs its own files and "
                f"modules, or an installed package only when you allow it: sweep run --allow-package {top}")
    return None


def command_refusal(command: list[str]) -> str | None:
    """Why ``command`` may not be run, or None: only ``symlearn`` commands are."""
    from symlearn.sweep.cell import SYMLEARN_WORDS

    if command and command[0] in SYMLEARN_WORDS:
        return None
    return (f"a sweep command must start with 'symlearn', not {command[0]!r}" if command
            else "a sweep command must start with 'symlearn'")


def sweep_roots(base: Path) -> list[Path]:
    """Where a sweep's files may lie: the sweep file's folder and the current folder (resolved)."""
    return [_resolved(base), _resolved(Path.cwd())]


def _resolved(path: Path) -> Path:
    try:
        return path.expanduser().resolve()
    except (OSError, RuntimeError):  # a symlink loop: judged by its absolute spelling
        return Path(os.path.abspath(path))


def path_word(word: str) -> str | None:
    """The path a command word names when it climbs out of the folder it runs in, else None:
    the word itself or the value of ``--flag=VALUE``, absolute, starting with ``~`` or with a
    ``..`` step (``FILE.py:function`` is judged by its file)."""
    value = word.split("=", 1)[1] if word.startswith("-") and "=" in word else word
    if not value:
        return None
    if value.startswith(("/", "~")) and ".py:" in value:
        value = value[:value.rindex(".py:") + 3]
    climbs = ".." in value.replace("\\", "/").split("/")
    return value if value.startswith(("/", "~")) or climbs else None


def outside_refusal(named: str, base: Path) -> str | None:
    """Why the file or folder ``named`` (relative to ``base``, the sweep file's folder) may not be
    used, or None: it lies outside the sweep file's folder and the current folder."""
    target = _resolved(base / named)
    roots = sweep_roots(base)
    if any(target.is_relative_to(root) for root in roots):
        return None
    return (f"{named} lies outside the sweep file's folder ({roots[0]}) and the current folder; a sweep "
            "uses files from those only, unless you allow it: sweep run --allow-outside")
