"""``symlearn learn pdfa``: sub-goals, a PDFA of their orderings and the preferred plan (thesis, chapter 6).

``symlearn learn pdfa (--demos D.npz|D.jsonl [--env GYM-ID|module:EnvId] | --env blocks-place-K|blocks-stack-R [--n-demos N])
[--subsets 'red=0,1,2;blue=3,4,5'] [--features a,b,...] [--eps E] [--min-samples M]
[--method dbscan|hdbscan] [--probabilities consistent|thesis] [-o plan.json] [--dot plan.dot] [--json]``

* ``--demos``: a frame archive (NPZ with ``states`` = frames x features, NaN = not observed, and
  ``lengths``; :mod:`symlearn.data.frame_archive`) or symlearn demonstrations (NPZ/JSONL) with
  vector or feature-dict states.
* ``--env``: the simulated block world's scripted demonstrator (``--n-demos`` demonstrations,
  ``--seed``); the result is then also scored against the ground truth (key ``truth``). With
  ``--demos``, ``--env`` names their features; demonstrations whose ``metadata["env"]`` names
  another gymnasium id are read all the same, with a ``warning:`` line on stderr.
* ``--subsets``: the candidate feature subsets (default: all features as one subset), by column
  index or feature name: ``--features``, else the names ``--env`` gives, else the names the file
  records (``metadata["feature_names"]``: ``record()``'s ``robot.pos[0]`` of a Dict observation).

JSON keys: ``subgoals`` (name -> centre, radius, subset, features), ``states`` (name, accepting,
termination), ``edges`` (source, target, sub-goal, probability, count), ``words`` (each distinct
word and its count), ``plan`` (sub-goal names), ``plan_probability``, ``clusters`` (per subset:
frames, points, ``eps`` and ``eps_source`` -- ``given``, ``dwelling noise`` or ``half the travel
step`` --, ``min_samples``, clusters found and dropped),
``seconds``, ``timings``, ``warnings`` (a subset that clusters on a feature constant within every
demonstration -- an episode's setting --, with the ``--subsets`` that leave it out). ``-o plan.json`` writes the PDFA's automaton JSON with ``subgoals``,
``plan`` and ``words`` added (``symlearn automaton show plan.json`` draws it); ``--dot`` writes
the drawing with sub-goal names and probabilities (and, with Graphviz, an ``.svg`` beside it).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from symlearn.cli.flag_values import demo_count


def register_learn(commands, common) -> None:
    cmd = commands.add_parser(
        "pdfa", parents=[common()], help="learn sub-goals and a PDFA of their preferred orderings",
        description="Cluster each feature subset of the demonstrations' frames into sub-goals (DBSCAN), turn every "
                    "demonstration into a word of sub-goals, build the probabilistic automaton of their orderings "
                    "and print its most preferred plan.")
    cmd.add_argument("--demos", help="a frame archive (.npz: states, lengths; NaN = unobserved) or "
                                     "demonstrations (.npz/.jsonl) with vector states")
    cmd.add_argument("--env", help="the block world's scripted demonstrator: blocks-place-K (K = 2..6) or "
                                   "blocks-stack-R (R rounds of three blocks); or your environment (a gymnasium id "
                                   "or module:EnvId) with --demos, which names the features")
    cmd.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments of --env (a JSON object)")
    cmd.add_argument("--n-demos", type=demo_count, default=100, help="demonstrations to record with --env (100)")
    cmd.add_argument("--subsets", help="candidate feature subsets, e.g. 'red=0,1,2;blue=3,4,5' (default: all "
                                       "features as one subset; with --env: each block's xyz)")
    cmd.add_argument("--features", help="comma-separated names of the state vector's columns")
    cmd.add_argument("--eps", type=float, help="DBSCAN radius (default: from the data, per subset: from the "
                                                     "dwelling noise, at most half the travel step)")
    cmd.add_argument("--min-samples", type=float,
                     help="frames a sub-goal needs within eps (default: 1.5 x number of demonstrations)")
    cmd.add_argument("--method", choices=("dbscan", "hdbscan"), default="dbscan", help="clustering (dbscan)")
    cmd.add_argument("--probabilities", choices=("consistent", "thesis"), default="consistent",
                     help="consistent: each state's edges and stopping sum to 1 (default); thesis: eqs. 6.2/6.3")
    cmd.add_argument("-o", "--output", help="write the plan here (.json: the PDFA with sub-goals, plan, words)")
    cmd.add_argument("--dot", help="draw the PDFA here (.dot; with Graphviz also .svg beside it)")
    cmd.set_defaults(handler=_pdfa)


def _check_outputs(args: argparse.Namespace) -> None:
    from symlearn.errors import DataError

    if args.output and Path(args.output).suffix != ".json":
        raise DataError(f"-o {args.output}: the plan is written as JSON; the name must end in .json")
    if args.dot and Path(args.dot).suffix != ".dot":
        raise DataError(f"--dot {args.dot}: the name must end in .dot (the .svg goes beside it)")


def _demonstrations(args: argparse.Namespace, note=None):
    """``(frames or Demonstrations, feature names or None, subsets, task or None)``."""
    from symlearn.errors import DataError

    from symlearn.envs.registry import Kind
    from symlearn.recipes.environments import parse_feature_names, resolve_env

    if not args.demos and not args.env:
        raise DataError("give the frames (--demos FILE) or a block-world task with a demonstrator (--env NAME)")
    features = list(parse_feature_names(args.features)) if args.features else None
    target = resolve_env(args.env, args.env_kwargs, kind=Kind.SUBGOALS if not args.demos else None,
                         what="sub-goal task") if args.env else None
    if target is None and args.env_kwargs:
        raise DataError("--env-kwargs needs --env")
    if target is not None and not args.demos:
        if not target.has_kind(Kind.SUBGOALS):
            raise DataError(f"{target.display} has no expert: give your demonstrations with --demos FILE",
                            hint="bundled sub-goal tasks: blocks-place-K (K = 2..6), blocks-stack-R (R = 1..4)")
        task = target.entry.task()
        runs = target.expert_demonstrations(args.n_demos, seed=args.seed or 0)
        return runs, list(target.feature_names(override=features)), args.subsets or task.subsets(), task
    if target is not None and features is None:
        names = target.feature_names()
        features = None if names is None else list(names)
    path = Path(args.demos)
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    if path.suffix == ".npz":
        from symlearn.data.frame_archive import is_frame_archive, load_frames

        if is_frame_archive(path):
            runs, names = load_frames(path)
            if features is not None and names is not None and tuple(features) != names:
                raise DataError(f"--features names {', '.join(features)}, the archive names {', '.join(names)}",
                                file=str(path), hint="drop --features to use the archive's names")
            return runs, features or names, args.subsets, None
    from symlearn.data import load
    from symlearn.recipes.experts import check_recorded_env

    demos = load(path)
    check_recorded_env(target, demos, path, note)  # recorded elsewhere: read all the same, with a warning
    if features is None:
        # names the file carries (record()'s names of a Dict observation's columns, robot.pos[0], a
        # flattened Minari/D4RL observation's), as learn dnf reads them: usable in --subsets
        meta = demos.metadata if isinstance(demos.metadata, dict) else {}
        named = meta.get("feature_names")
        if isinstance(named, list) and named and all(isinstance(n, str) for n in named):
            try:
                features = list(parse_feature_names(named, flag='metadata "feature_names"'))
            except DataError as exc:
                raise DataError(exc.message, file=str(path), hint=exc.hint) from None
    return demos, features, args.subsets, None


def _pdfa(args: argparse.Namespace, out) -> None:
    from symlearn.errors import DataError
    from symlearn.learners.subgoals import SubgoalPDFALearner

    _check_outputs(args)
    demos, features, subsets, task = _demonstrations(args, out.note)
    learner = SubgoalPDFALearner(subsets=subsets, eps=args.eps, min_samples=args.min_samples, method=args.method,
                                 probabilities=args.probabilities)
    import warnings

    try:
        with warnings.catch_warnings():  # the learner's warnings go into the result (text and JSON)
            warnings.simplefilter("ignore", UserWarning)
            learner.fit(demos, features)
    except DataError as exc:
        # the file's fault, unless the message is about the --subsets text (the frames' values are the file's)
        if args.demos and not exc.file and ("subset" not in exc.message or "frame" in exc.message):
            raise DataError(exc.message, file=args.demos, hint=exc.hint) from None
        raise
    pdfa, counts = learner.pdfa_, learner.counts_
    named = counts.named_edge_counts()
    edges = []
    for source, guard, target, p in pdfa.edges():
        (symbol,) = guard.satisfying_label()
        edges.append({"source": pdfa.name(source), "target": pdfa.name(target), "subgoal": symbol,
                      "probability": p, "count": named.get((source, symbol), 0)})
    from collections import Counter

    from symlearn.backends.subgoal_plan import greedy_plan

    plan = greedy_plan(pdfa)
    doc = {"subgoals": {g.name: {"centre": list(g.centre), "radius": g.radius, "subset": g.subset,
                                 "features": list(g.features)} for g in learner.subgoals_},
           "states": [{"name": pdfa.name(q), "accepting": q in pdfa.accepting, "termination": pdfa.termination[q]}
                      for q in pdfa.states],
           "edges": edges,
           "words": [{"word": list(w), "count": n} for w, n in Counter(learner.words_).most_common()],
           "plan": list(plan.subgoals), "plan_probability": plan.probability,
           "demonstrations": learner.result_.metrics["demonstrations"], "probabilities": args.probabilities,
           "clusters": [r.as_dict() for r in learner.history_],
           "seconds": learner.result_.timings["total"], "timings": dict(learner.result_.timings),
           "warnings": list(learner.warnings_)}
    if task is not None:
        doc["truth"] = _score(learner, task)
    files = []
    if args.output:
        from symlearn.logic.automata.pdfa import PDFA

        if args.probabilities == "thesis":
            try:
                PDFA.from_dict(pdfa.to_dict())
            except Exception:
                raise DataError("with --probabilities thesis this automaton's states do not sum to 1, so its JSON "
                                "could not be read back as a PDFA", hint="write it with --probabilities consistent; "
                                "--json shows the thesis values") from None
        files.append(str(learner.save(args.output)))  # the file SubgoalPDFALearner.save writes in Python
    if args.dot:
        from symlearn.atomic import write_text
        from symlearn.learners.subgoals.pdfa_dot import subgoal_pdfa_dot
        from symlearn.rendering import dot_available, render_dot

        dot = subgoal_pdfa_dot(pdfa, plan_states=plan.states, edge_counts=named,
                               title=f"sub-goal PDFA from {doc['demonstrations']} demonstrations")
        files.append(str(write_text(args.dot, dot)))
        if dot_available():
            files.append(str(render_dot(dot, Path(args.dot).with_suffix(".svg"))))
    if files:
        doc["files"] = files
    out.result(doc, _render)


def _score(learner, task) -> dict:
    """The learned result against the block world's ground truth."""
    from symlearn.learners.subgoals.scoring import renamed

    truth = task.truth_subgoals()
    mapping = learner.subgoals_.match(truth, tolerance=0.01)
    score = {"subgoals": len(truth), "matched_within_1cm": len(mapping), "extra": len(learner.subgoals_) - len(mapping)}
    if len(mapping) == len(learner.subgoals_) == len(truth):
        same, _ = renamed(learner.pdfa_, mapping).equivalent(task.truth_pdfa().dfa)
        preferred = [task.subgoal_name(j) for j in task.preferred_order()]
        score.update(language_equivalent=same, plan_is_preferred=[mapping[s] for s in learner.plan_] == preferred)
    return score


def _render(doc: dict) -> str:
    lines = [f"{len(doc['subgoals'])} sub-goals, {len(doc['states'])} states, {len(doc['edges'])} edges from "
             f"{doc['demonstrations']} demonstrations ({len(doc['words'])} distinct words, {doc['seconds']:.2f} s)"]
    for name, goal in doc["subgoals"].items():
        centre = ", ".join(f"{v:.4g}" for v in goal["centre"])
        lines.append(f"  {name}: {goal['subset']} within {goal['radius']:.3g} of ({centre})")
    lines.append(f"plan: {' -> '.join(doc['plan']) or '(stop at once)'} (p = {doc['plan_probability']:.3g})")
    if "truth" in doc:
        lines.append("truth: " + ", ".join(f"{k} {v}" for k, v in doc["truth"].items()))
    lines += [f"warning: {w}" for w in doc.get("warnings", [])]
    lines += [f"wrote {f}" for f in doc.get("files", [])]
    return "\n".join(lines)
