"""Locate the bundled text resources: lark grammars and clingo background knowledge.

In the repository they are the top-level folders ``grammars/`` and ``background_kb/``;
``pyproject.toml`` installs them as the data packages ``symlearn.grammars`` and
``symlearn.background_kb``, so the same lookup works from a wheel.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from pathlib import Path

from symlearn.errors import SymlearnError

_REPO_ROOT = Path(__file__).resolve().parent.parent


def _folder(package: str, repo_folder: str) -> Path:
    try:
        return Path(str(resources.files(package)))
    except ModuleNotFoundError:
        return _REPO_ROOT / repo_folder


@cache
def grammar_text(name: str) -> str:
    """The text of ``grammars/<name>.lark``."""
    path = _folder("symlearn.grammars", "grammars") / f"{name}.lark"
    if not path.is_file():
        raise SymlearnError(f"grammar {name!r} is not bundled (looked for {path})")
    return path.read_text(encoding="utf-8")


def background_kb_path(*parts: str) -> Path:
    """Path of a bundled background-knowledge file or folder, e.g. ``("hanoi", "bk.lp")``."""
    path = _folder("symlearn.background_kb", "background_kb").joinpath(*parts)
    if not path.exists():
        raise SymlearnError(f"no bundled background knowledge {'/'.join(parts)!r} (looked for {path})")
    return path
