"""Run the demo pipelines and write ``summary.md`` / ``summary.json`` into the report folder."""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from symlearn import __version__
from symlearn.atomic import write_text
from symlearn.demo.registry import DemoContext, Pipeline, Section, pipelines
from symlearn.errors import SymlearnError


def run_demo(
    out_dir: str | Path = "symlearn-demo",
    *,
    only: Sequence[str] = (),
    seed: int = 0,
    quick: bool = False,
    log=None,
) -> dict[str, Any]:
    """Run the selected pipelines (all by default); return the JSON summary that was written."""
    available = pipelines()
    names = [p.name for p in available]
    unknown = [n for n in only if n not in names]
    if unknown:
        raise SymlearnError(f"unknown demo pipeline {unknown[0]!r}", hint=f"choose from: {', '.join(names)}")
    chosen = [p for p in available if not only or p.name in only]
    context = DemoContext(Path(out_dir), seed=seed, quick=quick)
    context.out_dir.mkdir(parents=True, exist_ok=True)

    sections: list[tuple[Pipeline, Section, float]] = []
    for pipeline in chosen:
        if log:
            log(f"demo: running {pipeline.name} ...")
        start = time.perf_counter()
        section = pipeline.run(context)
        sections.append((pipeline, section, time.perf_counter() - start))

    summary = {
        "symlearn_version": __version__,
        "seed": seed,
        "quick": quick,
        "out_dir": str(context.out_dir),
        "pipelines": [
            {"name": p.name, "title": s.title, "seconds": round(sec, 3), "figures": s.figures, "files": s.files}
            for p, s, sec in sections
        ],
    }
    write_text(context.out_dir / "summary.json", json.dumps(summary, indent=2) + "\n")
    write_text(context.out_dir / "summary.md", _markdown(summary, sections))
    return summary


def _markdown(summary: dict[str, Any], sections: list[tuple[Pipeline, Section, float]]) -> str:
    lines = [
        "# symlearn demo report",
        "",
        f"symlearn {summary['symlearn_version']}, seed {summary['seed']}"
        + (", quick settings" if summary["quick"] else ""),
        "",
    ]
    for pipeline, section, seconds in sections:
        lines += [f"## {section.title}", "", f"_pipeline `{pipeline.name}`, {seconds:.1f} s_", "",
                  section.markdown.strip(), ""]
        if section.files:
            lines += ["Files:", ""] + [f"- [`{f}`]({f})" for f in section.files] + [""]
    return "\n".join(lines)
