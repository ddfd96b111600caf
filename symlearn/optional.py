"""Optional engines: detected when first asked for, never required by the core.

Adapters call :func:`require` (which raises :class:`MissingDependencyError` with an install hint)
and tests call :func:`available` to skip oracle checks cleanly.
"""

from __future__ import annotations

import importlib.util
import shutil
from dataclasses import dataclass
from functools import cache

from symlearn.errors import MissingDependencyError


@dataclass(frozen=True)
class Engine:
    name: str
    modules: tuple[str, ...]  # Python modules that must import
    programs: tuple[str, ...]  # executables that must be on PATH
    purpose: str
    install_hint: str


def _extra(name: str, make_test: bool = True) -> str:
    """The install hint of an extra, worded as the README's table words it (a checkout's .venv;
    the wheel form in parentheses)."""
    command = f".venv/bin/pip install -e '.[{name}]'"
    first = f"installed by `make test`; else {command}" if make_test else command
    return f"{first} (from a wheel: pip install 'symlearn[{name}]')"


# The hints say what the README's "Optional engines" table says (tests/hostile checks they agree).
ENGINES: dict[str, Engine] = {
    e.name: e
    for e in (
        Engine("spot", ("spot",), (), "LTL/automata cross-checks and HOA interoperability",
               "not on PyPI; install it from your distribution or conda-forge ('spot')"),
        Engine("mona", ("ltlf2dfa",), ("mona",), "LTLf -> DFA oracle (LTLf2DFA + MONA)",
               _extra("peers") + " and apt-get install mona"),
        Engine("scarlet", ("Scarlet",), (), "LTL learning peer (Scarlet)", _extra("peers")),
        Engine("aalpy", ("aalpy",), (), "automata learning peer (AALpy)", _extra("peers")),
        Engine("dfa_identify", ("dfa_identify",), (), "DFA identification peer", _extra("peers")),
        Engine("sumo", ("traci", "sumo"), (), "SUMO traffic demonstrations", _extra("sumo")),
        Engine("mujoco", ("mujoco",), (), "MuJoCo environments", _extra("mujoco")),
        Engine("highway", ("highway_env",), (), "highway-env environments", _extra("highway")),
        Engine("ray", ("ray",), (), "sweeps on Ray (symlearn sweep run; --local needs nothing)", _extra("sweep")),
        Engine("sb3", ("stable_baselines3",), (), "stable-baselines3 agents on shields and reward machines",
               _extra("sb3")),
        Engine("sb3_contrib", ("sb3_contrib",), (), "masked policies (MaskablePPO) on shields", _extra("sb3")),
        Engine("h5py", ("h5py",), (), "D4RL tables in HDF5 and Minari dataset folders (symlearn data)",
               _extra("formats")),
        Engine("graphviz", (), ("dot",), "rendering automata to SVG/PNG",
               "installed by `make demo` and `make test`; else apt-get install graphviz (macOS: brew install graphviz)"),
    )
}


def _engine(name: str) -> Engine:
    try:
        return ENGINES[name]
    except KeyError:
        raise ValueError(f"unknown optional engine {name!r}; known: {', '.join(ENGINES)}") from None


@cache
def available(name: str) -> bool:
    """Whether every module and program of engine ``name`` is present (checked without importing)."""
    engine = _engine(name)
    modules_ok = all(importlib.util.find_spec(m) is not None for m in engine.modules)
    return modules_ok and all(shutil.which(p) is not None for p in engine.programs)


def require(name: str, purpose: str | None = None) -> None:
    """Raise a clear :class:`MissingDependencyError` when engine ``name`` is missing."""
    if not available(name):
        engine = _engine(name)
        raise MissingDependencyError(f"{purpose or engine.purpose} needs {engine.name}, which is not installed",
                                     hint=engine.install_hint)


def report() -> list[dict[str, object]]:
    """One row per engine: name, available, purpose, install hint."""
    return [{"name": e.name, "available": available(e.name), "purpose": e.purpose, "install": e.install_hint}
            for e in ENGINES.values()]
