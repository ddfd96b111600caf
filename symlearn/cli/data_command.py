"""``symlearn data``: inspect, validate and convert demonstration files, and record them
(``record``: :mod:`symlearn.cli.data_record`).

Every subcommand reads what :func:`symlearn.data.load` reads: symlearn's ``.jsonl``/``.npz``,
D4RL tables (``.hdf5``/``.h5``/``.npz``) and Minari dataset folders; ``convert`` writes by the
target's suffix (``.hdf5``: a D4RL table; ``--to d4rl`` for a D4RL ``.npz``).
"""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    group = subparsers.add_parser("data", help="inspect, validate, convert and record demonstration files",
                                  description="Inspect, validate and convert demonstration files: symlearn's .jsonl and "
                                              ".npz, D4RL tables (.hdf5, .npz) and Minari dataset folders; record "
                                              "them from a policy `train` saved.")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="data_command", metavar="SUBCOMMAND")

    info = commands.add_parser("info", parents=[common()], help="summary statistics of a file",
                               description="Print summary statistics of a demonstrations file.")
    info.add_argument("file", help="a .jsonl, .npz or .hdf5 demonstrations file, or a Minari dataset folder")
    info.set_defaults(handler=_info)

    validate = commands.add_parser("validate", parents=[common()], help="check a file and report the first problem",
                                   description="Load a demonstrations file; exit 0 if it is valid, 2 with the problem if not.")
    validate.add_argument("file")
    validate.set_defaults(handler=_validate)

    convert = commands.add_parser("convert", parents=[common()],
                                  help="convert between .jsonl, .npz and D4RL tables (from Minari folders too)",
                                  description="Convert demonstrations to another format, chosen by the target's "
                                              "suffix: .jsonl, .npz (symlearn's archive), .hdf5/.h5 (a D4RL "
                                              "table). The source may also be a Minari dataset folder.")
    convert.add_argument("source", help="a demonstrations file or a Minari dataset folder")
    convert.add_argument("target", help="the file to write (.jsonl, .npz, .hdf5, .h5)")
    convert.add_argument("--to", choices=("symlearn", "d4rl"), default=None,
                         help="the target's layout: d4rl writes a D4RL table also to .npz (default: symlearn's "
                              "format for .jsonl/.npz, D4RL for .hdf5)")
    convert.set_defaults(handler=_convert)

    from symlearn.cli.data_record import register as register_record

    register_record(commands, common)


def _render_summary(doc: dict) -> str:
    s = doc["summary"]
    lines = [
        f"{doc['file']} ({doc['format']}): {s['n_trajectories']} trajectories, {s['n_steps']} steps",
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


def _load_noting(args: argparse.Namespace, out):
    """The demonstrations; for a D4RL table with next_observations, a warning where a row's next
    observation is not the next row's observation inside an episode (episodes joined without a
    timeouts flag, as in D4RL's v0 tables)."""
    from symlearn.data import load
    from symlearn.data.files import detect

    fmt = detect(args.file)
    if fmt not in ("d4rl-npz", "d4rl-hdf5"):
        return load(args.file)
    from symlearn.data.d4rl_format import read_d4rl_hdf5, read_d4rl_npz

    report: dict = {}
    demos = (read_d4rl_npz if fmt == "d4rl-npz" else read_d4rl_hdf5)(args.file, report)
    if report.get("joined_rows"):
        first, count = report["joined_rows"]
        out.note(f"warning: {args.file}: in {count} row(s) inside an episode (first: row {first}) the next "
                 "observation is not the next row's observation: episodes may have been joined without a "
                 "timeouts flag (they are cut only where terminals or timeouts say)")
    return demos


def _info(args: argparse.Namespace, out) -> None:
    from symlearn.data.files import detect

    demos = _load_noting(args, out)
    out.result({"file": args.file, "format": detect(args.file), "summary": demos.summary(),
                "metadata": demos.metadata}, _render_summary)


def _validate(args: argparse.Namespace, out) -> None:
    demos = _load_noting(args, out)
    out.result({"file": args.file, "valid": True, "n_trajectories": len(demos)},
               f"{args.file}: valid ({len(demos)} trajectories)")


def _convert(args: argparse.Namespace, out) -> None:
    from symlearn.data import load, save

    demos = load(args.source)
    save(demos, args.target, format=args.to)
    out.result({"source": args.source, "target": args.target, "n_trajectories": len(demos)},
               f"wrote {args.target} ({len(demos)} trajectories)")
