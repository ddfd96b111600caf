"""``symlearn sweep``: run a grid of experiments from a sweep file (TOML), resume it, report it.

``symlearn sweep run FILE.toml [--out DIR] [--local] [--address ADDR] [--workers N] [--retries N]
[--force] [--json]``: every cell (parameter set x seed) not finished yet, on an embedded Ray
(default), a Ray cluster (``--address``) or a local process pool (``--local``); one record per
attempt appended to ``DIR/results.jsonl``. Exit 0 when every cell finished, 2 when some failed
after their retries (their errors and tracebacks are in the store) or on bad input.

``symlearn sweep report DIR [--output REPORT_DIR] [--interval se|bootstrap] [--no-plots] [--json]``:
markdown tables, ``summary.json`` and figures (PNG and SVG) in ``DIR/report``.

The file format is described in :mod:`symlearn.sweep.spec`; the store in :mod:`symlearn.sweep.store`.
"""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    group = subparsers.add_parser("sweep", help="run, resume and report grids of experiments (sweep files)",
                                  description="Run a grid of experiments described by a sweep file, resumably, "
                                              "on Ray or a local process pool; aggregate and plot the results.")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="sweep_command", metavar="SUBCOMMAND")

    run = commands.add_parser(
        "run", parents=[common()], help="run the unfinished cells of a sweep file",
        description="Run every cell (parameter set x seed) of the sweep file that has no finished record in the "
                    "results folder yet; a crash or a timeout is recorded and the cell retried. Re-running the "
                    "same command resumes. Exit 2 when some cells failed after their retries.")
    run.add_argument("file", metavar="FILE.toml", help="the sweep file")
    run.add_argument("--out", metavar="DIR", help="results folder (default: FILE without .toml, plus '-results')")
    where = run.add_mutually_exclusive_group()
    where.add_argument("--local", action="store_true",
                       help="a process pool on this machine instead of Ray (no extra needed)")
    where.add_argument("--address", metavar="ADDR",
                       help="attach to a running Ray cluster (e.g. 'auto' or 'ray://head:10001') instead of "
                            "starting one on this machine")
    run.add_argument("--workers", type=int, metavar="N", help="cells at once (default: one per core / per "
                                                              "[sweep] cpus)")
    run.add_argument("--retries", type=int, metavar="N",
                     help="further attempts of a cell that raised, crashed or timed out (default: [sweep] "
                          "retries, else 2)")
    run.add_argument("--force", action="store_true",
                     help="write into a folder of another sweep file (its finished cells that this file also "
                          "has are kept) or a non-empty folder")
    run.add_argument("--allow-package", action="append", default=[], metavar="NAME",
                     help="let the sweep file name functions of this installed package (repeatable); without "
                          "it, a sweep runs functions from its own files and from modules outside the Python "
                          "installation only")
    run.add_argument("--allow-outside", action="store_true",
                     help="let the sweep file's function file and its command's paths lie outside its own folder "
                          "and the current folder; only for a file you trust")
    run.set_defaults(handler=_run)

    report = commands.add_parser(
        "report", parents=[common()], help="tables and plots of a sweep's results",
        description="Aggregate the results over seeds (mean and standard error, or a bootstrap interval) into "
                    "report.md, summary.json and figures (PNG and SVG).")
    report.add_argument("folder", metavar="DIR", help="the results folder of 'sweep run', or the sweep file whose "
                                                      "default results folder (FILE without .toml, plus "
                                                      "'-results') to report")
    report.add_argument("--output", metavar="REPORT_DIR", help="where to write the report (default: DIR/report)")
    report.add_argument("--interval", choices=("se", "bootstrap"), default="se",
                        help="band: mean ± standard error (default) or a 95%% bootstrap interval")
    report.add_argument("--no-plots", action="store_true", help="tables only")
    report.set_defaults(handler=_report)


def default_out(file: str) -> str:
    from pathlib import Path

    path = Path(file)
    return str(path.with_name(path.stem + "-results"))


def _results_folder(given: str) -> str:
    """The folder ``sweep report`` reads: a sweep file given in its place (as ``sweep run`` takes)
    stands for the folder ``sweep run`` wrote by default; an ``--out`` folder must be named."""
    from pathlib import Path

    path = Path(given)
    if path.suffix == ".toml" and path.is_file():
        folder = default_out(given)
        if not (Path(folder) / "sweep.json").is_file():
            from symlearn.errors import DataError

            raise DataError(f"{given} is a sweep file and its default results folder {folder} holds no results yet",
                            hint=f"run 'symlearn sweep run {given}' first, or give the --out folder it wrote")
        return folder
    return given


def _render_run(doc: dict) -> str:
    if not doc["attempts"]:
        lines = [f"{doc['name']}: all {doc['cells']} cells finished already; nothing to run"]
    else:
        workers = f"{doc['workers']} worker{'s' if doc['workers'] != 1 else ''}"
        lines = [f"{doc['name']}: {doc['finished']} cells finished now, {doc['skipped']} already finished, "
                 f"{doc['failed']} failed ({doc['cells']} cells; {doc['attempts']} attempts, {doc['retried']} "
                 f"retried; {doc['seconds']:.1f} s on {doc['backend']} with {workers})"]
    for failure in doc["failures"][:10]:
        lines.append(f"  failed: {failure['label']}: {failure['status']}: {failure['message']}")
    if len(doc["failures"]) > 10:
        lines.append(f"  ... and {len(doc['failures']) - 10} more")
    lines.append(f"results: {doc['out']}/results.jsonl (report: symlearn sweep report {doc['out']})")
    return "\n".join(lines)


def _run(args: argparse.Namespace, out) -> int | None:
    import sys

    from symlearn.sweep.runner import run_sweep
    from symlearn.sweep.spec import read_spec

    spec = read_spec(args.file, allow_packages=args.allow_package, allow_outside=args.allow_outside)
    folder = args.out or default_out(args.file)
    summary = run_sweep(spec, folder, backend="local" if args.local else "ray", workers=args.workers,
                        retries=args.retries, force=args.force, address=args.address).as_dict()
    out.result(summary, _render_run)
    if summary["failed"]:
        print(f"symlearn: error: {summary['failed']} of {summary['cells']} cells failed after their retries; "
              f"their errors are in {folder}/results.jsonl (run again to retry them)", file=sys.stderr)
        return 2
    return None


def _render_report(doc: dict) -> str:
    shown = doc["markdown"]
    return shown + f"\n\nwritten: {doc['report']}, summary.json, {len(doc['figures'])} figure files"


def _report(args: argparse.Namespace, out) -> None:
    from symlearn.sweep.report import write_report

    doc = write_report(_results_folder(args.folder), args.output, interval=args.interval, plots=not args.no_plots)
    if out.json_mode:
        doc = {k: v for k, v in doc.items() if k != "markdown"}
    out.result(doc, _render_report)
