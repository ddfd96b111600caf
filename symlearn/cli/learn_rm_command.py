"""``symlearn learn rm``: infer a reward machine and its labeling from video demonstrations.

``symlearn learn rm (--demos frames.npz | --env blockworld-TASK) [--features pca|autoencoder|random-cnn]
[--eps E] [--min-samples M] [--kappa K] [--gamma G | --no-shaping] [-o machine.json] [--dot machine.dot] [--json]``

* ``--demos``: demonstrations with image states (the NPZ ``image`` kind, ``(T, H, W[, C])`` per
  video); ``--env blockworld-stack2`` (``place2``, ``pyramid3``, ``stack3``, ``place3``): the
  rendered block world's scripted demonstrations (one per ordering, Table 7.1), front camera,
  rendering noise drawn from ``--seed``.
* eps, min samples and kappa default to values derived from the data (see
  ``learners/reward_machines/prototypes.py`` and ``labeling.py``); give them to override.
* ``-o machine.json`` writes the (shaped, unless ``--no-shaping``) machine and, beside it,
  ``machine.labeling.json`` (+ features), ``machine.prototypes/u<k>.png``, ``machine.prototypes.png``
  (grid), ``machine.md`` (report) and ``machine.dot`` (or ``--dot``), whose states are drawn as
  their prototype images.

JSON keys: ``states``, ``edges`` (``[from, proposition, to, reward]``), ``propositions``
(name -> meaning), ``kappa``, ``eps``, ``min_samples``, ``clusters``, ``frames``,
``multiple_label_frames``, ``seconds``, ``files``.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def register_learn(commands, common) -> None:
    cmd = commands.add_parser(
        "rm", parents=[common()], help="infer a reward machine from video demonstrations",
        description="Cluster the visual features of demonstration frames into sub-goals (DBSCAN), label frames "
                    "by their distance to the sub-goal prototypes, and build the reward machine of the label "
                    "sequences (thesis Algorithm 7.1) with potential-based shaping.")
    where = cmd.add_mutually_exclusive_group(required=True)
    where.add_argument("--demos", help="image demonstrations (.npz, states of shape (T, H, W[, C]))")
    where.add_argument("--env", help="a rendered block task: blockworld-stack2, -place2, -pyramid3, -stack3, -place3")
    cmd.add_argument("--features", choices=("pca", "autoencoder", "random-cnn"), default="pca",
                     help="frame features: pixels -> PCA (default), a convolutional autoencoder trained on the frames, "
                          "or a random convolutional network")
    cmd.add_argument("--eps", type=float, help="DBSCAN eps (default: derived from the data)")
    cmd.add_argument("--min-samples", type=int, help="DBSCAN min samples (default: derived from the data)")
    cmd.add_argument("--kappa", type=float, help="labeling radius (default: half the smallest prototype distance)")
    shaping = cmd.add_mutually_exclusive_group()
    shaping.add_argument("--gamma", type=float, default=0.9, help="discount of the goal-distance shaping (0.9)")
    shaping.add_argument("--no-shaping", action="store_true", help="write the sparse machine (1 on reaching the goal)")
    cmd.add_argument("-o", "--output", metavar="MACHINE.json",
                     help="write the machine here; labeling, prototypes, report and DOT go beside it")
    cmd.add_argument("--dot", metavar="MACHINE.dot", help="write the DOT drawing here (default: beside -o)")
    cmd.set_defaults(handler=_rm)


def _check_arguments(args: argparse.Namespace) -> None:
    import os

    from symlearn.atomic import NAME_MAX
    from symlearn.errors import DataError

    if args.output and Path(args.output).suffix.lower() != ".json":
        raise DataError(f"-o must name a .json file, got {args.output!r}",
                        hint="the labeling, prototypes, report and DOT are named after it")
    if args.output:
        # the longest file written beside the machine; checked before the learning, so a name the
        # file system refuses does not leave the machine written and its companions missing
        stem = Path(args.output).with_suffix("").name
        longest = f"{stem}.labeling.features.safetensors"
        if len(os.fsencode(longest)) > NAME_MAX:
            raise DataError(f"-o {args.output[:60]!r}... is too long a name: the files written beside it "
                            f"(e.g. NAME.labeling.features.safetensors) would have more than {NAME_MAX} bytes",
                            hint="choose a shorter file name")
    if args.dot and Path(args.dot).suffix.lower() != ".dot":
        raise DataError(f"--dot must name a .dot file, got {args.dot!r}")
    if args.dot and not args.output:
        raise DataError("--dot needs -o (the DOT file shows the prototype images written beside the machine)")
    if args.eps is not None and not args.eps > 0:
        raise DataError(f"--eps must be a positive number, got {args.eps}")
    if args.min_samples is not None and args.min_samples < 1:
        raise DataError(f"--min-samples must be at least 1, got {args.min_samples}")
    if args.kappa is not None and not args.kappa > 0:
        raise DataError(f"--kappa must be a positive number, got {args.kappa}")
    if not args.no_shaping and not 0 < args.gamma < 1:
        raise DataError(f"--gamma must be in (0, 1), got {args.gamma}")


def _demonstrations(args: argparse.Namespace):
    from symlearn.errors import DataError

    if args.demos:
        from symlearn.data import load
        from symlearn.data.frame_archive import is_frame_archive, load_video

        # frames stacked with their run lengths (an .npz of 'states' and 'lengths'): a camera tour's
        # natural file, read as image demonstrations
        if str(args.demos).lower().endswith(".npz") and is_frame_archive(args.demos):
            return load_video(args.demos), args.demos
        return load(args.demos), args.demos
    from symlearn.envs.registry import Kind
    from symlearn.recipes.environments import resolve_env

    target = resolve_env(args.env, kind=Kind.MACHINE, what="rendered block task")
    if not target.has_kind(Kind.MACHINE):
        raise DataError(f"{target.display} has no expert: give your image demonstrations with --demos FILE",
                        hint="record frames with env.render() into an .npz of the image kind (docs/FORMATS.md)")
    seed = getattr(args, "seed", 0) or 0
    return target.expert_demonstrations(1, seed=seed), f"{target.display} (scripted demonstrations, seed {seed})"


def _rm(args: argparse.Namespace, out) -> None:
    import warnings

    from symlearn.cli.output import blame_file
    from symlearn.learners.reward_machines.rm_inference import RewardMachineInference

    _check_arguments(args)  # before anything is read or learned
    demos, source = _demonstrations(args)
    learner = RewardMachineInference(features=args.features, eps=args.eps, min_samples=args.min_samples,
                                     kappa=args.kappa, gamma=None if args.no_shaping else args.gamma)
    with warnings.catch_warnings(record=True) as caught, blame_file(args.demos):
        warnings.simplefilter("always")
        learner.fit(demos)
    for w in caught:
        if issubclass(w.category, UserWarning):
            out.note(f"warning: {w.message}")
    machine = learner.shaped_machine_ or learner.machine_
    metrics = learner.result_.metrics
    from symlearn.learners.reward_machines.report import transitions_table

    doc = {"states": machine.n_states, "initial": machine.initial, "accepting": sorted(machine.accepting),
           "edges": [[f"u{u}", read, f"u{v}", reward] for u, read, v, reward in transitions_table(machine)],
           "propositions": learner.labeling_.meanings, "kappa": learner.kappa_, "eps": learner.eps_,
           "min_samples": learner.min_samples_, "clusters": metrics["clusters"], "frames": metrics["frames"],
           "multiple_label_frames": metrics["multiple_label_frames"], "features": metrics["features"],
           "warnings": [str(w.message) for w in caught], "seconds": learner.result_.timings["total"], "files": []}
    if args.output:
        from symlearn.learners.reward_machines.report import write_results

        files = write_results(learner, args.output, dot=args.dot, source=source,
                              title=f"reward machine inferred from {Path(source).name if args.demos else source}")
        doc["files"] = [str(f) for f in files]
    out.result(doc, _render)


def _render(doc: dict) -> str:
    lines = [f"{doc['states']} states from {doc['clusters']} clusters of {doc['frames']} frames "
             f"(eps {doc['eps']:.3g}, min samples {doc['min_samples']}, kappa {doc['kappa']:.3g}; {doc['seconds']:.2f} s)",
             f"initial u{doc['initial']}, goal " + ", ".join(f"u{u}" for u in doc["accepting"])]
    lines += [f"  {u} --{read}--> {v}   reward {reward:.3g}" for u, read, v, reward in doc["edges"]]
    shown = [f for f in doc["files"] if not Path(f).parent.name.endswith(".prototypes")]
    lines += [f"wrote {f}" for f in shown]
    if len(shown) < len(doc["files"]):
        lines.append(f"wrote {len(doc['files']) - len(shown)} prototype images")
    return "\n".join(lines)
