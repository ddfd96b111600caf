"""``symlearn learn dnf``: learn continuous constraints as a DNF formula with a one-class tree.

``symlearn learn dnf [--demos D.npz|D.jsonl] [--env NAME|GYM-ID|module:EnvId [--env-kwargs JSON] [--n-demos N]]
[--features a,b,...] [--inputs a,b] [--domain DIR] [--max-depth D] [--min-samples-leaf M] [-o rules.dnf] [--json]``

* ``--demos``: demonstrations with vector states (columns named by ``--features``, else by the
  file's ``metadata["feature_names"]`` -- a flattened Minari or D4RL observation -- else
  ``x0..x{k-1}``) or feature-dict states (names from the dicts); with ``--domain DIR`` the
  domain's feature map (``features = ...`` in ``domain.toml``) turns state ids into features.
* ``--env``: a bundled continuous environment (``toy-navigation``, ``safenav-*``, ``driving``),
  whose scripted expert records ``--n-demos`` episodes; features are the environment's (SafeNav:
  the thesis' 20: accelerations, velocities, 16 hazard lidar bins; driving: velocities, gaps to
  the cars ahead/behind in three lanes, distances to the road edges, from an IDM/MOBIL driver).
  Any other environment (a gymnasium id, or ``module:EnvId`` -- see
  :mod:`symlearn.recipes.environments`) has no expert: give ``--demos`` too; the environment then
  names the features (``feature_names``, the keys of a dict ``info["features"]``, or ``--features``).
  ``--demos`` recorded in another environment than ``--env`` (their ``metadata["env"]`` names
  another gymnasium id) are read all the same, with a ``warning:`` line on stderr.

JSON keys: ``formula`` (the text), ``conjunctions`` (one string each), ``leaves`` (safe boxes as
``{feature: [low, high]}``), ``features``, ``seconds``, ``unsafe_share`` (of the data's bounding
box), ``slivers_closed``, ``notes`` (how the thresholds were rounded and gaps closed) and
``warnings`` (e.g. more than half of the bounding box unsafe; in the text output too; then,
for 2 to 4 features and no ``--inputs``, ``inputs_options`` holds the formula over each feature
alone -- ``inputs``, ``conjunctions``, ``unsafe_share`` -- and a note lists them: demonstrations of
one route make a corridor of the features together, and a constraint about one of them is learned
from that one with ``--inputs NAME``; which one, the demonstrations cannot tell),
``validation`` with ``--validation FRACTION`` (held-out expert states the formula calls unsafe,
``per_demonstration`` of them per held-out episode: the false-alarm floor ``train --cost`` adds to a
positive ``--cost-limit``, read from the file's ``# validation:`` line;
where that is more than 5 %, ``shallower`` holds the same check for every smaller ``--max-depth``
and the warning names the one to try: :mod:`symlearn.learners.trees.depth_advice`);
``-o`` writes the editable ``.dnf`` file
(``symlearn dnf eval|show`` read it; ``symlearn train --cost`` uses it as a cost).
"""

from __future__ import annotations

import argparse
import warnings

from symlearn.cli.bounded_domain import add_domain_limits, load_domain
from symlearn.cli.flag_values import demo_count


def register_learn(commands, common) -> None:
    cmd = commands.add_parser(
        "dnf", parents=[common()], help="learn continuous constraints as a DNF formula (one-class tree)",
        description="Fit a one-class decision tree to the features of expert demonstrations; the complement of "
                    "its leaves (the safe boxes) is a DNF formula of the unsafe set.")
    cmd.add_argument("--demos", help="demonstrations (.npz or .jsonl) with vector or feature-dict states")
    cmd.add_argument("--env", help="a bundled environment with an expert (toy-navigation, safenav-point-goal, driving; "
                                   "see `symlearn envs`), a gymnasium id or module:EnvId (then --demos too): "
                                   "names the features")
    cmd.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments of the environment (a JSON object)")
    cmd.add_argument("--n-demos", type=demo_count, default=20, help="expert episodes to record with --env (20)")
    cmd.add_argument("--features", help="comma-separated names of the state vector's columns")
    cmd.add_argument("--domain", metavar="DIR", help="a domain folder whose feature map turns state ids into features")
    cmd.add_argument("--inputs", metavar="A,B,...",
                     help="the features the rules may test (default all), e.g. the positions of an observation "
                          "that also holds velocities")
    cmd.add_argument("--allow-outside", action="store_true", help="let the domain folder name files outside itself (paths, symlinks, #include); only for a trusted folder")
    add_domain_limits(cmd)
    cmd.add_argument("--max-depth", type=int, default=5, help="deepest split (5)")
    cmd.add_argument("--min-samples-leaf", type=int, default=5, help="fewest points a split may leave in a child (5)")
    cmd.add_argument("--validation", type=float, default=None, metavar="FRACTION",
                     help="hold out this share of the demonstrations (whole episodes, at random with --seed) and "
                          "report the share of held-out expert states the formula calls unsafe")
    cmd.add_argument("-o", "--output", help="write the formula here (.dnf text, or .json)")
    cmd.set_defaults(handler=_dnf)


def _demonstrations(args: argparse.Namespace, note=None):
    from symlearn.errors import DataError
    from symlearn.recipes.environments import parse_feature_names, resolve_env
    from symlearn.recipes.experts import demonstrations

    seed = getattr(args, "seed", 0) or 0
    if not args.demos and not args.env:
        raise DataError("give the demonstrations (--demos FILE) or an environment with an expert (--env NAME)")
    if args.domain and args.env:
        raise DataError("--domain and --env both name the features; give one")
    features = None
    if args.domain:
        domain = load_domain(args)
        if domain.feature_map is None:
            raise DataError(f"the domain {domain.name} names no feature map", file=args.domain,
                            hint='add features = "features.json" to domain.toml')
        if args.features:
            raise DataError("--features and --domain both name the features; give one")
        features = domain.feature_map
    target = resolve_env(args.env, args.env_kwargs) if args.env else None
    if target is None and args.env_kwargs:
        raise DataError("--env-kwargs needs --env")
    if target is not None and not args.demos and not target.has_expert:
        raise DataError(f"{target.display} has no expert to record demonstrations for learning DNF constraints",
                        hint="give your demonstrations with --demos FILE (--env then names their features)")
    if target is not None and args.features and args.demos:
        # --features names the file's columns (counted against the file by the learner), which
        # may be the observation where the environment's info["features"] holds fewer numbers
        features = list(parse_feature_names(args.features))
    elif target is not None:
        features = target.feature_names(override=args.features)
        if features is None and not args.demos:
            raise DataError(f"{target.display} names no features",
                            hint="give --features a,b,... (one name per observation column)")
    elif args.features:
        features = list(parse_feature_names(args.features))
    demos = demonstrations(target, args.demos, args.n_demos, seed=seed, note=note)
    if args.domain and demos.state_kind == "symbol":  # states by their names in states.jsonl
        demos = _states_as_ids(demos, domain, args.demos)
    if target is not None and demos.state_kind == "discrete" and _observes_ids(target):
        # a Discrete observation recorded as its ids: one numeric column, the id, which is what
        # `train --cost` reads a Discrete observation as (`cell == 5`); refused as "discrete
        # states" before, though the rule it learns is the one train takes
        demos = _ids_as_column(demos)
    if target is not None and args.demos and demos.state_kind == "vector" and features is not None \
            and not args.features:
        _check_states_are_features(target, demos, args.demos, tuple(features))
    if target is not None and args.demos and demos.state_kind == "vector" and features is None:
        # the environment names nothing, so nothing counts the columns later (named ones are
        # counted against the file by the learner): its observation's width, one probe
        _check_width(target, demos, args.demos)
    if features is None:  # names the file carries (a flattened Minari/D4RL observation, a bundled expert's)
        meta = demos.metadata if isinstance(demos.metadata, dict) else {}
        named = meta.get("feature_names", meta.get("features"))
        if isinstance(named, list) and named and all(isinstance(n, str) for n in named):
            try:
                features = list(parse_feature_names(named, flag='metadata "feature_names"'))
            except DataError as exc:  # the file's own names: say which file
                raise DataError(exc.message, file=args.demos, hint=exc.hint) from None
    return demos, None if features is None else (features if args.domain else list(features))


def _observes_ids(target) -> bool:
    """Whether ``target``'s environment observes a ``Discrete`` space (one id per step)."""
    from gymnasium import spaces

    env = target.make()
    try:
        return isinstance(env.observation_space, spaces.Discrete)
    finally:
        env.close()


def _ids_as_column(demos):
    """Demonstrations of integer ids as one float column per state (the id itself)."""
    import numpy as np

    from symlearn.data import Demonstrations, Trajectory

    metadata = {**(demos.metadata if isinstance(demos.metadata, dict) else {}), "observation_ids": True}
    return Demonstrations([Trajectory(states=np.asarray(t.states, dtype=np.float64).reshape(-1, 1),
                                      actions=t.actions, rewards=t.rewards, labels=t.labels, info=t.info)
                           for t in demos], metadata=metadata)


def _picture_shape(demos) -> tuple[int, ...] | None:
    """The shape of a state that is a picture -- an array of two or more dimensions with more than
    :data:`PICTURE_CELLS` entries --, else None."""
    import numpy as np

    if getattr(demos, "state_kind", "vector") not in ("vector", "image") or not len(demos) or not len(demos[0].states):
        return None
    shape = tuple(int(d) for d in np.shape(demos[0].states[0]))
    return shape if len(shape) >= 2 and int(np.prod(shape)) > PICTURE_CELLS else None


#: entries of a 2-D or larger state from which learn dnf calls it a picture
PICTURE_CELLS = 64


def _check_width(target, demos, path) -> None:
    """Vector demonstrations whose width is not what ``--env`` reads (its features, else its
    observation): refused, rather than learning over columns the environment does not have."""
    import numpy as np

    from symlearn.errors import DataError

    found = target.features(numbered=True)
    if found is None:
        return
    width = int(np.prod(np.asarray(demos[0].states[0]).shape))
    if width != len(found.names):
        what = 'info["features"]' if found.source == "info" else "observation"
        raise DataError(f"the demonstrations' states have {width} columns, {target.display}'s {what} has "
                        f"{len(found.names)}", file=path,
                        hint="were they recorded in this environment? (without --env the file's columns are "
                             "learned as they are)")


def _check_states_are_features(target, demos, path, order) -> None:
    """The environment's names are those of ``info["features"]`` where it reports them, but
    ``record()`` stores the observation: where the two differ and the file's first state is the
    observation, those names would be put on other numbers (a silent mislabelling, not an
    error downstream: ``train --cost`` reads ``info["features"]`` by the same names). Refused;
    a first state that is the features, or that neither matches (a start that is not seeded), passes."""
    from collections.abc import Mapping

    import numpy as np

    from symlearn.errors import DataError
    from symlearn.recipes.environments import features_and_observation, same_numbers as same

    first = demos[0]
    seed = (first.info or {}).get("seed") if isinstance(first.info, Mapping) else None
    env = target.make()
    try:
        observation, info = env.reset(seed=int(seed) if isinstance(seed, int) else 0)
        declared = getattr(env.unwrapped, "observation_names", None)   # for the hint below
    finally:
        env.close()
    # a dict's values in the order of the names the rules will use, not its own key order
    pair = features_and_observation(info, observation, order)
    if pair is None:   # no features, or a Dict observation, text: nothing to compare
        return
    features, observed = pair
    raw = info["features"]
    names = (list(order) if set(map(str, raw)) == set(order) else [str(k) for k in raw]) \
        if isinstance(raw, Mapping) else None
    try:
        state = np.asarray(first.states[0], dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        return
    if same(observed, features) or same(state, features) or not same(state, observed):
        return
    shown = ", ".join(f"{n}={v:.4g}" for n, v in zip(names, features)) if names else \
        ", ".join(f"{v:.4g}" for v in features)
    raise DataError(f"{target.display} names the columns of its info[\"features\"] ({shown} after "
                    f"reset), which are not its observation ({', '.join(f'{v:.4g}' for v in observed)}); the "
                    "demonstrations hold the observations (what record() stores), so those names would label "
                    "other numbers", file=path,
                    hint=f"name the observation's columns with --features {_observation_names(declared, observed)} "
                         f"(train --cost reads {', '.join(names or order)} from info[\"features\"] by name: keep the "
                         f"rules to those columns with --inputs {','.join(names or order)}), or record the features as "
                         "the states (symlearn data record --states features)")


def _observation_names(names, observed) -> str:
    """The observation's column names to suggest: the environment's ``observation_names``
    (``names``) where they count its entries, else ``a,b,...``."""
    if isinstance(names, (list, tuple)) and len(names) == len(observed) and all(isinstance(n, str) for n in names):
        return ",".join(names)
    return "a,b,..."


def _states_as_ids(demos, domain, path):
    """Demonstrations whose states are a domain's state names, with the names replaced by ids
    (what the domain's feature map is indexed by); an unknown name is located in the file."""
    from symlearn.cli.output import blame_file
    from symlearn.data import Demonstrations, Trajectory
    from symlearn.mdp.episodes import state_sequences

    with blame_file(path):
        ids = state_sequences(demos, domain.n_states, domain.state_names)
    return Demonstrations([Trajectory(states=s, actions=t.actions, rewards=t.rewards, labels=t.labels, info=t.info)
                           for s, t in zip(ids, demos)], metadata=demos.metadata)


def _dnf(args: argparse.Namespace, out) -> None:
    from symlearn.errors import DataError, SymlearnError
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint, UnknownInputs

    demos, features = _demonstrations(args, out.note)
    if demos.state_kind in ("discrete", "symbol") and not args.domain:
        # the learner's hint names its Python arguments; from here the ways out are files and flags
        raise DataError(f"cannot read features from {demos.state_kind} states: a DNF is learned over numeric "
                        "features", file=args.demos,
                        hint="ids of a Discrete observation are learned as one column with the --env they come "
                             "from; else record the states as numbers (record(env, policy, n, observation=lambda s: "
                             "[row, col]) for a cell id), or give a domain folder whose feature map turns the "
                             "ids into features (--domain DIR)")
    held = None
    if args.validation is not None:
        from symlearn.learners.validation import holdout

        demos, held = holdout(demos, args.validation, seed=getattr(args, "seed", 0) or 0)
    inputs = None
    if args.inputs:
        from symlearn.recipes.environments import parse_feature_names

        inputs = list(parse_feature_names(args.inputs, flag="--inputs"))
    meta = demos.metadata if isinstance(demos.metadata, dict) else {}
    # ids of a Discrete observation: a step 3 -> 5 does not pass through 4, so crossing closes no gap,
    # and a slab between two ids (x0 > 1 & x0 < 2) forbids nothing
    ids = bool(meta.get("observation_ids", False))
    learner = OneClassTreeConstraint(max_depth=args.max_depth, min_samples_leaf=args.min_samples_leaf, inputs=inputs,
                                     close_crossed=not ids, whole_numbers=ids)
    try:
        with warnings.catch_warnings():  # the learner's warnings go into the result (text and JSON)
            warnings.simplefilter("ignore", UserWarning)
            learner.fit(demos, features)
    except UnknownInputs as exc:   # the flag's name, not the learner parameter's
        raise SymlearnError(f"--inputs: no feature named {', '.join(map(repr, exc.unknown))}",
                            hint=f"the features are {', '.join(exc.names)}") from None
    except DataError as exc:
        if args.demos and not exc.file:
            raise DataError(exc.message, file=args.demos, hint=exc.hint) from None
        raise
    dnf = learner.dnf_
    names = list(learner.feature_names_)
    leaves = [{name: [float(lo), float(hi)] for name, lo, hi in zip(names, box.lower, box.upper)}
              for box in learner.safe_boxes_]
    doc = {"formula": str(dnf), "conjunctions": [str(c) for c in dnf.conjunctions], "leaves": leaves,
           "features": names, "samples": learner.n_samples_, "seconds": learner.result_.timings["total"],
           "unsafe_share": learner.unsafe_share_, "slivers_closed": learner.slivers_closed_,
           "notes": list(learner.notes_), "warnings": list(learner.warnings_)}
    picture = _picture_shape(demos)
    if picture is not None and inputs is None:
        # a row-major reading of a picture: each rule bounds single pixels (a user's camera module
        # gave ~1,300 rules), which is rarely the constraint meant
        doc["warnings"].append(f"the states are arrays of shape {picture}, read as {len(names):,} separate columns: "
                               "each rule bounds single pixels; learn over features instead (an environment's "
                               "info[\"features\"] recorded with data record --states features) or choose the "
                               "columns with --inputs")
    crowded = learner.warn_unsafe_share is not None and learner.unsafe_share_ > learner.warn_unsafe_share
    if held is None and crowded:
        doc["notes"].append("--validation 0.2 holds out a fifth of the demonstrations and counts the held-out "
                            "expert states the formula calls unsafe (with the --max-depth that calls fewer)")
    if crowded:
        options = _single_inputs(args, demos, features, names, inputs)
        if options:
            doc["inputs_options"] = options
            doc["notes"].append(
                "if the constraint concerns only some of the features (an angle, not its speed), learn over those "
                "alone with --inputs: the demonstrations cover a thin slice of the features together, not of each; "
                "alone, each gives " + "; ".join(f"--inputs {o['inputs']}: {' | '.join(o['conjunctions'])}"
                                                 for o in options))
    if held is not None:
        from symlearn.learners.trees.one_class_tree import feature_matrix
        from symlearn.learners.validation import unsafe_states_report

        states = [feature_matrix(type(held)([t]), features)[0] for t in held]
        report = unsafe_states_report(learner.predict, states, names, args.validation, len(demos))
        doc["validation"] = report.as_dict()
        if report.warning():
            doc["warnings"].append(report.warning() + _depth_advice(args, inputs, demos, features, states,
                                                                    report.share, doc["validation"]))
    if args.output:
        if held is not None and not str(args.output).endswith(".json"):
            from symlearn.atomic import write_text

            doc["files"] = [str(write_text(args.output, _with_validation(learner.artefact_text(), doc)))]
        else:  # the file OneClassTreeConstraint.save writes in Python
            doc["files"] = [str(learner.save(args.output))]
    out.result(doc, _render)


#: at most this many features get their one-feature formulas listed (SafeNav's 20 would be a page)
MAX_LISTED_INPUTS = 4


def _single_inputs(args, demos, features, names, inputs) -> list[dict]:
    """The formula over each feature alone, where most of the bounding box is unsafe: a tree over
    every feature at once makes a corridor of demonstrations that cover one route (issue 24: an
    arm's swing in (theta, omega), 87-94 % unsafe, and `--inputs theta` -- the constraint is about
    the angle -- gave a formula that kept the agent safe). Which feature the constraint is about
    the demonstrations cannot say: each one-feature formula forbids only what lies beyond the
    demonstrated range, so all are listed, each with its rules, for the user to choose (measured
    on 8 tasks, docs/BENCHMARKS.md). ``[]`` for one feature, more than :data:`MAX_LISTED_INPUTS`,
    or ``--inputs`` already given."""
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    if inputs is not None or not 2 <= len(names) <= MAX_LISTED_INPUTS:
        return []
    options = []
    for name in names:
        single = OneClassTreeConstraint(max_depth=args.max_depth, min_samples_leaf=args.min_samples_leaf,
                                        inputs=[name], warn_unsafe_share=None)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            single.fit(demos, features)
        options.append({"inputs": name, "conjunctions": [str(c) for c in single.dnf_.conjunctions],
                        "unsafe_share": single.unsafe_share_})
    return options


def _depth_advice(args, inputs, train, features, held_states, share: float, validation: dict) -> str:
    """``"; " + advice`` when a shallower tree forbids less of the held-out expert states (the
    refits go into ``validation["shallower"]``), else ``""``."""
    from symlearn.learners.trees.depth_advice import ACCEPTABLE_SHARE, advice_text, advised, shallower_options
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    if share <= ACCEPTABLE_SHARE or args.max_depth <= 1:
        return ""
    options = shallower_options(
        lambda depth: OneClassTreeConstraint(max_depth=depth, min_samples_leaf=args.min_samples_leaf, inputs=inputs),
        train, features, held_states, args.max_depth)
    validation["shallower"] = [o.as_dict() for o in options]
    best = advised(options, share)
    return "" if best is None else "; " + advice_text(best)


def _with_validation(text: str, doc: dict) -> str:
    """The rule file's text with the validation line (and its warning) after its ``#`` header:
    how often the formula fires on held-out expert states is what a cost limit on it has to
    allow, so it stays with the file, not only on the terminal; ``train --cost`` reads the line
    back (:func:`symlearn.learners.validation.rule_file_validation`) and adds its count per held-out
    demonstration to a positive ``--cost-limit``."""
    from symlearn.cli.output import validation_line

    lines = text.splitlines(keepends=True)
    n = next((i for i, line in enumerate(lines) if not line.startswith("#")), len(lines))
    extra = [validation_line(doc["validation"], "held-out expert states unsafe")]
    extra += [f"warning: {w}" for w in doc["warnings"] if w not in text]
    body = "".join(lines[:n]) + "".join(f"# {line}\n" for line in extra) + "".join(lines[n:])
    return body if body.endswith("\n") else body + "\n"


def _render(doc: dict) -> str:
    lines = [f"{len(doc['conjunctions'])} rules over {len(doc['features'])} features from {doc['samples']} points, "
             f"{len(doc['leaves'])} safe boxes ({doc['seconds']:.2f} s)"]
    lines += [f"  {c}" for c in doc["conjunctions"][:40]]
    if len(doc["conjunctions"]) > 40:
        lines.append(f"  ... {len(doc['conjunctions']) - 40} more (see --json or -o)")
    if doc.get("validation"):
        from symlearn.cli.output import validation_line

        lines.append(validation_line(doc["validation"], "held-out expert states unsafe"))
    lines += [f"note: {n}" for n in doc.get("notes", [])]
    lines += [f"warning: {w}" for w in doc.get("warnings", [])]
    lines += [f"wrote {f}" for f in doc.get("files", [])]
    return "\n".join(lines)
