"""One PPO update from a collected rollout: GAE advantages for the reward and every cost
(:func:`_gae`), the running scales of their returns (:class:`_ReturnScales`), the Lagrangian's
mixed advantage, then the clipped-surrogate epochs over minibatches (:func:`_update`); with
``normalize_values`` the critics' output layers follow the scales (:func:`_rescale_critics`). The
rationale of the mix, the scales and the normalisation is the package docstring's
(:mod:`symlearn.rl.ppo`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.rl.ppo.config import LagrangianConfig, PPOConfig
from symlearn.rl.ppo.networks import ActorCritic
from symlearn.rl.ppo.rollouts import RolloutBatch

RETURN_SCALE_MEMORY = 0.9  # per iteration, for the running standard deviation of each signal's returns
RETURN_SCALE_FLOOR = 1e-2  # a signal's scale never drops below this share of the largest it had


class _ReturnScales:
    """The running standard deviation of each signal's returns (reward, then every cost): an
    exponential average over iterations (memory :data:`RETURN_SCALE_MEMORY`), never below
    :data:`RETURN_SCALE_FLOOR` times the largest value it reached, so a constraint the agent stopped
    breaking keeps a finite scale; a signal whose returns never varied has scale 1. The reward's
    scale in the Lagrangian's mix (:meth:`mix_scales`, not the critics' unit) is floored at
    ``reward_floor`` times its largest value instead (``LagrangianConfig.reward_scale_floor``)."""

    def __init__(self, reward_floor: float = RETURN_SCALE_FLOOR, cost_floor: float = RETURN_SCALE_FLOOR) -> None:
        self.values: np.ndarray | None = None
        self.peak: np.ndarray | None = None
        self.reward_floor = float(reward_floor)
        self.cost_floor = float(cost_floor)

    def update(self, returns: np.ndarray) -> np.ndarray:
        now = np.asarray(returns, dtype=np.float64).std(axis=0)
        if self.values is None or self.values.shape != now.shape:
            self.values, self.peak = now.copy(), now.copy()
        else:
            self.values = RETURN_SCALE_MEMORY * self.values + (1 - RETURN_SCALE_MEMORY) * now
            self.peak = np.maximum(self.peak, self.values)
        return self.scales()

    def scales(self) -> np.ndarray:
        if self.values is None:
            return np.zeros(0)
        return np.where(self.peak > 0, np.maximum(self.values, RETURN_SCALE_FLOOR * self.peak), 1.0)

    def mix_scales(self) -> np.ndarray:
        """:meth:`scales` with the reward's floored at ``reward_floor`` of its largest value and each
        cost's at ``cost_floor`` of its own: the units the Lagrangian's advantages are mixed in."""
        scales = self.scales()
        if scales.size and self.peak[0] > 0:
            scales[0] = max(scales[0], self.reward_floor * self.peak[0])
        if scales.size > 1:
            costs = self.peak[1:] > 0
            scales[1:][costs] = np.maximum(scales[1:][costs], self.cost_floor * self.peak[1:][costs])
        return scales



def _gae(rewards: np.ndarray, values: np.ndarray, last_values: np.ndarray, dones: np.ndarray,
         gamma: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray]:
    """Generalised advantage estimation for ``C`` signals at once (reward and costs):
    ``rewards``/``values`` ``(T, N, C)``, ``last_values`` ``(N, C)``, ``dones`` ``(T, N)`` (the
    episode ended at step t), ``gamma`` ``(C,)``. Returns advantages and returns ``(T, N, C)``."""
    advantages = np.zeros_like(rewards)
    running = np.zeros_like(last_values)
    for t in reversed(range(len(rewards))):
        next_values = last_values if t == len(rewards) - 1 else values[t + 1]
        alive = (1.0 - dones[t])[:, None]
        delta = rewards[t] + gamma * next_values * alive - values[t]
        running = delta + gamma * lam * alive * running
        advantages[t] = running
    return advantages, advantages + values


def _update(agent: ActorCritic, optimizer: torch.optim.Optimizer, cost_optimizer: torch.optim.Optimizer | None,
            data: RolloutBatch, config: PPOConfig, lagrangian: LagrangianConfig | None, lambdas: np.ndarray,
            rng: np.random.Generator, device: torch.device, return_scales: _ReturnScales | None = None,
            critics_in_returns: bool = False) -> dict[str, Any]:
    """Advantages for the rollout, then the clipped-surrogate epochs. Returns the diagnostics."""
    T, N = data.rewards.shape
    n_costs = agent.n_costs if lagrangian is not None else 0
    as_tensor = lambda x: torch.as_tensor(x, device=device)  # noqa: E731
    obs = as_tensor(data.obs.reshape(T * N, -1))
    actions = as_tensor(data.actions.reshape(T * N, *data.actions.shape[2:]))

    signals = np.concatenate([data.rewards[..., None], data.costs[..., :n_costs]], axis=2)
    cost_gamma = config.gamma if lagrangian is None or lagrangian.cost_gamma is None else lagrangian.cost_gamma
    gamma = np.array([config.gamma] + [cost_gamma] * n_costs)
    # the critics' output unit (normalize_values: the running scale of each signal's returns, else 1)
    n_signals = 1 + n_costs
    old_scales = np.ones(n_signals)
    if config.normalize_values and return_scales is not None:
        if return_scales.scales().shape != (n_signals,):  # first update: scales of the returns without critics
            zeros = np.zeros_like(signals)
            return_scales.update(_gae(signals, zeros, zeros[0], data.dones, gamma, 1.0)[1].reshape(T * N, -1))
        old_scales = return_scales.scales()
        if critics_in_returns:  # a continued policy's critics output returns: put them in the new unit
            _rescale_critics(agent, n_costs, 1.0 / old_scales)
    unit = as_tensor(old_scales.astype(np.float32))

    # values, cost values and old log-probabilities of the whole rollout in one pass each
    with torch.no_grad():
        def signal_values(x: torch.Tensor) -> torch.Tensor:
            return torch.cat([agent.value(x)[:, None], agent.cost_values(x)[:, :n_costs]], 1) * unit

        values = signal_values(obs).double().cpu().numpy().reshape(T, N, 1 + n_costs)
        last_values = signal_values(as_tensor(data.last_obs)).double().cpu().numpy()
        old_log_prob, _ = agent.log_prob_entropy(obs, actions)
        if config.entropy_mode == "reward":  # soft return: the entropy of every later step counts too
            signals[..., 0] -= config.ent_coef * old_log_prob.double().cpu().numpy().reshape(T, N)
        if data.truncated:  # a time limit is not a terminal state: bootstrap with its value
            ts, envs, last = zip(*data.truncated)
            final = signal_values(as_tensor(np.stack(last))).double().cpu().numpy()
            signals[list(ts), list(envs)] += gamma * final
    advantages, returns = _gae(signals, values, last_values, data.dones, gamma, config.gae_lambda)
    advantages, returns = advantages.reshape(T * N, -1), returns.reshape(T * N, -1)

    scales = np.zeros(0)
    if return_scales is not None and (lagrangian is not None or config.normalize_values):
        scales = return_scales.update(returns)
    targets = returns
    if config.normalize_values:  # new unit: rescale the critics' last layers so their values stay put
        _rescale_critics(agent, n_costs, old_scales / scales)
        targets = returns / scales
    # the Lagrangian's advantage (the docstring of symlearn.rl.ppo); lambda = 0 is plain PPO
    mixed = advantages
    if lagrangian is not None and lagrangian.advantage_scale == "returns":  # in standard deviations of returns
        mixed = advantages / return_scales.mix_scales()
    policy_adv = (mixed[:, 0] - mixed[:, 1:1 + len(lambdas)] @ lambdas) / (1.0 + lambdas.sum())
    policy_adv_t = as_tensor(policy_adv.astype(np.float32))
    returns_t = as_tensor(targets.astype(np.float32))

    main_params = [p for group in optimizer.param_groups for p in group["params"]]
    sums = {"policy_loss": 0.0, "value_loss": 0.0, "entropy": 0.0, "approx_kl": 0.0, "clip_fraction": 0.0}
    cost_loss_sum = np.zeros(n_costs)
    n_updates, stopped_early, minibatches_per_epoch = 0, False, -(-(T * N) // config.batch_size)
    bonus = config.ent_coef if config.entropy_mode == "bonus" else 0.0  # "reward": in the returns already
    for _epoch in range(config.n_epochs):
        order = torch.as_tensor(rng.permutation(T * N), device=device)
        for start in range(0, T * N, config.batch_size):
            idx = order[start:start + config.batch_size]
            log_prob, entropy = agent.log_prob_entropy(obs[idx], actions[idx])
            log_ratio = log_prob - old_log_prob[idx]
            ratio = log_ratio.exp()
            with torch.no_grad():
                approx_kl = float(((ratio - 1) - log_ratio).mean())  # the k3 estimator (Schulman's blog)
            if config.target_kl is not None and approx_kl > 1.5 * config.target_kl:
                stopped_early = True
                break
            adv = policy_adv_t[idx]
            if config.normalize_advantage and len(idx) > 1:
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
            clipped = ratio.clamp(1 - config.clip_range, 1 + config.clip_range)
            policy_loss = -torch.min(adv * ratio, adv * clipped).mean()
            value_loss = (agent.value(obs[idx]) - returns_t[idx, 0]).pow(2).mean()
            entropy_mean = entropy.mean()
            loss = policy_loss - bonus * entropy_mean + config.vf_coef * value_loss
            optimizer.zero_grad(set_to_none=True)
            loss.backward()
            nn.utils.clip_grad_norm_(main_params, config.max_grad_norm)
            optimizer.step()
            if n_costs:
                cost_losses = (agent.cost_values(obs[idx]) - returns_t[idx, 1:]).pow(2).mean(0)
                cost_optimizer.zero_grad(set_to_none=True)
                cost_losses.sum().backward()
                nn.utils.clip_grad_norm_(agent.cost_critics.parameters(), config.max_grad_norm)
                cost_optimizer.step()
                cost_loss_sum += cost_losses.detach().cpu().numpy()
            n_updates += 1
            sums["policy_loss"] += policy_loss.item()
            sums["value_loss"] += value_loss.item()
            sums["entropy"] += entropy_mean.item()
            sums["approx_kl"] += approx_kl
            sums["clip_fraction"] += float(((ratio - 1).abs() > config.clip_range).float().mean())
        if stopped_early:
            break
    means = {k: v / n_updates if n_updates else math.nan for k, v in sums.items()}
    variance = np.var(returns[:, 0])
    residual = returns[:, 0] - values.reshape(T * N, -1)[:, 0]
    explained = math.nan if variance == 0 else float(1 - np.var(residual) / variance)
    return {**means, "cost_value_loss": tuple(float(x) for x in cost_loss_sum / max(n_updates, 1)),
            "return_scales": tuple(float(x) for x in scales),
            "explained_variance": explained, "epochs": n_updates / minibatches_per_epoch,
            "stopped_early": stopped_early}


def _rescale_critics(agent: ActorCritic, n_costs: int, factors: np.ndarray) -> None:
    """Multiply the output layer of the reward critic (``factors[0]``) and of each cost critic by a
    factor: the outputs scale by it (how PopArt keeps a critic's values when their unit changes)."""
    critics = [agent.critic, *list(agent.cost_critics)[:n_costs]]
    with torch.no_grad():
        for critic, factor in zip(critics, factors):
            if factor != 1.0:
                last = critic[-1]
                last.weight.mul_(float(factor))
                last.bias.mul_(float(factor))

