"""``symlearn learn dnf``: learn continuous constraints as a DNF formula with a one-class tree.

``symlearn learn dnf (--demos D.npz|D.jsonl [--features a,b,...] [--domain DIR] | --env NAME [--n-demos N])
[--max-depth D] [--min-samples-leaf M] [-o rules.dnf] [--json]``

* ``--demos``: demonstrations with vector states (columns named by ``--features``, default
  ``x0..x{k-1}``) or feature-dict states (names from the dicts); with ``--domain DIR`` the
  domain's feature map (``features = ...`` in ``domain.toml``) turns state ids into features.
* ``--env``: a bundled continuous environment (``toy-navigation``, ``safenav-*``, ``driving``),
  whose scripted expert records ``--n-demos`` episodes; features are the environment's (SafeNav:
  the thesis' 20: accelerations, velocities, 16 hazard lidar bins; driving: velocities, gaps to
  the cars ahead/behind in three lanes, distances to the road edges, from an IDM/MOBIL driver).

JSON keys: ``formula`` (the text), ``conjunctions`` (one string each), ``leaves`` (safe boxes as
``{feature: [low, high]}``), ``features``, ``seconds``; ``-o`` writes the editable ``.dnf`` file
(``symlearn dnf eval|show`` read it; ``symlearn train --cost`` uses it as a cost).
"""

from __future__ import annotations

import argparse

def register_learn(commands, common) -> None:
    cmd = commands.add_parser(
        "dnf", parents=[common()], help="learn continuous constraints as a DNF formula (one-class tree)",
        description="Fit a one-class decision tree to the features of expert demonstrations; the complement of "
                    "its leaves (the safe boxes) is a DNF formula of the unsafe set.")
    where = cmd.add_mutually_exclusive_group(required=True)
    where.add_argument("--demos", help="demonstrations (.npz or .jsonl) with vector or feature-dict states")
    where.add_argument("--env", help="a bundled continuous environment with a scripted expert "
                                     "(toy-navigation, safenav-point-goal, driving, ...; see `symlearn envs`)")
    cmd.add_argument("--n-demos", type=int, default=20, help="expert episodes to record with --env (20)")
    cmd.add_argument("--features", help="comma-separated names of the state vector's columns")
    cmd.add_argument("--domain", metavar="DIR", help="a domain folder whose feature map turns state ids into features")
    cmd.add_argument("--allow-outside", action="store_true", help="let the domain folder name files outside itself (paths, symlinks, #include); only for a trusted folder")
    cmd.add_argument("--max-depth", type=int, default=5, help="deepest split (5)")
    cmd.add_argument("--min-samples-leaf", type=int, default=5, help="fewest points a split may leave in a child (5)")
    cmd.add_argument("-o", "--output", help="write the formula here (.dnf text, or .json)")
    cmd.set_defaults(handler=_dnf)


def _demonstrations(args: argparse.Namespace):
    from symlearn.errors import DataError

    seed = getattr(args, "seed", 0) or 0
    if args.demos:
        from symlearn.data import load

        demos = load(args.demos)
        features = None
        if args.domain:
            from symlearn.grounding import Domain

            domain = Domain.from_folder(args.domain, allow_outside=args.allow_outside)
            if domain.feature_map is None:
                raise DataError(f"the domain {domain.name} names no feature map", file=args.domain,
                                hint='add features = "features.json" to domain.toml')
            features = domain.feature_map
        if args.features:
            if features is not None:
                raise DataError("--features and --domain both name the features; give one")
            features = [name.strip() for name in args.features.split(",") if name.strip()]
        return demos, features
    if args.n_demos < 1:
        raise DataError(f"--n-demos must be at least 1, got {args.n_demos}")
    if args.env == "toy-navigation":
        from symlearn.envs.toy_navigation import expert_demonstrations

        return expert_demonstrations(args.n_demos, seed=seed), ["x", "y"]
    if args.env.startswith("safenav-") and args.env.count("-") == 2:
        from symlearn.envs.registry import Kind, get
        from symlearn.envs.safenav.observation import FEATURE_NAMES
        from symlearn.envs.safenav_expert import expert_demonstrations

        get(args.env, Kind.CONTINUOUS, what="continuous environment")
        _, agent, task = args.env.split("-")
        return expert_demonstrations(agent, task, args.n_demos, seed=seed), list(FEATURE_NAMES)
    if args.env.strip().lower() == "driving":
        from symlearn.envs.driving.expert import expert_demonstrations
        from symlearn.envs.driving.features import FEATURE_NAMES

        return expert_demonstrations(args.n_demos, seed=seed), list(FEATURE_NAMES)
    raise DataError(f"{args.env!r} has no scripted expert for learning DNF constraints",
                    hint="use toy-navigation, safenav-<point|car>-<goal|push> or driving, or give --demos")


def _dnf(args: argparse.Namespace, out) -> None:
    from symlearn.errors import DataError
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint

    demos, features = _demonstrations(args)
    learner = OneClassTreeConstraint(max_depth=args.max_depth, min_samples_leaf=args.min_samples_leaf)
    try:
        learner.fit(demos, features)
    except DataError as exc:
        if args.demos and not exc.file:
            raise DataError(exc.message, file=args.demos, hint=exc.hint) from None
        raise
    dnf = learner.dnf_
    names = list(learner.feature_names_)
    leaves = [{name: [float(lo), float(hi)] for name, lo, hi in zip(names, box.lower, box.upper)}
              for box in learner.safe_boxes_]
    doc = {"formula": str(dnf), "conjunctions": [str(c) for c in dnf.conjunctions], "leaves": leaves,
           "features": names, "samples": learner.n_samples_, "seconds": learner.result_.timings["total"]}
    if args.output:
        source = args.demos or f"{args.n_demos} expert episodes of {args.env}"
        dnf.save(args.output, header=f"unsafe set learned by a one-class tree (max depth {args.max_depth}) "
                                     f"from {source}; one rule per line, edit freely")
        doc["files"] = [args.output]
    out.result(doc, _render)


def _render(doc: dict) -> str:
    lines = [f"{len(doc['conjunctions'])} rules over {len(doc['features'])} features from {doc['samples']} points, "
             f"{len(doc['leaves'])} safe boxes ({doc['seconds']:.2f} s)"]
    lines += [f"  {c}" for c in doc["conjunctions"][:40]]
    if len(doc["conjunctions"]) > 40:
        lines.append(f"  ... {len(doc['conjunctions']) - 40} more (see --json or -o)")
    lines += [f"wrote {f}" for f in doc.get("files", [])]
    return "\n".join(lines)
