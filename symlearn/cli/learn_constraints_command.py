"""``symlearn learn constraints``: learn the constraints an expert obeys in a discrete environment.

``symlearn learn constraints --env junction-lights [--demos D.jsonl | --n-demos N]
[--method logic|ml|mce-icrl] [--iterations N] [-o rules.lp]``

* ``logic`` (default where the environment has ASP facts): maximum-likelihood inference plus
  ILP induction each iteration; ``-o`` writes the rules as an editable ``.lp`` file.
* ``ml``: maximum-likelihood constraint inference alone; ``-o`` writes the forbidden pairs.
* ``mce-icrl``: maximum causal entropy inverse constrained RL (needs the environment's reward:
  ``gridworld``); ``-o`` writes the forbidden pairs and the multipliers.

The scores (``fpr``, ``fnr``, ``accuracy``) compare the learned forbidden pairs with the
environment's ground truth over every pair that exists.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

METHODS = ("logic", "ml", "mce-icrl")


def register_learn(commands, common) -> None:
    from symlearn.envs.constraint_envs import CONSTRAINT_ENVS

    cmd = commands.add_parser(
        "constraints", parents=[common()], help="learn the constraints an expert obeys (rules, constraint sets)",
        description="Learn constraints from demonstrations in a discrete environment: ASP rules (logic constraint "
                    "inference), maximum-likelihood constraint sets, or MCE-ICRL cost maps.")
    cmd.add_argument("--env", required=True, choices=tuple(CONSTRAINT_ENVS), metavar="ENV",
                     help=f"one of {', '.join(CONSTRAINT_ENVS)} (see `symlearn envs`)")
    source = cmd.add_mutually_exclusive_group()
    source.add_argument("--demos", help="demonstrations (.jsonl or .npz) with the environment's state/action ids or names")
    source.add_argument("--n-demos", type=int, default=50, help="generate N demonstrations of the bundled expert (50)")
    cmd.add_argument("--expert", choices=("native", "sumo"), default="native",
                     help="who drives the generated junction demonstrations: our traffic model (native, default) "
                          "or SUMO's car-following and junction logic (sumo extra)")
    cmd.add_argument("--method", choices=METHODS, default=None,
                     help="logic (default where rules can be learned), ml, or mce-icrl (default for gridworld)")
    cmd.add_argument("--iterations", type=int, default=None,
                     help="inference iterations (logic: 20, ml: 200) or dual steps (mce-icrl: 300)")
    cmd.add_argument("--horizon", type=int, default=30, help="planning horizon of the MaxEnt passes (30)")
    cmd.add_argument("--known", help="an .lp file of rules known in advance (logic environments)")
    cmd.add_argument("--noise", action="store_true",
                     help="treat demonstrated steps that break --known rules as noise (warn) instead of an error")
    cmd.add_argument("--stochasticity", type=float, default=0.0, help="slip probability p of the gridworld (0)")
    cmd.add_argument("-o", "--output", help="write the rules (.lp) or the forbidden pairs (.json) here")
    cmd.set_defaults(handler=_constraints)


def _constraints(args: argparse.Namespace, out) -> None:
    from symlearn.envs.constraint_envs import constraint_setting
    from symlearn.errors import DataError, SymlearnError

    setting = constraint_setting(args.env, args.stochasticity)
    method = args.method or ("logic" if setting.logic is not None else "mce-icrl")
    if method == "logic" and setting.logic is None:
        raise SymlearnError(f"{args.env} has no ASP facts, so no rules can be learned there",
                            hint="use --method ml or --method mce-icrl")
    if method == "mce-icrl" and setting.reward != "given":
        raise SymlearnError(f"mce-icrl needs the environment's reward, which {args.env} does not define",
                            hint="use --method logic or ml here, or --env gridworld")
    if args.known and setting.logic is None:
        raise SymlearnError("--known rules need an environment with ASP facts")
    seed = getattr(args, "seed", 0) or 0
    if args.demos:
        from symlearn.data import load

        demos = load(args.demos)
    else:
        if args.n_demos < 1:
            raise DataError(f"--n-demos must be at least 1, got {args.n_demos}")
        if args.expert == "sumo":
            if setting.logic is None:
                raise DataError("--expert sumo drives the junctions only")
            demos = setting.logic.expert_demonstrations(args.n_demos, seed, source="sumo")
        else:
            demos = setting.expert(args.n_demos, seed)
    known = setting.known
    if args.known:
        known = known | setting.logic.rule_mask(Path(args.known))
    try:
        doc, learned, learner = _run(method, setting, demos, args, known, out)
    except DataError as exc:
        if args.demos and not exc.file:
            raise DataError(exc.message, file=args.demos, hint=exc.hint) from None
        raise
    from symlearn.learners.constraints.constraint_metrics import constraint_metrics

    scores = constraint_metrics(learned, setting.truth, setting.space)
    doc.update({"env": args.env, "method": method, "constraints": scores["forbidden"],
                "fpr": scores["fpr"], "fnr": scores["fnr"], "accuracy": scores["accuracy"]})
    if args.output:
        doc["files"] = [_write(args.output, method, doc, learned, setting, learner)]
    out.result(doc, _render)


def _run(method, setting, demos, args, known, out):
    import numpy as np

    if method == "logic":
        from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference

        learner = LogicConstraintInference(setting.logic, iterations=args.iterations or 20, horizon=args.horizon,
                                           noise=args.noise, known=known).fit(demos)
        for step in learner.history_:
            out.note(f"iteration {step.iteration}: inferred {step.inferred}; {len(step.rules)} rule(s), "
                     f"{step.n_constraints} forbidden pairs (inference {step.inference_seconds:.2f} s, "
                     f"induction {step.induction_seconds:.2f} s)")
        doc = {"rules": learner.rules_, "iterations": len(learner.history_), "seconds": learner.seconds_,
               "history": [h.as_dict() for h in learner.history_]}
        return doc, learner.rule_constraints_, learner
    if method == "ml":
        from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference

        learner = MLConstraintInference(setting.mdp, reward=setting.reward, horizon=args.horizon,
                                        max_iterations=args.iterations or 200, known_constraints=known,
                                        on_violation="warn" if args.noise else "error",
                                        rationality=setting.rationality).fit(demos)
        doc = {"rules": None, "iterations": len(learner.history_), "seconds": learner.seconds_}
        return doc, learner.constraints_ & ~known, learner
    from symlearn.learners.constraints.mce_icrl import MCEICRL

    learner = MCEICRL(setting.mdp, n_iterations=args.iterations or 300,
                      on_violation="warn" if args.noise else "error").fit(demos)
    # A state whose multiplier ends above the threshold is a forbidden cell: every move into it is.
    targets = np.argmax(setting.mdp.transitions, axis=2)
    learned = learner.constraint_map_[targets] & setting.space
    doc = {"rules": None, "iterations": learner.n_iter_, "seconds": learner.seconds_,
           "multipliers": {setting.mdp.state_names[s]: float(v) for s, v in enumerate(learner.lambda_) if v > 0}}
    return doc, learned, learner


def _write(output: str, method: str, doc: dict, learned, setting, learner) -> str:
    from symlearn.atomic import write_text

    path = Path(output)
    if method == "logic":
        learner.to_lp(path)
        return str(path)
    names_s, names_a = setting.mdp.state_names, setting.mdp.action_names
    pairs = [[names_s[s], names_a[a]] for s, a in zip(*learned.nonzero())]
    payload = {"format": "symlearn-constraints", "version": 1, "env": setting.name, "method": method,
               "forbidden": pairs}
    if "multipliers" in doc:
        payload["multipliers"] = doc["multipliers"]
    write_text(path, json.dumps(payload, indent=1) + "\n")
    return str(path)


def _render(doc: dict) -> str:
    lines = [f"{doc['env']}: {doc['method']} ({doc['iterations']} iterations, {doc['seconds']:.1f} s)"]
    if doc.get("rules") is not None:
        lines.append("rules:" if doc["rules"] else "rules: (none induced)")
        lines += [f"  {r}" for r in doc["rules"]]
    lines.append(f"forbidden pairs: {doc['constraints']}   against the ground truth: FPR {doc['fpr']:.3f}  "
                 f"FNR {doc['fnr']:.3f}  accuracy {doc['accuracy']:.3f}")
    lines += [f"wrote {f}" for f in doc.get("files", [])]
    return "\n".join(lines)
