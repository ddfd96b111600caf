"""Whole episodes of a policy as padded arrays, and demonstrations read into the same form.

ICRL compares feature expectations of a policy and of the expert over whole episodes from
their start (discounted sums ``sum_t gamma^t phi(s_t, a_t)``), and its metrics
(:mod:`~symlearn.rl.episode_metrics`) are per episode too; both need episodes as arrays
``[E, T, ...]`` with a mask of the steps that happened. :func:`sample_episodes` steps ``E``
environments side by side with one batched policy call per step; :func:`demonstration_batch`
reads :class:`~symlearn.data.Demonstrations` into an :class:`EpisodeBatch` (the state-action
pairs: every state in which an action was taken). It lives in ``rl`` (it needs only a policy
and environments) so that the PPO-Lagrangian expert (:mod:`~symlearn.rl.lagrangian_expert`)
records its demonstrations with it as the neural ICRL learners sample theirs.

Not the evaluation loop (:func:`symlearn.rl.evaluation.run_episodes`): that one plays episodes
one after another and keeps only their sums (one environment, any length); this one keeps every
step of ``E`` episodes at once, as feature expectations need, and its batched sampling draws
other random numbers than one action at a time would.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError
from symlearn.rl.episode_stats import summed_cost


@dataclass(frozen=True)
class EpisodeBatch:
    """``E`` episodes padded to the longest, ``T`` steps: ``obs`` ``[E, T, ...]`` (the state each
    step started in), ``actions`` ``[E, T, ...]`` (a Discrete action as the space's id, as in
    demonstrations), ``rewards`` and ``costs`` ``[E, T]``
    (``costs``: the environment's ``info["cost"]``, summed over constraints; 0 where unknown),
    ``mask`` ``[E, T]`` (True for steps that happened)."""

    obs: np.ndarray
    actions: np.ndarray
    rewards: np.ndarray
    costs: np.ndarray
    mask: np.ndarray

    @property
    def n_episodes(self) -> int:
        return int(self.mask.shape[0])

    @property
    def lengths(self) -> np.ndarray:
        return self.mask.sum(axis=1)

    def pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """The steps that happened, flattened: ``obs`` ``(n, ...)``, ``actions`` ``(n, ...)``."""
        return self.obs[self.mask], self.actions[self.mask]

    def discount_weights(self, gamma: float) -> np.ndarray:
        """``[E, T]``: ``gamma^t / E`` on the steps that happened, 0 elsewhere; a sum of
        ``weights * f(s_t, a_t)`` is the mean discounted episode sum of ``f``."""
        t = np.arange(self.mask.shape[1])
        return np.where(self.mask, gamma ** t[None, :], 0.0) / max(self.n_episodes, 1)


Policy = Callable[[np.ndarray, np.random.Generator], Any]


def policy_actions(policy: Any, deterministic: bool) -> Policy:
    """A batched ``(observations, rng) -> actions`` from an
    :class:`~symlearn.rl.ppo.ActorCritic` (the actions learned from: continuous ones before
    clipping, as PPO records them) or from such a callable."""
    if callable(policy) and not hasattr(policy, "numpy_actor"):
        return policy
    actor = policy.numpy_actor()

    def act(obs: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        x = policy.encode(obs)
        return actor.mode(x) if deterministic else actor.sample(x, rng)
    return act


def sample_episodes(policy: Any, env_fn: Callable[[], Any], n_episodes: int, *, seed: int | None = 0,
                    deterministic: bool = False, max_steps: int = 10_000) -> EpisodeBatch:
    """``n_episodes`` episodes of ``policy``, environment ``i`` reset with ``seed + i``; each
    runs until it terminates or is truncated (at most ``max_steps``)."""
    if n_episodes < 1:
        raise DataError(f"n_episodes must be at least 1, got {n_episodes}")
    envs = [env_fn() for _ in range(n_episodes)]
    rng = np.random.default_rng(seed)
    act = policy_actions(policy, deterministic)
    to_env = getattr(policy, "env_action", None) or (lambda a: a)
    # a Discrete action is kept as the environment's id (``start`` added), as demonstrations hold it;
    # a continuous one as learned from (before clipping)
    start = int(policy.action_spec.get("start", 0)) if getattr(policy, "discrete", False) else 0
    recorded = (lambda a: a + start) if start else (lambda a: a)
    current = np.stack([np.asarray(env.reset(seed=None if seed is None else seed + i)[0])
                        for i, env in enumerate(envs)])
    alive = np.ones(n_episodes, dtype=bool)
    rows: dict[str, list[np.ndarray]] = {"obs": [], "actions": [], "rewards": [], "costs": [], "mask": []}
    for t in range(max_steps):
        if not alive.any():
            break
        actions = np.asarray(act(current, rng))
        rewards, costs = np.zeros(n_episodes), np.zeros(n_episodes)
        following = current.copy()
        taken = alive.copy()  # this round's step happened for the episodes still running
        for i in np.flatnonzero(alive):
            o, r, term, trunc, info = envs[i].step(to_env(actions[i]))
            rewards[i] = r
            costs[i] = summed_cost(info, where=lambda: f"sampled episode {i}, step {t}") or 0.0
            following[i] = np.asarray(o)
            if term or trunc:
                alive[i] = False
        for key, value in (("obs", current), ("actions", recorded(actions)), ("rewards", rewards), ("costs", costs),
                           ("mask", taken)):
            rows[key].append(value)
        current = following
    for env in envs:
        env.close()
    return EpisodeBatch(**{key: np.stack(value, axis=1) for key, value in rows.items()})


def demonstration_batch(demonstrations: Any) -> EpisodeBatch:
    """Demonstrations as an :class:`EpisodeBatch` of their state-action pairs (a trajectory's
    last state, where no action was taken, is left out). Rewards missing: 0; costs: 0 (the
    expert's costs are not known to a learner)."""
    episodes = list(demonstrations)
    if not episodes:
        raise DataError("no demonstrations")
    if any(t.actions is None or len(t.actions) == 0 for t in episodes):
        raise DataError("every demonstration needs actions (state-action pairs)",
                        hint="record the expert's actions with the states")
    lengths = [len(t.actions) for t in episodes]
    T = max(lengths)
    first_obs = np.asarray(episodes[0].states[0])
    first_act = np.asarray(episodes[0].actions[0])
    obs = np.zeros((len(episodes), T, *first_obs.shape), dtype=np.float64 if first_obs.dtype.kind == "f"
                   else first_obs.dtype)
    actions = np.zeros((len(episodes), T, *first_act.shape), dtype=first_act.dtype)
    rewards = np.zeros((len(episodes), T))
    mask = np.zeros((len(episodes), T), dtype=bool)
    for e, t in enumerate(episodes):
        n = lengths[e]
        obs[e, :n] = np.asarray(t.states)[:n]
        actions[e, :n] = np.asarray(t.actions)[:n]
        if t.rewards is not None:
            rewards[e, :n] = np.asarray(t.rewards)[:n]
        mask[e, :n] = True
    return EpisodeBatch(obs, actions, rewards, np.zeros_like(rewards), mask)


__all__ = ["EpisodeBatch", "demonstration_batch", "policy_actions", "sample_episodes"]
