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
                    "SAMPLES.json (the JSON format of the public LTLf learning benchmarks). Exit 0 with "
                    "'formula: null' when no formula is found within the bounds.")
    learn.add_argument("samples", metavar="SAMPLES.json", help="labelled traces (positive_traces, negative_traces)")
    learn.add_argument("--timeout", type=float, default=10.0, metavar="S", help="seconds before the best formula so "
                       "far is returned (default 10)")
    learn.add_argument("--max-size", type=int, default=40, metavar="K", help="largest formula size (syntax-tree "
                       "nodes) to consider (default 40)")
    learn.add_argument("--operators", default=None, metavar="OPS",
                       help="comma-separated operators among ! X N F G & | -> U R W T "
                            "(default: ! X F G & | -> U, those of the benchmarks)")
    learn.set_defaults(handler=_learn)
    return learn


def _render(doc: dict) -> str:
    if doc["formula"] is None:
        return f"no formula found: {doc['message']}"
    kind = "smallest" if doc["optimal"] else "not proven smallest"
    return f"{doc['formula']}\n  size {doc['size']} ({kind}), {doc['seconds']:.2f} s"


def _learn(args: argparse.Namespace, out) -> None:
    from symlearn.data.ltl_samples import load_sample
    from symlearn.errors import SymlearnError
    from symlearn.learners.temporal.separating_ltl import DEFAULT_OPERATORS, learn_from_sample

    if args.timeout <= 0:
        raise SymlearnError(f"--timeout must be positive, not {args.timeout}")
    if args.max_size < 1:
        raise SymlearnError(f"--max-size must be at least 1, not {args.max_size}")
    operators = DEFAULT_OPERATORS if args.operators is None else tuple(
        op.strip() for op in args.operators.split(",") if op.strip())
    sample = load_sample(args.samples)
    result = learn_from_sample(sample, timeout=args.timeout, max_size=args.max_size, operators=operators)
    out.result(result.to_json(), _render)
