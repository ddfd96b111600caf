"""Helpers of the sweep tests: sweep files over ``cells.py`` and reading the store."""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
CELLS = HERE / "cells.py"


def sweep_text(function: str, grid: dict, *, fixed: dict | None = None, seeds=2, extra: str = "") -> str:
    """A sweep file running ``cells.py:function``."""
    lines = ["[sweep]", f'function = "{CELLS}:{function}"', f"seeds = {json.dumps(seeds)}", extra, "[grid]"]
    lines += [f"{k} = {json.dumps(v)}" for k, v in grid.items()]
    if fixed:
        lines += ["[fixed]"] + [f"{k} = {json.dumps(v)}" for k, v in fixed.items()]
    return "\n".join(lines) + "\n"


def records(folder: Path) -> list[dict]:
    lines = (Path(folder) / "results.jsonl").read_text().splitlines()
    return [json.loads(line) for line in lines]
