"""What the neural ICRL benchmarks share: the JSON document every one of them writes.

One layout (benchmark name, the command that produced it, settings, machine facts with the load
average before and after, runs, summary, seconds), written atomically.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

import torch

from symlearn.atomic import write_text


def write_document(path: Path, benchmark: str, argv: list[str] | None, settings: dict[str, Any], runs: list[dict],
                   summary: dict[str, Any], started: float, load_before: tuple[float, float, float],
                   **extra: Any) -> dict[str, Any]:
    """Write ``path`` (atomically) and return the document; ``started`` is a ``perf_counter``
    reading from the benchmark's start, ``load_before`` its ``os.getloadavg()``."""
    document = {
        "benchmark": benchmark, **extra,
        "command": f"python benchmarks/{benchmark}.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "settings": {k: (str(v) if isinstance(v, Path) else v) for k, v in settings.items()},
        "machine": {"python": platform.python_version(), "platform": platform.platform(), "cpus": os.cpu_count(),
                    "torch": torch.__version__, "load_average_before": load_before,
                    "load_average_after": os.getloadavg()},
        "summary": summary, "runs": runs, "seconds": round(time.perf_counter() - started, 1)}
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text(path, json.dumps(document, indent=1) + "\n")
    print(f"wrote {path} ({document['seconds']:.0f} s)")
    return document
