"""``symlearn train --algo sb3-ppo|sb3-sac|sb3-dqn|sb3-ppo-lag|sb3-sac-lag``: stable-baselines3 as the learner.

The environment is the one ``train`` resolved; a learned cost (:mod:`symlearn.cli.train_costs`)
reaches the learner through gymnasium wrappers (:mod:`symlearn.backends.lagrangian`): its value
on every step as ``info["learned_cost"]``, then the reward ``r - lambda . c``. ``sb3-*-lag``
updates ``lambda`` by :func:`symlearn.backends.sb3.lagrangian_callback` (``--cost-limit``,
``--multiplier-update``, ``--multiplier-lr``), from the learned cost or, without ``--cost``, from
the environment's ``info["cost"]``; plain ``sb3-*`` with ``--cost`` subtracts the cost
(``lambda`` fixed at 1). The networks have our PPO's sizes (two hidden layers of 64; tanh for
PPO, ReLU for SAC and DQN as in stable-baselines3), ``--n-envs`` copies side by side
(``DummyVecEnv``); PPO's rollout is ``--n-steps`` per copy and its other settings are our PPO's
defaults (minibatch 128, 4 epochs, learning rate 2.5e-4 annealed to 0, entropy 0.01).

Discrete spaces numbered from another ``start`` and a scalar ``Box`` observation are shown to
stable-baselines3 as it reads them (:mod:`symlearn.backends.sb3_spaces`), outside the cost wrappers.
Evaluation is greedy (``deterministic=True``) on a fresh environment without the cost wrappers:
its ``info["cost"]`` is the ground truth reported. ``-o agent.safetensors`` writes the policy with
:func:`symlearn.backends.sb3.save_policy` (safetensors + JSON; stable-baselines3's ``.zip`` is
never written or read). A progress bar shows the latest return and cost on a terminal; ``--log
run.csv`` / ``--tensorboard DIR`` write one row per rollout (on-policy) or per 1,000 steps
(off-policy) with the columns of our PPO's log (:func:`symlearn.backends.sb3.monitor_callback`).
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np


def train_sb3(args: argparse.Namespace, target: Any, cost: Any, watch: Any = None) -> dict[str, Any]:
    from symlearn.backends.sb3 import (algorithm_class, check_action_space, lagrangian_callback, monitor_callback,
                                       quiet_logger, save_policy)
    from symlearn.cli.train_command import LearnedCostTally, evaluation_document

    algo = args.algo.removeprefix("sb3-").removesuffix("-lag")
    lagrangian = args.algo.endswith("-lag")
    probe = target.make()
    try:
        check_action_space(algo, probe.action_space)
    finally:
        probe.close()
    algorithm = algorithm_class(algo)   # the install hint when stable-baselines3 is absent
    import torch
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    from symlearn.backends.lagrangian import LagrangianReward, SharedMultipliers, StepCostWrapper
    from symlearn.backends.finite_observations import FiniteObservations
    from symlearn.backends.sb3_spaces import sb3_spaces
    from symlearn.errors import SymlearnError
    from symlearn.rl.ppo import LagrangianConfig

    seed = getattr(args, "seed", 0) or 0
    multipliers = None
    cost_key = "cost" if cost is None else "learned_cost"
    # without --cost the Lagrangian constrains info["cost"], which may be a vector (one entry per
    # constraint; our PPO keeps a multiplier each): sized from the environment's first report, as
    # ours is -- one multiplier for a 2-entry cost stopped with "has 2 entries for 1 multiplier(s)"
    n_costs = cost.n_costs if cost is not None else _reported_cost_width(target, seed) if lagrangian else 1
    if lagrangian:
        # SB3's measured rule (train_command's docstring), unless the flags name another
        multipliers = SharedMultipliers(LagrangianConfig(cost_limit=args.cost_limit,
                                                         update=args.multiplier_update or "gradient",
                                                         lr=args.multiplier_lr or 0.05,
                                                         init=args.multiplier_init or 0.0), n_costs)
    elif cost is not None:
        multipliers = SharedMultipliers(n_costs=n_costs, fixed=[1.0] * n_costs)

    def make() -> Any:
        env = target.make()
        if cost is not None:
            env = StepCostWrapper(cost.wrap(env) if cost.wrap else env, cost.step_cost)
        if multipliers is not None:
            env = LagrangianReward(env, multipliers, cost_key=cost_key)
        # outside the cost wrappers: the cost reads the environment's values; NaN observations refused
        return Monitor(FiniteObservations(sb3_spaces(env)))

    venv = DummyVecEnv([make] * args.n_envs)
    venv.seed(seed)
    settings: dict[str, Any] = {"seed": seed, "device": "cpu", "verbose": 0,
                                "policy_kwargs": {"net_arch": [64, 64]}}
    if algo == "ppo":  # our PPO's defaults (CleanRL's), so that `--algo ppo` and `sb3-ppo` are peers
        settings.update(n_steps=args.n_steps, batch_size=min(128, args.n_envs * args.n_steps), n_epochs=4,
                        learning_rate=lambda remaining: 2.5e-4 * remaining, ent_coef=0.01)
        settings["policy_kwargs"]["activation_fn"] = torch.nn.Tanh
    elif algo == "dqn":
        settings.update(learning_starts=min(1000, args.steps // 10), exploration_fraction=0.2)
    else:
        settings.update(learning_starts=min(1000, args.steps // 10))
    threads = torch.get_num_threads()
    torch.set_num_threads(1)   # small networks: one thread is faster and leaves the cores to the others
    try:
        from gymnasium import spaces

        policy = "MultiInputPolicy" if isinstance(venv.observation_space, spaces.Dict) else "MlpPolicy"
        try:
            model = algorithm(policy, venv, **settings)
        except (ValueError, NotImplementedError, AssertionError, KeyError) as exc:  # SB3's checks of the spaces
            raise SymlearnError(f"stable-baselines3 {algorithm.__name__} cannot train on {target.display}: "
                                f"{type(exc).__name__}: {exc}") from None
        model.set_logger(quiet_logger())
        from symlearn.rl.training_log import TrainingLog

        with TrainingLog(args.log, args.tensorboard) as log:
            callbacks = [lagrangian_callback(multipliers, cost_key=cost_key)] if lagrangian else []
            # after the multiplier's update, so a row shows the multipliers the next window trains with
            callbacks.append(monitor_callback(args.steps, log=log if (args.log or args.tensorboard) else None,
                                              multipliers=multipliers if lagrangian else None,
                                              learned_cost=cost is not None, desc=f"{args.algo} on {target.display}"))
            started = time.perf_counter()
            model.learn(args.steps, callback=callbacks)
            seconds = time.perf_counter() - started
        tally = LearnedCostTally(cost)
        returns, lengths, true_costs = _evaluate(model, target, args.eval_episodes, seed + 10_000, tally.wrap)
    finally:
        torch.set_num_threads(threads)
        venv.close()
    doc = evaluation_document(args, cost, returns, lengths, true_costs,
                              reported=watch is not None and watch.seen, learned=tally.per_episode())
    doc.update({"multipliers": [float(m) for m in multipliers.values] if lagrangian else None,
                "steps": int(model.num_timesteps), "seconds": seconds})
    if lagrangian and not callbacks[0].updates:
        # SAC's window is 1,000 steps: a shorter run trained r - lambda c at the starting lambda throughout
        doc["warnings"].append(f"the multiplier was never updated: {int(model.num_timesteps):,} steps are fewer than "
                               f"one update window of {callbacks[0].update_every:,}, so the run trained at the "
                               f"starting multiplier ({', '.join(f'{m:g}' for m in multipliers.values)}) throughout; "
                               "raise --steps")
    if args.output:
        path = save_policy(model, args.output, {"env": args.env, "env_kwargs": target.kwargs, "algo": args.algo,
                                                "steps": int(model.num_timesteps)})
        doc["files"] += [str(path), str(path.with_suffix(".json"))]
    return doc


def _reported_cost_width(target: Any, seed: int, max_steps: int = 256) -> int:
    """The number of entries of ``info["cost"]`` on the first step (of a random walk in a separate
    copy, at most ``max_steps``) that reports one; 1 where none does (the callback then refuses a
    first window without any)."""
    env = target.make()
    try:
        env.reset(seed=seed)
        env.action_space.seed(seed)
        for _ in range(max_steps):
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            if isinstance(info, dict) and info.get("cost") is not None:
                try:
                    return max(1, int(np.asarray(info["cost"], dtype=np.float64).size))
                except (TypeError, ValueError):
                    return 1   # no number: the cost reader says so, in one line, when training reads it
            if terminated or truncated:
                env.reset()
        return 1
    finally:
        env.close()


def _evaluate(model: Any, target: Any, n_episodes: int, seed: int,
              wrap: Any = None) -> tuple[np.ndarray, np.ndarray, Any]:
    """Greedy episodes on a fresh environment, through the loop our PPO is evaluated with: returns,
    lengths, and the summed ``info["cost"]`` ``(E, k)`` -- or None when the environment reports none.
    ``wrap``: around the environment, inside SB3's view (the learned cost's tally, as in training)."""
    from symlearn.backends.sb3_spaces import predicted_action, sb3_spaces
    from symlearn.rl.evaluation import run_episodes

    env = sb3_spaces(wrap(target.make()) if wrap is not None else target.make())
    try:
        episodes = run_episodes(env, lambda observation: predicted_action(model.predict(observation,
                                                                                        deterministic=True)[0]),
                                n_episodes, seed=seed)
    finally:
        env.close()
    return episodes.returns, episodes.lengths, episodes.costs if episodes.costs.shape[1] else None


__all__ = ["train_sb3"]
