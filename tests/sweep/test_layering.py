"""The sweep package sits between the learners and the CLI: nothing below imports it, and it
imports no command-line or demo code (and nothing heavy at module level)."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "symlearn"


def _imports(path: Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            found.add(node.module)
    return found


def test_only_the_cli_imports_the_sweep_package():
    offenders = [str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*.py")
                 if not p.is_relative_to(PACKAGE / "sweep") and not p.is_relative_to(PACKAGE / "cli")
                 and any(m == "symlearn.sweep" or m.startswith("symlearn.sweep.") for m in _imports(p))]
    assert offenders == []


def test_the_sweep_package_imports_no_cli_or_demo():
    for path in (PACKAGE / "sweep").rglob("*.py"):
        bad = [m for m in _imports(path) if m.startswith(("symlearn.cli", "symlearn.demo"))]
        assert bad == [], path


def test_importing_the_package_and_command_loads_nothing_heavy():
    code = ("import sys, symlearn.sweep.spec, symlearn.sweep.store, symlearn.sweep.runner, "
            "symlearn.cli.sweep_command; "
            "print(sorted(m for m in ('ray', 'numpy', 'matplotlib', 'torch') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
