"""``symlearn ilp``: learn ASP rules from an ILASP-style task file, check and inspect hypotheses.

Every sub-command reads and grounds the user's programs in a worker process
(:mod:`symlearn.worker`) bounded by ``--timeout`` and ``--max-memory``: clingo cannot
interrupt grounding, and a recursive background grounds until memory is gone. The parent only
parses arguments, waits, prints and writes the output file.
"""

from __future__ import annotations

import argparse
import re
import shlex
import sys
import time

_TIMEOUT_HELP = "time limit in seconds for the whole command, grounding included ('inf': none; default {})"
_MEMORY_HELP = ("memory limit of the worker that grounds and solves, in MB (0: none; default: "
                "$SYMLEARN_MAX_MEMORY_MB or 1024)")


def _limits(parser: argparse.ArgumentParser, default_timeout: str) -> None:
    parser.add_argument("--timeout", default=default_timeout, metavar="S", help=_TIMEOUT_HELP.format(default_timeout))
    parser.add_argument("--max-memory", default=None, metavar="MB", help=_MEMORY_HELP)


def register(subparsers, common) -> None:
    group = subparsers.add_parser("ilp", help="learn ASP rules from ILASP-style task files",
                                  description="Inductive logic programming on ILASP-compatible task files (.las).")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="ilp_command", metavar="SUBCOMMAND")

    learn = commands.add_parser("learn", parents=[common()], help="learn a minimum-cost hypothesis",
                                description="Learn the cheapest rules covering the task's examples. Exit 2 when "
                                            "no hypothesis covers them or time runs out before one is found.")
    learn.add_argument("task", metavar="TASK.las", help="task file: background, #pos/#neg examples, mode bias")
    learn.add_argument("--bk", action="append", default=[], metavar="F.lp", help="extra background file (repeatable)")
    _limits(learn, "60")
    learn.add_argument("--noise", action="store_true", help="examples with @penalty may stay uncovered at that cost")
    learn.add_argument("--max-body", type=int, default=None, metavar="N", help="max body literals per rule (default 3)")
    learn.add_argument("--method", choices=("auto", "single", "general"), default="auto",
                       help="search path (default: auto)")
    learn.add_argument("--dialect", choices=("ilasp", "fastlas"), default="ilasp",
                       help="ilasp: #modeb atoms may also be negated unless (positive); fastlas: modes as written")
    learn.add_argument("--coverage", action="store_true", help="also print which example each rule covers")
    learn.add_argument("-o", "--output", metavar="OUT.lp", help="write the rules as an editable .lp file")
    learn.set_defaults(handler=_learn)

    check = commands.add_parser(
        "check", parents=[common()], help="re-score a (possibly edited) hypothesis",
        description="Load rules from an .lp file and report which examples of the task they cover, their cost "
                    "and score. Exit 0 when every example without a penalty is covered, 2 otherwise (so a CI job "
                    "fails on an edit that breaks a hard example); the report is printed either way.")
    check.add_argument("task", metavar="TASK.las", help="the task file the rules are checked against")
    check.add_argument("hypothesis", metavar="HYP.lp", help="rules (.lp), e.g. written by 'ilp learn -o'")
    check.add_argument("--bk", action="append", default=[], metavar="F.lp", help="extra background file (repeatable)")
    check.add_argument("--dialect", choices=("ilasp", "fastlas"), default="ilasp",
                       help="how the task file is read (as for 'ilp learn')")
    check.add_argument("--coverage", action="store_true",
                       help="for every uncovered example, also the rule that excludes it (a positive) or that "
                            "no rule excludes it (a negative)")
    _limits(check, "60")
    check.set_defaults(handler=_check)

    space = commands.add_parser("space", parents=[common()], help="size and a sample of the hypothesis space",
                                description="Generate the hypothesis space of the task's mode bias.")
    space.add_argument("task", metavar="TASK.las", help="task file with the mode bias")
    space.add_argument("--max-body", type=int, default=None, metavar="N", help="max body literals per rule (default 3)")
    space.add_argument("--dialect", choices=("ilasp", "fastlas"), default="ilasp",
                       help="ilasp: #modeb atoms may also be negated unless (positive); fastlas: modes as written")
    space.add_argument("--sample", type=int, default=10, metavar="K", help="rules to show (default 10)")
    _limits(space, "60")
    space.set_defaults(handler=_space)


# -- words: the library speaks Python, the command line speaks flags ------------------------------

_CLI_WORDS = [
    (re.compile(r"noise=True"), "--noise"),
    (re.compile(r"method='general'"), "--method general"),
    (re.compile(r"\bmax_body\b"), "--max-body"),
    (re.compile(r"\braise the timeout\b"), "raise --timeout"),
    (re.compile(r"\bor raise the limit\b"), "or simplify the mode bias"),
]


def cli_words(text: str | None) -> str | None:
    """A library message or hint with API names replaced by the command's flags."""
    if text is None:
        return None
    for pattern, words in _CLI_WORDS:
        text = pattern.sub(words, text)
    return text


def _translated(error):
    """The same error with its message and hint in the command's words."""
    from symlearn.errors import SymlearnError

    if not isinstance(error, SymlearnError):
        return error
    return type(error)(cli_words(error.message), file=error.file, line=error.line, column=error.column,
                       hint=cli_words(error.hint))


# -- the worker side: everything that reads or grounds the user's programs ------------------------

def _load(job: dict):
    from symlearn.errors import SymlearnError
    from symlearn.logic.ilp import load_task

    task = load_task(job["task"], extra_background=job.get("bk", []), dialect=job.get("dialect", "ilasp"))
    if job.get("max_body") is not None:
        if job["max_body"] < 1:
            raise SymlearnError("--max-body must be at least 1")
        task.max_body = job["max_body"]
    return task


def _learn_job(job: dict) -> dict:
    from symlearn.errors import LimitExceededError
    from symlearn.worker import remaining
    from symlearn.logic.ilp import learn

    task = _load(job)
    result = learn(task, timeout=remaining(job["started"], job["seconds"]), noise=job["noise"],
                   method=job["method"])
    if result.hypothesis is None and result.timed_out:
        raise LimitExceededError(f"time ran out: no hypothesis found within --timeout {job['seconds']:g} s "
                                 f"({result.space_size} candidate rules)", file=job["task"],
                                 hint=_timeout_hint(result.diagnostics.hints))
    doc = result.to_dict()
    doc["diagnostics"]["hints"] = [cli_words(h) for h in doc["diagnostics"]["hints"]]
    doc["diagnostics_text"] = cli_words(result.diagnostics.render())
    if result.hypothesis is not None and job["coverage"]:
        doc["matrix"] = _coverage(task, result.hypothesis, job, task.examples)
    if result.hypothesis is not None and job["output"]:
        header = (f"learned by symlearn ilp learn from {job['task']}\n"
                  f"score {result.score} ({'optimal' if result.optimal else 'not proven optimal'}), "
                  f"{result.space_size} candidate rules")
        doc["lp_text"] = result.hypothesis.lp_text(header, recheck=_recheck_command(job))
    return doc


def _timeout_hint(hints: list[str]) -> str:
    """The learner's time-out hint without what the message already says ("raise --timeout",
    with its warning where the space may hold no hypothesis at all)."""
    said = "time ran out before a hypothesis was found: "
    return cli_words(hints[0]).removeprefix(said) if hints else "raise --timeout"


def _recheck_command(job: dict) -> str:
    words = ["symlearn", "ilp", "check", job["task"], job["output"]]
    for extra in job.get("bk", []):
        words += ["--bk", extra]
    if job.get("dialect", "ilasp") != "ilasp":
        words += ["--dialect", job["dialect"]]
    return " ".join(shlex.quote(str(w)) for w in words)


def _check_job(job: dict) -> dict:
    from symlearn.logic.asp import Hypothesis
    from symlearn.logic.asp.program import Program
    from symlearn.worker import remaining
    from symlearn.logic.ilp import score

    task = _load(job)
    hypothesis = Hypothesis.from_lp(job["hypothesis"], background=task.background)
    report = score(task, hypothesis, timeout=remaining(job["started"], job["seconds"]))
    report["rules"] = hypothesis.rules
    report["passed"] = not report["uncovered_without_penalty"]
    rules_program = Program.from_file(job["hypothesis"], expand=False)
    report["warnings"] = _undefined_predicates(task, rules_program) + _unmatched_arguments(task, hypothesis,
                                                                                           rules_program)
    matrix = None
    if job["coverage"]:  # the report names the rules that exclude an uncovered positive: only those columns
        wanted = [e for e in task.examples if e.positive and not report["coverage"][e.id]]
        matrix = _coverage(task, hypothesis, job, wanted)
    report["uncovered"] = [_uncovered(e, matrix) for e in task.examples if not report["coverage"][e.id]]
    return report


def _coverage(task, hypothesis, job: dict, examples) -> dict:
    """``--coverage``: each rule alone on ``examples``, in what is left of ``--timeout``."""
    from symlearn.errors import LimitExceededError
    from symlearn.logic.ilp import coverage_matrix
    from symlearn.worker import remaining

    try:
        return coverage_matrix(task, hypothesis, timeout=remaining(job["started"], job["seconds"]), examples=examples)
    except LimitExceededError:  # its own budget is what was left: name the user's
        raise LimitExceededError(f"time limit of {job['seconds']:g} s reached while checking each of the "
                                 f"{len(hypothesis.rules)} rules alone (--coverage)", hint="raise --timeout") from None


def _undefined_predicates(task, rules) -> list[dict]:
    """Body predicates of the rule file that the background, the examples and the rules define nowhere."""
    from symlearn.logic.asp.predicates import defined_signatures, undefined_predicates

    defined = defined_signatures([task.background] + [e.context for e in task.examples if e.context.text.strip()])
    defined |= {(a.name, len(a.arguments)) for e in task.examples for a in (*e.inclusions, *e.exclusions)}
    return [u.as_dict() for u in undefined_predicates(rules, defined)]


def _unmatched_arguments(task, hypothesis, rules) -> list[dict]:
    """Arguments of the rule file's atoms that no atom the task can derive matches (a string for a
    constant, a one-off capitalised variable for a constant): read from one grounding of the
    background, every context and the rules, which over-approximates what any answer set holds."""
    import clingo

    from symlearn.logic.asp import clingo_adapter as cl
    from symlearn.logic.asp.argument_values import argument_values, unmatched_arguments
    from symlearn.logic.asp.program import Program
    from symlearn.logic.ilp.encoding import ACTIVE, examples_program, tagged_rules

    indexed = list(enumerate(task.examples))
    program = (examples_program(task, indexed, accept=False) + tagged_rules(hypothesis.program())
               + Program.from_text("\n".join(f"{ACTIVE}({i})." for i, _ in indexed), source="<examples>"))
    control = cl.ground(program)  # kept alive while its atoms are read (they belong to it)
    symbols = [a.symbol for a in control.symbolic_atoms]
    # every atom carries its example's index as its first argument: dropped here
    values = argument_values(clingo.Function(s.name, s.arguments[1:], s.positive) for s in symbols
                             if s.type == clingo.SymbolType.Function and s.arguments and s.name != ACTIVE)
    return [u.as_dict() for u in unmatched_arguments(rules, values)]


def _uncovered(example, matrix: dict | None) -> dict:
    """An uncovered example for the report: polarity, where, context and (with --coverage) why."""
    context = " ".join(example.context.text.split())
    doc = {"id": example.id, "polarity": "positive" if example.positive else "negative", "line": example.line,
           "penalty": example.penalty, "context": context if len(context) <= 200 else context[:197] + "...",
           "inclusions": [str(a) for a in example.inclusions], "exclusions": [str(a) for a in example.exclusions]}
    if matrix is not None:
        if example.positive:  # the rules that reject it on their own
            doc["excluded_by"] = [rule for rule, row in matrix.items() if not row[example.id]]
        else:
            doc["excluded_by"] = []
    return doc


def _space_job(job: dict) -> dict:
    from symlearn.worker import remaining
    from symlearn.logic.ilp import generate_space

    task = _load(job)
    space = generate_space(task, timeout=remaining(job["started"], job["seconds"]))
    step = max(1, len(space) // max(job["sample"], 1))
    sample = space.candidates[::step][:job["sample"]]
    return {"size": len(space), "truncated": space.truncated, "notes": space.notes,
            "sample": [{"rule": c.text, "cost": c.cost} for c in sample]}


# -- the parent side -----------------------------------------------------------------------------

def _run(function, args: argparse.Namespace, **job) -> dict:
    """``function(job)`` in the bounded worker, with the command's limits and words."""
    from symlearn.worker import memory_limit_mb, run_limited, seconds_limit

    started = time.monotonic()
    seconds = seconds_limit(args.timeout, name="--timeout")
    memory = memory_limit_mb(args.max_memory, name="--max-memory")
    job.update(task=args.task, bk=list(getattr(args, "bk", [])), dialect=getattr(args, "dialect", "ilasp"),
               max_body=getattr(args, "max_body", None), seconds=seconds, started=started)
    try:
        return run_limited(function, job, seconds=seconds, memory_mb=memory, started=started,
                           what=f"grounding and solving {args.task}", time_hint="raise --timeout",
                           memory_hint="raise --max-memory (or SYMLEARN_MAX_MEMORY_MB; 0: no limit) if the task "
                                       "is meant to be this large, else look for a recursive rule or a huge "
                                       "interval in the background")
    except Exception as error:  # noqa: BLE001 - re-raised in the command's words
        translated = _translated(error)
        if translated is error:
            raise
        raise translated from None


def _render_learn(doc: dict) -> str:
    if not doc["rules"] and doc["score"] is None:
        return "no hypothesis found\n" + doc["diagnostics_text"]
    lines = list(doc["rules"]) or ["% (empty hypothesis)"]
    proven = "optimal" if doc["optimal"] else "NOT proven optimal"
    if not doc["optimal"] and doc["diagnostics"].get("timed_out"):
        proven += ": time ran out (raise --timeout)"
    lines.append(f"% score {doc['score']} ({proven}), "
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
    doc = _run(_learn_job, args, noise=args.noise, method=args.method, coverage=args.coverage, output=args.output)
    lp_text = doc.pop("lp_text", None)
    if lp_text is not None:
        from symlearn.atomic import write_text

        write_text(args.output, lp_text)
        doc["written"] = args.output
    out.result(doc, _render_learn)
    return None if doc["rules"] or doc["score"] is not None else 2  # like bad input: the task admits no solution


def _render_check(doc: dict) -> str:
    lines = [f"{doc['covered']}/{doc['total']} examples covered; cost {doc['cost']}, penalty {doc['penalty']}, "
             f"score {doc['score'] if doc['score'] is not None else 'n/a (an example without penalty is uncovered)'}"]
    for u in doc.get("uncovered", []):
        where = f", task line {u['line']}" if u["line"] else ""
        penalty = f", penalty {u['penalty']}" if u["penalty"] is not None else ""
        line = f"  uncovered: {u['id']} ({u['polarity']}{where}{penalty}) context: {u['context'] or '(empty)'}"
        if u["polarity"] == "positive" and (u["inclusions"] or u["exclusions"]):
            line += f"; must include {{{', '.join(u['inclusions'])}}}, exclude {{{', '.join(u['exclusions'])}}}"
        if "excluded_by" in u:
            if u["polarity"] == "negative":
                line += " -- no rule excludes it (every rule misses it)"
            elif u["excluded_by"]:
                line += " -- excluded by " + "; ".join(u["excluded_by"])
            else:
                line += " -- excluded by the rules together (no single rule excludes it)"
        lines.append(line)
    for w in doc.get("warnings", []):
        lines.append(f"warning: {w['file']}:{w['line']}:{w['column']}: {w['message']}")
    return "\n".join(lines)


def _check(args: argparse.Namespace, out) -> int | None:
    report = _run(_check_job, args, hypothesis=args.hypothesis, coverage=args.coverage)
    out.result(report, _render_check)
    if report["passed"]:
        return None
    missed = report["uncovered_without_penalty"]
    shown = ", ".join(missed[:5]) + (f" and {len(missed) - 5} more" if len(missed) > 5 else "")
    print(f"symlearn: error: {args.hypothesis}: {len(missed)} example{'s' if len(missed) > 1 else ''} without a "
          f"penalty not covered: {shown}", file=sys.stderr)
    return 2


def _render_space(doc: dict) -> str:
    lines = [f"{doc['size']} candidate rules" + (" (truncated)" if doc["truncated"] else "")]
    lines += [f"  {r['rule']}   % cost {r['cost']}" for r in doc["sample"]]
    lines += [f"note: {n}" for n in doc["notes"]]
    return "\n".join(lines)


def _space(args: argparse.Namespace, out) -> None:
    if args.sample < 0:
        from symlearn.errors import SymlearnError

        raise SymlearnError(f"--sample must be at least 0, not {args.sample}")
    doc = _run(_space_job, args, sample=args.sample)
    out.result(doc, _render_space)
