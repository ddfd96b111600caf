"""The training loop: :func:`train_ppo` makes the environments and the networks, then alternates
collecting a rollout (:mod:`~symlearn.rl.ppo.rollouts`), updating the multipliers from its cost
estimate (:class:`~symlearn.rl.ppo.multipliers.Multipliers`) and the PPO update
(:mod:`~symlearn.rl.ppo.update`), recording a :class:`~symlearn.rl.ppo.records.PPOIteration` each
iteration.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import torch

from symlearn.errors import DataError, SymlearnError
from symlearn.progress import ProgressBar
from symlearn.rl.episode_stats import CostReader, NoCostReported, episode_costs
from symlearn.rl.ppo.config import LagrangianConfig, PPOConfig
from symlearn.rl.ppo.multipliers import Multipliers
from symlearn.rl.ppo.networks import ActorCritic, _space_spec
from symlearn.rl.ppo.records import PPOIteration, PPOResult
from symlearn.rl.ppo.rollouts import Rollout, _info_keys, _Rollouts, _signal
from symlearn.rl.ppo.stall import LagrangianStall
from symlearn.rl.ppo.update import _ReturnScales, _rescale_critics, _update


def train_ppo(
    env_fn: Callable[[], Any] | str,
    total_steps: int,
    config: PPOConfig | None = None,
    lagrangian: LagrangianConfig | None = None,
    callback: Callable[[PPOIteration, ActorCritic], bool | None] | None = None,
    *,
    reward_fn: Callable[[Rollout], Any] | None = None,
    cost_fn: Callable[[Rollout], Any] | None = None,
    policy: ActorCritic | None = None,
) -> PPOResult:
    """Train PPO (or PPO-Lagrangian) for at least ``total_steps`` environment steps.

    ``env_fn`` returns a fresh environment (it is called ``n_envs`` times) or is a gymnasium id.
    ``callback(record, policy)`` runs after every iteration; returning ``False`` stops training.

    ``reward_fn(rollout)`` and ``cost_fn(rollout)`` see each iteration's :class:`Rollout` once,
    after it was collected, and return the rewards to learn from (``[T, N]``; the episode returns
    reported stay the environment's) and the costs (``[T, N]`` or ``[T, N, k]``, instead of
    ``info["cost"]``): a learned reward or cost is then one vectorised evaluation per rollout,
    not a call per step. Info keys they need are named in their ``info_keys`` attribute.
    ``policy`` continues training an existing :class:`ActorCritic` (same spaces) in place.
    """
    config = config or PPOConfig()
    if isinstance(policy, ActorCritic) and config.normalize_observations is None:
        # a continued policy keeps its own inputs (a nominal PPO phase, then a Lagrangian one)
        config = replace(config, normalize_observations=policy.obs_normalization)
    config = config.resolved()
    if not isinstance(total_steps, (int, np.integer)) or total_steps < 1:
        raise SymlearnError(f"total_steps must be a positive integer, got {total_steps!r}")
    for name, fn in (("reward_fn", reward_fn), ("cost_fn", cost_fn)):
        if fn is not None and not callable(fn):
            raise SymlearnError(f"{name} must be callable, got {fn!r}")
    if policy is not None and not isinstance(policy, ActorCritic):
        raise SymlearnError(f"policy must be an ActorCritic, got {type(policy).__name__}")
    envs = _make_envs(env_fn, config.n_envs)
    previous_threads = torch.get_num_threads()
    try:
        if config.torch_threads is not None:
            torch.set_num_threads(config.torch_threads)
        return _train(envs, int(total_steps), config, lagrangian, callback, reward_fn, cost_fn, policy)
    finally:
        torch.set_num_threads(previous_threads)
        for env in envs:
            env.close()


def _train(envs: list[Any], total_steps: int, config: PPOConfig, lagrangian: LagrangianConfig | None,
           callback: Callable[[PPOIteration, ActorCritic], bool | None] | None,
           reward_fn: Callable[[Rollout], Any] | None = None, cost_fn: Callable[[Rollout], Any] | None = None,
           policy: ActorCritic | None = None) -> PPOResult:
    started = time.perf_counter()
    seed = config.seed
    rng = np.random.default_rng(seed)
    generator = torch.Generator().manual_seed(seed if seed is not None else int(rng.integers(2**62)))
    device = torch.device(config.device)
    if policy is None:
        agent = ActorCritic.for_spaces(envs[0].observation_space, envs[0].action_space,
                                       hidden_sizes=config.hidden_sizes, activation=config.activation,
                                       log_std_init=config.log_std_init, generator=generator,
                                       obs_normalization=config.normalize_observations)
    else:
        agent = _continued(policy, envs[0], config)
    costs = CostReader(None if lagrangian is None else lagrangian.n_constraints)
    if policy is not None and lagrangian is not None and agent.n_costs:
        if costs.n is not None and costs.n != agent.n_costs:
            raise SymlearnError(f"the policy has {agent.n_costs} cost critic(s) but the cost limits name {costs.n}")
        costs.n = agent.n_costs
    elif lagrangian is not None and costs.n is not None:
        agent.add_cost_critics(costs.n, generator)
    agent.to(device)
    main_params = [p for name, p in agent.named_parameters() if not name.startswith("cost_critics.")]
    # foreach=True: one pass over all parameter tensors per Adam step (torch picks the per-tensor loop
    # on CPU by default); about 20 % faster for networks this small
    optimizer = torch.optim.Adam(main_params, lr=config.learning_rate, eps=1e-5, foreach=True)
    cost_optimizer = None if not agent.n_costs else \
        torch.optim.Adam(agent.cost_critics.parameters(), lr=config.learning_rate, eps=1e-5, foreach=True)
    multipliers = None
    step_peak = 0.0  # the largest cost of one step seen so far, per constraint
    stall: LagrangianStall | None = None
    kept: tuple[list[torch.Tensor], list[dict]] | None = None   # the actor a stall reset replaced, on trial
    return_scales = _ReturnScales() if lagrangian is None else _ReturnScales(lagrangian.reward_scale_floor,
                                                                                    lagrangian.cost_scale_floor)
    rollouts = _Rollouts(envs, agent, costs, seed, _info_keys(reward_fn, cost_fn), read_costs=cost_fn is None)
    fresh_critics = policy is not None  # their outputs are in returns, not yet in the running scales
    batch = config.n_envs * config.n_steps
    n_iterations = -(-total_steps // batch)
    history: list[PPOIteration] = []
    desc = "PPO-Lagrangian" if lagrangian is not None else "PPO"
    bar = ProgressBar(n_iterations, desc=desc, unit="iter")
    with bar:
        for iteration in range(1, n_iterations + 1):
            iteration_start = time.perf_counter()
            lr = config.learning_rate * (1.0 - (iteration - 1) / n_iterations if config.anneal_lr else 1.0)
            for opt in (optimizer, cost_optimizer):
                for group in (opt.param_groups if opt is not None else ()):
                    group["lr"] = lr

            data = rollouts.collect(config.n_steps, agent.numpy_actor(), rng, cost_fn)
            if reward_fn is not None:  # the agent learns from these; the episode returns stay the environment's
                learned = _signal(reward_fn(data.rollout), "reward_fn", data.rewards.shape)
                if learned.ndim != 2:
                    raise DataError(f"reward_fn returned shape {learned.shape}; expected {data.rewards.shape}")
                data = replace(data, rewards=learned)
            if agent.obs_normalization:  # this rollout joins the statistics, then is learned from with them
                agent.update_observation_stats(data.obs.reshape(-1, agent.obs_dim))
                data = replace(data, obs=agent.normalize(data.obs), last_obs=agent.normalize(data.last_obs),
                               truncated=tuple((t, i, agent.normalize(x)) for t, i, x in data.truncated))
            n_costs = costs.n or 0
            if lagrangian is not None:
                if not costs.seen:  # decided from the steps of the first rollout, not from the first step
                    raise NoCostReported("PPO-Lagrangian got no info['cost'] in its first rollout "
                                         f"({batch} steps)", steps=batch,
                                         hint="report info['cost'] on the steps that pay it (a step without "
                                              "it costs 0), or give a cost_fn, e.g. from symlearn.backends.cost")
                if agent.n_costs == 0:  # a scalar limit: the first rollout told how many constraints there are
                    new_params = agent.add_cost_critics(n_costs, generator)
                    cost_optimizer = torch.optim.Adam(new_params, lr=lr, eps=1e-5, foreach=True)
                    agent.cost_critics.to(device)
                if multipliers is None:
                    multipliers = Multipliers(lagrangian, n_costs)
                    if lagrangian.reset_actor == "auto":
                        stall = LagrangianStall(n_iterations, multipliers.limits)
            episodes = data.episodes
            mean_return = float(np.mean([e.episode_return for e in episodes])) if episodes else math.nan
            mean_cost = episode_costs(episodes, n_costs).mean(axis=0) if episodes else np.full(n_costs, np.nan)
            estimate = None
            if multipliers is not None:
                if lagrangian.cost_estimate == "rollout":
                    estimate = rollouts.cost_estimate(data.costs)
                elif episodes:
                    estimate = mean_cost
                if estimate is not None:
                    # one step at the largest step cost seen: the unit of LagrangianConfig.zero_limit_slack
                    step_peak = np.maximum(step_peak, data.costs.reshape(-1, n_costs).max(axis=0))
                    multipliers.update(estimate, step_peak)
            lambdas = multipliers.values.copy() if multipliers is not None else np.zeros(0)
            verdict = None if stall is None else stall.update(
                iteration, estimate, lambdas, mean_return,
                return_scales.mix_scales() if lagrangian.advantage_scale == "returns" else None)
            if verdict == "reset":   # stuck over the limit under a rising price: learn again at that price
                kept = _actor_state(agent, optimizer)
                agent.reset_actor(generator)
                for parameter in agent.actor_parameters():
                    optimizer.state.pop(parameter, None)
            elif verdict == "restore":   # the fresh actor did worse by the Lagrangian: the old one back
                _restore_actor(agent, optimizer, kept)
                kept = None

            stats = _update(agent, optimizer, cost_optimizer, data, config, lagrangian, lambdas, rng, device,
                            return_scales, fresh_critics)
            fresh_critics = False
            seconds = time.perf_counter() - iteration_start
            record = PPOIteration(
                iteration=iteration, steps=rollouts.steps, episodes=len(episodes),
                mean_return=mean_return,
                mean_length=float(np.mean([e.length for e in episodes])) if episodes else math.nan,
                mean_cost=tuple(float(c) for c in mean_cost), multipliers=tuple(float(x) for x in lambdas),
                cost_estimate=() if estimate is None else tuple(float(c) for c in estimate),
                true_cost=rollouts.true_cost_estimate(data.true_costs), actor_reset=verdict == "reset",
                actor_restored=verdict == "restore",
                learning_rate=lr, steps_per_second=batch / seconds, seconds=seconds, **stats)
            history.append(record)
            bar.update(1, **{"return": record.mean_return, "cost": float(np.sum(record.mean_cost))
                             if record.mean_cost else None, "lambda": float(np.max(lambdas)) if lambdas.size else None})
            if callback is not None and callback(record, agent) is False:
                break
    agent.eval()
    n_costs = costs.n or 0
    if config.normalize_values and return_scales.values is not None:  # the critics output returns again
        _rescale_critics(agent, n_costs if lagrangian is not None else 0, return_scales.scales())
    return PPOResult(policy=agent, config=config, lagrangian=lagrangian, history=history,
                     episodes=rollouts.episode_stats(n_costs),
                     multipliers=np.zeros(0) if multipliers is None else multipliers.values.copy(),
                     steps=rollouts.steps, seconds=time.perf_counter() - started,
                     provenance={"environment": _env_name(envs[0]), "torch": torch.__version__})


def _actor_state(agent: ActorCritic, optimizer: torch.optim.Optimizer) -> tuple[list[torch.Tensor], list[dict]]:
    """Copies of the actor's parameters and of their Adam moments."""
    import copy

    parameters = agent.actor_parameters()
    return ([p.detach().clone() for p in parameters], [copy.deepcopy(optimizer.state.get(p, {})) for p in parameters])


def _restore_actor(agent: ActorCritic, optimizer: torch.optim.Optimizer,
                   kept: tuple[list[torch.Tensor], list[dict]] | None) -> None:
    if kept is None:
        return
    values, states = kept
    with torch.no_grad():
        for parameter, value, state in zip(agent.actor_parameters(), values, states, strict=True):
            parameter.copy_(value)
            if state:
                optimizer.state[parameter] = state
            else:
                optimizer.state.pop(parameter, None)


def _continued(policy: ActorCritic, env: Any, config: PPOConfig) -> ActorCritic:
    """``policy`` checked against the environment's spaces before training goes on with it."""
    want_obs = _space_spec(env.observation_space, "observation")
    want_act = _space_spec(env.action_space, "action")
    if policy.observation_spec != want_obs or policy.action_spec != want_act:
        raise SymlearnError("the policy was made for other spaces than this environment's",
                            hint=f"policy: observation {policy.observation_spec}, action {policy.action_spec}; "
                                 f"environment: observation {want_obs}, action {want_act}")
    if policy.obs_normalization != config.normalize_observations:
        raise SymlearnError(f"the policy {'has' if policy.obs_normalization else 'has no'} observation "
                            f"normalisation but PPOConfig.normalize_observations={config.normalize_observations}")
    policy.train()
    return policy


def _env_name(env: Any) -> str:
    spec = getattr(env, "spec", None)
    return getattr(spec, "id", None) or type(getattr(env, "unwrapped", env)).__name__



def _make_envs(env_fn: Callable[[], Any] | str, n: int) -> list[Any]:
    if isinstance(env_fn, str):
        import gymnasium

        env_id = env_fn
        env_fn = lambda: gymnasium.make(env_id)  # noqa: E731
    if not callable(env_fn):
        raise SymlearnError(f"env_fn must be a gymnasium id or a function returning an environment, got {env_fn!r}")
    return [env_fn() for _ in range(n)]

