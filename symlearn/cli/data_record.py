"""``symlearn data record``: demonstrations from a policy that ``symlearn train`` saved.

``symlearn data record --env ENV [--env-kwargs JSON] --policy agent.safetensors [--episodes 20]
[--stochastic] [--max-steps N] [--states observations|features] [--seed S] -o demos.npz|demos.jsonl``

The step between training an expert (``train --algo ppo-lag`` on the environment's own
``info["cost"]``, or any ``train -o``) and learning from it (``learn dnf|icrl|pdfa --demos``), from
the command line: :func:`symlearn.data.record` runs the policy in the environment and the file is
written atomically. The policy may be our PPO's (``--algo ppo|ppo-lag``) or a stable-baselines3
one (``--algo sb3-*``), both the safetensors + JSON pairs ``train -o`` writes; it acts on the
numeric view of the observations it was trained on, while the file keeps the environment's own
observations (a ``Dict`` flattened and named as ``record()`` does) and its own actions (a
``MultiDiscrete`` action, not the index of its combination). Greedy (the mean or most likely
action) unless ``--stochastic``. A policy trained for other spaces is refused in one line.
``--policy random`` samples the action space (seeded by ``--seed``), as ``record(env, "random")``.
``--states features`` stores each step's ``info["features"]`` instead of the observation, named
as ``train --cost`` names them (the keys of a dict, else the environment's ``feature_names``, in
the file's ``metadata["feature_names"]``): what ``learn dnf`` needs where the features a
constraint reads are not the observation -- positions out of a position-and-velocity
observation, or a flag of the action just taken that no observation holds (issue 24's second
pass: a rover whose boost is forbidden on a low battery). ``learn icrl`` learns from observations:
record those (the default) for it.

JSON keys: ``env``, ``policy``, ``episodes``, ``steps``, ``return`` (mean per episode), ``cost``
(mean ``info["cost"]`` per episode, null where no step reported one), ``files``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from symlearn.cli.flag_values import MAX_DEMOS as MAX_EPISODES  # one bound for every recorded-episode count

MAX_EPISODE_STEPS = 10_000_000


def register(commands, common) -> None:
    cmd = commands.add_parser("record", parents=[common()], help="record demonstrations of a policy `train` saved",
                              description="Run a policy saved by `symlearn train -o` (our PPO's or a "
                                          "stable-baselines3 one) in an environment and write its episodes as "
                                          "demonstrations (.npz or .jsonl).")
    cmd.add_argument("--env", required=True, help="a bundled name, a gymnasium id or module:EnvId")
    cmd.add_argument("--env-kwargs", metavar="JSON", help="keyword arguments of the environment, a JSON object")
    cmd.add_argument("--policy", required=True, metavar="AGENT.safetensors",
                     help="what `symlearn train -o` wrote, or 'random': actions sampled from the action space "
                          "(seeded by --seed), the aimless baseline")
    cmd.add_argument("--episodes", type=float, default=20, help="episodes to record (20)")
    cmd.add_argument("--stochastic", action="store_true",
                     help="sample the policy's actions (default: its mean or most likely action)")
    cmd.add_argument("--max-steps", type=float, default=None, help="cap on an episode's length (default: the "
                                                                    "environment's own time limit, else 10000)")
    cmd.add_argument("--states", choices=("observations", "features"), default="observations",
                     help="store the observations (default; what learn icrl reads) or each step's info[\"features\"] "
                          "(what learn dnf and train --cost read, where the environment reports them)")
    cmd.add_argument("-o", "--output", required=True, metavar="DEMOS.npz", help="the file to write (.npz or .jsonl)")
    cmd.set_defaults(handler=run)


class _Features:
    """Each step's ``info["features"]`` as a flat vector, for ``record(..., observation=...)``:
    the wrapper keeps the latest one, and the stored state ignores the observation it is given."""

    def __init__(self) -> None:
        self.latest = None
        self.steps = 0

    def wrap(self, env: Any) -> Any:
        import gymnasium as gym

        keeper = self

        class Kept(gym.Wrapper):
            def reset(self, **kwargs: Any) -> Any:
                observation, info = self.env.reset(**kwargs)
                keeper.keep(info)
                return observation, info

            def step(self, action: Any) -> Any:
                result = self.env.step(action)
                keeper.keep(result[4])
                return result

        return Kept(env)

    def keep(self, info: Any) -> None:
        from collections.abc import Mapping

        import numpy as np

        from symlearn.errors import DataError

        raw = info.get("features") if isinstance(info, Mapping) else None
        if raw is None:
            raise DataError(f"--states features: step {self.steps} reported no info[\"features\"]",
                            hint="record the observations (the default), or report info[\"features\"] on every step")
        values = list(raw.values()) if isinstance(raw, Mapping) else raw
        self.latest = np.asarray(values, dtype=np.float64).reshape(-1).tolist()
        self.steps += 1

    def stored(self, observation: Any) -> Any:
        return self.latest


class _EpisodeCost:
    """Sums ``info["cost"]`` per episode while recording (None while no step reported one), read
    as ``train`` reads it (:class:`~symlearn.rl.episode_stats.CostReader`: a number or a vector,
    summed over its constraints as ``train``'s report sums them; ``None``, text or NaN are refused
    in one line, where ``float()`` raised an internal ``TypeError``)."""

    def __init__(self) -> None:
        from symlearn.rl.episode_stats import CostReader

        self.totals: list[float] = []
        self.seen = False
        self.reader = CostReader(None)
        self.steps = 0

    def wrap(self, env: Any) -> Any:
        import gymnasium as gym

        watch = self

        class Summed(gym.Wrapper):
            def reset(self, **kwargs: Any) -> Any:
                watch.totals.append(0.0)
                watch.steps = 0   # an error names the step within its episode
                return self.env.reset(**kwargs)

            def step(self, action: Any) -> Any:
                result = self.env.step(action)
                cost = watch.reader.read(result[4], where=lambda: f"episode {len(watch.totals) - 1}, step {watch.steps}")
                watch.steps += 1
                if cost is not None:
                    watch.seen = True
                    watch.totals[-1] += float(cost.sum())
                return result

        return Summed(env)


def _policy(path: str, env: Any, stochastic: bool, seed: int):
    """``observation -> the environment's own action`` for the policy in ``path``, acting through
    the views ``train`` trained it on."""
    import numpy as np

    from symlearn.errors import ModelError
    from symlearn.recipes.action_spaces import policy_actions
    from symlearn.recipes.spaces import numeric_observations
    from symlearn.rl.model_files import read_model_kind
    from symlearn.rl.ppo import MODEL_KIND, ActorCritic, _space_spec

    numeric = numeric_observations(env)
    joint = policy_actions(numeric)
    observe = numeric.observation if numeric is not env else (lambda o: o)
    kind = read_model_kind(path)
    if kind == MODEL_KIND:
        agent = ActorCritic.load(path)
        try:
            wanted = (_space_spec(joint.observation_space, "observation"), _space_spec(joint.action_space, "action"))
        except Exception as exc:  # a space our PPO cannot act in: this policy was not trained here
            raise ModelError(f"the policy cannot act in this environment ({exc})", file=path) from None
        if (agent.observation_spec, agent.action_spec) != wanted:
            raise ModelError(f"the policy was trained for observations {agent.observation_spec} and actions "
                             f"{agent.action_spec}; this environment has {wanted[0]} and {wanted[1]}", file=path)
        to_env = joint.action if joint is not numeric else (lambda a: a)
        rng = np.random.default_rng(seed)
        return lambda o: to_env(agent.act(observe(o), deterministic=not stochastic, rng=rng))
    from symlearn.backends.sb3 import POLICY_KIND, load_policy

    if kind != POLICY_KIND:
        raise ModelError(f"the file holds a {kind!r} model, not a policy `symlearn train -o` writes", file=path)
    from symlearn.backends.sb3_spaces import SB3Spaces, env_action, predicted_action, sb3_spaces

    # trained on the numeric view (sb3-dqn also on the joint actions) as stable-baselines3 reads it
    # (train_sb3: Discrete ids from 0, a scalar observation as a vector of one): act through the
    # same view, else a Discrete(3, start=-1) environment gets SB3's ids 0..2 as its own
    views = [numeric] if joint is numeric else [numeric, joint]
    for view in views:
        plain = sb3_spaces(view)
        try:
            model = load_policy(path, plain)
            break
        except ModelError:
            if view is views[-1]:
                raise
    shown = plain.observation if isinstance(plain, SB3Spaces) else (lambda o: o)
    to_view = plain.action if isinstance(plain, SB3Spaces) else (lambda a: a)
    to_env = view.action if view is not numeric else (lambda a: a)

    def act(o: Any) -> Any:
        action, _ = model.predict(shown(observe(o)), deterministic=not stochastic)
        # SB3's MultiBinary actions are floats: the environment gets its own dtype
        return env_action(env.action_space, to_env(to_view(predicted_action(action))))

    return act


def run(args: argparse.Namespace, out) -> None:
    import numpy as np

    from symlearn.cli.env_errors import environment_file, raised_by_environment
    from symlearn.cli.flag_values import whole
    from symlearn.data import record
    from symlearn.data.recording import UnstorableObservations
    from symlearn.errors import SymlearnError
    from symlearn.recipes.environments import resolve_env
    from symlearn.recipes.spaces import numeric_observations, refuse_variable_size

    episodes = whole("--episodes", args.episodes, 1, MAX_EPISODES)
    max_steps = None if args.max_steps is None else whole("--max-steps", args.max_steps, 1, MAX_EPISODE_STEPS)
    if not str(args.output).endswith((".npz", ".jsonl")):
        raise SymlearnError(f"cannot tell the format of {args.output}: write a .npz or .jsonl file",
                            hint="-o demos.npz (numeric states) or -o demos.jsonl")
    seed = getattr(args, "seed", 0) or 0
    target = resolve_env(args.env, kwargs=args.env_kwargs)
    costs = _EpisodeCost()
    env = costs.wrap(target.make())
    shape = getattr(env.observation_space, "shape", None)
    from gymnasium import spaces

    refuse_variable_size(env.observation_space, target.display)   # before the episodes are run
    if str(args.output).endswith(".jsonl") and isinstance(env.observation_space, spaces.Box) and len(shape) >= 2:
        # before the episodes are run: JSONL holds no arrays of 2 or more dimensions per step
        raise SymlearnError(f"{args.output}: {target.display} observes arrays of shape {tuple(shape)}, which JSONL "
                            "cannot hold", hint=f"write {Path(args.output).with_suffix('.npz')}")
    # 'random' as record() takes it; a file of that name is a model's (random.safetensors)
    policy = "random" if args.policy == "random" else _policy(args.policy, env, args.stochastic, seed)
    metadata = {"policy": str(args.policy), "stochastic": bool(args.stochastic)}
    kept = None
    if getattr(args, "states", "observations") == "features":
        names = target.feature_names(env)
        if names is None:
            raise SymlearnError(f"--states features: {target.display} names no features",
                                hint="give it feature_names, or report info[\"features\"] as a dict of named numbers")
        kept = _Features()
        env = kept.wrap(env)
        metadata.update(states="features", feature_names=list(names))
    with raised_by_environment(None if target.bundled else environment_file(env), f"recording in {target.display}"):
        try:
            demos = record(env, policy, episodes, seed=seed, max_steps=max_steps, metadata=metadata,
                           observation=None if kept is None else kept.stored)
        except UnstorableObservations as exc:
            # an image inside a Dict (MiniGrid's): keep the numeric view the policy reads instead,
            # what docs/FORMATS.md tells a Python user to record
            view = numeric_observations(env)
            if view is env:
                raise
            note = f"{exc.message}; stored the numeric view the policy reads ({len(view.column_names)} columns)"
            if view.dropped:
                note += f", without {', '.join(view.dropped)}"
            metadata["observation_view"] = "numeric"
            metadata["feature_names"] = list(view.column_names)
            costs.totals.clear()
            demos = record(env, policy, episodes, seed=seed, max_steps=max_steps, observation=view.observation,
                           metadata=metadata)
            out.note(f"note: {note}")
    env.close()
    demos.save(args.output)
    returns = [float(np.sum(t.rewards)) if t.rewards is not None else 0.0 for t in demos]
    doc = {"env": args.env, "policy": str(args.policy), "episodes": len(demos),
           "steps": int(sum(len(t.actions) for t in demos)), "return": float(np.mean(returns)),
           "cost": float(np.mean(costs.totals[:len(demos)])) if costs.seen else None, "files": [str(args.output)]}
    out.result(doc, _render)


def _render(doc: dict) -> str:
    cost = "n/a" if doc["cost"] is None else f"{doc['cost']:.3g}"
    return (f"{doc['env']}: {doc['episodes']} episodes, {doc['steps']} steps of {doc['policy']}; "
            f"return {doc['return']:.4g}, true cost {cost} per episode\nwrote {doc['files'][0]}")


__all__ = ["register", "run"]
