"""``symlearn automaton``: show, explain and convert automaton files.

* ``show FILE [--dot OUT.dot] [--svg OUT.svg]``: summary and transition table of a DFA, PDFA or
  reward machine (JSON, or DOT written by MONA/LTLf2DFA, or reward-machines text).
* ``explain FILE --trace T``: where a trace fails and a shortest fix; ``T`` is a JSON list of
  lists of propositions (``'[["a"], [], ["b"]]'``) or a file holding one.
* ``convert IN OUT``: between formats, chosen by suffix (``.json``; ``.dot`` MONA/LTLf2DFA
  in, Graphviz out; ``.txt`` reward-machines text; ``.hoa`` out; ``.svg``/``.png`` out).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def register(subparsers, common) -> None:
    group = subparsers.add_parser("automaton", help="show, explain and convert automata",
                                  description="Show, explain and convert automaton files (DFA, PDFA, reward machine).")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="automaton_command", metavar="SUBCOMMAND")

    show = commands.add_parser("show", parents=[common()], help="summary and transitions of an automaton",
                               description="Print an automaton's states and transitions; optionally draw it.")
    show.add_argument("file", help="automaton file: .json (symlearn), .dot (MONA/LTLf2DFA) or .txt (reward machine)")
    show.add_argument("--dot", metavar="OUT.dot", help="write Graphviz DOT")
    show.add_argument("--svg", metavar="OUT.svg", help="render to SVG (needs Graphviz)")
    show.set_defaults(handler=_show)

    explain = commands.add_parser("explain", parents=[common()], help="why a trace is rejected, and a shortest fix",
                                  description="Run a trace through the automaton; report where it fails and the "
                                              "fewest step edits (substitute/delete/insert) that make it accepted.")
    explain.add_argument("file", help="automaton file")
    explain.add_argument("--trace", required=True, metavar="T",
                         help="JSON list of lists of true propositions, or a file containing one")
    explain.set_defaults(handler=_explain)

    convert = commands.add_parser("convert", parents=[common()], help="convert between automaton formats",
                                  description="Convert an automaton; formats follow the suffixes "
                                              "(.json, .dot, .txt, .hoa, .svg, .png).")
    convert.add_argument("source")
    convert.add_argument("target")
    convert.add_argument("--variables", help="comma-separated names of raw MONA DOT variables, in MONA's order")
    convert.set_defaults(handler=_convert)


def load(path: str, variables: list[str] | None = None):
    """Read an automaton file, choosing the reader by suffix."""
    from symlearn.errors import ParseError
    from symlearn.logic.automata import load_automaton, read_mona_dot, read_rm_text

    suffix = Path(path).suffix.lower()
    if suffix == ".json":
        return load_automaton(path)
    if suffix in (".dot", ".gv"):
        return read_mona_dot(path, variables=variables)
    if suffix == ".txt":
        return read_rm_text(path)
    raise ParseError(f"cannot tell the format of {path!r} from its suffix", file=path,
                     hint="use .json (symlearn), .dot (MONA/LTLf2DFA) or .txt (reward-machines text)")


def _kind(automaton) -> str:
    from symlearn.logic.automata import DFA, PDFA

    return "dfa" if isinstance(automaton, DFA) else "pdfa" if isinstance(automaton, PDFA) else "reward_machine"


def _edges(automaton) -> list[dict]:
    rows = []
    for edge in automaton.edges():
        source, guard, target = edge[0], edge[1], edge[2]
        row = {"source": source, "target": target, "guard": str(guard)}
        if len(edge) == 4:
            row["probability" if _kind(automaton) == "pdfa" else "reward"] = edge[3]
        rows.append(row)
    return rows


def _draw(automaton, args, document) -> None:
    from symlearn.atomic import write_text
    from symlearn.rendering import render_dot

    if getattr(args, "dot", None):
        write_text(args.dot, automaton.to_dot())
        document["dot"] = args.dot
    if getattr(args, "svg", None):
        render_dot(automaton.to_dot(), args.svg)
        document["svg"] = args.svg


def _show(args: argparse.Namespace, out) -> None:
    automaton = load(args.file)
    kind = _kind(automaton)
    document = {
        "file": args.file, "kind": kind, "states": automaton.n_states, "edges": automaton.n_edges,
        "alphabet": sorted(automaton.alphabet), "initial": automaton.initial,
        "accepting": sorted(automaton.accepting),
        "state_names": None if automaton.state_names is None else list(automaton.state_names),
        "transitions": _edges(automaton),
    }
    if kind == "dfa":
        document["complete"] = automaton.is_complete()
        document["minimal_states"] = automaton.minimize().n_states
    if kind == "pdfa":
        document["termination"] = list(automaton.termination)
    if kind == "reward_machine":
        document["terminal"] = sorted(automaton.terminal)
    _draw(automaton, args, document)
    out.result(document, _render_show)


def _render_show(doc: dict) -> str:
    names = doc["state_names"]

    def name(q: int) -> str:
        return names[q] if names else str(q)

    lines = [f"{doc['file']}: {doc['kind']}, {doc['states']} states, {doc['edges']} edges, "
             f"alphabet {{{', '.join(doc['alphabet'])}}}"]
    lines.append(f"  initial: {name(doc['initial'])}   accepting: "
                 + (", ".join(name(q) for q in doc["accepting"]) or "none"))
    if "terminal" in doc:
        lines.append("  terminal: " + (", ".join(name(q) for q in doc["terminal"]) or "none"))
    if "minimal_states" in doc:
        lines.append(f"  complete: {'yes' if doc['complete'] else 'no'}   "
                     f"minimal complete DFA: {doc['minimal_states']} states")
    for row in doc["transitions"]:
        extra = f" / p={row['probability']:g}" if "probability" in row else (
            f" / r={row['reward']:g}" if "reward" in row else "")
        lines.append(f"  {name(row['source'])} --[{row['guard']}{extra}]--> {name(row['target'])}")
    if "termination" in doc:
        stops = [f"{name(q)}={p:g}" for q, p in enumerate(doc["termination"]) if p > 0]
        lines.append("  stop: " + (", ".join(stops) or "none"))
    for key in ("dot", "svg"):
        if key in doc:
            lines.append(f"wrote {doc[key]}")
    return "\n".join(lines)


def read_trace(text: str) -> list[frozenset[str]]:
    """A trace from JSON text or from a file holding it. Errors name the file, or ``--trace``
    for the text itself (a bare ``1:11:`` located nothing)."""
    from symlearn.errors import DataError, ParseError
    from symlearn.input_limits import load_json, read_input_text

    source = "--trace"
    path = Path(text)
    if not text.lstrip().startswith("["):
        if path.exists():
            source, text = str(path), read_input_text(path, what="trace file")
        elif not text.lstrip().startswith(("{", '"')):
            raise DataError(f"{text!r} is neither a trace file nor a JSON trace", file="--trace",
                            hint='give a file holding the trace, or the trace itself: [["a"], [], ["a", "b"]]')
    try:
        value = load_json(text, source=source, syntax="the trace is not valid JSON")
    except ParseError as exc:
        if exc.hint is None and "Extra data" in exc.message and source != "--trace":
            # a traces file of ltl eval (one trace per line): explain runs one
            exc.hint = "explain runs one trace; this file holds more than one (one per line): give one of them"
        elif exc.hint is None and "not valid JSON" in exc.message:
            exc.hint = 'write it like [["a"], [], ["a", "b"]]'
        raise
    if not isinstance(value, list):
        raise DataError("a trace must be a JSON list of steps", file=source, hint='e.g. [["a"], [], ["b"]]')
    steps = []
    for i, step in enumerate(value):
        if not isinstance(step, list) or not all(isinstance(p, str) for p in step):
            several = isinstance(step, list) and all(isinstance(p, list) for p in step)  # [[["a"], []], [["b"]]]
            shown = json.dumps(step)
            raise DataError(f"trace step {i} must be a list of proposition names, got "
                            f"{shown if len(shown) <= 80 else shown[:77] + '...'}", file=source,
                            hint="explain runs one trace, and this looks like a list of traces: give one of them "
                                 "(ltl eval --traces takes many, one per line)" if several
                            else 'e.g. [["a"], [], ["b"]]')
        steps.append(frozenset(step))
    return steps


def _explain(args: argparse.Namespace, out) -> None:
    from symlearn.errors import ModelError
    from symlearn.logic.automata import DFA, explain

    automaton = load(args.file)
    dfa = automaton if isinstance(automaton, DFA) else automaton.dfa
    if not dfa.accepting:
        # the file is named once, by the error's location (not again in the message)
        terminal = " (a reward machine's terminal states are not accepting states)" if dfa is not automaton else ""
        raise ModelError(f"the automaton has no accepting states{terminal}, so there is nothing to explain "
                         "against", file=args.file)
    trace = read_trace(args.trace)
    unknown = sorted(set().union(*trace) - dfa.alphabet) if trace else []
    if unknown:
        out.note(f"note: propositions {', '.join(unknown)} are not in the automaton's alphabet and are ignored")
    report = explain(dfa, trace)
    document = {"file": args.file, "trace": [sorted(s) for s in trace], **report.to_dict(),
                "state_names": [dfa.name(q) for q in report.states], "summary": report.summary()}
    out.result(document, _render_explain)


def _render_explain(doc: dict) -> str:
    def step(labels) -> str:
        return "{" + ", ".join(labels) + "}"

    lines = [f"trace: {' '.join(step(s) for s in doc['trace']) or '(empty)'}",
             f"run:   {' -> '.join(doc['state_names'])}"]
    lines.append(("ACCEPTED" if doc["accepted"] else "REJECTED") + f": {doc['summary']}")
    if doc["fixed_trace"] is not None and not doc["accepted"]:
        lines.append(f"fixed: {' '.join(step(s) for s in doc['fixed_trace']) or '(empty)'}")
    return "\n".join(lines)


def _convert(args: argparse.Namespace, out) -> None:
    from symlearn.atomic import write_text
    from symlearn.errors import ModelError
    from symlearn.logic.automata import DFA, RewardMachine
    from symlearn.rendering import render_dot

    variables = [v.strip() for v in args.variables.split(",")] if args.variables else None
    automaton = load(args.source, variables)
    suffix = Path(args.target).suffix.lower()
    if suffix == ".json":
        write_text(args.target, automaton.to_json())
    elif suffix in (".dot", ".gv"):
        write_text(args.target, automaton.to_dot())
    elif suffix in (".svg", ".png", ".pdf"):
        render_dot(automaton.to_dot(), args.target)
    elif suffix == ".hoa":
        if isinstance(automaton, RewardMachine):
            # HOA holds a language; a reward machine's rewards and terminal states have no place in it,
            # and the file written (no accepting state) accepted nothing, without a word
            raise ModelError(f"{args.source} is a reward machine: HOA holds an automaton's language, with no place "
                             "for rewards or terminal states", hint="write it as .json, .txt (reward-machine text), "
                                                                   ".dot or .svg")
        dfa = automaton if isinstance(automaton, DFA) else automaton.dfa
        write_text(args.target, dfa.to_hoa(name=Path(args.source).stem))
        out.note("note: HOA has no finite-word acceptance; the DFA is encoded as in Spot's from_ltlf (proposition "
                 "'alive' holds along the word, Buchi acceptance on an extra 'end' state), as the file's header says")
    elif suffix == ".txt":
        if isinstance(automaton, DFA):
            automaton = RewardMachine.from_dfa(automaton, minimize=False)
        if not isinstance(automaton, RewardMachine):
            raise ModelError("only reward machines and DFAs can be written as reward-machine text")
        write_text(args.target, automaton.to_text())
    else:
        raise ModelError(f"cannot write {args.target!r}: unknown suffix",
                         hint="use .json, .dot, .svg, .png, .pdf, .hoa or .txt")
    out.result({"source": args.source, "target": args.target, "kind": _kind(automaton),
                "states": automaton.n_states}, f"wrote {args.target} ({automaton.n_states} states)")
