"""symlearn: learn interpretable symbolic models of behaviour from demonstrations.

The package is layered (see ``docs/ARCHITECTURE.md``); importing ``symlearn`` itself loads only
the error types and the data model, never torch or a solver.
"""

from typing import Any

from symlearn.errors import SymlearnError

__all__ = ["__version__", "SymlearnError"]


def __getattr__(name: str) -> Any:
    # the version is read from the installed metadata only when asked for: importlib.metadata
    # costs ~30 ms of every command's start (issue 27's one-line `ltl parse` budget is 150 ms)
    if name == "__version__":
        from symlearn._version import __version__

        return __version__
    raise AttributeError(f"module 'symlearn' has no attribute {name!r}")
