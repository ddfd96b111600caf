"""``symlearn learn icrl``: learn a neural cost by inverse constrained RL in a continuous environment.

``symlearn learn icrl --env NAME [--method mce-icrl|me-icrl|vme-icrl|gacl] [--demos D.npz | --n-demos N] [--steps N]
[--iterations I] [--beta B] [--cost-inputs x,y|all] [--select-inputs TOL] [--cost-sparsity S]
[--cost-memory all|current] [--reset-actor never|every|last|auto] [--lambda-lr L] [--env-kwargs JSON] [--expert-steps N]
[--expert-cache DIR] [-o cost.safetensors] [--log run.csv] [--json]``

* ``--env``: a bundled environment with ``mce-icrl`` among its methods (``blocked-point``,
  ``point-circle``; see ``symlearn envs``), a gymnasium id, or ``module:EnvId`` (a user's
  environment: give ``--demos``), built with ``--env-kwargs`` (a JSON object of its
  constructor's keyword arguments, e.g. ``'{"wall": -4.0}'``; an unknown key is refused).
  Where no step of learning or evaluation reports ``info["cost"]``, ``violation_rate`` and
  ``feasible_reward`` are null (n/a); once one does, a step without it costs 0 (a cost reported
  only on the steps that pay it). Where it has no ``is_unsafe``, the recovery figures are null.
* ``--demos``: expert demonstrations (``.npz``/``.jsonl``) whose states are the environment's
  observations and which carry actions; otherwise ``--n-demos`` episodes of the environment's
  scripted expert (BlockedPoint: full speed away from the wall), generated from ``--seed``, or,
  where there is none (the blocked MuJoCo tasks), of a PPO-Lagrangian expert trained on the true
  cost for ``--expert-steps`` (:mod:`symlearn.rl.lagrangian_expert`; minutes, so
  cached under ``--expert-cache``, default ``~/.cache/symlearn/experts``; ``none`` = no cache).
  A file whose ``metadata["env"]`` names another gymnasium id than ``--env`` is read all the same,
  with a ``warning:`` line on stderr (:func:`symlearn.recipes.experts.check_recorded_env`).
* ``--method``: ``mce-icrl`` (thesis chapter 2, the default), ``me-icrl`` (Malik et al.'s
  baseline: feasibility network, PPO-Lagrangian with cost limit 0), ``vme-icrl`` (Liu et al.'s
  variational baseline: Beta-distributed feasibility, KL from a prior) or ``gacl`` (a GAIL
  discriminator, the policy learning from ``r + log D``).
* ``--steps``: PPO steps in all: one eighth for the nominal policy, the rest split evenly over
  the ``--iterations``. ``--beta``: the entropy coefficient of the policy phases (> 0; by default
  each method's own: 0.03 for ``mce-icrl``, 0.01 for the others). ``--cost-inputs``: the
  observation entries the cost may read (its candidates), by name (``x,y``) or index, or ``all``;
  by default the entries the environment declares its constraints to be about (its
  ``feature_names``, where each names an observation entry: ``x,y`` on BlockedPoint, ``x`` on the
  blocked MuJoCo tasks), else all (:mod:`symlearn.learners.neural.fit_setup` says why). ``--select-inputs TOL``: of those
  candidates the cost reads the fewest that tell the expert's states from the nominal policy's
  within ``TOL`` of all of them (held-out AUC; default 0.01, 0 = every candidate;
  :mod:`symlearn.learners.neural.input_selection`). ``--cost-sparsity S``: MCE-ICRL's
  group-sparsity penalty on the cost network's inputs (default 0 = off;
  :mod:`symlearn.learners.neural.input_sparsity`). ``--reset-actor``: which policy phases start
  from a fresh actor (critic kept), see :mod:`symlearn.learners.neural.mce_icrl`;
  ``--lambda-lr``: the multiplier step per iteration of MCE-ICRL (default 0.02) and of ME-/VME-ICRL
  (the same rule and default, on their learned cost's discounted sum).

After learning, the policy is evaluated on 20 episodes (mean action) against the environment's
ground truth (``info["cost"]``), and the cost's recovery of the true unsafe set is measured on
states sampled around the expert's, in the expert states' box widened until it holds both safe
and unsafe states (``recovery_margin``; :mod:`symlearn.learners.neural.icrl_metrics`).

JSON keys: ``reward``, ``violation_rate``, ``feasible_reward``, ``recovery_auc``,
``recovery_iou``, ``recovery_margin``, ``expert_reward`` (null when the demonstrations hold no
rewards), ``lambda``, ``expert_cost`` (the learned
cost's sum per demonstration episode: ``mean``, ``min``, ``max``, ``episodes``, ``mean_length``; the
mean is the limit ``symlearn train --cost`` holds an agent to by default), ``cost_inputs`` (``entries``,
``names``, ``from``: given / declared features / all, ``selection``: candidates, selected, AUCs,
``shares`` of the first layer's weight; ``names`` from the environment's ``observation_names``,
else its ``feature_names`` where there is one per observation entry, else null),
``demonstrations`` (where they came from: their ``metadata["source"]``, the ``--demos`` file or
the expert that was run; also in the cost file's provenance),
``iterations``, ``actor_resets`` (the iterations whose policy phase started from a fresh actor),
``seconds``, ``timings`` (``nominal``, ``pretrain``, ``policy``, ``cost``), ``history`` (per
iteration), ``files``.
``-o`` must end in ``.safetensors``; the configuration goes to the ``.json`` beside it.
``--log run.csv``: the same per-iteration history as a CSV table (one row per iteration, a column
per number; :mod:`symlearn.rl.training_log`).
"""

from __future__ import annotations

import argparse
from typing import Any

from symlearn.cli.flag_values import demo_count

METHODS = ("mce-icrl", "me-icrl", "vme-icrl", "gacl")
EVAL_EPISODES = 20


def register_learn(commands, common) -> None:
    cmd = commands.add_parser(
        "icrl", parents=[common()], help="learn a neural cost by inverse constrained RL (continuous spaces)",
        description="Maximum causal entropy inverse constrained RL with a neural feature network (thesis "
                    "chapter 2, Algorithm 2.1): PPO on r - lambda.phi(s,a) alternating with steps on lambda "
                    "and phi that match the expert's discounted feature sums; --method me-icrl / vme-icrl / gacl run "
                    "the baselines (Malik et al.'s maximum entropy ICRL, Liu et al.'s variational ICRL, a GAIL-style "
                    "discriminator) instead. Reports reward, violation rate, feasible reward and the recovery "
                    "of the environment's unsafe set.")
    cmd.add_argument("--env", required=True, help="a bundled environment (blocked-point, point-circle, the blocked "
                                                   "MuJoCo tasks: see symlearn envs), a gymnasium id or module:EnvId "
                                                   "(then --demos)")
    cmd.add_argument("--method", choices=METHODS, default="mce-icrl",
                     help="mce-icrl (maximum causal entropy, default), me-icrl (Malik et al.'s baseline), vme-icrl "
                          "(Liu et al.'s variational baseline) or gacl (GAIL-style discriminator)")
    source = cmd.add_mutually_exclusive_group()
    source.add_argument("--demos", help="expert demonstrations (.npz or .jsonl) with observations and actions")
    source.add_argument("--n-demos", type=demo_count, default=20,
                        help="episodes of the expert to record (20): the scripted one, else PPO-Lagrangian")
    cmd.add_argument("--expert-steps", type=int, default=1_000_000,
                     help="PPO-Lagrangian steps of the expert where there is no scripted one (1000000)")
    cmd.add_argument("--expert-cache", metavar="DIR",
                     help="where trained experts' demonstrations are cached (default ~/.cache/symlearn/experts; "
                          "'none': no cache)")
    cmd.add_argument("--steps", type=int, default=240_000,
                     help="PPO steps in all: 1/8 nominal, the rest over the iterations (240000)")
    cmd.add_argument("--iterations", type=int, default=10, help="ICRL iterations (10)")
    cmd.add_argument("--beta", type=float, default=None,
                     help="entropy coefficient of the policy phases, > 0 (mce-icrl 0.03, the others 0.01)")
    cmd.add_argument("--cost-inputs", help="candidate observation entries of the cost: names (x,y; x0,x1 where "
                                            "nothing names them; a Discrete observation's states cell=3, "
                                            "or its name for all of them), indices or 'all' (default: the environment's "
                                            "declared constraint features, else all)")
    cmd.add_argument("--select-inputs", type=float, default=0.01, metavar="TOL",
                     help="keep the fewest candidate inputs that tell expert from nominal states within TOL of all "
                          "of them (held-out AUC; default 0.01, 0 = every candidate)")
    cmd.add_argument("--cost-sparsity", type=float, default=0.0,
                     help="mce-icrl: group-sparsity penalty on the cost network's inputs (default 0 = off)")
    cmd.add_argument("--cost-memory", choices=("all", "current"), default=None,
                     help="mce-icrl: which policies' samples the cost network learns from: every iteration's "
                          "since the first policy phase (all, default: what the cost learned early is kept) or the "
                          "current policy's only (current: the thesis' Algorithm 2.1)")
    cmd.add_argument("--reset-actor", choices=("never", "every", "last", "auto"), default="auto",
                     help="which policy phases start from a fresh actor (critic kept): auto (default: after two "
                          "phases in a row that left the learned cost's excess over the expert's almost "
                          "unchanged), never, every, or the last (the returned policy learns afresh on the "
                          "final cost)")
    cmd.add_argument("--lambda-lr", type=float,
                     help="the multipliers' step per iteration, mce-icrl, me-icrl and vme-icrl (default 0.02; 0.1 met "
                          "the blocked HalfCheetah target with mce-icrl)")
    cmd.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments of the environment (a JSON object)")
    cmd.add_argument("-o", "--output", metavar="COST.safetensors",
                     help="write the learned cost here (and COST.json beside it)")
    cmd.add_argument("--log", metavar="FILE.csv", help="one CSV row per ICRL iteration (reward, true violation "
                                                        "rate, multipliers, seconds, ...)")
    cmd.set_defaults(handler=_icrl)


# --- arguments -------------------------------------------------------------------------------------


def _check_arguments(args: argparse.Namespace) -> None:
    """Everything that can be refused before any work."""
    import math

    from symlearn.errors import DataError

    if args.output and not str(args.output).endswith(".safetensors"):
        raise DataError(f"-o must end in .safetensors, got {args.output!r}",
                        hint="the cost is two files, NAME.safetensors and NAME.json")
    if args.beta is not None and not (math.isfinite(args.beta) and args.beta > 0):
        raise DataError(f"--beta must be a number > 0, got {args.beta:g}",
                        hint="beta weighs the policy's entropy; MCE-ICRL needs some (e.g. 0.01)")
    if args.iterations < 1:
        raise DataError(f"--iterations must be at least 1, got {args.iterations}")
    if args.lambda_lr is not None and (args.method == "gacl" or not (math.isfinite(args.lambda_lr)
                                                                      and args.lambda_lr > 0)):
        raise DataError(f"--lambda-lr must be a number > 0 and is for --method mce-icrl, me-icrl or vme-icrl, got "
                        f"{args.lambda_lr:g} with {args.method}")
    if not (math.isfinite(args.select_inputs) and 0 <= args.select_inputs <= 0.5):
        raise DataError(f"--select-inputs must be a number in [0, 0.5] (an AUC tolerance; 0 = off), got "
                        f"{args.select_inputs:g}")
    if not (math.isfinite(args.cost_sparsity) and args.cost_sparsity >= 0) or (
            args.cost_sparsity and args.method != "mce-icrl"):
        raise DataError(f"--cost-sparsity must be a number >= 0 and is for --method mce-icrl only, got "
                        f"{args.cost_sparsity:g} with {args.method}")
    if args.expert_steps < 1:
        raise DataError(f"--expert-steps must be at least 1, got {args.expert_steps}")
    if args.steps < 8 * args.iterations:
        raise DataError(f"--steps {args.steps} is too few for {args.iterations} iterations")


def _input_entries(env: Any, names: Any, width: int) -> tuple[Any, int]:
    """The entries the cost network reads and their names. A ``Discrete`` observation reaches the
    networks one-hot: one entry per state, named ``cell=3`` (``x=3`` where nothing names the
    observation), where the observation's own width would be one entry of its id."""
    space = env.observation_space
    if type(space).__name__ != "Discrete":
        return names, width
    base = names[0] if names is not None and len(names) == 1 else "x"
    return tuple(f"{base}={int(space.start) + i}" for i in range(int(space.n))), int(space.n)


def _cost_inputs(text: str | None, names: Any, width: int) -> list[int] | None:
    from symlearn.errors import DataError

    if not text:
        return None
    if text.strip() == "all":
        return list(range(width))
    dims = []
    for item in (part.strip() for part in text.split(",")):
        one_hot = [i for i, name in enumerate(names or ()) if name.startswith(f"{item}=")]
        if one_hot and item not in (names or ()):   # a Discrete observation's name: all its entries
            dims.extend(one_hot)
            continue
        if item.lstrip("-").isdigit():
            index = int(item)
        elif names is not None and item in names:
            index = list(names).index(item)
        elif names is None and len(item) > 1 and item[0] == "x" and item[1:].isdigit():
            index = int(item[1:])   # unnamed entries are x0, x1, ... as learn dnf names them
        else:
            raise DataError(f"--cost-inputs: unknown observation entry {item!r}",
                            hint="observation entries: " + (", ".join(names) if names
                                                            else f"x0..x{width - 1} (or 0..{width - 1})"))
        if not 0 <= index < width:
            raise DataError(f"--cost-inputs: index {index} outside the observation's {width} entries")
        dims.append(index)
    return dims


# --- the command -----------------------------------------------------------------------------------


def _icrl(args: argparse.Namespace, out) -> None:
    import time

    from symlearn.cli.output import blame_file
    from symlearn.envs.registry import Kind, entries
    from symlearn.errors import DataError
    from symlearn.recipes.environments import CostWatch, observation_width, resolve_env
    from symlearn.recipes.experts import demonstrations

    _check_arguments(args)
    started = time.perf_counter()
    target = resolve_env(args.env, args.env_kwargs)
    if target.bundled and not (target.has_kind(Kind.CONTINUOUS) and "mce-icrl" in target.entry.methods):
        # the tabular gridworld's mce-icrl is `symlearn learn constraints`
        usable = [e.name for e in entries(Kind.CONTINUOUS) if "mce-icrl" in e.methods]
        raise DataError(f"{target.display} is no environment for neural ICRL",
                        hint="use " + ", ".join(usable) + ", or your own environment (module:EnvId) with --demos")
    # a Dict observation (MiniGrid's) flattened to what the networks read; a MultiDiscrete or
    # MultiBinary action space seen as one Discrete of its combinations (what our PPO acts in)
    target = target.as_numeric(actions=True)
    env = target.make()
    names = target.observation_names(env)
    entry_names, width = _input_entries(env, names, observation_width(env) or 1)
    obs_dims = _cost_inputs(args.cost_inputs, entry_names, width)
    seed = getattr(args, "seed", 0) or 0
    demos = demonstrations(target, args.demos, args.n_demos, seed=seed, expert_steps=args.expert_steps,
                           expert_cache=args.expert_cache, note=out.note)
    demos = _in_the_view(demos, env, args.demos, names)
    # whether the environment reports a cost is read from every step learning and evaluation take
    # (one may report info["cost"] only on the steps that pay it), not from a first step
    watch = CostWatch()
    target = target.watched(watch)

    import torch

    from symlearn.learners.neural import NeuralGACL, NeuralMCEICRL, NeuralMEICRL, NeuralVMEICRL
    from symlearn.learners.neural.icrl_metrics import recovery
    from symlearn.rl.episode_metrics import episode_metrics
    from symlearn.rl.episodes import demonstration_batch, sample_episodes
    from symlearn.rl.training_log import TrainingLog

    torch.set_num_threads(1)  # small networks: a second thread only contends on 2 shared cores

    nominal = max(args.steps // 8, 1)
    method = {"mce-icrl": NeuralMCEICRL, "me-icrl": NeuralMEICRL, "vme-icrl": NeuralVMEICRL,
              "gacl": NeuralGACL}[args.method]
    if args.cost_memory is not None and args.method != "mce-icrl":
        raise DataError(f"--cost-memory is a setting of --method mce-icrl, not {args.method}")
    learner = method(**({} if args.beta is None else {"beta": args.beta}),  # None: the method's own default
                     n_iterations=args.iterations, nominal_steps=nominal,
                     policy_steps=max((args.steps - nominal) // args.iterations, 1), obs_dims=obs_dims,
                     random_state=seed, reset_actor=args.reset_actor, select_inputs=args.select_inputs,
                     **({} if args.lambda_lr is None else {"lambda_lr": args.lambda_lr}),
                     **({} if not args.cost_sparsity else {"input_sparsity": args.cost_sparsity}),
                     **({} if args.cost_memory is None else {"cost_memory": args.cost_memory}))

    env_fn = _within_the_demonstrations_horizon(target, env, demos, out.note)
    log = TrainingLog(args.log, step_key="iteration") if args.log else None  # an unwritable path fails now
    from symlearn.cli.env_errors import environment_file, raised_by_environment

    # an exception from the user's environment code is theirs: one line naming its file and line
    with raised_by_environment(None if target.bundled else environment_file(env), f"learning in {target.display}"):
        with blame_file(args.demos):
            learner.fit(demos, env_fn)
        if log is not None:
            for record in learner.history_:
                log.write(record.as_dict())
        evaluation = episode_metrics(sample_episodes(learner.policy_, env_fn, EVAL_EPISODES, seed=seed + 50_000,
                                                     deterministic=True))
    expert_obs, _ = demonstration_batch(demos).pairs()
    unsafe = getattr(env.unwrapped, "is_unsafe", None)
    rec = None if unsafe is None else recovery(learner.cost_, unsafe, expert_obs.reshape(len(expert_obs), -1),
                                               seed=seed, margin="auto")
    result = learner.result_
    has_cost = watch.seen   # once one step reported info["cost"], the steps without it cost 0
    doc = {"env": target.display, "method": args.method, "reward": evaluation.reward,
           # a user's environment without info["cost"] has no ground truth: n/a, never 0
           "violation_rate": evaluation.violation_rate if has_cost else None,
           "feasible_reward": evaluation.feasible_reward if has_cost else None,
           "recovery_auc": None if rec is None else rec.as_dict()["auc"],
           "recovery_iou": None if rec is None else rec.as_dict()["iou"],
           "recovery_margin": None if rec is None else rec.margin,
           # demonstrations written without rewards say nothing of the expert's: n/a, never 0
           "expert_reward": result.metrics["expert_reward"] if any(t.rewards is not None for t in demos) else None,
           "lambda": [float(x) for x in learner.cost_.lambdas.numpy()],
           # what the cost charges the demonstrations per episode: `train --cost`'s default limit
           "expert_cost": learner.cost_.provenance.get("expert_cost"),
           "cost_inputs": _named_inputs(result.metrics["cost_inputs"], entry_names),
           "demonstrations": learner.cost_.learned_from,
           "iterations": len(learner.history_), "actor_resets": result.metrics.get("actor_resets"),
           "seconds": time.perf_counter() - started,
           "timings": {k: v for k, v in result.timings.items() if k != "total"},
           "history": [h.as_dict() for h in learner.history_], "files": []}
    doc["warnings"] = lambda_warnings(doc["lambda"], doc["cost_inputs"], negligible_charge(doc))
    if args.output:
        path = learner.save(args.output)
        doc["files"] = [str(path), str(path.with_suffix(".json"))]
    out.result(doc, _render)


def _in_the_view(demos: Any, env: Any, path: Any, names: Any = None) -> Any:
    """Demonstrations recorded in the environment itself, seen as the policy and the cost see it:
    a ``Dict``-observing environment's own observations (``record`` keeps a dict of scalars as
    feature states, and a Dict of vectors as named columns) as the flat numeric view
    (:mod:`symlearn.recipes.spaces`), MultiDiscrete or MultiBinary actions as the ids of their
    combinations (:mod:`symlearn.recipes.action_spaces`); feature-dict states of an environment
    with an array observation, placed by the names of its entries (``names``:
    ``observation_names``, else ``feature_names`` one per entry)."""
    from collections.abc import Mapping

    import numpy as np

    from symlearn.data import Demonstrations, Trajectory
    from symlearn.errors import DataError
    from symlearn.recipes.action_spaces import find_joint_actions
    from symlearn.recipes.spaces import find_numeric_view

    if demos.state_kind == "symbol":
        raise DataError("the demonstrations' states are symbols (text); neural ICRL reads numeric observations",
                        file=path, hint="give the observations as numbers (vector states)")


    joint = find_joint_actions(env)
    if joint is not None:   # recorded actions of the environment's own space, as ids of the view
        try:
            demos = Demonstrations([Trajectory(t.states, None if t.actions is None else
                                               np.array([joint.index_of(a) for a in t.actions], dtype=np.int64),
                                               t.rewards, t.labels, t.info) for t in demos],
                                   metadata=demos.metadata)
        except DataError as exc:
            raise DataError(f"the demonstrations' actions do not fit: {exc.message}", file=path,
                            hint="were they recorded in this environment?") from None
    observed = find_numeric_view(env)
    if observed is None:
        if isinstance(demos[0].states[0], Mapping):
            return _placed_by_name(demos, env, path, names)
        return demos
    columns = demos.metadata.get("feature_names")
    if not isinstance(demos[0].states[0], Mapping):
        if columns and list(columns) == list(observed.column_names):
            return demos   # recorded in the view itself (`data record` where the observation holds an image)
        if not (columns and demos.state_kind == "vector"):
            return _vectors_in_the_view(demos, observed, path)

        # named columns of a Dict observation (record, Minari): rebuilt by name, so a Discrete
        # part becomes the one-hot columns the policy reads
        def view(row: Any) -> Any:
            return observed.from_columns(dict(zip(columns, np.asarray(row).tolist())))
    else:
        view = observed.observation
    try:
        items = [Trajectory(np.stack([view(s) for s in t.states]), t.actions, t.rewards, t.labels, t.info)
                 for t in demos]
    except DataError as exc:
        raise DataError(exc.message, file=path, hint=exc.hint) from None
    except (KeyError, TypeError, ValueError, AssertionError) as exc:
        raise DataError(f"the demonstrations' states do not fit the observation space {observed.env.observation_space}"
                        f" ({type(exc).__name__}: {exc})", file=path,
                        hint="were they recorded in this environment?") from None
    return Demonstrations(items, metadata=demos.metadata)


def _placed_by_name(demos: Any, env: Any, path: Any, names: Any) -> Any:
    """Feature-dict states (``{"x": .., "y": ..}``, a JSONL file's named columns) as the vectors of an
    array observation, each entry taken from the key that names it."""
    import numpy as np

    from symlearn.data import Demonstrations, Trajectory
    from symlearn.errors import DataError

    keys = sorted(demos[0].states[0])
    space = env.observation_space
    if names is None:
        raise DataError(f"the demonstrations' states are named features ({', '.join(keys)}) but the environment's "
                        f"observation {space} does not name its entries", file=path,
                        hint="give vector states in the observation's order, or give the environment an "
                             "observation_names (or feature_names) attribute")
    missing = [n for n in names if n not in demos[0].states[0]]
    if missing:
        raise DataError(f"the demonstrations' states lack the observation entr{'y' if len(missing) == 1 else 'ies'} "
                        f"{', '.join(map(repr, missing))} (their features: {', '.join(keys)}; the observation's: "
                        f"{', '.join(map(str, names))})", file=path, hint="were they recorded in this environment?")
    shape = getattr(space, "shape", None) or (len(names),)
    try:
        items = [Trajectory(np.asarray([[s[n] for n in names] for s in t.states], dtype=np.float64).reshape(
            len(t.states), *shape), t.actions, t.rewards, t.labels, t.info) for t in demos]
    except (TypeError, ValueError) as exc:
        raise DataError(f"the demonstrations' features do not fit the observation {space} ({exc})", file=path,
                        hint="the observation's entries must be numbers") from None
    return Demonstrations(items, metadata=demos.metadata)


def _within_the_demonstrations_horizon(target: Any, env: Any, demos: Any, note: Any) -> Any:
    """The environment factory; for a user's environment without a time limit (no gymnasium
    ``TimeLimit``) whose demonstrations were all cut off rather than ended (``record()``'s
    ``max_steps``: ``info["truncated"]``), episodes cut at the longest demonstration's length,
    so the policy's sampled episodes are as long as the ones they are compared with (and do not
    run to the sampler's cap of 10,000 steps). Not where the environment truncates its episodes
    by itself within that length (a replay of the longest demonstration shows it)."""
    if target.bundled or getattr(getattr(env, "spec", None), "max_episode_steps", None) is not None:
        return target.env_fn
    infos = [getattr(t, "info", None) or {} for t in demos]
    if not all(i.get("truncated") is True and i.get("terminated") is False for i in infos):
        return target.env_fn
    horizon = max((len(t.actions) for t in demos if t.actions is not None), default=0)
    if horizon < 1 or _truncates_itself(target, max(demos, key=lambda t: 0 if t.actions is None else len(t.actions))):
        return target.env_fn
    from gymnasium.wrappers import TimeLimit

    note(f"note: {target.display} registers no time limit and every demonstration was cut off, none ended: its "
         f"episodes are cut at {horizon} steps, the demonstrations' longest "
         "(gymnasium.register(..., max_episode_steps=N) sets a limit)")
    return lambda: TimeLimit(target.make(), max_episode_steps=horizon)


def _truncates_itself(target: Any, longest: Any) -> bool:
    """Whether the environment ends an episode by itself (``truncated``) when the longest
    demonstration's actions are replayed from its seed, at or before the demonstration's length:
    then it has a time limit of its own, if not a registered one. A replay that fails, or ends
    (terminated) where the demonstration went on, says nothing: False."""
    seed = (getattr(longest, "info", None) or {}).get("seed")
    env = target.make()
    try:
        env.reset(seed=seed if isinstance(seed, int) else None)
        for action in longest.actions:
            _, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                return bool(truncated) and not terminated
        return False
    except Exception:  # noqa: BLE001 -- the run itself reports a failing environment, in its own words
        return False
    finally:
        env.close()


def _vectors_in_the_view(demos: Any, env: Any, path: Any) -> Any:
    """Vector states ``record()`` stored for a Dict/Tuple observation (a Discrete part one integer
    column) rebuilt and seen through the numeric view ``env`` (where it is one-hot); states that
    already have the view's width are taken as they are."""
    import numpy as np

    from symlearn.data import Demonstrations, Trajectory
    from symlearn.errors import DataError
    from symlearn.recipes.environments import observation_width
    from symlearn.recipes.spaces import from_record_columns, record_columns_width

    space = env.env.observation_space
    shape = np.asarray(demos[0].states[0]).shape
    width = int(np.prod(shape, dtype=np.int64))
    if width == observation_width(env):
        return demos
    if width != record_columns_width(space):
        parts = (f"Dict of {', '.join(map(str, space.spaces))}" if hasattr(space.spaces, "keys")
                 else f"Tuple of {len(space.spaces)} parts")
        raise DataError(f"the demonstrations' states have shape {shape}; the policy and the cost read the "
                        f"observation ({parts}) as {observation_width(env)} numbers", file=path,
                        hint="record them in the view the policy reads: record(symlearn.recipes.spaces."
                             "numeric_observations(env), policy, n)")
    try:
        items = [Trajectory(np.stack([env.observation(from_record_columns(space, s)) for s in t.states]),
                            t.actions, t.rewards, t.labels, t.info) for t in demos]
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise DataError(f"the demonstrations' states do not fit the observation space {space}"
                        f" ({type(exc).__name__}: {exc})", file=path,
                        hint="were they recorded in this environment?") from None
    return Demonstrations(items, metadata=demos.metadata)


def _named_inputs(inputs: dict, names: Any) -> dict:
    """The learner's report of the cost's inputs, its entries named by what the CLI knows of the
    observation (``EnvTarget.observation_names``: ``observation_names``, else ``feature_names``
    one per observation entry) where the cost itself carries no names; ``x0, x1, ...`` when nothing
    names them (what ``learn dnf`` and ``learn spec`` call them, and ``--cost-inputs`` reads)."""
    if inputs.get("names") is not None:
        return inputs
    if names is None:
        return {**inputs, "names": [f"x{int(i)}" for i in inputs["entries"]]}
    names = list(names)
    if any(not 0 <= int(i) < len(names) for i in inputs["entries"]):
        return inputs
    return {**inputs, "names": [str(names[int(i)]) for i in inputs["entries"]]}


#: below this held-out AUC the cost's inputs hardly tell the demonstrations' states from the
#: nominal policy's (boost_rover, whose constraint is about an action: 0.66; lava_grid 0.99)
SEPARABLE_AUC = 0.75


#: a cost that charges the policy's episodes less than this share of the reward the policy earns
#: over the expert cannot move it: 0 in effect (boost_rover with the dual step's fix: lambda
#: <= 0.0002, 0.0003 per episode against a gap of 2.7; every other run measured: >= 0.3)
NEGLIGIBLE_SHARE = 0.01


def negligible_charge(doc: dict) -> tuple[float, float] | None:
    """``(charge, gap)`` when the learned cost is 0 in effect though some lambda is not: the final
    multipliers times the last iteration's policy feature sums (what it charges the policy's
    discounted episode) are under :data:`NEGLIGIBLE_SHARE` of the reward the policy earns over the
    demonstrations; None otherwise or where the result does not say (no history, no expert
    reward)."""
    history, expert_reward = doc.get("history") or [], doc.get("expert_reward")
    if not history or expert_reward is None or doc.get("reward") is None or not any(doc["lambda"]):
        return None
    features = history[-1].get("policy_features") if isinstance(history[-1], dict) else None
    if not features or len(features) != len(doc["lambda"]):
        return None
    charge = float(sum(l * f for l, f in zip(doc["lambda"], features)))
    gap = float(doc["reward"]) - float(expert_reward)
    return (charge, gap) if gap > 0 and charge < NEGLIGIBLE_SHARE * gap else None


def lambda_warnings(lambdas: list[float], cost_inputs: dict | None = None,
                    in_effect: tuple[float, float] | None = None) -> list[str]:
    """A warning when every lambda is 0: the cost is 0 everywhere and `train --cost` constrains
    nothing (issue 24: a fresh conveyor arm, seed 2, whose report said only "lambda 0, 0, 0, 0"),
    or when it is 0 in effect (``in_effect``: :func:`negligible_charge`'s charge and reward gap).
    ``cost_inputs`` (the result's, with the input selection's held-out AUC of telling the
    demonstrations' states from the nominal policy's): where that AUC is low the warning names it
    as the likely cause (docs/BENCHMARKS.md, "Fresh user modules, second pass")."""
    if any(lambdas) and in_effect is None:
        return []
    if in_effect is None:
        what = "every lambda is 0: the learned cost is 0 everywhere and constrains nothing"
    else:
        what = (f"the learned cost is 0 in effect (lambda at most {max(lambdas):.3g}): it charges the policy's "
                f"episodes {in_effect[0]:.3g}, against the {in_effect[1]:.3g} of reward they earn over the "
                "demonstrations, and constrains nothing")
    selection = (cost_inputs or {}).get("selection") or {}
    auc = selection.get("all_candidates_auc") if isinstance(selection, dict) else None
    names = ", ".join(map(str, (cost_inputs or {}).get("names") or ())) or "its inputs"
    if isinstance(auc, (int, float)) and auc < SEPARABLE_AUC:
        return [f"{what}. The cost reads "
                f"{names}, which hardly tell the demonstrations' states from the unconstrained policy's "
                f"(held-out AUC {auc:.2f}): a constraint on actions, or on what these entries do not hold, "
                "cannot be learned from them; name the entries that matter with --cost-inputs (all: every "
                "entry), or learn a rule over the environment's features (data record --states features, "
                "learn dnf)"]
    return [f"{what} (the steps on lambda "
            "never grew it: the policy's feature sums never exceeded the demonstrations'); learn again with "
            "another --seed or more --iterations / --steps"]


#: inputs named on the cost-inputs line of the text report
SHOWN_INPUTS = 12


def _render_inputs(inputs: dict) -> str:
    """One line: where the cost's candidate inputs came from, whether they were selected, and the
    entries read with their share of the first layer's weight."""
    names = inputs["names"] or inputs["entries"]
    pairs = list(zip(names, inputs["shares"]))
    more = ""
    if len(pairs) > SHOWN_INPUTS:   # a camera's pixels: the largest shares, the rest counted
        pairs = sorted(pairs, key=lambda pair: -pair[1])[:SHOWN_INPUTS]
        more = f", ... {len(names) - SHOWN_INPUTS} more (the largest shares shown; --json lists every one)"
    read = ", ".join(f"{name} {share:.2f}" for name, share in pairs)
    return f"  cost inputs ({inputs['from']}{', selected' if inputs['selection'] else ''}): {read}{more}"


def _render(doc: dict) -> str:
    def number(x: Any) -> str:
        return "n/a" if x is None else f"{x:.3f}"

    lines = [f"{doc['method']} on {doc['env']}: {doc['iterations']} iterations in {doc['seconds']:.1f} s",
             f"  reward {doc['reward']:.2f} (expert "
             + ("n/a" if doc["expert_reward"] is None else f"{doc['expert_reward']:.2f}") + "), violation rate "
             f"{number(doc['violation_rate'])}, feasible reward "
             + ("n/a" if doc["feasible_reward"] is None else f"{doc['feasible_reward']:.2f}"),
             f"  recovery of the unsafe set: AUC {number(doc['recovery_auc'])}, IoU {number(doc['recovery_iou'])}",
             "  lambda " + ", ".join(f"{x:.3g}" for x in doc["lambda"]),
             _render_inputs(doc["cost_inputs"])]
    if doc.get("expert_cost"):
        level = doc["expert_cost"]
        lines.append(f"  the cost charges the expert {level['mean']:.3g} per episode ({level['min']:.3g} .. "
                     f"{level['max']:.3g}): the limit `symlearn train --cost` holds an agent to by default")
    if doc.get("demonstrations"):
        lines.append(f"  learned from {doc['demonstrations']}")
    lines += [f"wrote {f}" for f in doc["files"]]
    lines += [f"warning: {w}" for w in doc.get("warnings") or ()]
    return "\n".join(lines)
