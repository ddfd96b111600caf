"""symlearn: learn interpretable symbolic models of behaviour from demonstrations.

The package is layered (see ``docs/ARCHITECTURE.md``); importing ``symlearn`` itself loads only
the error types and the data model, never torch or a solver.
"""

from symlearn._version import __version__
from symlearn.errors import SymlearnError

__all__ = ["__version__", "SymlearnError"]
