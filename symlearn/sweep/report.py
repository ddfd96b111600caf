"""``symlearn sweep report OUT/``: the results of a sweep aggregated over seeds, as markdown
tables, a JSON summary and figures.

Rows are the parameter sets (every parameter that takes more than one value; the fixed ones go
in the header), columns the metrics, each "mean ± standard error" over the seeds with an ``ok``
record (or the bootstrap interval). With an x parameter and a group parameter (``[report]``, or
guessed: the first numeric grid parameter and the first other one) each metric also gets a
pivot table, x down and groups across, as the benchmark tables are laid out. Figures are drawn by
:mod:`~symlearn.sweep.plots`.

Only the records of the cells of the sweep file in ``sweep.json`` count: a folder adopted with
``--force`` may hold records of cells the current file no longer has.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symlearn.atomic import write_text
from symlearn.errors import DataError, clipped
from symlearn.sweep.spec import SweepSpec
from symlearn.sweep.statistics import summarize, summarize_curves
from symlearn.sweep.store import read_meta, read_records


@dataclass
class Group:
    """The cells of one parameter set, over the seeds: values per metric."""

    params: dict[str, Any]
    seeds: list[int] = field(default_factory=list)
    values: dict[str, list[Any]] = field(default_factory=dict)

    def key(self, names: list[str]) -> tuple:
        return tuple(json.dumps(self.params.get(n), sort_keys=True) for n in names)


@dataclass
class SweepResults:
    spec: SweepSpec
    groups: list[Group]
    varying: list[str]
    scalars: list[str]
    curves: list[str]
    counts: dict[str, int]
    failures: list[dict[str, Any]]

    def label(self, name: str) -> str:
        return str((self.spec.report.get("labels") or {}).get(name, name.replace("_", " ")))


def load_results(folder: str | Path) -> SweepResults:
    """The records of ``folder`` for the cells of its sweep, grouped by parameter set."""
    meta = read_meta(folder)
    try:
        spec = SweepSpec.from_json(meta["spec"])
    except DataError as exc:
        raise DataError(exc.message, file=Path(folder) / "sweep.json") from None
    except (KeyError, TypeError, AttributeError) as exc:
        raise DataError(f"the recorded sweep is incomplete ({exc})", file=Path(folder) / "sweep.json") from None
    cells = spec.cells()
    recorded = meta.get("cells")  # what the runner wrote: a hand edit that contradicts it is named
    if recorded is not None and (type(recorded) is not int or recorded != len(cells)):
        raise DataError(f"the recorded sweep says \"cells\": {clipped(json.dumps(recorded))}, "
                        f"its grid has {len(cells)}", file=Path(folder) / "sweep.json")
    wanted = {c.id: c for c in cells}
    latest_ok: dict[str, dict] = {}
    last_failure: dict[str, dict] = {}
    for record in read_records(folder):
        if record["cell"] not in wanted:
            continue
        if record["status"] == "ok":
            latest_ok.setdefault(record["cell"], record)  # the first success: later ones are --force leftovers
        else:
            last_failure[record["cell"]] = record
    groups: dict[str, Group] = {}
    for cell in cells:
        key = json.dumps(cell.params, sort_keys=True)
        group = groups.setdefault(key, Group(dict(cell.params)))
        record = latest_ok.get(cell.id)
        if record is None:
            continue
        group.seeds.append(cell.seed)
        for name, value in (record.get("metrics") or {}).items():
            if value is not None:  # null: the cell has no such value (unsolved, not finite)
                group.values.setdefault(name, []).append(_as_number(value))
    names = spec.parameter_names()
    varying = [n for n in names if len({json.dumps(g.params.get(n), sort_keys=True) for g in groups.values()}) > 1]
    scalars, curves = [], []
    for group in groups.values():
        for name, values in group.values.items():
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
                if name not in scalars:
                    scalars.append(name)
            elif all(isinstance(v, list) and v and all(isinstance(x, (int, float)) for x in v) for v in values):
                if name not in curves:
                    curves.append(name)
    scalars = [n for n in scalars if n not in curves]
    failed = [c for c in wanted if c not in latest_ok and c in last_failure]
    counts = {"cells": len(cells), "finished": len(latest_ok), "failed": len(failed),
              "not_run": len(cells) - len(latest_ok) - len(failed)}
    failures = [{"cell": c, "label": wanted[c].label(), "status": last_failure[c]["status"],
                 "message": (last_failure[c].get("error") or {}).get("message")} for c in failed]
    return SweepResults(spec, list(groups.values()), varying, scalars, curves, counts, failures)


def axes(results: SweepResults) -> tuple[str | None, str | None]:
    """The x parameter (numeric, several values) and the group parameter of tables and plots."""
    report = results.spec.report
    x, group = report.get("x"), report.get("group")

    def numeric(name):
        return all(isinstance(g.params.get(name), (int, float)) and not isinstance(g.params.get(name), bool)
                   for g in results.groups)

    if x is None:
        x = next((n for n in results.varying if numeric(n)), None)
    if group is None:
        group = next((n for n in results.varying if n != x), None)
    return x, group


def _as_number(value: Any) -> Any:
    """A JSON integer beyond a float's range as the infinity it rounds to (as JSON's ``1e400``
    reads): the statistics are floats, and a 1001-digit metric stopped the report with an
    OverflowError. Anything else unchanged (lists, strings are sorted out by kind later)."""
    if isinstance(value, int) and not isinstance(value, bool):
        try:
            float(value)
        except OverflowError:
            return math.inf if value > 0 else -math.inf
    elif isinstance(value, list):
        return [_as_number(v) for v in value]
    return value


def _format(value: float | None, digits: int = 3) -> str:
    if value is None:
        return "-"
    return f"{value:.{digits}f}"


def _cell_text(stats: dict | None, interval: str) -> str:
    """``mean ± s.e.`` with 3 decimals (1 from 100 on); a value that is the same whole number
    for every seed (a count, a size) without decimals or band."""
    if stats is None:
        return "-"
    mean = stats["mean"]
    digits = 1 if abs(mean) >= 100 else 3
    if (stats["se"] in (None, 0.0)) and float(mean).is_integer():
        return str(int(mean))
    if stats["low"] is None:
        return _format(mean, digits)
    if interval == "bootstrap":
        return f"{_format(mean, digits)} [{_format(stats['low'], digits)}, {_format(stats['high'], digits)}]"
    return f"{_format(mean, digits)} ± {_format(stats['se'], digits)}"


def aggregate(results: SweepResults, interval: str) -> list[dict[str, Any]]:
    rows = []
    for group in results.groups:
        row = {"params": group.params, "seeds": len(group.seeds), "metrics": {}, "curves": {}}
        for name in results.scalars:
            values = group.values.get(name)
            row["metrics"][name] = summarize(values, interval=interval) if values else None
        for name in results.curves:
            values = group.values.get(name)
            row["curves"][name] = summarize_curves(values, interval=interval) if values else None
        rows.append(row)
    return rows


def _markdown(results: SweepResults, rows: list[dict[str, Any]], interval: str, figures: list[str]) -> str:
    spec = results.spec
    band = ("mean [95 % bootstrap interval]" if interval == "bootstrap" else "mean ± standard error")
    counts = results.counts
    lines = [f"# {spec.name}", "",
             f"{counts['finished']} of {counts['cells']} cells finished, {counts['failed']} failed, "
             f"{counts['not_run']} not run; seeds {', '.join(map(str, spec.seeds))}; {band} over seeds.", ""]
    fixed = {k: v for k, v in rows[0]["params"].items() if k not in results.varying} if rows else {}
    if fixed:
        lines += ["Fixed: " + ", ".join(f"{k} = {json.dumps(v)}" for k, v in fixed.items()), ""]
    if results.scalars:
        header = [results.label(n) for n in results.varying] + ["seeds"] + [results.label(m) for m in results.scalars]
        lines += ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        for row in rows:
            cells = [_plain(row["params"].get(n)) for n in results.varying] + [str(row["seeds"])]
            cells += [_cell_text(row["metrics"][m], interval) for m in results.scalars]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    x, group = axes(results)
    if x and group and len(results.varying) == 2:
        xs = _values(rows, x)
        gs = _values(rows, group)
        index = {(json.dumps(r["params"][x]), json.dumps(r["params"][group])): r for r in rows}
        for metric in results.scalars:
            lines += [f"## {results.label(metric)}", "",
                      "| " + results.label(x) + " | " + " | ".join(_plain(g) for g in gs) + " |",
                      "|---|" + "---|" * len(gs)]
            for xv in xs:
                cells = []
                for gv in gs:
                    row = index.get((json.dumps(xv), json.dumps(gv)))
                    cells.append(_cell_text(row["metrics"][metric] if row else None, interval))
                lines.append(f"| {_plain(xv)} | " + " | ".join(cells) + " |")
            lines.append("")
    if figures:
        lines += ["## Figures", ""] + [f"![{Path(f).stem}]({f})" for f in figures if f.endswith(".png")] + [""]
    if results.failures:
        lines += ["## Failed cells", "", "| cell | status | error |", "|---|---|---|"]
        for failure in results.failures:
            message = str(failure["message"] or "").replace("|", "\\|").replace("\n", " ")[:200]
            lines.append(f"| {failure['label']} | {failure['status']} | {message} |")
        lines += ["", "Tracebacks: the `error` field of these cells' records in `results.jsonl`.", ""]
    return "\n".join(lines)


def _values(rows: list[dict[str, Any]], name: str) -> list[Any]:
    seen: dict[str, Any] = {}
    for row in rows:
        seen.setdefault(json.dumps(row["params"].get(name), sort_keys=True), row["params"].get(name))
    return list(seen.values())


def _plain(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value)


def write_report(folder: str | Path, out: str | Path | None = None, *, interval: str = "se",
                 plots: bool = True, formats: tuple[str, ...] = ("png", "svg")) -> dict[str, Any]:
    """Write ``report.md``, ``summary.json`` and the figures into ``out`` (default
    ``FOLDER/report``); return the summary."""
    if interval not in ("se", "bootstrap"):
        raise DataError(f"unknown interval {interval!r}", hint="se or bootstrap")
    results = load_results(folder)
    out = Path(out) if out is not None else Path(folder) / "report"
    rows = aggregate(results, interval)
    figures: list[str] = []
    if plots and results.counts["finished"]:
        from symlearn.sweep.plots import draw_figures

        figures = [str(Path(p).relative_to(out)) for p in draw_figures(results, rows, out, interval, formats)]
    markdown = _markdown(results, rows, interval, figures)
    summary = {"sweep": results.spec.name, "folder": str(folder), "interval": interval, **results.counts,
               "varying": results.varying, "metrics": results.scalars, "curves": results.curves,
               "rows": rows, "failures": results.failures, "figures": figures,
               "report": str(out / "report.md")}
    write_text(out / "report.md", markdown + "\n")
    write_text(out / "summary.json", json.dumps(summary, indent=1) + "\n")
    summary["markdown"] = markdown
    return summary
