"""``symlearn ilp``: learn ASP rules from an ILASP-style task file, check and inspect hypotheses."""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    group = subparsers.add_parser("ilp", help="learn ASP rules from ILASP-style task files",
                                  description="Inductive logic programming on ILASP-compatible task files (.las).")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="ilp_command", metavar="SUBCOMMAND")

    learn = commands.add_parser("learn", parents=[common()], help="learn a minimum-cost hypothesis",
                                description="Learn the cheapest rules covering the task's examples.")
    learn.add_argument("task", help="task file (.las)")
    learn.add_argument("--bk", action="append", default=[], metavar="F.lp", help="extra background file (repeatable)")
    learn.add_argument("--timeout", type=float, default=60.0, metavar="S", help="time limit in seconds (default 60)")
    learn.add_argument("--noise", action="store_true", help="examples with @penalty may stay uncovered at that cost")
    learn.add_argument("--max-body", type=int, default=None, metavar="N", help="max body literals per rule (default 3)")
    learn.add_argument("--method", choices=("auto", "single", "general"), default="auto",
                       help="search path (default: auto)")
    learn.add_argument("--dialect", choices=("ilasp", "fastlas"), default="ilasp",
                       help="ilasp: #modeb atoms may also be negated unless (positive); fastlas: modes as written")
    learn.add_argument("--coverage", action="store_true", help="also print which example each rule covers")
    learn.add_argument("-o", "--output", metavar="OUT.lp", help="write the rules as an editable .lp file")
    learn.set_defaults(handler=_learn)

    check = commands.add_parser("check", parents=[common()], help="re-score a (possibly edited) hypothesis",
                                description="Load rules from an .lp file and report which examples they cover.")
    check.add_argument("task")
    check.add_argument("hypothesis", help="rules (.lp), e.g. written by 'ilp learn -o'")
    check.add_argument("--bk", action="append", default=[], metavar="F.lp")
    check.add_argument("--timeout", type=float, default=60.0, metavar="S")
    check.set_defaults(handler=_check)

    space = commands.add_parser("space", parents=[common()], help="size and a sample of the hypothesis space",
                                description="Generate the hypothesis space of the task's mode bias.")
    space.add_argument("task")
    space.add_argument("--max-body", type=int, default=None, metavar="N")
    space.add_argument("--dialect", choices=("ilasp", "fastlas"), default="ilasp")
    space.add_argument("--sample", type=int, default=10, metavar="K", help="rules to show (default 10)")
    space.set_defaults(handler=_space)


def _load(args):
    from symlearn.logic.ilp import load_task

    task = load_task(args.task, extra_background=getattr(args, "bk", []),
                     dialect=getattr(args, "dialect", "ilasp"))
    if getattr(args, "max_body", None) is not None:
        if args.max_body < 1:
            from symlearn.errors import SymlearnError

            raise SymlearnError("--max-body must be at least 1")
        task.max_body = args.max_body
    return task


def _render_learn(doc: dict) -> str:
    if not doc["rules"] and doc["score"] is None:
        return "no hypothesis found\n" + doc["diagnostics_text"]
    lines = list(doc["rules"]) or ["% (empty hypothesis)"]
    lines.append(f"% score {doc['score']} ({'optimal' if doc['optimal'] else 'NOT proven optimal'}), "
                 f"{doc['seconds']:.2f} s, {doc['space_size']} candidate rules, {doc['method']} search")
    uncovered = [k for k, v in doc["coverage"].items() if not v]
    if uncovered:
        lines.append(f"% uncovered (penalised): {', '.join(uncovered)}")
    if doc.get("matrix"):
        for rule, row in doc["matrix"].items():
            lines.append(f"% {rule}  covers {sum(row.values())}/{len(row)} alone")
    if doc.get("written"):
        lines.append(f"% written to {doc['written']}")
    return "\n".join(lines)


def _learn(args: argparse.Namespace, out) -> int | None:
    from symlearn.logic.ilp import coverage_matrix, learn

    task = _load(args)
    result = learn(task, timeout=args.timeout, noise=args.noise, method=args.method)
    doc = result.to_dict()
    doc["diagnostics_text"] = result.diagnostics.render()
    if result.hypothesis is not None and args.coverage:
        doc["matrix"] = coverage_matrix(task, result.hypothesis, timeout=args.timeout)
    if result.hypothesis is not None and args.output:
        header = (f"learned by symlearn ilp learn from {args.task}\n"
                  f"score {result.score} ({'optimal' if result.optimal else 'not proven optimal'}), "
                  f"{result.space_size} candidate rules")
        result.hypothesis.to_lp(args.output, header=header)
        doc["written"] = args.output
    out.result(doc, _render_learn)
    return None if result.hypothesis is not None else 2  # like bad input: the task admits no solution


def _render_check(doc: dict) -> str:
    lines = [f"{doc['covered']}/{doc['total']} examples covered; cost {doc['cost']}, penalty {doc['penalty']}, "
             f"score {doc['score'] if doc['score'] is not None else 'n/a (an example without penalty is uncovered)'}"]
    for ident, ok in doc["coverage"].items():
        if not ok:
            lines.append(f"  uncovered: {ident}")
    return "\n".join(lines)


def _check(args: argparse.Namespace, out) -> int | None:
    from symlearn.logic.asp import Hypothesis
    from symlearn.logic.ilp import score

    task = _load(args)
    hypothesis = Hypothesis.from_lp(args.hypothesis, background=task.background)
    report = score(task, hypothesis, timeout=args.timeout)
    report["rules"] = hypothesis.rules
    out.result(report, _render_check)
    return None


def _render_space(doc: dict) -> str:
    lines = [f"{doc['size']} candidate rules" + (" (truncated)" if doc["truncated"] else "")]
    lines += [f"  {r['rule']}   % cost {r['cost']}" for r in doc["sample"]]
    lines += [f"note: {n}" for n in doc["notes"]]
    return "\n".join(lines)


def _space(args: argparse.Namespace, out) -> None:
    from symlearn.logic.ilp import generate_space

    task = _load(args)
    space = generate_space(task)
    step = max(1, len(space) // max(args.sample, 1))
    sample = space.candidates[::step][:args.sample]
    out.result({"size": len(space), "truncated": space.truncated, "notes": space.notes,
                "sample": [{"rule": c.text, "cost": c.cost} for c in sample]}, _render_space)
