"""``symlearn domain check DIR``: read a domain folder, check it, and score a rule file against it.

``symlearn domain check DIR [--rules RULES.lp] [--known KNOWN.lp] [--demos D.jsonl] [--json]``

Without options it loads the folder (every error one line, naming file and line), checks that
every state-action context has exactly one answer set, and prints the domain's size. With
``--rules`` (learned, edited or hand-written integrity constraints) it counts the pairs they
forbid, scores them against the folder's truth rules when there are any (FPR, FNR, accuracy,
and which truth rules they miss), and, with ``--demos``, counts the demonstrated steps the rules
would forbid: the re-check after editing a learned rule file (``--known``: the rules that were given to
``learn constraints --known``, scored together with them). ``--demos`` alone reads your
demonstrations against the domain before you learn from them: an unknown state or action, or a
move that does not exist, is an error at its line and column; it counts episodes, steps and
distinct state-action pairs, and warns about steps the model gives probability zero.
"""

from __future__ import annotations

import argparse
import warnings

from symlearn.cli.output import blame_file


def register(subparsers, common) -> None:
    parser = subparsers.add_parser("domain", help="check a domain folder and score rules against it",
                                   description="Work with your own domain folders (domain.toml; docs/FORMATS.md).")
    commands = parser.add_subparsers(dest="domain_command", metavar="COMMAND", required=True)
    check = commands.add_parser("check", parents=[common()], help="load and check a domain folder; score a rule file",
                                description=__doc__.split("\n\n")[2].replace("\n", " ") if __doc__ else None)
    check.add_argument("folder", metavar="DIR", help="the domain folder (with domain.toml)")
    check.add_argument("--rules", help="an .lp file of integrity constraints to score against the domain")
    check.add_argument("--known", help="an .lp file of rules given in advance (learn constraints --known): "
                                        "scored together with --rules")
    check.add_argument("--demos", help="demonstrations (.jsonl/.npz): check them against the domain, and count "
                                        "the steps the --rules forbid")
    check.add_argument("--timeout", default="600", metavar="S",
                       help="seconds for loading, grounding and scoring ('inf': no limit; default 600)")
    check.add_argument("--max-memory", default=None, metavar="MB",
                       help="memory limit of the worker that grounds the folder's programs (default "
                            "SYMLEARN_MAX_MEMORY_MB or 1024; 0: none)")
    check.add_argument("--allow-outside", action="store_true",
                       help="let the domain folder name files outside itself (paths, symlinks, #include); only for a trusted folder")
    check.set_defaults(handler=_check)


def _check(args: argparse.Namespace, out) -> None:
    from symlearn.worker import memory_limit_mb, run_limited, seconds_limit

    # the folder's background and rules are the user's programs: a recursive rule grounds until
    # memory is gone, and clingo cannot be interrupted, so the work runs in a bounded worker
    if args.known and not args.rules:
        from symlearn.errors import SymlearnError

        raise SymlearnError("--known is scored together with --rules", hint="give the learned rule file too: "
                            "symlearn domain check DIR --rules RULES.lp --known KNOWN.lp")
    doc = run_limited(_check_document, args.folder, args.rules, args.demos, args.allow_outside, args.known,
                      seconds=seconds_limit(args.timeout, name="--timeout"),
                      memory_mb=memory_limit_mb(args.max_memory, name="--max-memory"),
                      what=f"grounding and scoring the domain {args.folder}", time_hint="raise --timeout",
                      memory_hint="raise --max-memory (or SYMLEARN_MAX_MEMORY_MB; 0: no limit) if the "
                                  "programs are meant to be this large")
    out.result(doc, _render)


def _check_document(folder: str, rules: str | None, demos: str | None, allow_outside: bool = False,
                    known: str | None = None) -> dict:
    from pathlib import Path

    import numpy as np

    from symlearn.grounding import Domain

    domain = Domain.from_folder(folder, allow_outside=allow_outside)
    doc = {"domain": domain.name, "description": domain.description, "states": domain.n_states,
           "actions": domain.n_actions, "pairs": len(domain.pair_ids),
           "forbidden_by_truth": None if domain.truth is None else int(domain.truth_forbidden.sum()),
           "labeling": None if domain.labeling is None else list(domain.labeling.propositions),
           "bias_warnings": [w.as_dict() for w in domain.bias_warnings()],
           "truth_warnings": [u.as_dict() for u in domain.undefined_predicates(domain.sources["truth"])]
           if domain.truth is not None and "truth" in domain.sources else []}
    if demos:
        doc["demonstrations"] = _demonstrations_report(domain, demos)
    if rules:
        from symlearn.learners.constraints.constraint_metrics import constraint_metrics

        hypothesis = domain.hypothesis(Path(rules))
        learned = domain.rule_mask(Path(rules))
        given = []
        if known:
            # a file learned with --known holds the learned rules only; scored alone it "missed" the
            # truth rules that were given, so the re-check its header named reported a false FNR
            given = list(domain.hypothesis(Path(known)).rules)
            learned = learned | domain.rule_mask(Path(known))
            hypothesis = domain.hypothesis(list(hypothesis.rules) + given)
        doc.update({"rules": list(hypothesis.rules)[:len(hypothesis.rules) - len(given)], "known_rules": given,
                    "forbidden": int(learned.sum()),
                    "fpr": None, "fnr": None, "accuracy": None, "missed_truth_rules": None,
                    "warnings": [u.as_dict() for u in domain.undefined_predicates(rules)]
                    + ([u.as_dict() for u in domain.undefined_predicates(known)] if known else [])
})
        doc["warnings"] += _idle_rules(domain, domain.hypothesis(Path(rules)), doc["warnings"])
        if domain.truth is not None:
            from symlearn.learners.constraints.constraint_metrics import reach_scores

            scores = constraint_metrics(learned, domain.truth_forbidden, ~domain.unavailable)
            truth = domain.hypothesis(domain.truth)
            missed = [rule for rule in truth.rules if (domain.rule_mask([rule]) & ~learned).any()]
            doc.update({"fpr": scores["fpr"], "fnr": scores["fnr"], "accuracy": scores["accuracy"],
                        "missed_truth_rules": missed,
                        **reach_scores(learned, domain.truth_forbidden, domain.mdp, ~domain.unavailable)})
        if demos:
            from symlearn.data import load

            with warnings.catch_warnings(), blame_file(demos):
                warnings.simplefilter("ignore", UserWarning)  # counted in "demonstrations" already
                episodes = domain.episodes(load(demos))
            hits = [(i, t) for i, e in enumerate(episodes)
                    for t in np.flatnonzero(learned[e.states[: len(e.actions)], e.actions]).tolist()]
            doc["demonstrated_steps_forbidden"] = len(hits)
            doc["first_forbidden_step"] = None
            if hits:
                i, t = hits[0]
                s, a = int(episodes[i].states[t]), int(episodes[i].actions[t])
                doc["first_forbidden_step"] = {"demonstration": i, "step": t, "pair": domain.describe_pair(s, a),
                                               "rules": [r for r in hypothesis.rules if domain.rule_mask([r])[s, a]]}
    return doc


#: rules of a file checked one by one for forbidding nothing (one grounding each); a hand-edited file
#: is short, a learned one of thousands is checked as a whole only
IDLE_RULES_CHECKED = 50


def _idle_rules(domain, hypothesis, warned: list[dict]) -> list[dict]:
    """A warning per rule that forbids no available pair: its body holds in no pair's answer set
    (``fragile(O), metal(O)``; ``busy, not holding(_)`` where ``busy`` means holding). Such a rule
    in a hand-edited file is a mistake that scores like a deleted rule and says nothing -- the
    DNF reader warns about its empty conjunctions the same way. Predicates defined nowhere are
    warned about already (and are why such a rule is idle), so those rules are not named twice."""
    rules = list(hypothesis.rules)
    if not rules or len(rules) > IDLE_RULES_CHECKED:
        return []
    origins = hypothesis.origins if hypothesis.origins and len(hypothesis.origins) == len(rules) else None
    # lines already warned about (a predicate defined nowhere, an argument no pair has): a rule
    # from there up to the next rule's line is idle for that reason, named already
    lines = {w.get("line") for w in warned}
    starts = [o[1] for o in origins] + [float("inf")] if origins else None
    out = []
    for k, rule in enumerate(rules):
        if starts and any(starts[k] <= n < max(starts[k + 1], starts[k] + 1) for n in lines if n):
            continue
        if domain.rule_mask([rule]).any():
            continue
        file, line, column = origins[k] if origins else (None, 0, 0)
        out.append({"file": file, "line": line, "column": column, "rule": rule,
                    "message": f"rule {rule} forbids no state-action pair: its body holds in no pair of "
                               f"{domain.name} (conditions that never hold together?)"})
    return out


def _demonstrations_report(domain, demos: str) -> dict:
    """The demonstrations read against the domain: an unknown state or action, or a move that does
    not exist, is an error located in the file; steps the model gives probability zero are counted."""
    import numpy as np

    from symlearn.data import load
    from symlearn.learners.constraints.logic_constraint_inference import check_available

    with warnings.catch_warnings(), blame_file(demos):
        warnings.simplefilter("ignore", UserWarning)  # the impossible steps are counted below
        episodes = domain.episodes(load(demos))
        check_available(episodes, domain)
    P = domain.mdp.transitions
    impossible = [(i, t) for i, e in enumerate(episodes) for t in range(min(len(e.actions), len(e.states) - 1))
                  if P[e.states[t], e.actions[t], e.states[t + 1]] == 0]
    first = None
    if impossible:
        i, t = impossible[0]
        e = episodes[i]
        first = {"demonstration": i, "step": t, "pair": domain.describe_pair(int(e.states[t]), int(e.actions[t])),
                 "next_state": domain.state_names[int(e.states[t + 1])]}
    return {"episodes": len(episodes), "steps": int(sum(len(e.actions) for e in episodes)),
            "pairs": int(np.unique(np.concatenate([e.states[: len(e.actions)] * domain.n_actions + e.actions
                                                   for e in episodes])).size),
            "impossible_steps": len(impossible), "first_impossible_step": first}


def reach_lines(doc: dict) -> list[str]:
    """The scores on the pairs a truth-abiding agent can meet, when some pairs lie in states it never
    reaches (shared by ``domain check`` and ``learn constraints``)."""
    if not doc.get("unreachable"):
        return []
    return [f"  on the {doc['reach_pairs']} pairs an agent obeying the truth can reach from the model's start: "
            f"FPR {doc['reach_fpr']:.3f}  FNR {doc['reach_fnr']:.3f} (the other {doc['unreachable']} lie in states "
            "no rule-abiding demonstration visits: what a rule forbids there, no demonstration can show)"]


def _render(doc: dict) -> str:
    lines = [f"{doc['domain']}: {doc['states']} states x {doc['actions']} actions, {doc['pairs']} state-action pairs; "
             "every context has one answer set"]
    if doc["forbidden_by_truth"] is not None:
        lines.append(f"truth rules forbid {doc['forbidden_by_truth']} pairs")
    if doc["labeling"] is not None:
        lines.append("labeling: " + ", ".join(doc["labeling"]))
    for w in [*doc.get("bias_warnings", []), *doc.get("truth_warnings", [])]:
        where = ":".join(str(w[k]) for k in ("file", "line", "column") if w[k] is not None)
        lines.append(f"warning: {where}: {w['message']}" if where else f"warning: {w['message']}")
    if "demonstrations" in doc:
        d = doc["demonstrations"]
        lines.append(f"demonstrations: {d['episodes']} episodes, {d['steps']} steps, {d['pairs']} distinct "
                     "state-action pairs")
        if d["impossible_steps"]:
            f = d["first_impossible_step"]
            lines.append(f"warning: {d['impossible_steps']} step(s) have probability zero under the model (first: "
                         f"demonstration {f['demonstration']}, step {f['step']}: {f['pair']} -> {f['next_state']})")
    if "rules" in doc:
        lines.append(f"rules ({len(doc['rules'])}" + (f" and {len(doc['known_rules'])} known" if doc.get("known_rules")
                                                     else "") + f") forbid {doc['forbidden']} pairs")
        if doc["fpr"] is not None:
            lines.append(f"against the truth: FPR {doc['fpr']:.3f}  FNR {doc['fnr']:.3f}  accuracy {doc['accuracy']:.3f}")
            lines += reach_lines(doc)
            lines += [f"  misses (partly) the truth rule {r}" for r in doc["missed_truth_rules"]]
        if "demonstrated_steps_forbidden" in doc:
            n = doc["demonstrated_steps_forbidden"]
            first = doc["first_forbidden_step"]
            lines.append(f"demonstrated steps the rules forbid: {n}" + (
                f" (first: demonstration {first['demonstration']}, step {first['step']}: {first['pair']}, "
                f"forbidden by {'; '.join(first['rules'])})" if n else ""))
        for w in doc.get("warnings", []):
            lines.append(f"warning: {w['file']}:{w['line']}:{w['column']}: {w['message']}")
    return "\n".join(lines)
