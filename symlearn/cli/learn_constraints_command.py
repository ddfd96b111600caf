"""``symlearn learn constraints``: learn the constraints an expert obeys in a discrete world.

``symlearn learn constraints (--env NAME | --domain DIR) [--demos D.jsonl | --n-demos N]
[--method logic|ml|mce-icrl] [--iterations N] [-o rules.lp]``

* ``--env``: a bundled environment (``symlearn envs``); ``--domain DIR``: a user's domain folder
  (``domain.toml``, see docs/FORMATS.md), with ``--demos`` (state ids; action ids or atoms).
* ``logic`` (default where the world has ASP facts): maximum-likelihood inference plus ILP
  induction each iteration, ``--iterations`` a cap (the result says why it stopped:
  ``stop_reason``/``stop``); likely constraints the bias cannot express are listed as
  ``unexplained``; ``-o`` writes the rules as an editable ``.lp`` file (both in its header).
* ``ml``: maximum-likelihood constraint inference alone; ``-o`` writes the forbidden pairs.
* ``mce-icrl``: maximum causal entropy inverse constrained RL (with the world's reward, or a sparse
  one for reaching where demonstrations end); prints the learned cost map, and ``-o X.json`` writes
  the forbidden pairs and the multipliers, the cost map as text (``X.costmap.txt``) and as a
  picture (``X.costmap.dot``, ``X.costmap.svg`` with Graphviz).

``--validation FRACTION`` holds out that share of the demonstrations (whole episodes) before
learning and reports (``validation`` in the JSON) the share of held-out expert steps the learned
constraint forbids -- a check that needs no ground truth; a warning (``warnings``) when it is
not 0. ``warnings`` also holds what the data or the folder's files give reason to doubt: steps the
model gives probability zero, noise counted under ``--noise``, and (``--domain``) bias
declarations, truth rules or ``--known`` rules that name a predicate defined nowhere.

With ``--domain`` the whole run (reading the folder, grounding, learning, writing ``-o``) happens
in a worker process bounded by ``--timeout`` (default 600 s) and ``--max-memory`` (default
``SYMLEARN_MAX_MEMORY_MB`` or 1024 MB), as in ``domain check``: the folder's programs are the
user's, and grounding them cannot be interrupted. Its notes are printed when it ends.

``-o`` must end in ``.lp`` for ``logic`` and in ``.json`` otherwise: a mismatch is refused before
anything is learned (``--method ml -o X.lp`` would put JSON into a file named like rules).

The scores (``fpr``, ``fnr``, ``accuracy``) compare the learned forbidden pairs (with those of the
``--known`` rules: what an agent obeys; ``known_constraints`` counts the pairs only they forbid) with
the ground truth over every pair that exists; they are ``null`` for a domain without truth rules. With a
truth, ``reach_fpr`` and ``reach_fnr`` score the pairs an agent obeying the truth can reach from
the model's start (``reach_pairs``; ``unreachable`` counts the others, in states no rule-abiding
demonstration can visit), printed as a second line when some pairs are unreachable.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from symlearn.cli.bounded_domain import add_domain_limits, run_on_domain
from symlearn.cli.output import blame_file
from symlearn.cli.flag_values import demo_count

METHODS = ("logic", "ml", "mce-icrl")


@dataclass(frozen=True)
class _World:
    """What the command learns in: a bundled environment or a user's domain, read alike."""

    name: str
    mdp: Any
    space: Any  # (S, A) pairs that exist
    truth: Any  # (S, A) forbidden by the ground truth, or None
    has_reward: bool
    domain: Any = None  # a symlearn.grounding.Domain where rules can be learned
    expert: Any = None  # (n, seed) -> Demonstrations, bundled worlds only
    bundled: Any = None  # the LogicMDP of a bundled logic domain (SUMO experts)
    rationality: float | str = "auto"  # a bundled setting's tuned value, else fitted (``"auto"``)
    features: str = "state"
    grid: Any = None  # a grid environment to draw the learned cost map on, where the world is one
    starts: tuple[int, int] = (0, 0)  # the first ids of a user's Discrete(n, start=k) observations, actions


def register_learn(commands, common) -> None:
    from symlearn.envs.constraint_envs import CONSTRAINT_ENVS

    cmd = commands.add_parser(
        "constraints", parents=[common()], help="learn the constraints an expert obeys (rules, constraint sets)",
        description="Learn constraints from demonstrations in a discrete environment: ASP rules (logic constraint "
                    "inference), maximum-likelihood constraint sets, or MCE-ICRL cost maps.")
    where = cmd.add_mutually_exclusive_group(required=True)
    where.add_argument("--env", metavar="ENV",
                       help=f"a bundled environment: {', '.join(CONSTRAINT_ENVS)} (see `symlearn envs`), or a "
                            "discrete gymnasium environment that exposes its model (a gymnasium id such as "
                            "CliffWalking-v1, or module:EnvId; env.unwrapped.P or to_tabular(); methods ml and "
                            "mce-icrl, with --demos); a world with ASP facts is a domain folder (--domain)")
    cmd.add_argument("--env-kwargs", metavar="JSON",
                     help="keyword arguments of your own --env (a JSON object)")
    where.add_argument("--domain", metavar="DIR", help="your own domain folder (domain.toml; see docs/FORMATS.md)")
    cmd.add_argument("--allow-outside", action="store_true", help="let the domain folder name files outside itself (paths, symlinks, #include); only for a trusted folder")
    add_domain_limits(cmd, "reading, grounding and learning")
    source = cmd.add_mutually_exclusive_group()
    source.add_argument("--demos", help="demonstrations (.jsonl or .npz) with the environment's state/action ids or names")
    source.add_argument("--n-demos", type=demo_count, default=50, help="generate N demonstrations of the bundled expert (50)")
    cmd.add_argument("--expert", choices=("native", "sumo"), default="native",
                     help="who drives the generated junction demonstrations: our traffic model (native, default) "
                          "or SUMO's car-following and junction logic (sumo extra)")
    cmd.add_argument("--method", choices=METHODS, default=None,
                     help="logic (default where rules can be learned), ml, or mce-icrl (default for gridworld)")
    cmd.add_argument("--iterations", type=int, default=None,
                     help="inference iterations (logic: at most 20, it stops on convergence; ml: 200) or dual steps "
                          "(mce-icrl: 300)")
    cmd.add_argument("--horizon", type=int, default=30, help="planning horizon of the MaxEnt passes (30)")
    cmd.add_argument("--reward", choices=("given", "sparse"), default=None,
                     help="plan with the world's reward (default where it has one) or a sparse reward for "
                          "reaching where demonstrations end")
    cmd.add_argument("--rationality", default=None, metavar="BETA|auto",
                     help="logic/ml: inverse temperature of the MaxEnt model (--domain: auto, fitted to the "
                          "demonstrations by maximum likelihood; bundled worlds: their setting's, 1, 3 for gridworld)")
    cmd.add_argument("--min-evidence", type=float, default=None, metavar="NATS",
                     help="logic: keep an iteration's constraint only if what it forbids makes the demonstrations at "
                          "least this many nats likelier under the nominal planner (default 1: Akaike's price of a "
                          "parameter; 0 turns the test off)")
    cmd.add_argument("--known", help="an .lp file of rules known in advance (logic environments)")
    cmd.add_argument("--noise", action="store_true",
                     help="treat demonstrated steps that break --known rules as noise (warn) instead of an error")
    cmd.add_argument("--max-body", type=int, default=None, metavar="N",
                     help="logic: the longest rule body the bias's rules may have (default 3); a rule that joins "
                          "two variables, ':- put, at(P), hot(P), holding(O), fragile(O).', needs 5")
    cmd.add_argument("--stochasticity", type=float, default=0.0, help="slip probability p of the gridworld (0)")
    cmd.add_argument("--features", choices=("state", "state_action"), default=None,
                     help="mce-icrl: one multiplier per state (gridworld default) or per state-action pair "
                          "(default for --domain)")
    cmd.add_argument("--validation", type=float, default=None, metavar="FRACTION",
                     help="hold out this share of the demonstrations (whole episodes, at random with --seed) and "
                          "report the share of held-out expert steps the learned constraint forbids")
    cmd.add_argument("-o", "--output", metavar="FILE",
                     help="write the rules (logic: FILE.lp) or the forbidden pairs (ml, mce-icrl: FILE.json; "
                          "mce-icrl also writes the cost map as FILE.costmap.txt/.dot/.svg)")
    cmd.set_defaults(handler=_constraints)


def _world(args: argparse.Namespace) -> _World:
    if args.domain:
        import numpy as np

        from symlearn.grounding import Domain

        d = Domain.from_folder(args.domain, allow_outside=args.allow_outside)
        return _World(d.name, d.mdp, ~d.unavailable, d.truth_forbidden, bool(np.any(d.mdp.rewards != 0)),
                      domain=d, features="state_action")
    from symlearn.envs.constraint_envs import CONSTRAINT_ENVS, constraint_setting

    from symlearn.errors import DataError, UnknownNameError

    env_kwargs = getattr(args, "env_kwargs", None)
    if env_kwargs and args.env.strip().lower() in CONSTRAINT_ENVS:  # before the bundled world is built
        raise DataError(f"{args.env} is a bundled environment; --env-kwargs is for your own environment")
    try:
        setting = constraint_setting(args.env, args.stochasticity)
    except UnknownNameError as exc:
        gym_world = _gymnasium_world(args.env, env_kwargs)  # a user's discrete world, or None
        if gym_world is not None:
            return gym_world
        from symlearn.recipes.environments import gymnasium_id_hint

        close = "" if exc.hint and "did you mean" in exc.hint else gymnasium_id_hint(args.env)
        raise UnknownNameError(exc.message, hint=close + (exc.hint or "") +
                               "; a discrete gymnasium environment with its "
                               "model (env.unwrapped.P or to_tabular()): a gymnasium id or module:EnvId; a world "
                               "with ASP facts: --domain DIR with --demos (a folder with domain.toml, "
                               "docs/FORMATS.md)") from None
    lm = setting.logic
    return _World(setting.name, setting.mdp, setting.space, setting.truth, setting.reward == "given",
                  domain=lm.domain if lm is not None else None, expert=setting.expert, bundled=lm,
                  rationality=setting.rationality, grid=setting.grid)


def _gymnasium_world(name: str, env_kwargs: Any) -> _World | None:
    """A discrete gymnasium environment (an id, or ``module:EnvId``) as a world to learn in, read
    through its model (:meth:`~symlearn.mdp.TabularMDP.from_gymnasium`); None when ``name`` names
    no such environment (not a gymnasium id, not ``module:EnvId``). Ground truth, where the
    environment knows it: a ``constraint_mask()`` method returning the forbidden ``(S, A)`` pairs."""
    import numpy as np

    from symlearn.errors import DataError, ModelError, UnknownNameError
    from symlearn.mdp import TabularMDP
    from symlearn.recipes.environments import resolve_env

    if ":" not in name:
        try:
            import gymnasium

            import symlearn.envs  # noqa: F401 -- registers the symlearn/ ids
        except ImportError:
            return None
        if name.strip() not in gymnasium.registry:
            return None
    try:
        target = resolve_env(name, env_kwargs)
    except UnknownNameError:
        return None
    env = target.make()
    try:
        try:
            mdp = TabularMDP.from_gymnasium(env)
        except ModelError as exc:
            raise DataError(f"{target.display}: {exc.message}; learn constraints needs a discrete world with its "
                            "model", hint="env.unwrapped.P[s][a] = [(p, s', r, terminated), ...] (gymnasium's "
                            "toy-text convention) or a to_tabular() method; for continuous states: symlearn learn "
                            "dnf or learn icrl") from None
        truth = None
        mask = getattr(env.unwrapped, "constraint_mask", None)
        if callable(mask):
            truth = np.asarray(mask(), dtype=bool)
            if truth.shape != (mdp.n_states, mdp.n_actions):
                raise DataError(f"{target.display}.constraint_mask() has shape {truth.shape}, the model "
                                f"({mdp.n_states}, {mdp.n_actions})")
    finally:
        env.close()
    space = np.ones((mdp.n_states, mdp.n_actions), dtype=bool)
    space[mdp.terminal] = False
    starts = (int(getattr(env.observation_space, "start", 0)), int(getattr(env.action_space, "start", 0)))
    return _World(target.display, mdp, space, None if truth is None else truth & space,
                  bool(np.any(mdp.rewards != 0)), starts=starts)


def _from_starts(demos, starts: tuple[int, int]):
    """Demonstrations recorded in a ``Discrete(n, start=k)`` world (ids ``k..``) as the model's
    rows ``0..n-1`` (the model names them by the ids again). Text states (names) are left alone."""
    import numpy as np

    from symlearn.data import Demonstrations, Trajectory

    s0, a0 = starts
    if (s0, a0) == (0, 0) or getattr(demos, "state_kind", None) != "discrete":
        return demos
    shifted = []
    for t in demos:
        actions = t.actions
        if actions is not None and a0 and getattr(demos, "action_kind", None) == "discrete":
            actions = np.asarray(actions) - a0
        shifted.append(Trajectory(states=np.asarray(t.states) - s0, actions=actions, rewards=t.rewards,
                                  labels=t.labels, info=t.info))
    return Demonstrations(shifted, metadata=demos.metadata)


def _constraints(args: argparse.Namespace, out) -> None:
    if args.domain and getattr(args, "env_kwargs", None):
        from symlearn.errors import DataError

        raise DataError("--env-kwargs goes with --env, not --domain")
    if args.output and args.method:  # before the world is built: a mismatch costs nothing
        _check_output(args.output, args.method)
    if args.rationality is not None:  # likewise, before a worker reads the folder
        _rationality(args, None)
    if not args.domain:
        _learn(args, out)
        return
    # a domain folder's background and bias are the user's programs: grounding them (or a bias
    # whose hypothesis space explodes) can take any time and memory, and clingo cannot be
    # interrupted, so the whole run happens in the bounded worker `domain check` and `ilp` use
    job = {key: value for key, value in vars(args).items()  # what the worker needs: the options, not the handler
           if isinstance(value, (str, int, float, bool, list, tuple, type(None)))}
    notes, doc = run_on_domain(_learn_in_worker, job, args=args,
                               what=f"learning constraints in the domain {args.domain}")
    for line in notes:
        out.note(line)
    out.result(doc, _render)


class _Collected:
    """What the worker's run would print: its notes and its result document, sent back whole."""

    def __init__(self) -> None:
        self.notes: list[str] = []
        self.doc = None

    def note(self, message: str) -> None:
        self.notes.append(message)

    def result(self, document, render=None) -> None:
        self.doc = document


def _learn_in_worker(job: dict) -> tuple[list[str], dict]:
    collected = _Collected()
    _learn(argparse.Namespace(**job), collected)
    return collected.notes, collected.doc


def _learn(args: argparse.Namespace, out) -> None:
    from symlearn.errors import DataError, SymlearnError

    if args.min_evidence is not None and not (math.isfinite(args.min_evidence) and args.min_evidence >= 0):
        raise SymlearnError(f"--min-evidence must be a number of nats >= 0, got {args.min_evidence:g}",
                            hint="leave it out for the default (1); 0 turns the test off")
    if args.iterations is not None and args.iterations < 1:  # 0 would read as "the default" below
        raise SymlearnError(f"--iterations must be at least 1, got {args.iterations}",
                            hint="leave it out for the default (logic: at most 20, stopping on convergence)")
    max_body = getattr(args, "max_body", None)
    if max_body is not None and max_body < 1:  # before the world is read: a wrong number costs nothing
        raise SymlearnError(f"--max-body must be at least 1, got {max_body}",
                            hint="leave it out for the default, 3 body literals")
    world = _world(args)
    method = args.method or ("logic" if world.domain is not None else "mce-icrl")
    if max_body is not None and method != "logic":
        raise SymlearnError(f"--max-body bounds the rules of --method logic; --method {method} learns no rules",
                            hint="leave --max-body out, or use --method logic")
    if method == "logic" and world.domain is None:
        raise SymlearnError(f"{world.name} has no ASP facts, so no rules can be learned there",
                            hint="use --method ml or --method mce-icrl")
    if args.known and world.domain is None:
        raise SymlearnError("--known rules need a world with ASP facts")
    if args.output:
        _check_output(args.output, method)
    seed = getattr(args, "seed", 0) or 0
    if args.demos:
        from symlearn.data import load

        demos = _from_starts(load(args.demos), world.starts)
    elif world.expert is None:
        raise DataError(f"{world.name} has no bundled expert: give your demonstrations with --demos FILE")
    else:
        if args.expert == "sumo":
            if world.bundled is None:
                raise DataError("--expert sumo drives the junctions only")
            demos = world.bundled.expert_demonstrations(args.n_demos, seed, source="sumo")
        else:
            demos = world.expert(args.n_demos, seed)
    reading_warnings: list[str] = []
    if world.domain is not None:
        import warnings

        from symlearn.learners.constraints.logic_constraint_inference import check_available

        # read against the domain once, before any are held out: a mistake is named by its
        # place in the file (line, column), atoms are matched as ASP reads them, and what looks
        # like noise (a step of probability zero) is one warning of the result
        with warnings.catch_warnings(record=True) as caught, blame_file(args.demos):
            warnings.simplefilter("always")
            demos = world.domain.episodes(demos)
            check_available(demos, world.domain)
        reading_warnings = [f"{args.demos}: {m}" if args.demos else m for m in _user_warnings(caught)]
    known = None
    if args.known:
        known = world.domain.rule_mask(Path(args.known))
        if not args.noise:
            with blame_file(args.demos):
                _check_known(demos, known, world.domain, args.known)
    held, held_numbers = None, None
    if args.validation is not None:
        from symlearn.learners.validation import holdout, holdout_indices

        n_all = len(demos)
        demos, held = holdout(demos, args.validation, seed=seed)
        held_numbers = holdout_indices(n_all, args.validation, seed=seed)[1]  # their places in the file
    import warnings

    with warnings.catch_warnings(record=True) as caught, blame_file(args.demos):
        warnings.simplefilter("always")  # the learner's warnings (noise counted) belong in the result
        doc, learned, learner = _run(method, world, demos, args, known, out)
    from symlearn.learners.constraints.rule_support import WeakRuleWarning

    # a rule the demonstrations do not need is a remark about the evidence: a note, not a warning
    doc["notes"] = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, WeakRuleWarning)))
    doc["warnings"] = reading_warnings + list(dict.fromkeys(
        _user_warnings([w for w in caught if not issubclass(w.category, WeakRuleWarning)])))
    if args.domain:  # a misspelt bias, truth or --known file is silent to clingo: say where it is
        doc["warnings"] += [w.located() for w in world.domain.bias_warnings()]
        truth_file = world.domain.sources.get("truth")
        if world.domain.truth is not None and truth_file:
            doc["warnings"] += [f"{u.file}:{u.line}:{u.column}: truth: {u.message()}"
                                for u in world.domain.undefined_predicates(truth_file)]
    if known is not None:
        doc["warnings"] += [f"{u.file}:{u.line}:{u.column}: --known: {u.message()}"
                            for u in world.domain.undefined_predicates(args.known)]
    if held is not None:
        doc["validation"] = _validation(world, learned, held, args.validation, len(demos), held_numbers)
        warning = doc["validation"].pop("warning")
        if warning:
            doc["warnings"].append(warning)
    scores = {"fpr": None, "fnr": None, "accuracy": None}
    # what an agent obeys is the learned rules and the given ones together: scored without the
    # --known rules, a truth rule given in advance counted as missed (FNR 0.316 for a complete set)
    obeyed = learned if known is None else learned | (known & world.space)
    doc["known_constraints"] = None if known is None else int((obeyed & ~learned).sum())
    if world.truth is not None:
        from symlearn.learners.constraints.constraint_metrics import constraint_metrics, reach_scores

        scores = constraint_metrics(obeyed, world.truth, world.space)
        doc.update(reach_scores(obeyed, world.truth, world.mdp, world.space))
    doc.update({"env": world.name, "method": method, "constraints": int(obeyed.sum()),
                "fpr": scores["fpr"], "fnr": scores["fnr"], "accuracy": scores["accuracy"]})
    if method == "mce-icrl":
        doc["cost_map"] = _cost_map(world, learner, args)
    if args.output:
        if method == "logic" and learner.hypothesis_ is None:
            if not learner.needed_none() or any("#mode" in w for w in doc["warnings"]):
                raise _nothing_to_write(args.output, learner, doc["warnings"])
            doc["warnings"].append(f"no rule learned: {_why_no_rules(learner, [])}")
        doc["files"] = _write(args.output, method, doc, world, learner, args)
    out.result(doc, _render)


def _nothing_to_write(output: str, learner, warnings: list[str]):
    """No rules for ``-o``: say why the loop found none, and what to change."""
    from symlearn.errors import SymlearnError

    return SymlearnError(f"no rules were induced ({learner.stop_text()}), so there is nothing to write to {output}",
                         hint=_why_no_rules(learner, warnings))


def _why_no_rules(learner, warnings: list[str]) -> str:
    """Why the loop found no rule and what to change: the hint of :func:`_nothing_to_write`, and
    the warning of a run that needed none (``learner.needed_none()``)."""
    bias = [w for w in warnings if "#mode" in w]
    if bias:
        hint = (f"{len(bias)} declaration(s) of the bias can give no literal, e.g. {bias[0]}; fix the bias "
                "(symlearn domain check DIR lists them)")
    elif learner.stop_reason_ == "no_candidates":
        hint = ("no rule of the bias forbids an undemonstrated pair without forbidding a demonstrated one: widen "
                "the bias (more #modeb literals, a larger #maxv)")
    elif learner.stop_reason_ in ("min_evidence", "min_visitation"):
        hint = (f"the demonstrations never needed a constraint: at the rationality {learner.rationality_:g} a planner "
                "as deliberate as the expert does what it did without one. Give rules you know with --known, "
                "demonstrations where breaking them would have paid, or --min-evidence 0 with a lower --rationality "
                "to guess from a more random planner")
    else:
        hint = "give more demonstrations or more iterations"
    return hint


def _user_warnings(caught) -> list[str]:
    """The messages of the recorded ``UserWarning`` s (symlearn's remarks about the data, for the
    result); any other category (a library's deprecation, numpy's overflow) is shown as usual."""
    import warnings

    messages = []
    for w in caught:
        if issubclass(w.category, UserWarning):
            messages.append(str(w.message))
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return messages


def _check_known(episodes, known, domain, rules: str) -> None:
    """A demonstrated step that the ``--known`` rules forbid is a contradiction unless the data
    is declared noisy: name the first one (its place in the file, the pair by name)."""
    import numpy as np

    from symlearn.errors import DemonstrationError

    hits = [(i, int(t)) for i, e in enumerate(episodes)
            for t in np.flatnonzero(known[e.states[: len(e.actions)], e.actions])]
    if hits:
        i, t = hits[0]
        pair = domain.describe_pair(int(episodes[i].states[t]), int(episodes[i].actions[t]))
        raise DemonstrationError(f"demonstration {i}, step {t}: {pair} breaks the given constraints (--known "
                                 f"{rules}; {len(hits)} demonstrated step(s) in all)", demonstration=i, key="actions", step=t,
                                 hint="fix the demonstrations or the rules, or pass --noise to treat such steps "
                                      "as noise")


def _validation(world: _World, learned, held, fraction: float, n_train: int, numbers=None) -> dict:
    """The held-out expert steps the learned constraint forbids (see symlearn.learners.validation)."""
    from symlearn.learners.validation import forbidden_pairs_report
    from symlearn.mdp.episodes import tabular_episodes

    episodes = [(e.states, e.actions) for e in tabular_episodes(held, world.mdp)]
    names = getattr(world.mdp, "state_names", None)
    actions = getattr(world.mdp, "action_names", None)
    describe = (world.domain.describe_pair if world.domain is not None else
                (lambda s, a: f"{names[s]} / {actions[a]}") if names is not None and actions is not None else None)
    report = forbidden_pairs_report(learned, episodes, fraction, n_train, describe, numbers)
    return {**report.as_dict(), "warning": report.warning()}


_SUFFIXES = {"logic": (".lp", "ASP rules"), "ml": (".json", "a JSON constraint set"),
             "mce-icrl": (".json", "a JSON constraint set with the cost multipliers")}


def _check_output(output: str, method: str) -> None:
    """Refuse an output name whose suffix promises another format, before anything is learned."""
    from symlearn.errors import SymlearnError

    suffix, what = _SUFFIXES[method]
    found = Path(output).suffix.lower()
    if found != suffix:
        raise SymlearnError(f"-o {output}: --method {method} writes {what}, which does not belong in a "
                            f"{found or 'suffix-less'} file", hint=f"name the output {Path(output).stem}{suffix}")


def _cost_map(world: _World, learner, args) -> dict:
    """The learned cost per state (max over actions for state-action features), and the grid
    drawing for the gridworld."""
    import numpy as np

    per_state = np.asarray(learner.cost_).max(axis=1)
    names = world.mdp.state_names
    doc = {"threshold": learner.threshold,
           "cost": {str(names[s]): round(float(c), 6) for s, c in enumerate(per_state) if c > 0}}
    if world.grid is not None:
        from symlearn.demo.gridworld_pipeline import cost_map_text

        per_cell = learner.constraint_map_.shape == (world.mdp.n_states,)
        doc["grid"] = cost_map_text(world.grid, per_state, learner.threshold,
                                    learner.headed_for_ if per_cell else None)
    return doc


def _run(method: str, world: _World, demos, args, known, out):
    if method == "logic":
        from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference

        learner = LogicConstraintInference(iterations=args.iterations or 20, horizon=args.horizon,
                                           reward=_reward(args, world), rationality=_rationality(args, world),
                                           noise=args.noise, max_body=getattr(args, "max_body", None),
                                           **_min_evidence(args),
                                           known=Path(args.known) if args.known else None).fit(demos, world.domain)
        for step in learner.history_:
            # the rules' own pairs are what the final count reports; the inference also holds pairs
            # that no rule covers, so its count alone read as a different answer from the result's
            pairs = (f"{step.n_constraints} forbidden pairs" if step.rule_pairs is None else
                     f"{step.rule_pairs} forbidden pairs by the rules, {step.n_constraints} held by the inference")
            out.note(f"iteration {step.iteration}: inferred {step.inferred}; {len(step.rules)} rule(s), "
                     f"{pairs} (inference {step.inference_seconds:.2f} s, "
                     f"induction {step.induction_seconds:.2f} s)")
        doc = {"rules": learner.rules_, "known_rules": learner.known_rules_,
               "iterations": len(learner.history_), "seconds": learner.seconds_,
               "rationality": learner.rationality_fit_.as_dict(),
               "stop_reason": learner.stop_reason_, "stop": learner.stop_text(),
               "unexplained": [u.as_dict() for u in learner.unexplained_], "max_body": learner.max_body,
               "rule_support": [r.as_dict() for r in learner.rule_support_],
               "history": [h.as_dict() for h in learner.history_]}
        return doc, learner.rule_constraints_, learner
    target = world.domain if world.domain is not None else world.mdp
    if method == "ml":
        from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference

        # a Domain's moves that do not exist are known constraints inside the learner already
        learner = MLConstraintInference(reward=_reward(args, world),
                                        horizon=args.horizon, max_iterations=args.iterations or 200,
                                        known_constraints=known,
                                        on_violation="warn" if args.noise else "error",
                                        rationality=_rationality(args, world)).fit(demos, target)
        doc = {"rules": None, "iterations": len(learner.history_), "seconds": learner.seconds_,
               "stop_reason": learner.stop_reason_, "stop": learner.stop_text(),
               "rationality": learner.rationality_fit_.as_dict()}
        return doc, learner.constraints_ & ~learner.known_, learner
    from symlearn.learners.constraints.mce_icrl import MCEICRL

    learner = MCEICRL(reward=_reward(args, world), features=args.features or world.features,
                      n_iterations=args.iterations or 300,
                      known_constraints=known, on_violation="warn" if args.noise else "error").fit(demos, target)
    learned = learner.forbidden_ & world.space
    doc = {"rules": None, "iterations": learner.n_iter_, "seconds": learner.seconds_,
           "stop_reason": learner.stop_reason_, "stop": learner.stop_text(),
           "multipliers": learner.multipliers_ or {}}
    return doc, learned, learner


def _reward(args: argparse.Namespace, world: _World) -> str:
    from symlearn.errors import SymlearnError

    if args.reward == "given" and not world.has_reward:
        raise SymlearnError(f"{world.name} defines no reward", hint="use --reward sparse")
    return args.reward or ("given" if world.has_reward else "sparse")


def _min_evidence(args: argparse.Namespace) -> dict[str, float | None]:
    """``--min-evidence`` as the logic learner's keyword: nothing when not given (the learner's
    default), None (off) at 0."""
    if args.min_evidence is None:
        return {}
    return {"min_evidence": None if args.min_evidence == 0 else float(args.min_evidence)}


def _rationality(args: argparse.Namespace, world: _World | None) -> float | str:
    from symlearn.errors import SymlearnError
    from symlearn.learners.constraints.rationality_fit import check_rationality

    if args.rationality is None:
        return world.rationality
    if str(args.rationality).strip().lower() == "auto":
        return "auto"
    try:
        value = float(args.rationality)
    except ValueError:
        raise SymlearnError(f"--rationality must be a positive number or 'auto', got {args.rationality!r}") from None
    return check_rationality(value, "--rationality")


def _write(output: str, method: str, doc: dict, world: _World, learner, args=None) -> list[str]:
    """The learner's own file (``save``: what Python gives for the same fit; for rules learned on a
    domain folder the header's re-check command names the folder, the file and the demonstrations),
    and for MCE-ICRL the cost map beside it."""
    path = Path(output)
    if method == "logic":
        recheck = None
        if getattr(args, "domain", None):  # the header's re-check command, ready to paste
            import shlex

            recheck = f"symlearn domain check {shlex.quote(args.domain)} --rules {shlex.quote(output)}"
            if args.known:  # the file holds the learned rules only: score the given ones with them
                recheck += f" --known {shlex.quote(args.known)}"
            if args.demos:
                recheck += f" --demos {shlex.quote(args.demos)}"
        learner.to_lp(path, recheck=recheck)  # refusing an empty rule set with a hint
        return [str(path)]
    files = [str(learner.save(path))]
    if method == "mce-icrl":
        files += _write_cost_map(path.with_suffix(""), doc["cost_map"], world, learner)
    return files


def _write_cost_map(stem: Path, cost_map: dict, world: _World, learner) -> list[str]:
    """``STEM.costmap.txt`` (the grid, or one line per state with a cost) and, for the gridworld,
    ``STEM.costmap.dot`` / ``.svg`` (darker = costlier, thick border = truly forbidden)."""
    import numpy as np

    from symlearn.atomic import write_text
    from symlearn.rendering import dot_available, render_dot

    base = stem.with_name(stem.name + ".costmap")
    header = (f"# MCE-ICRL learned cost per state in {world.name} (max over actions); "
              f"threshold {cost_map['threshold']}\n")
    if "grid" in cost_map:
        text = header + ("# * = above the threshold (forbidden), ~ = above it but the expert heads there (not "
                         "forbidden), ! = truly forbidden, S start, G goal\n") + cost_map["grid"]
    else:
        rows = sorted(cost_map["cost"].items(), key=lambda kv: -kv[1])
        text = header + "".join(f"{value:10.4f}  {name}\n" for name, value in rows) if rows else \
            header + "# no state has a positive cost\n"
    files = [str(write_text(base.parent / (base.name + ".txt"), text))]
    if "grid" in cost_map:
        from symlearn.demo.gridworld_pipeline import constraint_map_dot

        dot = constraint_map_dot(world.grid, np.asarray(learner.cost_).max(axis=1), "MCE-ICRL learned cost per cell")
        dot_path = base.parent / (base.name + ".dot")
        write_text(dot_path, dot)
        files.append(str(dot_path))
        if dot_available():
            svg_path = base.parent / (base.name + ".svg")
            render_dot(dot, svg_path)
            files.append(str(svg_path))
    return files


def _render(doc: dict) -> str:
    lines = [f"{doc['env']}: {doc['method']} ({doc['iterations']} iterations, {doc['seconds']:.1f} s)"]
    if doc.get("rules") is not None:
        lines.append("rules:" if doc["rules"] else "rules: (none induced)")
        lines += [f"  {r}" for r in doc["rules"]]
    if doc.get("known_rules"):
        lines.append("given (--known, not learned):")
        lines += [f"  {r}" for r in doc["known_rules"]]
    if doc.get("stop"):
        lines.append(f"stopped: {doc['stop']}")
    if (doc.get("rationality") or {}).get("source") == "fitted":
        lines.append(f"rationality: {doc['rationality']['value']:g} (fitted to the demonstrations; --rationality sets it)")
    if doc.get("unexplained"):
        from symlearn.learners.constraints.logic_constraint_inference import Unexplained, unexplained_lines

        lines += unexplained_lines([Unexplained(**u) for u in doc["unexplained"]], shown=10,
                                   max_body=doc.get("max_body"))
    pairs = str(doc["constraints"]) + (f" ({doc['known_constraints']} of them by the --known rules alone)"
                                       if doc.get("known_constraints") else "")
    if doc["fpr"] is None:
        lines.append(f"forbidden pairs: {pairs}   (no ground truth to score against)")
    else:
        lines.append(f"forbidden pairs: {pairs}   against the ground truth: FPR {doc['fpr']:.3f}  "
                     f"FNR {doc['fnr']:.3f}  accuracy {doc['accuracy']:.3f}")
        from symlearn.cli.domain_command import reach_lines

        lines += reach_lines(doc)
    if doc.get("cost_map"):
        cost_map = doc["cost_map"]
        if "grid" in cost_map:
            lines.append(f"learned cost per cell (* above the threshold {cost_map['threshold']}: forbidden; ~ above it, "
                         "but the expert heads there; ! truly forbidden):")
            lines += ["  " + row for row in cost_map["grid"].rstrip("\n").split("\n")]
        else:
            costly = sorted(cost_map["cost"].items(), key=lambda kv: -kv[1])
            lines.append(f"learned cost: {len(costly)} state(s) with a positive cost"
                         + ("; highest: " + ", ".join(f"{n} {v:.2f}" for n, v in costly[:5]) if costly else ""))
    if doc.get("validation"):
        from symlearn.cli.output import validation_line

        lines.append(validation_line(doc["validation"], "held-out expert steps forbidden"))
    lines += [f"note: {n}" for n in doc.get("notes", [])]
    lines += [f"warning: {w}" for w in doc.get("warnings", [])]
    lines += [f"wrote {f}" for f in doc.get("files", [])]
    return "\n".join(lines)
