"""``symlearn learn``: learn symbolic models from demonstrations.

The group is open: each sub-command lives in a module with ``register_learn(commands, common)``
listed in :data:`LEARN_SUBCOMMANDS` (``spec`` is defined here). To add ``learn constraints``,
write ``symlearn/cli/learn_constraints_command.py`` with such a function and add ONE line to
the tuple (``constraints`` lives in ``learn_constraints_command.py``).

``symlearn learn spec --env office-1 [--demos D.jsonl | --n-demos N] [--props given|learn] [-o spec.ltl]``
writes the formula (``spec.ltl``), the labeling (``spec.labeling.json``; in a user's environment a
table or feature labeling, also one given as a ``{proposition: condition}`` object, but not a
``FILE.py:function``, which cannot be saved: the output says so in one line and in the JSON's
``labeling_not_written``) and the automaton (``spec.dot`` and, with Graphviz, ``spec.svg``).
The propositions are printed with their meanings: the labeling's own, else a feature
labeling's condition, else, for a Python function, its ``(FILE.py:function)``.
``-o`` must end in ``.ltl``: the other files are
named after it, so ``-o notes.txt`` would overwrite ``notes.dot``/``notes.svg`` (refused before
learning). Demonstrations given with ``--demos`` must come from the environment: a file whose
metadata names another task, or whose labels disagree with the environment's labeling, is refused.

``symlearn learn spec --env GYM-ID|module:EnvId [--env-kwargs JSON] --demos D --labeling
FILE.json|FILE.py:function [--features a,b] [--policy auto|tabular|ppo] [--q-steps N] [--ppo-steps N]``
learns in a user's environment (resolved by :mod:`symlearn.recipes.environments`): no expert, so
``--demos`` is required; no tabular model, so each policy update is RL on the product of the
environment and the candidate formula's automaton (:mod:`symlearn.learners.temporal.spec_env_world`).
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path

from symlearn.cli.bounded_domain import add_domain_limits, load_domain
from symlearn.cli.output import blame_file
from symlearn.cli.flag_values import demo_count

# Modules defining register_learn(commands, common); this module registers "spec" itself.
LEARN_SUBCOMMANDS: tuple[str, ...] = ("symlearn.cli.learn_constraints_command", "symlearn.cli.learn_dnf_command",
                                      "symlearn.cli.learn_pdfa_command", "symlearn.cli.learn_icrl_command",
                                      "symlearn.cli.learn_rm_command")


def register(subparsers, common) -> None:
    group = subparsers.add_parser("learn", help="learn symbolic models from demonstrations",
                                  description="Learn symbolic models (task specifications, ...) from demonstrations.")
    group.set_defaults(group_parser=group)
    commands = group.add_subparsers(dest="learn_command", metavar="SUBCOMMAND")
    register_learn(commands, common)
    for name in LEARN_SUBCOMMANDS:
        importlib.import_module(name).register_learn(commands, common)


def register_learn(commands, common) -> None:
    spec = commands.add_parser(
        "spec", parents=[common()], help="learn an LTLf task specification from expert demonstrations",
        description="Alternate information-gain template search and CRM Q-learning of a nominal policy until "
                    "the learned LTLf formula separates expert from nominal behaviour.")
    where = spec.add_mutually_exclusive_group(required=True)
    where.add_argument("--env", help="a bundled task (office-1, craft-2), a gymnasium id, or module:EnvId "
                                     "(your own environment: give --demos and --labeling)")
    where.add_argument("--domain", metavar="DIR",
                       help="your own domain folder (domain.toml with a labeling; stochastic moves are sampled)")
    spec.add_argument("--allow-outside", action="store_true", help="let the domain folder name files outside itself (paths, symlinks, #include); only for a trusted folder")
    add_domain_limits(spec)
    source = spec.add_mutually_exclusive_group()
    source.add_argument("--demos", help="expert demonstrations (.jsonl or .npz): state ids for a bundled task; "
                                        "in your own environment, labelled while recorded (or replayable)")
    source.add_argument("--n-demos", type=demo_count, default=None,
                        help="generate N optimal expert demonstrations of a bundled task (default 50)")
    spec.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments for the environment, a JSON object")
    spec.add_argument("--props", choices=("given", "learn"), default="given",
                      help="use the environment's propositions, or learn propositions from states")
    spec.add_argument("--labeling", metavar="FILE.json|FILE.py:function",
                      help="the propositions: a labeling JSON file (a table, or {proposition: condition} over the "
                           "features; that object may also be given here as it is), or a Python function "
                           "(observation, info) -> names")
    spec.add_argument("--features", metavar="A,B,...",
                      help="names of the observation's columns, for a feature labeling {prop: 'a > 0.5'}")
    spec.add_argument("--policy", choices=("auto", "tabular", "ppo"), default="auto",
                      help="policy update in your own environment: tabular CRM Q-learning over observations "
                           "(auto: discrete observations and actions) or PPO (auto: otherwise)")
    spec.add_argument("--q-steps", type=int, default=None,
                      help="environment steps per tabular policy update in your own environment (default 40000)")
    spec.add_argument("--ppo-steps", type=int, default=None,
                      help="environment steps per PPO policy update in your own environment (default 50000)")
    spec.add_argument("--threshold", type=float, default=0.2, help="stop when the best information gain is below (0.2)")
    spec.add_argument("--max-iterations", type=int, default=25,
                      help="at most this many iterations (25; the loop stops earlier once the best gain is below --threshold)")
    spec.add_argument("--horizon", type=int, default=None,
                      help="length of nominal rollouts (default: the environment's, 200 for a domain)")
    spec.add_argument("--no-prune", action="store_true", help="keep every learned conjunct")
    spec.add_argument("-o", "--output", metavar="SPEC.ltl",
                      help="write the formula here; SPEC.dot, SPEC.svg and the labeling as SPEC.labeling.json go "
                           "next to it (not a FILE.py:function labeling, which cannot be saved)")
    spec.set_defaults(handler=_spec)


def _render(doc: dict) -> str:
    lines = [f"formula: {doc['formula']}"]
    if doc["propositions"]:
        lines.append("propositions:")
        lines += [f"  {name}: {meaning}".rstrip() for name, meaning in doc["propositions"].items()]
    if doc["success_rate"] is not None:
        lines.append(f"success rate on the ground-truth task: {doc['success_rate']:.2f}")
    entropy = "n/a" if doc["entropy"] is None else f"{doc['entropy']:.3f}"
    lines.append(f"policy entropy: {entropy}   iterations: {doc['iterations']}   "
                 f"length: {doc['length']}   {doc['seconds']:.1f} s")
    if doc["pruned"]:
        lines.append("pruned: " + ", ".join(doc["pruned"]))
    lines += [f"rejected: {r['formula']} ({r['why']})" for r in doc.get("rejected", [])]
    lines += [f"wrote {f}" for f in doc["files"]]
    if doc.get("labeling_not_written"):
        lines.append(doc["labeling_not_written"])
    return "\n".join(lines)


def _spec(args: argparse.Namespace, out) -> None:
    if args.output:  # before anything is imported or learned
        _check_output(args.output)
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task
    from symlearn.errors import DataError
    from symlearn.learners.temporal.spec_from_demos import SpecLearner
    from symlearn.grounding.labeling import load_labeling

    seed = getattr(args, "seed", 0)
    target = _resolve(args)
    if target is not None and target.entry is None:
        return _spec_in_user_env(args, out, target, seed)
    for flag, value in (("--features", args.features), ("--q-steps", args.q_steps), ("--ppo-steps", args.ppo_steps)):
        if value is not None:
            raise DataError(f"{flag} is for your own environment; {args.env or args.domain} has its own")
    if args.policy != "auto":
        raise DataError("--policy is for your own environment; a bundled task trains on its tabular model")
    task = get_task(target.entry.name) if target is not None else None
    if args.n_demos is None:
        args.n_demos = 50
    if args.demos:
        from symlearn.data import load

        demos = load(args.demos)
    elif task is None:
        raise DataError("a domain has no bundled expert: give your demonstrations with --demos FILE")
    else:
        demos = expert_demonstrations(task, args.n_demos, seed=seed)
    if args.labeling and args.props == "learn":
        raise DataError("--labeling gives propositions, which contradicts --props learn")
    if task is not None:
        env = task.make_env()
        labeling = load_labeling(args.labeling) if args.labeling else None
    else:
        env = load_domain(args)
        labeling = _domain_labeling(args, env)

    learner = SpecLearner(propositions=args.props, labeling=labeling, threshold=args.threshold,
                          max_iterations=args.max_iterations, prune=not args.no_prune, random_state=seed,
                          horizon=args.horizon, callback=_reporter(out))
    if args.demos:
        _check_demos_world(demos, args.demos, task, env)
    with blame_file(args.demos):
        learner.fit(demos, env)
    files, not_written = _write_outputs(learner, args.output) if args.output else ([], None)
    doc = {
        "env": task.name if task is not None else env.name,
        "formula": str(learner.formula_),
        "propositions": _meanings(learner.labeling_),
        "success_rate": learner.success_rate(task.formula) if task is not None else None,
        "entropy": learner.entropy_,
        "iterations": learner.iterations_,
        "length": learner.length_,
        "pruned": learner.pruned_,
        "rejected": learner.rejected_,
        "stopped_because": learner.stopped_because_,
        "seconds": learner.seconds_,
        "files": files,
        "labeling_not_written": not_written,
    }
    out.result(doc, _render)


def _domain_labeling(args: argparse.Namespace, domain):
    """``--labeling`` in a domain folder, in every form ``--env`` takes it (a saved labeling,
    ``{proposition: condition}`` over the folder's feature map, ``FILE.py:function`` of a state id),
    a feature labeling reading each state's features; None for the folder's own labeling. With
    ``--props given`` and no labeling anywhere, one line naming the ways to give one."""
    from symlearn.errors import DataError
    from symlearn.grounding.domain_folder import labeling_of_states
    from symlearn.grounding.labeling_function import read_labeling

    if not args.labeling:
        if domain.labeling is None and args.props == "given":
            raise DataError(f"the domain {args.domain} has no labeling, so there are no given propositions",
                            hint='add labeling = "labeling.json" to its domain.toml, give --labeling FILE.json (or '
                                 '{"p": "feature > 1"} over its feature map), or learn propositions with --props learn')
        return None
    names = domain.feature_map.names if domain.feature_map is not None else None
    labeling = read_labeling(args.labeling, feature_names=names,
                             names_hint='the domain names no features: add a feature map of every state (features = '
                                        '"features.json" in domain.toml), or give a table labeling')
    return labeling_of_states(labeling, domain.feature_map, args.labeling, domain.n_states, domain.state_names)


def _meanings(labeling, conditions=None, source: str | None = None) -> dict[str, str]:
    """What each proposition means, as printed: the labeling's own meaning, else its condition
    (a feature labeling, or ``conditions``: the one a wrapped labeling reads), else, for a
    Python function, where it came from (``(labels.py:label)``) -- never an empty line."""
    from symlearn.grounding.labeling_function import FunctionLabeling

    given = labeling.meanings
    out = {}
    for p in labeling.propositions:
        text = given.get(p, "")
        for holder in (conditions, labeling):
            if not text and hasattr(holder, "condition") and p in holder.propositions:
                text = holder.condition(p).to_string(one_line=True)
        if not text and isinstance(labeling, FunctionLabeling):
            text = f"({source or labeling.name})"
        out[p] = text
    return out


def _reporter(out):
    def report(record: dict) -> None:
        if "iteration" in record:
            # "below threshold" was printed with gain 0 where no formula was even scored: the nominal
            # traces repeated every demonstration's labels (random demonstrations, say)
            if record["added"]:
                verdict = "added"
            elif record.get("formula"):
                verdict = "stop (below threshold)"
            elif record.get("nominal_reproduced") == 1.0:
                verdict = "stop (every nominal label trace repeats a demonstration's: no formula to score)"
            else:
                verdict = "stop (no candidate formula)"
            out.note(f"iteration {record['iteration']}: {record['formula'] or '-'}  gain {record['gain']:.3f}  "
                     f"{verdict}  ({record['seconds']:.1f} s)")
        elif "pruned" in record:
            out.note(f"pruned {record['pruned']} (satisfied without it: {record['satisfied_without_it']:.2f})")
    return report


def _resolve(args):
    """The ``--env`` target (None for ``--domain``); a bundled name must be a specification task."""
    if not args.env:
        if args.env_kwargs is not None:
            from symlearn.errors import DataError

            raise DataError("--env-kwargs goes with --env, not --domain")
        return None
    from symlearn.envs.registry import Kind
    from symlearn.recipes.environments import resolve_env

    target = resolve_env(args.env, args.env_kwargs, kind=Kind.SPEC, what="environment/task")
    if target.entry is not None and target.kwargs:
        from symlearn.errors import DataError

        raise DataError(f"{target.display} is a bundled task; --env-kwargs is for your own environment")
    return target


def _spec_in_user_env(args, out, target, seed: int) -> None:
    """``learn spec`` in a user's environment: their demonstrations, their labeling, and RL on the
    product of the environment and each candidate's automaton for the policy updates."""
    from symlearn.data import load
    from symlearn.errors import DataError
    from symlearn.learners.temporal.spec_from_demos import SpecLearner
    from symlearn.recipes.environments import record_hint

    if not args.demos:
        raise DataError(f"{target.display} has no expert: give your demonstrations with --demos FILE",
                        hint=record_hint(target) + "; unlabelled episodes are labelled by replaying them")
    if args.props == "learn":
        raise DataError("--props learn names states of a tabular model; in your own environment give "
                        "--labeling FILE.json|FILE.py:function")
    for flag, value in (("--q-steps", args.q_steps), ("--ppo-steps", args.ppo_steps)):
        if value is not None and value < 1:
            raise DataError(f"{flag} must be at least 1, got {value}")
    target = target.with_joint_actions()   # MultiDiscrete/MultiBinary: one Discrete of the combinations
    env = target.make()
    labeling, saved = _user_labeling(args, target, env)
    demos = load(args.demos)
    learner = SpecLearner(labeling=labeling, threshold=args.threshold, max_iterations=args.max_iterations,
                          prune=not args.no_prune, random_state=seed, horizon=args.horizon, q_steps=args.q_steps,
                          ppo_steps=args.ppo_steps, policy=args.policy, callback=_reporter(out))
    with blame_file(args.demos):
        learner.fit(demos, env)
    files, not_written = _write_outputs(learner, args.output, saved, args.labeling) if args.output else ([], None)
    doc = {
        "env": target.display,
        "formula": str(learner.formula_),
        "propositions": _meanings(learner.labeling_, saved, args.labeling),
        "success_rate": None,
        "entropy": learner.entropy_,
        "iterations": learner.iterations_,
        "length": learner.length_,
        "pruned": learner.pruned_,
        "rejected": learner.rejected_,
        "stopped_because": learner.stopped_because_,
        "policy_update": learner.world_.route,
        "seconds": learner.seconds_,
        "files": files,
        "labeling_not_written": not_written,
    }
    out.result(doc, _render)


def _without_numbers(env) -> bool:
    """Whether the observation is text, which no feature labeling can read."""
    from gymnasium import spaces

    return isinstance(env.observation_space, spaces.Text)


def _user_labeling(args, target, env):
    """``--labeling`` read for a user's environment, and the labeling to save as SPEC.labeling.json
    (None for a Python function); a feature labeling's names from ``--features`` or the
    environment (checked against the observation's width), else, for a ``Dict``/``Tuple``
    observation, the names ``record`` gives its parts' numbers. A feature labeling that reads
    ``info["features"]`` or the parts is saved as the feature labeling it is: given again as
    ``--labeling SPEC.labeling.json`` in the same environment, it reads the same columns."""
    from symlearn.grounding.labeling_function import read_labeling

    names = target.feature_names(env, override=args.features) if args.features else None
    if not args.labeling:
        return None, None
    by_part = False
    if names is None and (args.labeling.lower().endswith(".json") or args.labeling.lstrip().startswith("{")):
        names = target.feature_names(env)  # a file, or the {proposition: condition} object given as it is
        if names is None:
            names = _part_names(env)
            by_part = names is not None
        if names is None:  # nothing names them: x0, x1, ... as `learn dnf` and `train --cost` call them
            numbered = target.features(env, numbered=True)
            names = None if numbered is None else numbered.names
    hint = {}
    if names is None and _without_numbers(env):
        # a Text observation: --features (the default hint) cannot help, a Python function can
        hint["names_hint"] = (f"{target.display} observes {env.observation_space}, which has no numeric columns to "
                              "name: label it with a Python function --labeling FILE.py:function (called with the "
                              "observation and info)")
    labeling = read_labeling(args.labeling, feature_names=names, **hint)
    columns = None  # where a feature labeling's columns come from, when not the observation itself
    if by_part and hasattr(labeling, "feature_map"):
        from symlearn.data.flat_observations import observation_features

        # conditions over the parts by name ("achieved_goal[0]" > 0.5), as record names them
        columns = lambda obs, _info: observation_features(obs)  # noqa: E731
    elif names is not None and hasattr(labeling, "feature_map"):
        features = target.features(env, override=args.features, numbered=True)
        if features is not None and features.source == "info":  # the columns are info["features"]
            columns = lambda _obs, info: info["features"]  # noqa: E731
    if columns is not None:
        from symlearn.grounding.labeling_function import FunctionLabeling

        inner = labeling
        return FunctionLabeling(lambda obs, info: inner.label(columns(obs, info)), inner.propositions,
                                meanings=inner.meanings, name=args.labeling), inner
    return labeling, (labeling if hasattr(labeling, "to_json") else None)   # a Python function is not saved


def _part_names(env):
    """The names of a ``Dict``/``Tuple`` observation's numbers (``achieved_goal[0]``, ``cell``), as
    ``record`` names the columns it stores (``None`` for any other observation space)."""
    from gymnasium import spaces

    from symlearn.data.flat_observations import observation_features

    if not isinstance(env.observation_space, (spaces.Dict, spaces.Tuple)):
        return None
    # the names follow the space's structure, so a sample names them without resetting the environment
    return tuple(observation_features(env.observation_space.sample())) or None


def _check_output(output: str) -> None:
    """``-o`` names the formula file; the labeling and the automaton take its stem, so only
    ``.ltl`` is accepted (``-o notes.txt`` would silently replace ``notes.dot``/``notes.svg``)."""
    from symlearn.errors import SymlearnError

    path = Path(output)
    if path.suffix.lower() != ".ltl":
        stem = path.stem if path.suffix else path.name
        raise SymlearnError(f"-o {output}: learn spec writes an LTLf formula and names its companion files "
                            f"after it, so the name must end in .ltl",
                            hint=f"-o {stem}.ltl writes {stem}.ltl, {stem}.labeling.json, {stem}.dot and {stem}.svg")
    import os

    from symlearn.atomic import NAME_MAX

    # the longest companion; checked before the learning, so a name the file system refuses does not
    # leave SPEC.ltl written and the labeling missing (a 254-byte -o did, held-out pass 2026-12-07)
    longest = f"{path.with_suffix('').name}.labeling.json"
    if len(os.fsencode(longest)) > NAME_MAX:
        raise SymlearnError(f"-o {output[:60]!r}... is too long a name: the files written beside it "
                            f"(NAME.labeling.json) would have more than {NAME_MAX} bytes",
                            hint="choose a shorter file name")


def _check_demos_world(demos, source: str, task, env) -> None:
    """Refuse demonstrations recorded in another environment: metadata naming another task, or
    labels that disagree with the environment's labeling of the same state."""
    from symlearn.errors import DataError

    recorded = demos.metadata.get("task") if isinstance(demos.metadata, dict) else None
    if task is not None and isinstance(recorded, str) and recorded.lower() != task.name.lower():
        raise DataError(f"the demonstrations were recorded in task {recorded!r}, not {task.name!r}", file=source,
                        hint=f"use --env {recorded}, or record demonstrations in {task.name}")
    labeling = getattr(env, "labeling", None)
    if labeling is None or not demos.has_labels:
        return
    n_states = getattr(getattr(env, "observation_space", None), "n", None)
    for i, trajectory in enumerate(demos):
        if trajectory.state_kind != "discrete":
            return
        for t, (state, label) in enumerate(zip(trajectory.states, trajectory.labels)):
            state = int(state)
            if state < 0 or (n_states is not None and state >= n_states):
                return  # the learner reports states outside the environment, naming them
            expected = frozenset(labeling.label(state))
            if frozenset(label) != expected:
                raise DataError(f"trajectory {i}, step {t}: state {state} is labelled {sorted(label)} in the file but "
                                f"{sorted(expected)} in {task.name if task is not None else 'the domain'}",
                                file=source, hint="these demonstrations come from another environment or labeling")


def _write_outputs(learner, output: str, labeling=None, source: str | None = None) -> tuple[list[str], str | None]:
    """The files written (formula, labeling, automaton) and, where no labeling file could be
    written (a Python function), the one line that says why. ``labeling``: the labeling to save
    (default: the learner's, where it can be saved)."""
    from symlearn.atomic import write_text
    from symlearn.rendering import dot_available, render_dot

    path = Path(output)
    stem = path.with_suffix("") if path.suffix else path
    files = [str(learner.save(path))]  # the formula, as SpecLearner.save writes it in Python
    labeling = labeling if labeling is not None else learner.labeling_
    labeling_path = stem.with_name(stem.name + ".labeling.json")
    not_written = None
    if hasattr(labeling, "save") and hasattr(labeling, "to_json"):
        labeling.save(labeling_path)
        files.append(str(labeling_path))
    else:   # a function cannot be saved, and a labeling file never names code to run
        given = source or getattr(labeling, "name", "the labeling")
        not_written = (f"no {labeling_path.name} written: the labeling is the Python function {given}, which "
                       f"cannot be saved; give --labeling {given} again with {path.name}")
    dot = learner.dfa_.to_dot(title=str(learner.formula_))
    dot_path = stem.with_name(stem.name + ".dot")
    write_text(dot_path, dot)
    files.append(str(dot_path))
    if dot_available():
        svg_path = stem.with_name(stem.name + ".svg")
        render_dot(dot, svg_path)
        files.append(str(svg_path))
    return files, not_written
