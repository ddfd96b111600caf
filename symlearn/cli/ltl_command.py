"""``symlearn ltl``: parse LTLf formulas, evaluate them on traces, translate them to minimal DFAs."""

from __future__ import annotations

import argparse


def register(subparsers, common) -> None:
    group = subparsers.add_parser("ltl", help="parse, evaluate and translate LTLf formulas",
                                  description="Parse LTLf formulas, evaluate them on traces and translate them "
                                              "to minimal DFAs.")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="ltl_command", metavar="SUBCOMMAND")
    from symlearn.cli.ltl_learn_command import add_learn_command  # separating formulas (its own module)

    add_learn_command(commands, common)

    def dialect_option(p):
        p.add_argument("--dialect", default="ours", choices=("ours", "spot", "ltlf2dfa"),
                       help="syntax of the input: bare X is strong next in ours/ltlf2dfa, weak in spot "
                            "(default: ours)")

    parse = commands.add_parser("parse", parents=[common()], help="print the canonical form and size",
                                description="Parse a formula and print its canonical form, size and propositions.")
    parse.add_argument("formula", nargs="?")
    parse.add_argument("--tlsf", metavar="FILE", help="read the formula of a basic TLSF specification (SYNTCOMP's "
                                                      "format) instead")
    dialect_option(parse)
    parse.add_argument("--to", dest="to_dialect", choices=("ours", "spot", "ltlf2dfa"),
                       help="print in this dialect (default: the input dialect); operators the tool cannot "
                            "read are expanded: T for spot and ltlf2dfa, W for ltlf2dfa")
    parse.add_argument("--simplify", action="store_true", help="also print a simplified equivalent formula")
    parse.set_defaults(handler=_parse)

    evaluate = commands.add_parser("eval", parents=[common()], help="verdict of a formula on each trace",
                                   description="Evaluate a formula on traces: a JSONL file with one trace per line, "
                                               "each a list of steps, each step a list of the true propositions; "
                                               "or on labelled demonstrations (re-check an edited SPEC.ltl).")
    evaluate.add_argument("formula", nargs="?")
    evaluate.add_argument("--file", help="read the formula from a file holding one (SPEC.ltl as learn spec "
                                         "writes it; lines starting with # are comments)")
    evaluate.add_argument("--traces", help="JSONL file, e.g. a line [[\"a\"], [], [\"a\", \"b\"]]")
    evaluate.add_argument("--demos", help="labelled demonstrations (.jsonl/.npz with labels, as "
                                          "symlearn.data.record(labeler=...) writes them): each one's label word")
    evaluate.add_argument("--labeling", metavar="FILE.json",
                          help="with --demos: label each demonstrated state with this labeling (the "
                               "SPEC.labeling.json learn spec writes next to SPEC.ltl, a table or feature labeling)")
    dialect_option(evaluate)
    evaluate.set_defaults(handler=_eval)

    dfa = commands.add_parser("dfa", parents=[common()], help="translate to a minimal DFA",
                              description="Translate a formula to its minimal complete DFA (states include the "
                                          "rejecting sink), or every formula of a file with --file.")
    dfa.add_argument("formula", nargs="?")
    dfa.add_argument("--file", help="one formula per line (blank lines and lines starting with # are skipped)")
    dfa.add_argument("--tlsf", metavar="FILE", help="the formula of a basic TLSF specification (SYNTCOMP's format)")
    dialect_option(dfa)
    dfa.add_argument("--dot", help="write the automaton as Graphviz DOT")
    dfa.add_argument("--svg", help="render the automaton to SVG (needs Graphviz's dot)")
    dfa.add_argument("--save", help="write the automaton as symlearn DFA JSON")
    dfa.add_argument("--max-states", type=int, default=None,
                     help="stop with an error beyond this many states explored (default 100000; checked before "
                          "the work for conjunctions of many independent conjuncts)")
    dfa.set_defaults(handler=_dfa)


def _parse(args: argparse.Namespace, out) -> None:
    from symlearn.logic.ltlf import operator_count, parse, propositions, simplify, size, temporal_depth, to_string

    from symlearn.logic.ltlf.printer import FOREIGN, for_dialect

    formula = _formula(args)
    target = args.to_dialect or args.dialect
    if args.to_dialect and args.to_dialect != "ours":
        expanded = for_dialect(formula, target)
        if expanded != formula:
            from symlearn.logic.ltlf.ast import subformulas

            present = {type(node) for node in subformulas(formula)}
            names = " and ".join(op.symbol for op in FOREIGN[target] if op in present)
            out.note(f"note: {target} cannot read {names}; printed the equivalent expansion")
            formula = expanded
    doc = {
        "formula": to_string(formula, target),
        "dialect": target,
        "unicode": to_string(formula, target, style="unicode"),
        "size": size(formula),
        "operators": operator_count(formula),
        "temporal_depth": temporal_depth(formula),
        "propositions": sorted(propositions(formula)),
    }
    if args.simplify:
        doc["simplified"] = to_string(simplify(formula, propositional=True), target)

    def render(d: dict) -> str:
        lines = [d["formula"], f"  size {d['size']} ({d['operators']} operators, temporal depth "
                               f"{d['temporal_depth']}), propositions: {', '.join(d['propositions']) or 'none'}"]
        if "simplified" in d:
            lines.append(f"  simplified: {d['simplified']}")
        return "\n".join(lines)

    out.result(doc, render)


def _formula(args: argparse.Namespace):
    """The formula on the command line, or the one a ``--tlsf`` file means."""
    from symlearn.errors import SymlearnError

    if getattr(args, "tlsf", None) is not None:
        if args.formula is not None:
            raise SymlearnError("give a FORMULA or --tlsf SPEC.tlsf, not both")
        if args.dialect != "ours":
            raise SymlearnError("--dialect does not apply to --tlsf (TLSF has its own syntax)")
        from symlearn.logic.ltlf.tlsf import load_tlsf

        return load_tlsf(args.tlsf).formula
    if args.formula is None:
        raise SymlearnError("give a FORMULA or --tlsf SPEC.tlsf", hint="symlearn ltl parse 'F a & G !b'")
    from symlearn.logic.ltlf import parse

    return parse(args.formula, args.dialect)


def _eval(args: argparse.Namespace, out) -> None:
    from symlearn.logic.ltlf import parse
    from symlearn.logic.ltlf.traces_file import read_traces
    from symlearn.logic.ltlf.vectorized import evaluate_many

    from symlearn.logic.ltlf import propositions

    from symlearn.errors import SymlearnError

    if (args.formula is None) == (args.file is None):
        raise SymlearnError("give one of a FORMULA or --file SPEC.ltl", hint="symlearn ltl eval 'F a' --traces t.jsonl")
    if (args.traces is None) == (args.demos is None):
        raise SymlearnError("give one of --traces TRACES.jsonl or --demos DEMOS.jsonl",
                            hint="--traces: one list of steps per line; --demos: labelled demonstrations")
    if getattr(args, "labeling", None) and not args.demos:
        raise SymlearnError("--labeling labels the states of --demos; traces are propositions already",
                            hint="symlearn ltl eval --file SPEC.ltl --demos D.jsonl --labeling SPEC.labeling.json")
    if args.file:
        number, text = _one_formula(args.file)
        formula = parse(text, args.dialect, source=args.file, line=number)
        args.formula = text.strip()
    else:
        formula = parse(args.formula, args.dialect)
    source = args.traces or args.demos
    traces = read_traces(args.traces) if args.traces else _demonstration_words(args.demos,
                                                                               getattr(args, "labeling", None))
    what = "traces" if args.traces else "demonstrations"
    named = propositions(formula)
    seen = set().union(*(step for trace in traces for step in trace)) if traces else set()
    never = sorted(named - seen)
    if never and traces:  # the traces' own names make a misspelling easy to spot
        others = sorted(seen - named)
        listed = ", ".join(others[:10]) + (" ..." if len(others) > 10 else "") if others else "none"
        out.note(f"warning: proposition(s) {', '.join(never)} of the formula never hold in {source}, so "
                 f"they are false at every step (propositions in the traces but not in the formula: {listed})")
    results = [bool(v) for v in evaluate_many(formula, traces)] if traces else []

    def render(doc: dict) -> str:
        noun = "trace" if what == "traces" else "demonstration"
        lines = [f"{noun} {i + 1}: {'holds' if v else 'fails'}" for i, v in enumerate(doc["results"])]
        lines.append(f"{sum(doc['results'])} of {len(doc['results'])} {what} satisfy {args.formula}")
        return "\n".join(lines)

    out.result({"results": results}, render)


def _one_formula(path: str) -> tuple[int, str]:
    """``(line number, text)`` of the one formula a file holds (blank lines and lines starting
    with ``#`` skipped, as ``ltl dfa --file`` reads them); more or none is an error at the file."""
    from symlearn.errors import SymlearnError

    lines, numbers = _formula_lines(path)
    if len(numbers) != 1:
        raise SymlearnError(f"the file holds {len(numbers)} formulas; --file here reads one", file=path,
                            hint="keep one formula in the file (lines starting with # are comments); "
                                 "ltl dfa --file translates a file of many")
    return numbers[0], lines[numbers[0] - 1]


def _formula_lines(path: str) -> tuple[list[str], list[int]]:
    """A formula file's lines and the numbers (from 1) of those holding a formula: blank lines and
    lines starting with ``#`` are skipped (``ltl dfa --file``, ``ltl eval --file``)."""
    from symlearn.input_limits import read_input_text

    lines = read_input_text(path, what="formula file").split("\n")
    return lines, [n for n, text in enumerate(lines, start=1) if text.strip() and not text.lstrip().startswith("#")]


def _demonstration_words(path: str, labeling: str | None = None) -> list:
    """Each demonstration's label word: its recorded labels, or its states through ``labeling``
    (a file); demonstrations without either are refused with the way on."""
    from symlearn.data import load
    from symlearn.errors import DataError

    demos = load(path)
    if labeling:
        from symlearn.cli.ltl_labeled_demos import labelled_words

        return labelled_words(demos, path, labeling)
    if len(demos) and not demos.has_labels:
        raise DataError(f"{path}: these demonstrations have no labels, so a formula has nothing to read",
                        hint="give the labeling of their states (--labeling SPEC.labeling.json, which learn spec "
                             "writes next to SPEC.ltl), record them with a labeling (symlearn.data.record(env, "
                             "policy, n, labeler=label)) or write traces of propositions for --traces")
    return [list(word) for word in demos.to_label_words()] if len(demos) else []


_SHOWN = 50  # states whose transitions the text output lists
_MATERIALISED = 1_000_000  # symlearn.logic.automata.transition_diagram.MAX_MATERIALISED_EDGES (not imported: start-up)


def _edges(dfa) -> int | None:
    """The DFA's edge count, ``None`` when its symbolic transitions have more than we would list."""
    return dfa.count_edges(_MATERIALISED)


def _edge_text(edges: int | None) -> str:
    return str(edges) if edges is not None else f">{_MATERIALISED:,}"


def _dfa(args: argparse.Namespace, out) -> None:
    import time

    from symlearn.errors import SymlearnError
    from symlearn.logic.ltlf import parse
    from symlearn.logic.ltlf.to_dfa import DEFAULT_MAX_STATES, translate

    # what a translation imports on first use (the automata and composition modules), loaded
    # before any clock starts: "seconds" times the translation, as MONA's figure times its
    # construction, not the first import of our code (20-30 ms without bytecode files, measured)
    import symlearn.logic.ltlf.composition  # noqa: F401

    if args.max_states is not None and args.max_states < 1:
        raise SymlearnError(f"--max-states must be at least 1, got {args.max_states}")
    max_states = args.max_states or DEFAULT_MAX_STATES
    if sum(x is not None for x in (args.formula, args.file, args.tlsf)) != 1:
        raise SymlearnError("give one of a FORMULA, --file FORMULAS.txt or --tlsf SPEC.tlsf",
                            hint="symlearn ltl dfa 'F a & G !b'")
    single = None
    if args.file:
        from symlearn.input_limits import check_size, limit

        lines, numbers = _formula_lines(args.file)
        if args.dot or args.svg or args.save:
            # an edited SPEC.ltl with a '# why' comment above its formula is one automaton: write it
            # (before, --save was refused with --file, and "$(cat SPEC.ltl)" fails on the comment)
            if len(numbers) != 1:
                raise SymlearnError(f"--dot, --svg and --save write one automaton; {args.file} holds "
                                    f"{len(numbers)} formulas", file=args.file,
                                    hint="keep one formula in the file (lines starting with # are comments), "
                                         "or drop --dot/--svg/--save to translate them all")
            single = parse(lines[numbers[0] - 1], args.dialect, source=args.file, line=numbers[0])
            args.formula = lines[numbers[0] - 1].strip()
    if args.file and single is None:
        bound = limit("SYMLEARN_MAX_FORMULAS")
        if bound is not None and len(numbers) > bound:  # refused before any is translated
            check_size(len(numbers), "SYMLEARN_MAX_FORMULAS", what="formulas in the file", file=args.file,
                       line=numbers[bound])
        rows = []
        for number in numbers:
            text = lines[number - 1]
            formula = parse(text, args.dialect, source=args.file, line=number)
            start = time.perf_counter()
            try:
                dfa = translate(formula, max_states=max_states)
            except SymlearnError as exc:
                exc.file, exc.line = args.file, number
                raise
            rows.append({"formula": text.strip(), "states": dfa.n_states, "edges": _edges(dfa),
                         "seconds": round(time.perf_counter() - start, 6)})

        def render_rows(doc: list) -> str:
            return "\n".join(f"{r['states']:6d} states {_edge_text(r['edges']):>6s} edges "
                             f"{r['seconds'] * 1000:9.2f} ms  {r['formula']}" for r in doc)

        out.result(rows, render_rows)
        return

    formula = single if single is not None else _formula(args)
    args.formula = args.formula if args.tlsf is None else str(formula)
    start = time.perf_counter()
    dfa = translate(formula, max_states=max_states)
    seconds = time.perf_counter() - start
    written = []
    if args.dot:
        from symlearn.atomic import write_text

        write_text(args.dot, dfa.to_dot(title=args.formula))
        written.append(args.dot)
    if args.svg:
        from symlearn.rendering import render_dot

        render_dot(dfa.to_dot(title=args.formula), args.svg)
        written.append(args.svg)
    if args.save:
        dfa.save(args.save)
        written.append(args.save)
    dead = dfa.sink_states()  # a minimal complete DFA has at most one dead state: the rejecting sink
    symbolic = dfa.is_symbolic()  # large: transitions kept as a decision diagram, not listed
    doc = {
        "formula": args.formula, "states": dfa.n_states, "edges": _edges(dfa),
        "accepting": sorted(dfa.accepting), "sink": min(dead, default=None), "propositions": sorted(dfa.alphabet),
        "seconds": round(seconds, 6), "written": written, "symbolic": symbolic,
        "diagram_nodes": dfa.diagram_nodes(),
    }
    # JSON lists every state's edges; the text lists the first _SHOWN states' only: a 1,029-state DFA
    # printed thousands of lines, and each guard's sum of products is most of such a run's time
    listed = dfa.states if out.json_mode else list(dfa.states)[:_SHOWN]
    doc["transitions"] = None if symbolic else [[{"guard": str(g), "target": t} for g, t in dfa.successors(q)]
                                                for q in listed]

    def render(d: dict) -> str:
        accepting = d["accepting"] if len(d["accepting"]) <= 20 else d["accepting"][:20] + ["..."]
        lines = [f"minimal DFA: {d['states']} states, {_edge_text(d['edges'])} edges "
                 f"(accepting: {', '.join(map(str, accepting)) or 'none'}"
                 + (f"; rejecting sink: {d['sink']}" if d["sink"] is not None else "") + ")"]
        if d["transitions"] is None:
            lines.append(f"  transitions kept symbolic: one shared decision diagram of {d['diagram_nodes']:,} nodes "
                         f"(too many edges to list; --dot/--save write them up to {_MATERIALISED:,} edges)")
        for q, edges in enumerate(d["transitions"] or ()):
            mark = "*" if q in d["accepting"] else " "
            lines.append(f" {mark}{q}: " + "; ".join(f"{e['guard']} -> {e['target']}" for e in edges))
        if d["transitions"] is not None and d["states"] > len(d["transitions"]):
            lines.append(f"  ... and {d['states'] - len(d['transitions']):,} more states (--json lists every "
                         "state's transitions; --dot/--save write the automaton)")
        lines += [f"wrote {path}" for path in d["written"]]
        return "\n".join(lines)

    out.result(doc, render)
