"""``symlearn train``: train a PPO or PPO-Lagrangian agent, optionally with a learned DNF as its cost.

``symlearn train --env NAME --algo ppo|ppo-lag [--cost rules.dnf [--per-rule]] [--cost-limit C]
[--multiplier-update gradient|adam|pid] [--multiplier-lr LR] [--advantage-scale raw|returns]
[--normalize-observations] [--normalize-values] [--n-envs N] [--n-steps T]
[--prune [--prune-threshold T]] [--steps N] [-o agent.safetensors] [--json]``

* ``--env``: a bundled continuous environment (``toy-navigation``, ``safenav-*``; see
  ``symlearn envs``) or any gymnasium id (``CartPole-v1``).
* ``--cost rules.dnf``: the cost is 1 when the formula holds on the features of the state reached
  (``info["features"]``); with ``--per-rule`` one cost (and, with ``ppo-lag``, one multiplier)
  per rule. ``--cost cost.safetensors``: a cost learned by ``symlearn learn icrl`` (refused when
  it was learned for other observation/action spaces), the constrained signal of ``ppo-lag`` or,
  with ``ppo``, subtracted from the reward (the thesis' transfer experiment). Without it, ``ppo-lag`` uses the environment's own cost (the ground truth: the
  baseline "PPO-Lagrangian on the true cost").
* ``--algo dqrm|dqn`` on a rendered block task (``blockworld-stack2`` ...): deep Q-learning with one
  Q-function per reward-machine state (DQRM; ``--machine`` from ``symlearn learn rm``, ``truth``,
  or inferred from the task's demonstrations) or DQN on the machine's shaped (``--reward shaped``)
  or the task's sparse reward; handled by :mod:`symlearn.cli.train_rm`.
* ``--advantage-scale returns``, ``--normalize-observations``, ``--normalize-values``: the options
  of :mod:`symlearn.rl.ppo` that made PPO-Lagrangian on the learned DNF solve the thesis' toy
  (docs/BENCHMARKS.md); off by default, as in the library.
* ``--prune``: after training, rules whose fired/evaluated ratio (conjunctions evaluated in
  ascending number of atoms) stayed below ``--prune-threshold`` (thesis: 0.001) are dropped; the
  pruned formula is written beside the cost file as ``NAME.pruned.dnf`` with a report.

JSON keys: ``cost_kind`` (``dnf``, ``neural`` or null), ``return`` and ``cost`` (mean per episode of greedy evaluation episodes; cost is the
environment's ground-truth cost), ``violation_rate`` (share of evaluation steps with ground-truth
cost), ``pruned`` (the dropped rules, or null), ``seconds``, ``steps``, ``files``.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def register(subparsers, common) -> None:
    cmd = subparsers.add_parser(
        "train", parents=[common()], help="train a PPO / PPO-Lagrangian agent (optionally on a learned DNF cost)",
        description="Train an agent with PPO or PPO-Lagrangian; a learned DNF formula can be its cost, and rules "
                    "the agent never ran into can be pruned afterwards.")
    cmd.add_argument("--env", required=True, help="a bundled continuous environment or a gymnasium id")
    cmd.add_argument("--algo", choices=("ppo", "ppo-lag", "dqrm", "dqn"), default="ppo-lag",
                     help="ppo, ppo-lag (default), or dqrm / dqn on a rendered block task (blockworld-*)")
    cmd.add_argument("--machine", metavar="MACHINE.json",
                     help="dqrm/dqn: a machine from `symlearn learn rm` (its .labeling.json beside it), or 'truth'; "
                          "default: inferred from the task's scripted demonstrations")
    cmd.add_argument("--reward", choices=("shaped", "sparse"), default="shaped",
                     help="dqn: the machine's shaped reward (default) or the task's sparse reward")
    cmd.add_argument("--cost", metavar="RULES.dnf|COST.safetensors",
                     help="a DNF formula over the environment's features, or a cost learned by "
                          "`symlearn learn icrl` (.safetensors), as the cost")
    cmd.add_argument("--per-rule", action="store_true", help="one cost (and multiplier) per rule of --cost")
    cmd.add_argument("--cost-limit", type=float, default=0.0,
                     help="ppo-lag: allowed expected cost per episode (default 0)")
    cmd.add_argument("--multiplier-lr", type=float, default=0.05, help="ppo-lag: multiplier step size (0.05)")
    cmd.add_argument("--multiplier-update", choices=("gradient", "adam", "pid"), default="gradient",
                     help="ppo-lag: multiplier update rule (gradient)")
    cmd.add_argument("--advantage-scale", choices=("raw", "returns"), default="raw",
                     help="ppo-lag: mix advantages in their own units (raw) or in standard deviations of "
                          "their returns (returns: the multiplier's range no longer depends on the units)")
    cmd.add_argument("--normalize-observations", action="store_true",
                     help="standardise the policy's inputs by running mean/std (saved with the model)")
    cmd.add_argument("--normalize-values", action="store_true",
                     help="critics learn returns divided by their running std (PopArt-style)")
    cmd.add_argument("--n-envs", type=int, default=4, help="environment copies stepped side by side (4)")
    cmd.add_argument("--n-steps", type=int, default=128, help="steps per copy per iteration (128)")
    cmd.add_argument("--prune", action="store_true", help="prune rules the agent never ran into (needs --cost)")
    cmd.add_argument("--prune-threshold", type=float, default=1e-3, help="fired/evaluated ratio to keep a rule")
    cmd.add_argument("--steps", type=int, default=None, help="environment steps (ppo: 50000; dqrm/dqn: 300)")
    cmd.add_argument("--eval-episodes", type=int, default=10, help="greedy evaluation episodes (10)")
    cmd.add_argument("-o", "--output", help="write the policy here (.safetensors + .json)")
    cmd.set_defaults(handler=_train)


def _make_env(name: str):
    """A constructor of ``name``: a bundled environment (its gymnasium id) or a gymnasium id."""
    import gymnasium as gym

    from symlearn.envs.registry import get
    from symlearn.errors import DataError

    try:
        entry = get(name)
    except DataError as exc:
        if name not in gym.registry:
            raise DataError(exc.message, hint=(exc.hint or "") + "; or a gymnasium id such as CartPole-v1") from None
        return lambda: gym.make(name)
    if entry.gym_id is None:
        raise DataError(f"{name} has no gymnasium environment to train in")
    import symlearn.envs  # noqa: F401 -- registers the symlearn/ ids
    return lambda: gym.make(entry.gym_id)


def _train(args: argparse.Namespace, out) -> None:
    import numpy as np

    from symlearn.errors import DataError, SymlearnError
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, evaluate, train_ppo

    if args.algo in ("dqrm", "dqn"):
        from symlearn.cli.train_rm import train_blocks

        args.steps = 300 if args.steps is None else args.steps
        return train_blocks(args, out)
    args.steps = 50_000 if args.steps is None else args.steps
    if args.steps < 1:
        raise SymlearnError(f"--steps must be at least 1, got {args.steps}")
    for flag, value in (("--n-envs", args.n_envs), ("--n-steps", args.n_steps)):
        if value < 1:
            raise SymlearnError(f"{flag} must be at least 1, got {value}")
    if args.cost_limit < 0:
        raise SymlearnError(f"--cost-limit must be >= 0, got {args.cost_limit}")
    if args.prune and not args.cost:
        raise SymlearnError("--prune needs the rules to prune: give --cost RULES.dnf")
    base = _make_env(args.env)
    seed = getattr(args, "seed", 0) or 0
    stats, dnf, cost_fn, reward_fn = None, None, None, None
    neural = bool(args.cost) and str(args.cost).endswith(".safetensors")
    if neural:
        if args.per_rule or args.prune:
            raise SymlearnError("--per-rule and --prune apply to DNF rules, not to a learned neural cost")
        from symlearn.learners.neural import NeuralCost

        probe = base()
        try:
            cost = NeuralCost.load(args.cost, probe)   # refuses a cost learned for other spaces
        finally:
            probe.close()
        # one batched forward pass per rollout: the cost of PPO-Lagrangian, or r - C for plain PPO
        if args.algo == "ppo-lag":
            cost_fn = cost.cost_fn()
        else:
            reward_fn = cost.reward_fn()
    elif args.cost:
        from symlearn.backends.dnf_cost import DnfRolloutCost, RuleStats
        from symlearn.logic.dnf import load

        dnf = load(args.cost)
        probe = base()
        names = getattr(probe.unwrapped, "feature_names", None)
        probe.close()
        if names is None:
            raise DataError(f"{args.env} reports no feature names, so a DNF cost cannot be read there")
        try:
            stats = RuleStats(dnf, names)
        except DataError as exc:
            raise DataError(exc.message, file=args.cost, hint=exc.hint) from None

        # evaluated once per rollout over all its steps (same costs and rule counts as the per-step
        # DnfCostWrapper, a fraction of its overhead)
        cost_fn = DnfRolloutCost(dnf, names, per_rule=args.per_rule, stats=stats)

    lagrangian = None
    if args.algo == "ppo-lag":
        lagrangian = LagrangianConfig(cost_limit=args.cost_limit, update=args.multiplier_update,
                                      lr=args.multiplier_lr, advantage_scale=args.advantage_scale)
    config = PPOConfig(seed=seed, n_envs=args.n_envs, n_steps=args.n_steps,
                       batch_size=min(128, args.n_envs * args.n_steps),
                       normalize_observations=args.normalize_observations, normalize_values=args.normalize_values)
    result = train_ppo(base, args.steps, config, lagrangian=lagrangian, cost_fn=cost_fn, reward_fn=reward_fn)
    episodes = evaluate(result.policy, base(), args.eval_episodes, seed=seed + 10_000)
    true_cost = episodes.costs.sum(axis=1) if episodes.costs.size else np.zeros(len(episodes.returns))
    doc = {"env": args.env, "algo": args.algo, "cost_kind": "neural" if neural else ("dnf" if args.cost else None),
           "return": float(np.mean(episodes.returns)),
           "cost": float(np.mean(true_cost)),
           "violation_rate": float(np.sum(true_cost) / max(int(np.sum(episodes.lengths)), 1)),
           "multipliers": [float(m) for m in np.atleast_1d(result.multipliers)] if lagrangian else None,
           "pruned": None, "steps": int(result.steps), "seconds": float(result.seconds), "files": []}
    if args.prune:
        pruned, verdicts = stats.prune(args.prune_threshold)
        path = Path(args.cost)
        target = path.with_name(path.stem + ".pruned" + (path.suffix or ".dnf"))
        report = "\n".join(f"{'kept   ' if v.kept else 'dropped'} fired {v.fired:>8} / evaluated {v.evaluated:>8}  {v.rule}"
                           for v in verdicts)
        pruned.save(target, header=f"pruned from {path.name} after {result.steps} training steps "
                                   f"(threshold {args.prune_threshold}):\n{report}")
        doc["pruned"] = [v.rule for v in verdicts if not v.kept]
        doc["kept"] = [v.rule for v in verdicts if v.kept]
        doc["files"].append(str(target))
    if args.output:
        result.save(args.output)
        doc["files"].append(str(args.output))
    out.result(doc, _render)


def _render(doc: dict) -> str:
    lines = [f"{doc['env']}: {doc['algo']}, {doc['steps']} steps in {doc['seconds']:.1f} s",
             f"greedy evaluation: return {doc['return']:.2f}, ground-truth cost {doc['cost']:.2f} per episode, "
             f"violation rate {doc['violation_rate']:.3f}"]
    if doc["multipliers"] is not None:
        lines.append("multipliers: " + ", ".join(f"{m:.3f}" for m in doc["multipliers"]))
    if doc["pruned"] is not None:
        lines.append(f"pruning kept {len(doc['kept'])} rule(s), dropped {len(doc['pruned'])}")
        lines += [f"  kept: {r}" for r in doc["kept"]]
    lines += [f"wrote {f}" for f in doc["files"]]
    return "\n".join(lines)
