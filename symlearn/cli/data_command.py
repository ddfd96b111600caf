"""``symlearn data``: inspect, validate and convert demonstration files."""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    group = subparsers.add_parser("data", help="inspect, validate and convert demonstration files",
                                  description="Inspect, validate and convert demonstration files (.jsonl, .npz).")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="data_command", metavar="SUBCOMMAND")

    info = commands.add_parser("info", parents=[common()], help="summary statistics of a file",
                               description="Print summary statistics of a demonstrations file.")
    info.add_argument("file", help="a .jsonl or .npz demonstrations file")
    info.set_defaults(handler=_info)

    validate = commands.add_parser("validate", parents=[common()], help="check a file and report the first problem",
                                   description="Load a demonstrations file; exit 0 if it is valid, 2 with the problem if not.")
    validate.add_argument("file")
    validate.set_defaults(handler=_validate)

    convert = commands.add_parser("convert", parents=[common()], help="convert between .jsonl and .npz",
                                  description="Convert a demonstrations file to another format (by suffix).")
    convert.add_argument("source")
    convert.add_argument("target")
    convert.set_defaults(handler=_convert)


def _render_summary(doc: dict) -> str:
    s = doc["summary"]
    lines = [
        f"{doc['file']}: {s['n_trajectories']} trajectories, {s['n_steps']} steps",
        f"  states:  {s['state_kind']}" + (f" {tuple(s['state_shape'])}" if s["state_shape"] else ""),
        f"  actions: {s['action_kind'] or 'none'}",
        "  length:  min {min:g}  mean {mean:.2f}  max {max:g}".format(**s["length"]),
    ]
    if "return" in s:
        lines.append("  return:  min {min:g}  mean {mean:.3f}  max {max:g}".format(**s["return"]))
    if "n_distinct_states" in s:
        lines.append(f"  distinct states: {s['n_distinct_states']}")
    if s.get("label_counts"):
        counts = ", ".join(f"{k}={v}" for k, v in s["label_counts"].items())
        lines.append(f"  labels (steps true): {counts}")
    return "\n".join(lines)


def _info(args: argparse.Namespace, out) -> None:
    from symlearn.data import load

    demos = load(args.file)
    out.result({"file": args.file, "summary": demos.summary(), "metadata": demos.metadata}, _render_summary)


def _validate(args: argparse.Namespace, out) -> None:
    from symlearn.data import load

    demos = load(args.file)
    out.result({"file": args.file, "valid": True, "n_trajectories": len(demos)},
               f"{args.file}: valid ({len(demos)} trajectories)")


def _convert(args: argparse.Namespace, out) -> None:
    from symlearn.data import load, save

    demos = load(args.source)
    save(demos, args.target)
    out.result({"source": args.source, "target": args.target, "n_trajectories": len(demos)},
               f"wrote {args.target} ({len(demos)} trajectories)")
