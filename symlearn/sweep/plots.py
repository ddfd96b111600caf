"""The figures of a sweep report (matplotlib, Agg; PNG and SVG, written atomically).

* metric vs parameter: for every scalar metric, the mean over seeds against the x parameter,
  one line per value of the other parameters, the band the report's interval;
* bars: without a numeric x parameter, one bar per parameter set, with the interval as error bars;
* learning curves: for every metric that is a list of numbers per cell, the pointwise mean with
  its band, one line per parameter set.

Axis text comes from ``[report.labels]`` (where units belong: "reward per episode", "time (s)");
a name without a label is shown with spaces for underscores. ``[report] curve_x`` names the x
axis of a curve metric (default "evaluation point"); ``[report] plot`` lists the metrics that get
figures (default: all).
"""

from __future__ import annotations

import io
import json
import re
from pathlib import Path
from typing import Any

from symlearn.atomic import write_bytes

MAX_LINES = 12
MAX_PANELS = 4


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(figure, stem: Path, formats: tuple[str, ...]) -> list[Path]:
    written = []
    for fmt in formats:
        buffer = io.BytesIO()
        # a fixed date keeps SVG files byte-identical between runs
        metadata = {"Date": None} if fmt == "svg" else {}
        figure.savefig(buffer, format=fmt, dpi=120, bbox_inches="tight", metadata=metadata)
        written.append(write_bytes(stem.with_suffix(f".{fmt}"), buffer.getvalue()))
    _pyplot().close(figure)
    return written


def _or(value, default):
    return default if value is None else value


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_") or "metric"


def _line_label(results, params: dict[str, Any], skip: set[str]) -> str:
    shown = [n for n in results.varying if n not in skip]
    if len(shown) == 1:
        value = params.get(shown[0])
        return value if isinstance(value, str) else json.dumps(value)
    return ", ".join(f"{results.label(n)}={params.get(n)}" for n in shown) or results.spec.name


def _plain(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value)


def _spans_decades(rows: list[dict[str, Any]], name: str) -> bool:
    """Whether the values of ``name`` are positive and span at least a factor of 50."""
    values = [r["params"].get(name) for r in rows]
    return all(v > 0 for v in values) and max(values) >= 50 * min(values)


def _unique(rows: list[dict[str, Any]], name: str | None) -> bool:
    """Whether ``name`` alone tells the rows apart."""
    return name is not None and len({json.dumps(r["params"].get(name)) for r in rows}) == len(rows)


def _panels(results, rows: list[dict[str, Any]], group: str | None) -> tuple[str | None, list]:
    """Rows split into side-by-side panels by the one varying parameter besides ``group`` (at
    most :data:`MAX_PANELS` values), so each panel has one line or bar per group value; else
    one panel of all rows."""
    others = [n for n in results.varying if n != group]
    if group in results.varying and len(others) == 1:
        facet = others[0]
        values: dict[str, Any] = {}
        for row in rows:
            values.setdefault(json.dumps(row["params"].get(facet)), row["params"].get(facet))
        if len(values) <= MAX_PANELS:
            return facet, [(v, [r for r in rows if r["params"].get(facet) == v]) for v in values.values()]
    return None, [(None, rows)]


def _row_label(results, row: dict[str, Any], short: bool, group: str | None) -> str:
    """The group's value alone when it tells the rows of a panel apart (``short``), else every
    varying parameter."""
    if short and group:
        return _plain(row["params"].get(group))
    return _line_label(results, row["params"], set())


def _legend_title(results, skip: set[str]) -> str | None:
    shown = [n for n in results.varying if n not in skip]
    return results.label(shown[0]) if len(shown) == 1 else None


def _band_note(interval: str, n_seeds: int) -> str:
    if n_seeds == 1:
        return "one seed (no band)"
    what = "95 % bootstrap interval" if interval == "bootstrap" else "± 1 standard error"
    return f"mean over {n_seeds} seeds; band: {what}"


def draw_figures(results, rows: list[dict[str, Any]], out: Path, interval: str,
                 formats: tuple[str, ...]) -> list[Path]:
    from symlearn.sweep.report import axes

    plt = _pyplot()
    folder = Path(out) / "figures"
    written: list[Path] = []
    seeds = len(results.spec.seeds)
    x, _group = axes(results)
    chosen = results.spec.report.get("plot")
    scalars = [m for m in results.scalars if chosen is None or m in chosen]
    curves = [m for m in results.curves if chosen is None or m in chosen]
    if x is not None:
        lines: dict[str, list[dict[str, Any]]] = {}
        for row in rows:
            lines.setdefault(_line_label(results, row["params"], {x}), []).append(row)
        for metric in scalars:
            figure, axis = plt.subplots(figsize=(6.4, 4.2))
            for label, members in list(lines.items())[:MAX_LINES]:
                points = sorted((r["params"][x], r["metrics"].get(metric)) for r in members
                                if r["metrics"].get(metric) is not None)
                if not points:
                    continue
                xs = [p[0] for p in points]
                (line,) = axis.plot(xs, [p[1]["mean"] for p in points], marker="o", label=label)
                if any(p[1]["low"] is not None for p in points):  # a point of one seed: no width
                    axis.fill_between(xs, [_or(p[1]["low"], p[1]["mean"]) for p in points],
                                      [_or(p[1]["high"], p[1]["mean"]) for p in points], alpha=0.2,
                                      color=line.get_color())
            axis.set_xlabel(results.label(x))
            if _spans_decades(rows, x):
                axis.set_xscale("log")  # e.g. 5 .. 500 demonstrations: evenly spread on a log axis
            axis.set_ylabel(results.label(metric))
            axis.set_title(f"{results.spec.name}\n{_band_note(interval, seeds)}", fontsize=10)
            if len(lines) > 1:
                axis.legend(title=_legend_title(results, {x}), fontsize=8)
            axis.grid(alpha=0.3)
            written += _save(figure, folder / f"{_slug(metric)}_vs_{_slug(x)}", formats)
    elif len(rows) > 1:
        facet, panels = _panels(results, rows, _group)
        short = facet is not None or _unique(rows, _group)
        for metric in scalars:
            if all(r["metrics"].get(metric) is None for r in rows):
                continue
            widest = max(len(members) for _, members in panels)
            figure, axes_list = plt.subplots(1, len(panels), squeeze=False,
                                             figsize=(max(4.8, (0.7 * widest + 1.5) * len(panels)), 4.4),
                                             layout="constrained")
            for axis, (value, members) in zip(axes_list[0], panels):
                stats = [r["metrics"].get(metric) for r in members]
                labels = [_row_label(results, r, short, _group) for r in members]
                means = [s["mean"] if s else 0.0 for s in stats]
                errors = None
                if all(s and s["low"] is not None for s in stats):
                    errors = [[s["mean"] - s["low"] for s in stats], [s["high"] - s["mean"] for s in stats]]
                axis.bar(range(len(members)), means, yerr=errors, capsize=4, color="tab:blue", alpha=0.8)
                tilt = len(members) > 4 or sum(len(t) + 2 for t in labels) > 9 * (0.7 * len(members) + 1.5)
                axis.set_xticks(range(len(members)), labels, rotation=30 if tilt else 0,
                                ha="right" if tilt else "center")
                axis.set_xlabel(results.label(_group) if short else "parameters")
                axis.set_ylabel(results.label(metric))
                if facet is not None:
                    axis.set_title(f"{results.label(facet)} = {_plain(value)}", fontsize=10)
                axis.grid(axis="y", alpha=0.3)
            figure.suptitle(f"{results.spec.name}\n{_band_note(interval, seeds)}", fontsize=10)
            written += _save(figure, folder / f"{_slug(metric)}_bars", formats)
    curve_x = results.spec.report.get("curve_x") or {}
    facet, panels = _panels(results, rows, _group)
    short = facet is not None or _unique(rows, _group)
    for metric in curves:
        figure, axes_list = plt.subplots(1, len(panels), squeeze=False, figsize=(5.2 * len(panels) + 1.2, 4.4),
                                         layout="constrained")
        skipped = 0
        for axis, (value, members) in zip(axes_list[0], panels):
            drawn = 0
            for row in members:
                curve = row["curves"].get(metric)
                if curve is None:
                    continue
                if drawn >= MAX_LINES:
                    skipped += 1
                    continue
                steps = list(range(1, curve["length"] + 1))
                (line,) = axis.plot(steps, curve["mean"], label=_row_label(results, row, short, _group))
                if curve["n"] > 1:
                    axis.fill_between(steps, curve["low"], curve["high"], alpha=0.2, color=line.get_color())
                drawn += 1
            axis.set_xlabel(str(curve_x.get(metric, "evaluation point")))
            axis.set_ylabel(results.label(metric))
            if facet is not None:
                axis.set_title(f"{results.label(facet)} = {_plain(value)}", fontsize=10)
            if drawn > 1:
                axis.legend(title=results.label(_group) if short else None, fontsize=8)
            axis.grid(alpha=0.3)
        note = _band_note(interval, seeds)
        if skipped:
            note += f"; {skipped} parameter sets not drawn (more than {MAX_LINES} lines)"
        figure.suptitle(f"{results.spec.name}\n{note}", fontsize=10)
        written += _save(figure, folder / f"{_slug(metric)}_curve", formats)
    return written
