"""Running one cell, in whichever worker process holds it; the result is one JSON record.

A job and its record cross process boundaries as JSON text only (no pickled objects): the job
names the function by reference (``module:function`` or ``file.py:function``) and carries the
parameters, the seed and the metrics to keep. Whatever the function raises becomes an ``error``
record with its traceback, so a failing cell never prints on the terminal and never stops the
sweep; crashes and timeouts are recorded by the executor, which sees the process die.
"""

from __future__ import annotations

import importlib
import importlib.util
import hashlib
import json
import math
import os
import random
import socket
import sys
import time
import traceback
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

SYMLEARN_WORDS = ("symlearn",)


def load_function(reference: str, base: str):
    """``module:function`` imported by name, or ``path.py:function`` loaded from ``path`` (relative
    to ``base``, the sweep file's folder) as its script would run: its folder first on
    ``sys.path``. Loaded once per process."""
    where, _, name = reference.rpartition(":")
    if where.endswith(".py"):
        path = (Path(base) / where).resolve()
        module_name = f"_symlearn_sweep_{path.stem}_{hashlib.sha256(str(path).encode()).hexdigest()[:8]}"
        module = sys.modules.get(module_name)
        if module is None:
            if not path.is_file():
                raise FileNotFoundError(f"no such file: {path}")
            if str(path.parent) not in sys.path:
                sys.path.insert(0, str(path.parent))
            spec = importlib.util.spec_from_file_location(module_name, path)
            module = importlib.util.module_from_spec(spec)
            sys.modules[module_name] = module
            try:
                spec.loader.exec_module(module)
            except BaseException:
                del sys.modules[module_name]
                raise
    else:
        # the current folder last on the path, as the cell workers have it (runner.py): a module
        # beside the command's folder loads when the file is checked as it will in the cells
        if os.getcwd() not in sys.path:
            sys.path.append(os.getcwd())
        module = importlib.import_module(where)
    function = getattr(module, name)
    if not callable(function):
        raise AttributeError(f"{name!r} in {where} is not callable")
    return function


def seed_everything(seed: int) -> None:
    """Seed the global generators a careless cell might use (the function gets ``seed`` too and
    should use it): Python's ``random``, numpy's legacy global (numpy is a dependency of symlearn,
    so it is loaded for this even when the cell imports it later), torch's if torch is loaded
    already (it is too heavy to load for a cell that may not use it; such a cell seeds it)."""
    import numpy

    random.seed(seed)
    numpy.random.seed(seed % 2**32)
    torch = sys.modules.get("torch")
    if torch is not None:
        torch.manual_seed(seed)


def json_ready(value: Any) -> Any:
    """``value`` as plain JSON: numpy scalars and arrays to numbers and lists, tuples to lists,
    non-finite floats to ``null`` (strict JSON readers such as DuckDB refuse NaN)."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    tolist = getattr(value, "tolist", None)  # numpy scalars and arrays
    if callable(tolist):
        return json_ready(tolist())
    raise TypeError(f"a metric of type {type(value).__name__} is not JSON (return numbers, strings or lists)")


def pick(result: Any, path: str) -> Any:
    """The value at dotted ``path`` in ``result`` (``a.b`` = ``result["a"]["b"]``)."""
    value = result
    for part in path.split("."):
        if isinstance(value, dict) and part in value:
            value = value[part]
        elif isinstance(value, list) and part.isdigit() and int(part) < len(value):
            value = value[int(part)]
        else:
            raise KeyError(path)
    return value


def keep_metrics(result: Any, metrics: list[str] | None) -> dict[str, Any]:
    if not isinstance(result, dict):
        raise TypeError(f"the cell returned {type(result).__name__}, not a mapping of metrics")
    if metrics is None:
        return json_ready(result)
    kept = {}
    for name in metrics:
        try:
            kept[name] = json_ready(pick(result, name))
        except KeyError:
            have = ", ".join(sorted(map(str, result))) or "nothing"
            raise KeyError(f"the result has no metric {name!r} (it has {have})") from None
    return kept


def _command_words(job: dict[str, Any]) -> list[str]:
    values = {**job["params"], "seed": job["seed"]}
    words = [word.format_map({k: v if isinstance(v, str) else json.dumps(v) for k, v in values.items()})
             for word in job["command"]]
    if words[0] in SYMLEARN_WORDS:  # the symlearn of this environment, not whichever is on PATH
        # -P: the command runs in the sweep file's folder, and `python -m` would put that folder first
        # on sys.path, so a json.py (or numpy.py, ...) lying there would be imported in place of the
        # library: code the sweep never named
        words = [sys.executable, "-P", "-m", "symlearn", *words[1:]]
    return words


def _run_command(job: dict[str, Any]) -> Any:
    import subprocess

    words = _command_words(job)
    done = subprocess.run(words, capture_output=True, text=True, cwd=job["base"], timeout=job.get("timeout"))
    if done.returncode != 0:
        tail = "\n".join(done.stderr.strip().splitlines()[-20:])
        raise RuntimeError(f"the command exited with {done.returncode}: {tail}")
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError as exc:
        raise ValueError(f"the command's output is not one JSON document ({exc.msg}; use --json)") from None


def execute(job: dict[str, Any]) -> dict[str, Any]:
    """Run the cell of ``job``; the record for the store (``status`` ``ok`` or ``error``)."""
    started = time.perf_counter()
    record: dict[str, Any] = {"cell": job["cell"], "params": job["params"], "seed": job["seed"],
                              "attempt": job["attempt"]}
    try:
        for entry in job.get("sys_path", []):
            if entry not in sys.path:
                sys.path.append(entry)
        if job.get("command") is not None:
            metrics = keep_metrics(_run_command(job), job.get("metrics"))
        else:
            function = load_function(job["function"], job["base"])
            seed_everything(job["seed"])
            metrics = keep_metrics(function(**job["params"], seed=job["seed"]), job.get("metrics"))
        record.update(status="ok", metrics=metrics, error=None)
    except Exception as exc:  # noqa: BLE001 - a failing cell is data: recorded, not raised
        record.update(status="error", metrics=None,
                      error={"type": type(exc).__name__, "message": str(exc), "traceback": traceback.format_exc()})
    record.update(seconds=round(time.perf_counter() - started, 6), host=socket.gethostname(), pid=os.getpid(),
                  finished=datetime.now(timezone.utc).isoformat(timespec="milliseconds"))
    return record


def execute_text(job_text: str) -> str:
    """:func:`execute` from JSON text to JSON text: what crosses a process boundary."""
    return json.dumps(execute(json.loads(job_text)), allow_nan=False)


def failure(job: dict[str, Any], status: str, message: str, seconds: float) -> dict[str, Any]:
    """The record of an attempt that returned nothing: the worker died (``crash``) or was
    stopped at the time limit (``timeout``); written by the executor, which saw it happen."""
    return {"cell": job["cell"], "params": job["params"], "seed": job["seed"], "attempt": job["attempt"],
            "status": status, "metrics": None, "error": {"type": status, "message": message, "traceback": None},
            "seconds": round(seconds, 6), "host": socket.gethostname(), "pid": None,
            "finished": datetime.now(timezone.utc).isoformat(timespec="milliseconds")}
