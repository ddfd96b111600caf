"""``symlearn demo``: run the bundled pipelines into a report folder."""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    parser = subparsers.add_parser(
        "demo", parents=[common()], help="run the bundled end-to-end pipelines into a report folder",
        description="Run every bundled pipeline (or those named with --only) and write learned "
                    "rules, formulas, automata (DOT/SVG) and summary.md into a report folder.")
    parser.add_argument("--out", default="symlearn-demo", help="report folder (default ./symlearn-demo)")
    parser.add_argument("--only", action="append", default=[], metavar="PIPELINE",
                        help="run only this pipeline (repeatable); see --list")
    parser.add_argument("--list", action="store_true", help="list the pipelines and exit")
    parser.add_argument("--quick", action="store_true", help="small settings (used by the tests)")
    parser.set_defaults(handler=_demo)


def _demo(args: argparse.Namespace, out) -> None:
    from symlearn.demo.registry import pipelines
    from symlearn.demo.runner import run_demo

    if args.list:
        listing = [{"name": p.name, "title": p.title} for p in pipelines()]
        out.result({"pipelines": listing}, "\n".join(f"{p['name']:<24} {p['title']}" for p in listing))
        return
    summary = run_demo(args.out, only=args.only, seed=args.seed, quick=args.quick, log=out.note)

    def render(doc: dict) -> str:
        lines = [f"wrote {doc['out_dir']}/summary.md"]
        for p in doc["pipelines"]:
            figures = ", ".join(f"{k}={_fmt(v)}" for k, v in p["figures"].items() if not isinstance(v, (dict, list)))
            lines.append(f"  {p['name']} ({p['seconds']:.1f} s): {figures}")
        return "\n".join(lines)

    out.result(summary, render)


def _fmt(value) -> str:
    return f"{value:.3g}" if isinstance(value, float) else str(value)
