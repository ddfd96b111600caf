"""``symlearn train``: train an agent in any environment, optionally with a learned cost.

``symlearn train --env ENV [--env-kwargs JSON] [--algo ALGO] [--cost rules.dnf|cost.safetensors
[--features a,b] [--per-rule] [--depth-weight W]] [--cost-limit C] [--false-alarm-floor auto|add|none] [--multiplier-update gradient|adam|pid]
[--multiplier-init M] [--multiplier-lr LR] [--learning-rate LR] [--log-std-init S] [--advantage-scale raw|returns] [--reward-scale-floor SHARE] [--cost-scale-floor SHARE] [--zero-limit-slack SHARE]
[--cost-estimate rollout|episodes] [--reset-actor auto|never] [--normalize-observations]
[--normalize-values] [--n-envs N] [--n-steps T] [--prune [--prune-threshold T]] [--steps N]
[--eval-episodes E] [-o agent.safetensors] [--log run.csv] [--tensorboard DIR] [--json]``

* ``--env``: a bundled name (``toy-navigation``, ``safenav-*``; see ``symlearn envs``), any
  registered gymnasium id (``CartPole-v1``), or ``module:EnvId`` (the module is imported and must
  register ``EnvId``; the current directory is importable), resolved by
  :func:`symlearn.recipes.environments.resolve_env`. ``--env-kwargs '{"size": 8}'``: keyword
  arguments of the environment's constructor (an unknown key is refused, naming its parameters).
* ``--algo``: ``ppo`` (default without ``--cost``), ``ppo-lag`` (default with ``--cost``; without
  one it constrains the environment's own ``info["cost"]`` -- "PPO-Lagrangian on the true cost"
  -- and is refused, after the first rollout, when none of its steps reported one), ``sb3-ppo``,
  ``sb3-sac``, ``sb3-dqn``,
  ``sb3-ppo-lag``, ``sb3-sac-lag`` (stable-baselines3, the ``sb3`` extra; handled by
  :mod:`symlearn.cli.train_sb3`), or ``dqrm``/``dqn`` on a rendered block task
  (:mod:`symlearn.cli.train_rm`).
* ``--cost rules.dnf``: the cost is 1 when the formula holds on the features of the state reached
  (``info["features"]`` when the environment reports them, else the observation); the feature
  names come from ``--features a,b``, the environment's ``feature_names`` attribute, or the keys
  of a dict ``info["features"]`` -- an environment with none of them is refused. ``--per-rule``:
  one cost (and, with a Lagrangian, one multiplier) per rule. ``--depth-weight W`` (default 0):
  ``1 + W x`` the state's depth in the unsafe set instead of 1 (:mod:`symlearn.backends.dnf_depth`),
  so an agent that cut across a narrow learned corridor learns the way out. ``--cost cost.safetensors``: a cost
  learned by ``symlearn learn icrl`` (refused when it was learned for other observation/action
  spaces). The learned cost is the constrained signal of ``ppo-lag`` / ``sb3-*-lag`` or, with
  ``ppo`` / ``sb3-*``, subtracted from the reward (the thesis' transfer experiment). It drives
  training only: the environment's ``info["cost"]`` stays the reported ground truth.
* ``--multiplier-update``/``--multiplier-lr`` (``adam``, 0.1; with ``sb3-*-lag`` ``gradient``, 0.05:
  Adam 0.1 left SB3's PPO running through BlockedPoint's wall on 3 seeds of 3, the gradient rule on
  1), ``--learning-rate`` and
  ``--log-std-init`` (1e-3 and -1, with a cost or without): the library's
  defaults, chosen on four tasks x 3 seeds (docs/BENCHMARKS.md, "PPO-Lagrangian defaults of
  `train`"): the earlier ``gradient``/0.05 with 2.5e-4 and 0 was safe everywhere but froze the
  toy's and a user's rover's agents at their start.
* ``--multiplier-init M`` (``ppo-lag``: 1 for a hard constraint -- limit 0, or a learned neural
  cost's expert level, its floor --, 0 under a positive ``--cost-limit``; ``sb3-*-lag``: 0): where
  the multipliers start. With return-unit advantages 1 weighs the cost as much as the reward from
  the first iteration; from 0 the policy learns from the reward alone while the multiplier climbs,
  long enough on BlockedPoint with a learned wall to commit to running through it (1 of 10 seeds;
  0 of 10 from 1). Under a budget the policy may spend, starting at 1 halved SafeNav CarGoal's
  return (docs/BENCHMARKS.md, "Where the multiplier starts"). SB3's reward ``r - lambda c`` has
  no such units, so its start stays 0.
* ``--advantage-scale raw|returns``, ``--[no-]normalize-observations``, ``--[no-]normalize-values``:
  options of :mod:`symlearn.rl.ppo`. With a Lagrangian (``ppo-lag``) they default to ``returns``
  and on: measured on BlockedPoint, a user's hazard robot and the toy (docs/BENCHMARKS.md,
  "PPO-Lagrangian defaults of `train`"), the old defaults (``raw``, off) gave safe agents that
  earned almost nothing (BlockedPoint 5.7 vs 59.4 with these; the expert earns 57). Plain ``ppo``
  has the same normalisation, learning rate and initial noise since they earned more on 11 of 15
  tasks than CleanRL's settings (docs/BENCHMARKS.md, "One default configuration for plain PPO").
  These are also the library's ``PPOConfig``/``LagrangianConfig`` defaults. Our PPO's only (refused with ``sb3-*``).
* ``--reward-scale-floor SHARE`` (``ppo-lag``; default 0.01): the reward's return scale in the
  Lagrangian's mix never drops below SHARE of the largest it had. Once every episode earns about
  the same (a pole balanced to its time limit) the scale collapses, and in its units the reward's
  small differences outweigh any cost: CartPole with a line the cart must keep left of was safe on
  3 of 5 seeds at the default, 5 of 5 with 1 -- but 1 costs SafeNav and BlockedPoint's learned wall
  (docs/BENCHMARKS.md, "A reward that stops varying"), so it is a remedy the run's warning names,
  not the default.
* ``--cost-scale-floor SHARE`` (``ppo-lag``; default 0.01): the same for each cost's return scale
  in the mix. As the agent stops paying a cost, the spread of its returns shrinks and every
  remaining violation weighs up to 1 / SHARE times more than at the start: what keeps a last lava
  step out of a grid walker's route, and what held a drone that must go round a no-fly disc at
  3.1 instead of the 20 it earns by the detour (with 1: 20.2 at cost 0, but the grid walker kept
  its lava step; docs/BENCHMARKS.md, "Fresh user modules, second pass"). A remedy the run's
  warning names when the return fell from what the run earned within the limit, not the default.
* ``--zero-limit-slack SHARE`` (``ppo-lag``; default 0): at ``--cost-limit 0`` the multipliers aim
  at SHARE violating steps per episode of the (stochastic) training policy instead of exactly 0.
  At the exact 0 a rollout without cost is no error, so a multiplier that an exploring agent's
  brushes raised never comes down, however cautious the agent has become. Opt-in: measured on the
  fresh user modules (docs/BENCHMARKS.md, "Over-cautious agents at limit 0").
* ``--reset-actor auto|never`` (``ppo-lag``; default ``never``, the library's): with ``auto`` a policy that stays over
  ``--cost-limit`` while the multiplier keeps rising gets fresh weights -- critics, observation
  statistics and multipliers kept -- at most twice, never in the last third of the run
  (:mod:`symlearn.rl.ppo.stall`): a policy that learned a forbidden behaviour before the multiplier
  priced it may never leave it (BlockedPoint with a learned wall: seed 2 ran through it at
  multiplier 10; with the rule, reset once, it earns the expert's return at cost 0). A reset is a
  trial: one window later the fresh actor is compared with the old one by the Lagrangian objective
  at the multipliers of that moment, and the old one is put back if it scores higher (a learned
  formula charging a balancing CartPole: a fresh actor learns to fall at once). JSON
  ``actor_resets`` / ``actor_restored``: the iterations of each. Not the default: on learned
  formulas no policy keeps (the rover's, SafeNav PointGoal's) it fires in nearly every run and
  cost the rover's return (docs/BENCHMARKS.md, "A fresh actor for a policy stuck over its limit").
* ``--cost-limit C``: the expected cost per episode a Lagrangian allows; by default 0, except for
  a neural cost from ``learn icrl``: what that cost charges its own demonstrations per episode
  (the file's ``provenance.expert_cost.mean``; :attr:`symlearn.learners.neural.NeuralCost.expert_level`).
  A sigmoid network charges every state something, so 0 is out of reach for every policy, the
  expert's included, and the multiplier then rises for the whole run; the thesis' hard constraint
  is the least cost a policy can reach, and the expert's level is one a policy is known to reach
  and the constraint the learner matched (eq. 2.2). Measured in docs/BENCHMARKS.md ("Where the
  multiplier starts, and a learned neural cost's limit").
* ``--false-alarm-floor auto|add|none`` (Lagrangians on a ``.dnf`` file whose header has the
  ``# validation: K of N held-out expert states unsafe (...; H demonstrations held out, ...)`` line
  of ``learn dnf --validation``): a learned formula also fires where the expert goes, K / H times
  per unseen expert episode (its false-alarm floor, :attr:`symlearn.learners.validation.Validation.per_demonstration`).
  ``auto`` (the default) reads a positive ``--cost-limit`` as violations per episode and trains on
  the formula's cost against the limit plus the floor; a limit of 0 stays 0 (a hard constraint:
  the floor would be spent on real violations). ``add`` adds it at 0 too, ``none`` never (the limit
  on the formula's own cost, as before). Not with ``--per-rule`` or ``--depth-weight``, whose
  costs are in other units. Measured in docs/BENCHMARKS.md ("A learned DNF's false-alarm floor in
  the limit").
* ``--cost-estimate rollout|episodes``: ``ppo-lag``'s multipliers are updated every iteration from
  the rollout's cost per step times the mean episode length (``rollout``, the default), or, as
  before, only in iterations in which an episode ended, from those episodes (``episodes``).
* ``--prune``: after training, rules whose fired/evaluated ratio (conjunctions evaluated in
  ascending number of atoms) stayed below ``--prune-threshold`` (thesis: 0.001) are dropped; the
  pruned formula is written beside the cost file as ``NAME.pruned.dnf`` with a report.
* Numeric flags are checked before anything runs: ``--steps`` 1 .. 10^9, ``--cost-limit`` and
  ``--depth-weight`` finite and >= 0, ``--multiplier-init`` 0 .. 10^6, ``--n-envs`` 1 .. 256, ``--n-envs`` x ``--n-steps`` (the rollout held in memory) at
  most 262,144 steps.
* ``--log run.csv`` / ``--tensorboard DIR``: one row per iteration -- steps, mean return
  of the episodes that ended, their cost per constraint (``mean_cost_i``; ``learned_cost_i`` with
  ``--cost`` under ``ppo-lag``, since the learned cost is what training sees; under ``--algo ppo`` a
  learned cost is a penalty in the reward and ``mean_cost_i`` is the environment's ``info["cost"]``), ``true_cost`` (the environment's
  ``info["cost"]`` per episode, estimated from the whole rollout; empty when it reports none), the
  estimate the multipliers were updated from (``cost_estimate_i``), the multipliers, losses, KL,
  steps/s -- written as training goes (:mod:`symlearn.rl.training_log`).
  On a terminal the progress bar shows the latest return, cost and largest multiplier. With
  ``sb3-*`` the same columns where they exist, one row per rollout (PPO) or per 1,000 steps
  (SAC, DQN), over the episodes that ended in it (:func:`symlearn.backends.sb3.monitor_callback`).
* ``-o agent.safetensors``: the policy as safetensors + JSON (our PPO's, or a stable-baselines3
  policy through :func:`symlearn.backends.sb3.save_policy`; a ``.zip`` is refused).

JSON keys: ``env``, ``algo``, ``cost_kind`` (``dnf``, ``neural`` or null), ``return`` and ``cost``
(mean per episode of greedy evaluation episodes; ``cost`` is the environment's ground-truth
``info["cost"]``), ``violation_rate`` (ground-truth cost per evaluation step) -- both ``null``
when no step of training or evaluation reported ``info["cost"]``; once one did, a step without
it costs 0 --, ``learned_cost`` (what ``--cost`` charges the greedy evaluation's episodes, summed
over rules, per episode; null without ``--cost``), ``cost_limit`` (the limit of a Lagrangian --
``ppo-lag``, ``sb3-*-lag`` -- on the learned cost, or on ``info["cost"]`` without ``--cost``; null
for the other algorithms) and ``cost_limit_from`` (``--cost-limit``, ``expert`` -- a learned neural
cost's expert level --, ``validation`` -- the limit given plus a DNF file's false-alarm floor -- or
``default``: 0), ``cost_limit_given`` (the limit before the floor) and ``false_alarm_floor`` (the
file's floor per episode, null without one), ``multipliers`` (null without a
Lagrangian), ``actor_resets`` (``ppo-lag``: the iterations whose actor was renewed, else null),
``pruned`` (the dropped rules, or null; with ``--prune`` also ``kept``), ``seconds``,
``steps``, ``files``, ``warnings`` (a Lagrangian whose multiplier rose while the cost stayed over the
limit, :mod:`symlearn.rl.ppo.limit_check`; one that kept its limit but is not useful -- its return fell
from what the run had earned within the limit, or ended where it started while only episodes that
paid earned more; else one whose greedy agent still pays more than the limit of what it was trained on).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

OUR_ALGOS = ("ppo", "ppo-lag")
SB3_ALGOS = ("sb3-ppo", "sb3-sac", "sb3-dqn", "sb3-ppo-lag", "sb3-sac-lag")
BLOCK_ALGOS = ("dqrm", "dqn")

MAX_STEPS = 10**9
MAX_ENVS = 256
MAX_ROLLOUT = 262_144   # n_envs x n_steps: the rollout PPO holds in memory (a few arrays per step)


def register(subparsers, common) -> None:
    cmd = subparsers.add_parser(
        "train", parents=[common()], help="train an agent (PPO, PPO-Lagrangian, stable-baselines3) in any environment",
        description="Train an agent in a bundled, gymnasium or module:Id environment; a learned DNF or neural "
                    "cost can constrain it, and rules the agent never ran into can be pruned afterwards.")
    cmd.add_argument("--env", required=True, help="a bundled name, a gymnasium id, or module:EnvId")
    cmd.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments of the environment, a JSON object")
    cmd.add_argument("--algo", choices=OUR_ALGOS + SB3_ALGOS + BLOCK_ALGOS, default=None,
                     help="ppo (default without --cost), ppo-lag (default with --cost), sb3-ppo|sb3-sac|sb3-dqn|"
                          "sb3-ppo-lag|sb3-sac-lag (stable-baselines3), or dqrm / dqn on a rendered block task")
    cmd.add_argument("--machine", metavar="MACHINE.json",
                     help="dqrm/dqn: a machine from `symlearn learn rm` (its .labeling.json beside it), or 'truth'; "
                          "default: inferred from the task's scripted demonstrations")
    cmd.add_argument("--reward", choices=("shaped", "sparse"), default="shaped",
                     help="dqn: the machine's shaped reward (default) or the task's sparse reward")
    cmd.add_argument("--cost", metavar="RULES.dnf|COST.safetensors",
                     help="a DNF formula over the environment's features, or a cost learned by "
                          "`symlearn learn icrl` (.safetensors), as the cost")
    cmd.add_argument("--features", metavar="A,B,...",
                     help="the names of the observation's entries, for a DNF cost (default: the environment's)")
    cmd.add_argument("--per-rule", action="store_true", help="one cost (and multiplier) per rule of --cost")
    cmd.add_argument("--depth-weight", type=float, default=0.0, metavar="W",
                     help="a DNF cost of 1 + W x how deep inside the unsafe set the state lies (in spans of the "
                          "formula's thresholds), so the cost points the way out; 0 (default): 1 per unsafe step")
    cmd.add_argument("--cost-limit", type=float, default=None,
                     help="Lagrangian: allowed expected cost per episode (default 0; for a cost learned by "
                          "`learn icrl`, what it charges the expert's demonstrations per episode, recorded in its file)")
    cmd.add_argument("--false-alarm-floor", dest="false_alarm_floor_mode", choices=("auto", "add", "none"),
                     default="auto",
                     help="Lagrangian on a DNF file from learn dnf --validation: add what the formula charged its "
                          "held-out expert episodes per episode (the file's validation line) to a positive "
                          "--cost-limit (auto, the default), to any limit, 0 included (add), or never (none: the "
                          "limit as given, on the formula's own cost)")
    cmd.add_argument("--multiplier-init", type=float, default=None,
                     help="Lagrangian: every multiplier's value at the start (ppo-lag: 1 -- the cost weighing as "
                          "much as the reward -- at limit 0 or a learned cost's expert level, 0 under a positive "
                          "--cost-limit; sb3-*-lag: 0)")
    cmd.add_argument("--multiplier-lr", type=float, default=None,
                     help="Lagrangian: multiplier step size (ppo-lag: 0.1; sb3-*-lag: 0.05)")
    cmd.add_argument("--multiplier-update", choices=("gradient", "adam", "pid"), default=None,
                     help="Lagrangian: multiplier update rule (ppo-lag: adam, steps of about --multiplier-lr "
                          "whatever the size of the violation; sb3-*-lag: gradient)")
    cmd.add_argument("--learning-rate", type=float, default=None,
                     help="our PPO's Adam step (default 1e-3, with --cost or without; CleanRL's was 2.5e-4)")
    cmd.add_argument("--log-std-init", type=float, default=None,
                     help="our PPO's initial log standard deviation of Box actions (default -1)")
    cmd.add_argument("--advantage-scale", choices=("raw", "returns"), default=None,
                     help="ppo-lag: mix advantages in their own units (raw) or in standard deviations of "
                          "their returns (returns, the default: the multiplier's range no longer depends on the units)")
    cmd.add_argument("--reward-scale-floor", type=float, default=None, metavar="SHARE",
                     help="ppo-lag: in the mix of reward and cost, the reward's return scale never drops below "
                          "SHARE x the largest it had (default 0.01; 1 when every episode earns about the same "
                          "and the cost stays over its limit: the run's warning says when)")
    cmd.add_argument("--cost-scale-floor", type=float, default=None, metavar="SHARE",
                     help="ppo-lag: in the mix, each cost's return scale never drops below SHARE x the largest it "
                          "had (default 0.01: a cost the agent stopped paying gets up to 100x dearer)")
    cmd.add_argument("--zero-limit-slack", type=float, default=None, metavar="SHARE",
                     help="ppo-lag: at --cost-limit 0 the multipliers aim at SHARE violating steps per episode of "
                          "the training policy, so rollouts without cost lower them (default 0: the exact limit, "
                          "a multiplier that can only rise; an opt-in for an agent the warning calls safe but "
                          "not useful)")
    cmd.add_argument("--cost-estimate", choices=("rollout", "episodes"), default="rollout",
                     help="ppo-lag: update the multipliers every iteration from the rollout's cost per step x the "
                          "mean episode length (rollout, the default) or only from episodes that ended in it (episodes)")
    cmd.add_argument("--reset-actor", choices=("auto", "never"), default=None,
                     help="ppo-lag: try the policy with fresh weights when it stays over --cost-limit while the multiplier "
                          "keeps rising (auto: a policy stuck in what the cost forbids), or never (the default)")
    cmd.add_argument("--normalize-observations", action=argparse.BooleanOptionalAction, default=None,
                     help="standardise the policy's inputs by running mean/std (saved with the model; "
                          "default: on)")
    cmd.add_argument("--normalize-values", action=argparse.BooleanOptionalAction, default=None,
                     help="critics learn returns divided by their running std (PopArt-style; default: on)")
    cmd.add_argument("--n-envs", type=float, default=4, help="environment copies stepped side by side (4)")
    cmd.add_argument("--n-steps", type=float, default=128, help="steps per copy per iteration (128)")
    cmd.add_argument("--prune", action="store_true", help="prune rules the agent never ran into (needs --cost)")
    cmd.add_argument("--prune-threshold", type=float, default=1e-3, help="fired/evaluated ratio to keep a rule")
    cmd.add_argument("--steps", type=float, default=None,
                     help="environment steps (ppo: 50000; dqrm/dqn: 300); with a cost, raise it when the safe route "
                          "is a detour the reward does not point to (docs/BENCHMARKS.md: a rover safe at 50k, at its "
                          "target by 150k)")
    cmd.add_argument("--eval-episodes", type=float, default=10, help="greedy evaluation episodes (10)")
    cmd.add_argument("-o", "--output", help="write the policy here (.safetensors + .json)")
    cmd.add_argument("--log", metavar="FILE.csv",
                     help="one CSV row per iteration (return, true and learned cost, multipliers, ...), "
                          "written as training goes")
    cmd.add_argument("--tensorboard", metavar="DIR",
                     help="the same numbers as TensorBoard scalars (needs the tensorboard package)")
    cmd.set_defaults(handler=_train)


def check_numbers(args: argparse.Namespace, default_steps: int) -> None:
    """Every numeric flag in range (in place: the counts become ints), before anything is built."""
    from symlearn.cli.flag_values import whole
    from symlearn.errors import SymlearnError

    args.steps = whole("--steps", default_steps if args.steps is None else args.steps, 1, MAX_STEPS)
    args.n_envs = whole("--n-envs", args.n_envs, 1, MAX_ENVS)
    args.n_steps = whole("--n-steps", args.n_steps, 1, MAX_ROLLOUT)
    args.eval_episodes = whole("--eval-episodes", args.eval_episodes, 1, 100_000)
    if args.n_envs * args.n_steps > MAX_ROLLOUT:
        raise SymlearnError(f"--n-envs {args.n_envs} x --n-steps {args.n_steps} = {args.n_envs * args.n_steps:,} "
                            f"steps per rollout, more than the {MAX_ROLLOUT:,} held in memory at once",
                            hint="lower --n-steps or --n-envs")
    if args.cost_limit is not None and not (math.isfinite(args.cost_limit) and args.cost_limit >= 0):
        raise SymlearnError(f"--cost-limit must be a finite number >= 0, got {args.cost_limit:g}")
    # above 10^6 the reward has no weight left in the mix (and lambda x cost can overflow a float)
    if args.multiplier_init is not None and not (math.isfinite(args.multiplier_init)
                                                 and 0 <= args.multiplier_init <= 1e6):
        raise SymlearnError(f"--multiplier-init must be a number in [0, 1e6], got {args.multiplier_init:g}")
    if args.multiplier_lr is not None and not (math.isfinite(args.multiplier_lr) and args.multiplier_lr > 0):
        raise SymlearnError(f"--multiplier-lr must be a finite number > 0, got {args.multiplier_lr:g}")
    if args.reward_scale_floor is not None and not (math.isfinite(args.reward_scale_floor)
                                                    and 0 < args.reward_scale_floor <= 1):
        raise SymlearnError(f"--reward-scale-floor must be a number in (0, 1], got {args.reward_scale_floor:g}")
    if args.cost_scale_floor is not None and not (math.isfinite(args.cost_scale_floor)
                                                  and 0 < args.cost_scale_floor <= 1):
        raise SymlearnError(f"--cost-scale-floor must be a number in (0, 1], got {args.cost_scale_floor:g}")
    if args.zero_limit_slack is not None and not (math.isfinite(args.zero_limit_slack)
                                                  and 0 <= args.zero_limit_slack <= 1):
        raise SymlearnError(f"--zero-limit-slack must be a number in [0, 1], got {args.zero_limit_slack:g}")
    if args.learning_rate is not None and not (math.isfinite(args.learning_rate) and 0 < args.learning_rate <= 1):
        raise SymlearnError(f"--learning-rate must be a number in (0, 1], got {args.learning_rate:g}")
    if args.log_std_init is not None and not (math.isfinite(args.log_std_init) and -20 <= args.log_std_init <= 5):
        raise SymlearnError(f"--log-std-init must be a number in [-20, 5], got {args.log_std_init:g}")
    if not (math.isfinite(args.prune_threshold) and 0 <= args.prune_threshold <= 1):
        raise SymlearnError(f"--prune-threshold must be in [0, 1], got {args.prune_threshold:g}")


def _train(args: argparse.Namespace, out) -> None:
    from symlearn.errors import SymlearnError

    if args.algo in BLOCK_ALGOS:
        from symlearn.cli.train_rm import train_blocks

        check_numbers(args, 300)
        return train_blocks(args, out)
    if args.algo is None:
        args.algo = "ppo-lag" if args.cost else "ppo"
    check_numbers(args, 50_000)
    if args.prune and not args.cost:
        raise SymlearnError("--prune needs the rules to prune: give --cost RULES.dnf")
    neural = bool(args.cost) and str(args.cost).endswith(".safetensors")
    if neural and (args.per_rule or args.prune):
        raise SymlearnError("--per-rule and --prune apply to DNF rules, not to a learned neural cost")
    if not math.isfinite(args.depth_weight) or args.depth_weight < 0:
        raise SymlearnError(f"--depth-weight must be a finite number >= 0, got {args.depth_weight:g}")
    if args.depth_weight and (not args.cost or neural):
        raise SymlearnError("--depth-weight shapes a DNF cost: give --cost RULES.dnf")
    if args.features and (not args.cost or neural):
        raise SymlearnError("--features names the observation's entries for a DNF cost: give --cost RULES.dnf")
    if args.algo in SB3_ALGOS:
        ours = [flag for flag, given in (("--normalize-observations", args.normalize_observations),
                                         ("--normalize-values", args.normalize_values),
                                         ("--advantage-scale", args.advantage_scale),
                                         ("--reward-scale-floor", args.reward_scale_floor),
                                         ("--cost-scale-floor", args.cost_scale_floor),
                                         ("--zero-limit-slack", args.zero_limit_slack),
                                         ("--learning-rate", args.learning_rate),
                                         ("--log-std-init", args.log_std_init),
                                         ("--reset-actor", args.reset_actor)) if given is not None]
        if ours:
            raise SymlearnError(f"{ours[0]} is an option of our PPO (--algo ppo|ppo-lag), not of --algo {args.algo}")
    if args.output and str(args.output).endswith(".zip"):
        raise SymlearnError("symlearn writes policies as .safetensors + .json, never stable-baselines3's "
                            "pickled .zip", hint="-o agent.safetensors")

    from symlearn.cli.train_costs import refused_without_cost, training_cost
    from symlearn.recipes.environments import CostWatch, resolve_env
    from symlearn.rl.episode_stats import NoCostReported

    # observed as one vector whatever the environment observes (MiniGrid's Dict with text, ...);
    # our PPO and SB3's DQN act in a MultiDiscrete/MultiBinary space as one Discrete of its combinations
    target = resolve_env(args.env, kwargs=args.env_kwargs).as_numeric(
        actions=args.algo in ("ppo", "ppo-lag", "sb3-dqn"))
    cost = None
    if args.cost:
        cost = training_cost(args.cost, target, features=args.features, per_rule=args.per_rule,
                             depth_weight=args.depth_weight)
    args.cost_limit_from = "--cost-limit" if args.cost_limit is not None else (
        "expert" if cost is not None and cost.expert_level is not None else "default")
    if args.cost_limit is None:
        args.cost_limit = cost.expert_level if args.cost_limit_from == "expert" else 0.0
    _add_false_alarm_floor(args, cost)
    from symlearn.cli.env_errors import environment_file, raised_by_environment

    # an exception from the user's environment code while training is theirs, one located line
    probe = target.make()
    env_file = None if target.bundled else environment_file(probe)
    probe.close()
    # whether the environment reports a cost: from every step training and evaluation take (one
    # may report info["cost"] only on the steps that pay it), not from a first step
    watch = CostWatch()
    target = target.watched(watch)
    try:
        with raised_by_environment(env_file, f"training on {target.display}"):
            if args.algo in SB3_ALGOS:
                from symlearn.cli.train_sb3 import train_sb3

                doc = train_sb3(args, target, cost, watch)
            else:
                doc = _train_ours(args, target, cost, watch)
    except NoCostReported as exc:   # --algo *-lag without --cost: the first rollout reported no cost
        if cost is not None:
            raise
        raise refused_without_cost(target, args.algo, exc.steps) from None
    kept = _limit_kept(args, cost, doc)
    if kept and not doc["warnings"]:
        doc["warnings"].append(kept)
    cut, cap = getattr(args, "evaluation_cut", (0, 0))
    if cut:
        doc["warnings"].append(f"{cut} of the {args.eval_episodes} evaluation episodes ran {cap:,} steps without "
                               f"ending and were cut there, so the return and costs above are sums over {cap:,} "
                               f"steps: {target.display} registers no time limit (gymnasium.register(..., "
                               "max_episode_steps=N) sets one)")
    if args.prune:
        pruned = _prune(args, cost.stats, doc["steps"])
        doc["files"].insert(0, pruned.pop("file"))
        doc.update(pruned)
    out.result(doc, _render)


def _add_false_alarm_floor(args: argparse.Namespace, cost) -> None:
    """A learned DNF's limit counts the states the formula wrongly calls unsafe: ``args.cost_limit``
    becomes the limit given (in violations per episode) plus the file's false-alarm floor -- what
    the formula charged the held-out expert episodes of ``learn dnf --validation``, per episode
    (``Validation.per_demonstration``). Without it a budget of 25 on a SafeNav formula that charges
    the scripted expert 19-36 per episode is out of every policy's reach, the expert's included.
    Measured, the floor alone trains within noise of the raw limit there: the agents' own false
    alarms are 5-10 times the expert's (docs/BENCHMARKS.md, "A learned DNF's false-alarm floor in
    the limit"). ``--false-alarm-floor auto`` (the default) adds it to a positive budget only: at
    limit 0 the constraint is hard, the floor would let the agent spend it on real violations, and
    the library's hard-limit handling (multiplier from 1) already copes; ``add`` adds it at 0 too,
    ``none`` keeps the limit as given (the behaviour before). Sets ``args.cost_limit_given`` and
    ``args.false_alarm_floor`` (the file's floor, or None) for the JSON."""
    from symlearn.errors import SymlearnError

    args.cost_limit_given = args.cost_limit
    recorded = getattr(cost, "validation", None) if cost is not None and cost.kind == "dnf" else None
    args.false_alarm_floor = None if recorded is None else recorded.per_demonstration
    mode = args.false_alarm_floor_mode
    if mode == "none" or not args.algo.endswith("-lag"):
        return
    if mode == "add" and recorded is None:
        if cost is not None and cost.kind == "neural":
            raise SymlearnError("--false-alarm-floor add is for a DNF cost: a learned neural cost's limit is its "
                                "expert's level already")
        raise SymlearnError("--false-alarm-floor add needs a DNF rule file whose header records a held-out check; "
                            + (f"{args.cost} records none" if cost is not None else "no --cost was given"),
                            hint="learn the formula with learn dnf --validation 0.2 -o rules.dnf")
    if recorded is None:
        return
    if args.per_rule or args.depth_weight:
        # the floor counts unsafe states of the whole formula at 1 each: a cost per rule or one
        # weighted by depth is in other units, so the file's number does not apply
        if mode == "add":
            raise SymlearnError("--false-alarm-floor add counts the whole formula's unsafe states at 1 each; it "
                                "does not apply with " + ("--per-rule" if args.per_rule else "--depth-weight"))
        return
    if mode == "auto" and args.cost_limit <= 0:
        return
    args.cost_limit = args.cost_limit + args.false_alarm_floor
    args.cost_limit_from = "validation"


def _train_ours(args: argparse.Namespace, target, cost, watch) -> dict:
    from symlearn.cli.train_costs import penalised
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, evaluate, train_ppo
    from symlearn.rl.training_log import TrainingLog

    seed = getattr(args, "seed", 0) or 0
    cost_fn = reward_fn = None
    if cost is not None:
        if args.algo == "ppo-lag":
            cost_fn = cost.rollout_cost
        else:  # plain PPO learns from r - C
            reward_fn = penalised(cost)
    env_fn = target.env_fn if cost is None or cost.wrap is None else (lambda: cost.wrap(target.make()))
    lagrangian = None
    constrained = args.algo == "ppo-lag"
    # with a Lagrangian, scale-free advantages and normalisation are the measured defaults (module doc)
    # None: the library's measured default (normalisation on with a Lagrangian, off without)
    if constrained:
        # a learned cost's expert level is its floor, the hard constraint in its own terms: from 1 as
        # a limit of 0 would (the library starts a positive budget at 0)
        # a floor added to a limit of 0 (--false-alarm-floor add) is the same case
        hard = args.cost_limit_from == "expert" or (args.cost_limit_from == "validation"
                                                    and args.cost_limit_given == 0)
        start = 1.0 if args.multiplier_init is None and hard else args.multiplier_init
        given = {key: value for key, value in (("update", args.multiplier_update), ("lr", args.multiplier_lr),
                                               ("init", start), ("reward_scale_floor", args.reward_scale_floor),
                                               ("cost_scale_floor", args.cost_scale_floor),
                                               ("zero_limit_slack", args.zero_limit_slack),
                                               ("reset_actor", args.reset_actor))
                 if value is not None}  # the rest: the library's defaults
        lagrangian = LagrangianConfig(cost_limit=args.cost_limit, advantage_scale=args.advantage_scale or "returns",
                                      cost_estimate=args.cost_estimate, **given)
    config = PPOConfig(seed=seed, n_envs=args.n_envs, n_steps=args.n_steps,
                       batch_size=min(128, args.n_envs * args.n_steps),
                       normalize_observations=args.normalize_observations, normalize_values=args.normalize_values,
                       learning_rate=args.learning_rate, log_std_init=args.log_std_init)
    with TrainingLog(args.log, args.tensorboard) as log:
        result = train_ppo(env_fn, args.steps, config, lagrangian=lagrangian, cost_fn=cost_fn, reward_fn=reward_fn,
                           callback=_logged(log, cost_fn is not None) if (args.log or args.tensorboard) else None)
    tally = LearnedCostTally(cost)
    episodes = evaluate(result.policy, tally.wrap(target.make()), args.eval_episodes, seed=seed + 10_000)
    doc = evaluation_document(args, cost, episodes.returns, episodes.lengths,
                              episodes.costs if episodes.costs.shape[1] else None, reported=watch.seen,
                              learned=tally.per_episode())
    doc.update({"multipliers": [float(m) for m in result.multipliers] if lagrangian else None,
                "actor_resets": [h.iteration for h in result.history if h.actor_reset] if lagrangian else None,
                "actor_restored": [h.iteration for h in result.history if h.actor_restored] if lagrangian else None,
                "steps": int(result.steps), "seconds": float(result.seconds)})
    if lagrangian:
        from symlearn.rl.ppo import limit_warnings

        doc["warnings"] = limit_warnings(result.history, [args.cost_limit] * len(result.multipliers),
                                         advantage_scale=lagrangian.advantage_scale,
                                         reward_floor=lagrangian.reward_scale_floor,
                                         cost_kind=None if cost is None else cost.kind,
                                         cost_floor=lagrangian.cost_scale_floor,
                                         zero_slack=lagrangian.zero_limit_slack)
        if doc["warnings"] and cost is not None and cost.kind == "dnf" and not args.depth_weight:
            # an agent that cut across a narrow safe set pays 1 on every step of the short cut
            # whichever way it turns; a depth-shaped cost tells it the way out (backends/dnf_depth)
            doc["warnings"] = [w + "; or shape the formula's cost by how deep the agent is in the unsafe set "
                                   "(--depth-weight 3)" for w in doc["warnings"]]
    if args.output:
        result.save(args.output)
        doc["files"].append(str(args.output))
    return doc


def _limit_kept(args: argparse.Namespace, cost, doc: dict) -> str | None:
    """A Lagrangian's greedy agent that still pays more than its limit of what it was trained on
    (the learned cost, else ``info["cost"]``) per episode, a neural cost held to 0, which no
    policy reaches, or (any algorithm) a neural cost that is 0 everywhere: one warning, whatever the multiplier's units (SB3's rule has no threshold on it
    that means anything); None otherwise."""
    if cost is not None and getattr(cost, "charges_nothing", False):
        # learn icrl ended with every lambda at 0 (issue 24, a fresh conveyor arm): the cost is 0
        # everywhere, the agent was trained on the reward alone -- not a limit out of reach; said
        # for every algorithm (ppo and sb3-sac learn from r - C, which is then r)
        return ("this learned neural cost is 0 everywhere (every lambda in it is 0: `learn icrl` found nothing in "
                "the demonstrations to charge), so it constrained nothing and the agent learned from the reward "
                "alone; learn it again (another --seed, more --iterations or --steps) or use a DNF file")
    if not args.algo.endswith("-lag"):
        return None
    if cost is not None and cost.kind == "neural" and args.cost_limit == 0:
        # a sigmoid charges every state something: 0 is out of reach by design
        if cost.expert_level is not None:
            return (f"a learned neural cost charges every state something, so --cost-limit 0 is out of reach; its "
                    f"own demonstrations pay {cost.expert_level:.3g} per episode (the limit without --cost-limit)")
        return ("a learned neural cost charges every state something, so --cost-limit 0 is out of reach; this file "
                "records no expert level to hold the agent to (learned by an older symlearn): learn it again, "
                "or give --cost-limit")
    paid = doc.get("learned_cost") if cost is not None else doc.get("cost")
    if paid is None or paid <= args.cost_limit + 1e-9:
        return None
    what = "the learned cost" if cost is not None else 'info["cost"]'
    advice = "raise --steps"
    limit = f"--cost-limit {args.cost_limit:g}"
    if args.cost_limit_from == "expert":
        limit = f"its limit, the expert's level of {args.cost_limit:.3g} per episode"
    elif args.cost_limit_from == "validation":
        limit = (f"its limit, {args.cost_limit_given:g} plus the formula's false-alarm floor of "
                 f"{args.false_alarm_floor:.3g} per episode")
    if cost is not None and cost.kind == "dnf":
        if getattr(args, "false_alarm_floor", None) is None:
            advice += ("; a formula that also flags the expert's own states cannot be kept (learn dnf --validation "
                       "0.2 counts them, and train then adds them to a positive --cost-limit)")
        elif args.cost_limit_from != "validation":
            allow = ("without --false-alarm-floor none they are added to the limit"
                     if getattr(args, "false_alarm_floor_mode", None) == "none" and args.cost_limit > 0
                     else "--false-alarm-floor add allows them")
            advice += (f"; the formula flags {args.false_alarm_floor:.3g} states of an unseen expert episode "
                       f"(its validation line): {allow}")
        if not args.depth_weight:
            # the speed cart of issue 24's second pass: its agent raced through the learned speed limit
            # (12 per episode, multiplier 7.4 after 50k steps); --depth-weight 3: 2.2 at cost 0
            advice += ("; an agent that cut across the formula's unsafe set pays 1 a step whichever way it turns: "
                       "--depth-weight 3 charges by depth and points the way out")
    return (f"the trained agent does not keep {limit}: its greedy episodes pay {paid:.3g} "
            f"per episode of {what} after {doc['steps']} steps; {advice}")


def _logged(log, learned: bool):
    """The training callback writing one log row per iteration: what :class:`PPOIteration` holds,
    with the finished episodes' cost named ``learned_cost`` when ``--cost`` is the Lagrangian's
    cost (``learned``: it is the learned one then). Under plain PPO a learned cost is a penalty in
    the reward and the episodes' cost is the environment's ``info["cost"]``, left as ``mean_cost``;
    ``true_cost`` is always the environment's own."""
    def write(record, policy) -> None:
        row = record.as_dict()
        if learned:
            row["learned_cost"] = row.pop("mean_cost")
        log.write(row)

    return write


class LearnedCostTally:
    """What the learned cost (``--cost``) charges the greedy evaluation's episodes, summed over its
    rules: the agent is trained to keep it under ``--cost-limit``, so an agent that did not is seen
    even where the environment reports no ``info["cost"]``. ``wrap`` is the identity without a cost."""

    def __init__(self, cost) -> None:
        self.cost, self.totals = cost, []

    def wrap(self, env):
        if self.cost is None:
            return env
        import gymnasium as gym
        import numpy as np

        from symlearn.backends.lagrangian import StepCostWrapper

        tally = self

        class Summed(gym.Wrapper):
            def reset(self, **kwargs):
                tally.totals.append(0.0)
                return self.env.reset(**kwargs)

            def step(self, action):
                result = self.env.step(action)
                tally.totals[-1] += float(np.sum(result[4]["learned_cost"]))
                return result

        return Summed(StepCostWrapper(self.cost.wrap(env) if self.cost.wrap else env, self.cost.step_cost))

    def per_episode(self) -> float | None:
        return None if self.cost is None or not self.totals else sum(self.totals) / len(self.totals)


def evaluation_document(args: argparse.Namespace, cost, returns, lengths, true_costs, *,
                        reported: bool = False, learned: float | None = None) -> dict:
    """The result keys both trainers share; ``true_costs`` ``(E, k)``, or None when no evaluation
    step reported ``info["cost"]``: then, where a training step did (``reported``), every
    evaluated step cost 0, and where none did, ``cost`` and ``violation_rate`` are null, never 0.
    ``learned``: the learned cost per episode (:class:`LearnedCostTally`), null without ``--cost``."""
    import numpy as np

    from symlearn.rl.evaluation import MAX_EPISODE_STEPS

    # an environment with no time limit whose greedy episodes never end is cut by the evaluation
    # loop: _train says so, since the return and cost are then sums over that many steps
    args.evaluation_cut = int(np.sum(np.asarray(lengths) >= MAX_EPISODE_STEPS)), MAX_EPISODE_STEPS
    per_episode = None
    if true_costs is None and reported:   # costs reported only where paid, and evaluation paid none
        true_costs = np.zeros((len(returns), 1))
    if true_costs is not None:   # summed over constraints
        per_episode = np.asarray(true_costs, dtype=np.float64).reshape(len(returns), -1).sum(axis=1)
    # a Lagrangian, on a learned cost or on info["cost"]: both keep a limit (0 unless given)
    limited = args.algo.endswith("-lag")
    return {"env": args.env, "algo": args.algo, "cost_kind": None if cost is None else cost.kind,
            "return": float(np.mean(returns)),
            "cost": None if per_episode is None else float(np.mean(per_episode)),
            "learned_cost": learned,
            "violation_rate": None if per_episode is None else
            float(np.sum(per_episode) / max(int(np.sum(lengths)), 1)),
            "cost_limit": float(args.cost_limit) if limited else None,
            "cost_limit_from": args.cost_limit_from if limited else None,
            # the limit before a DNF file's false-alarm floor was added, and that floor (the
            # file's held-out expert episodes' formula cost each; null for a file without one)
            "cost_limit_given": float(args.cost_limit_given) if limited else None,
            "false_alarm_floor": getattr(args, "false_alarm_floor", None),
            "actor_resets": None, "actor_restored": None, "pruned": None, "files": [], "warnings": []}


def _prune(args: argparse.Namespace, stats, steps: int) -> dict:
    pruned, verdicts = stats.prune(args.prune_threshold)
    path = Path(args.cost)
    target = path.with_name(path.stem + ".pruned" + (path.suffix or ".dnf"))
    report = "\n".join(f"{'kept   ' if v.kept else 'dropped'} fired {v.fired:>8} / evaluated {v.evaluated:>8}  {v.rule}"
                       for v in verdicts)
    pruned.save(target, header=f"pruned from {path.name} after {steps} training steps "
                               f"(threshold {args.prune_threshold}):\n{report}")
    return {"pruned": [v.rule for v in verdicts if not v.kept], "kept": [v.rule for v in verdicts if v.kept],
            "file": str(target)}


def _render(doc: dict) -> str:
    def number(value, digits: int) -> str:
        if value is None:
            return "n/a"
        # a small cost keeps its significant digits: "0.00" next to a limit of 0.000224 read as kept
        return f"{value:.{digits}f}" if value == 0 or abs(value) >= 10 ** -digits else f"{value:.2g}"

    lines = [f"{doc['env']}: {doc['algo']}, {doc['steps']} steps in {doc['seconds']:.1f} s",
             f"greedy evaluation: return {doc['return']:.2f}, "
             + ("" if doc.get("learned_cost") is None else f"learned cost {number(doc['learned_cost'], 2)} per episode"
                + ("" if doc.get("cost_limit") is None else f" (limit {doc['cost_limit']:.3g}"
                   + (", the expert's level" if doc.get("cost_limit_from") == "expert" else "")
                   + (f": {doc['cost_limit_given']:.3g} + the formula's false-alarm floor "
                      f"{doc['false_alarm_floor']:.3g}" if doc.get("cost_limit_from") == "validation" else "")
                   + ")") + ", ")
             + f"ground-truth cost {number(doc['cost'], 2)} per episode, "
             f"violation rate {number(doc['violation_rate'], 3)}"]
    if doc["multipliers"] is not None:
        lines.append("multipliers: " + ", ".join(f"{m:.3f}" for m in doc["multipliers"]))
    if doc.get("actor_resets"):
        lines.append("fresh actor at iteration " + ", ".join(map(str, doc["actor_resets"]))
                     + " (the policy stayed over the limit while the multiplier rose: --reset-actor)"
                     + ("; the old one put back at " + ", ".join(map(str, doc["actor_restored"]))
                        + " (the fresh one did worse)" if doc.get("actor_restored") else ""))
    if doc["pruned"] is not None:
        lines.append(f"pruning kept {len(doc['kept'])} rule(s), dropped {len(doc['pruned'])}")
        lines += [f"  kept: {r}" for r in doc["kept"]]
    lines += [f"warning: {w}" for w in doc.get("warnings") or ()]
    lines += [f"wrote {f}" for f in doc["files"]]
    return "\n".join(lines)
