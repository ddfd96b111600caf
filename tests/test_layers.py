"""The dependency direction of docs/ARCHITECTURE.md, checked on every import statement.

Every ``import`` and ``from ... import`` in the package counts, also those inside functions
(a lazy import is still a dependency). Docstrings and doctests do not: an example may build a
bundled environment to show a learner at work.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "symlearn"

# layer -> module prefixes it must never import
_ENTRY_POINTS = ("symlearn.cli", "symlearn.demo", "symlearn.sweep")
_BELOW_RECIPES = ("symlearn.recipes", *_ENTRY_POINTS)
FORBIDDEN = {
    "symlearn.logic": ("torch", "gymnasium", "symlearn.learners", "symlearn.envs", "symlearn.backends",
                       "symlearn.grounding", "symlearn.rl", *_BELOW_RECIPES),
    "symlearn.grounding": ("torch", "gymnasium", "symlearn.learners", "symlearn.envs", "symlearn.backends",
                           "symlearn.rl", *_BELOW_RECIPES),
    "symlearn.mdp": ("torch", "gymnasium", "symlearn.learners", "symlearn.envs", "symlearn.backends",
                     "symlearn.grounding", *_BELOW_RECIPES),
    "symlearn.data": ("torch", "symlearn.learners", "symlearn.envs", "symlearn.backends", "symlearn.grounding",
                      *_BELOW_RECIPES),
    "symlearn.rl": ("symlearn.learners", "symlearn.envs", "symlearn.backends", *_BELOW_RECIPES),
    "symlearn.learners": ("symlearn.envs", *_BELOW_RECIPES),
    "symlearn.envs": ("symlearn.learners", "symlearn.backends", *_BELOW_RECIPES),
    "symlearn.backends": ("symlearn.learners", *_BELOW_RECIPES),
    # the glue between the entry points and learners/envs/backends: it serves them, never calls up
    "symlearn.recipes": _ENTRY_POINTS,
    "symlearn.sweep": ("symlearn.cli", "symlearn.demo"),
    # the demo is an entry point of its own; what it shares with the CLI lives in recipes
    "symlearn.demo": ("symlearn.cli",),
}


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, located: Path | None = None) -> list[tuple[str, int]]:
    """(imported module, line) of every import statement, relative imports resolved as if the
    file were at ``located`` (default: where it is)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    located = located or path
    here = _module_name(located).split(".")
    package = here if located.name == "__init__.py" else here[:-1]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[: len(package) - node.level + 1] + ([base] if base else []))
            found.append((base, node.lineno))
            found += [(f"{base}.{alias.name}", node.lineno) for alias in node.names]
    return found


def _violations() -> list[str]:
    problems = []
    for path in sorted(PACKAGE.rglob("*.py")):
        module = _module_name(path)
        for layer, banned in FORBIDDEN.items():
            if module != layer and not module.startswith(layer + "."):
                continue
            for imported, line in _imports(path):
                for prefix in banned:
                    if imported == prefix or imported.startswith(prefix + "."):
                        problems.append(f"{path.relative_to(PACKAGE.parent)}:{line}: {layer} imports {imported}")
    return sorted(set(problems))


def test_layers_import_only_downwards():
    problems = _violations()
    assert not problems, "imports against the layer order:\n" + "\n".join(problems)


@pytest.mark.parametrize("source, imported", [
    ("from symlearn.envs.logic_mdp import logic_mdp", "symlearn.envs.logic_mdp"),
    ("import torch.nn as nn", "torch.nn"),
    ("def f():\n    from ...envs import registry", "symlearn.envs.registry"),
])
def test_the_checker_sees_every_kind_of_import(tmp_path, source, imported):
    """The checker itself must not go blind: absolute, aliased and lazy relative imports count."""
    fake = PACKAGE / "learners" / "constraints" / "_probe.py"
    path = tmp_path / "probe.py"
    path.write_text(source)
    names = [name for name, _ in _imports(path, fake)]
    assert imported in names
