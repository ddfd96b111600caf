"""``symlearn ltl learn``: a small LTLf formula separating labelled traces.

Wired into the ``ltl`` command group with :func:`add_learn_command`.
"""

from __future__ import annotations

import argparse


def add_learn_command(ltl_subparsers, common) -> argparse.ArgumentParser:
    """Add ``learn`` to the ``ltl`` group's sub-parsers."""
    learn = ltl_subparsers.add_parser(
        "learn", parents=[common()], help="learn a formula separating positive from negative traces",
        description="Learn a small LTLf formula that holds on every positive trace and on no negative trace of "
                    "SAMPLES.json (the JSON format of the public LTLf learning benchmarks, or traces written "
                    "as lists of steps: {\"positive_traces\": [[[\"a\"], [\"b\"]]], \"negative_traces\": "
                    "[[[\"b\"]]]}; docs/FORMATS.md). Exit 0 with "
                    "'formula: null' when no formula is found within the bounds.")
    learn.add_argument("samples", metavar="SAMPLES.json", help="labelled traces (positive_traces, negative_traces)")
    learn.add_argument("--timeout", default="10", metavar="S", help="seconds before the best formula so "
                       "far is returned ('inf': no limit; default 10)")
    learn.add_argument("--max-work", type=float, default=3e7, metavar="W",
                       help="work limit of the exact search, in words evaluated (about 30 ns each; default 3e7); "
                            "raise it when the result says 'stopped by work limit'")
    learn.add_argument("--max-size", type=int, default=40, metavar="K", help="largest formula size (syntax-tree "
                       "nodes) to consider (default 40)")
    learn.add_argument("--operators", default=None, metavar="OPS",
                       help="comma-separated operators among ! X N F G & | -> U R W T "
                            "(default: ! X F G & | -> U, those of the benchmarks)")
    learn.set_defaults(handler=_learn)
    return learn


_RAISE = {"work limit": "raise --max-work", "candidate limit": "raise --max-work", "deadline": "raise --timeout",
          "max_size": "raise --max-size"}


def _render(doc: dict) -> str:
    stopped = doc.get("stopped_by")
    hint = f"; {_RAISE[stopped]} to search further" if stopped in _RAISE and not doc["optimal"] else ""
    if doc["formula"] is None:
        return f"no formula found: {doc['message']}{hint}"
    kind = "smallest" if doc["optimal"] else f"not proven smallest{hint}"
    return f"{doc['formula']}\n  size {doc['size']} ({kind}), {doc['seconds']:.2f} s"


def _learn(args: argparse.Namespace, out) -> None:
    from symlearn.errors import SymlearnError
    from symlearn.worker import seconds_limit

    # options first: a typo is reported before the learner's imports
    seconds = seconds_limit(args.timeout, name="--timeout")
    if not args.max_work > 0 or args.max_work == float("inf"):
        raise SymlearnError(f"--max-work must be a positive number, not {args.max_work}")
    if args.max_size < 1:
        raise SymlearnError(f"--max-size must be at least 1, not {args.max_size}")

    from symlearn.data.ltl_samples import load_sample
    from symlearn.learners.temporal.separating_ltl import DEFAULT_OPERATORS, learn_from_sample

    operators = DEFAULT_OPERATORS if args.operators is None else tuple(
        op.strip() for op in args.operators.split(",") if op.strip())
    sample = load_sample(args.samples)
    result = learn_from_sample(sample, timeout=float("inf") if seconds is None else seconds, max_size=args.max_size,
                               operators=operators, max_work=args.max_work)
    doc = result.to_json()
    doc["stopped_by"] = result.stopped_by
    out.result(doc, _render)
