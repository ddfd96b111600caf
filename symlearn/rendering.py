"""Render DOT text to SVG/PNG with Graphviz's ``dot`` program when it is installed."""

from __future__ import annotations

import shutil
from pathlib import Path

from symlearn.atomic import write_bytes
from symlearn.errors import OptionalDependency

GRAPHVIZ = OptionalDependency("Graphviz's 'dot' program", "apt-get install graphviz (or brew install graphviz)")


def dot_available() -> bool:
    return shutil.which("dot") is not None


def render_dot(dot_source: str, target: str | Path) -> Path:
    """Render to ``target``; the format comes from its suffix (``.svg``, ``.png``, ``.pdf``)."""
    import graphviz

    target = Path(target)
    fmt = target.suffix.lstrip(".").lower()
    if fmt not in {"svg", "png", "pdf"}:
        raise ValueError(f"cannot render to {target.suffix!r}; use .svg, .png or .pdf")
    if not dot_available():
        raise GRAPHVIZ.error(f"rendering {target.name}")
    data = graphviz.Source(dot_source).pipe(format=fmt)
    return write_bytes(target, data)


def dot_to_svg_text(dot_source: str) -> str | None:
    """SVG markup for notebooks, or ``None`` when ``dot`` is missing."""
    if not dot_available():
        return None
    import graphviz

    return graphviz.Source(dot_source).pipe(format="svg").decode("utf-8")


def quote(text: str) -> str:
    """A DOT double-quoted string."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
