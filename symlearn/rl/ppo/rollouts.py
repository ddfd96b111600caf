"""Collecting experience: ``n_envs`` environments stepped in turn, each reset as soon as its
episode ends (:class:`_Rollouts`), the ``info["cost"]`` they report and the finished episodes
(read and counted by :mod:`symlearn.rl.episode_stats`, as evaluation does; episodes are carried
over from one rollout to the next), and what one iteration's steps become: a :class:`Rollout` for the ``reward_fn``/``cost_fn``
hooks and a :class:`RolloutBatch` for the update. Why a plain list of environments and a numpy
actor: the package docstring (:mod:`symlearn.rl.ppo`, "Speed").
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import DataError, SymlearnError
from symlearn.rl.episode_stats import CostReader, EpisodeStats, FinishedEpisode, episode_stats
from symlearn.rl.ppo.networks import ActorCritic, NumpyActor

LENGTH_MEMORY = 100  # finished episodes whose mean length turns a rollout's cost rate into J_c


@dataclass(frozen=True)
class Rollout:
    """One iteration's steps, as :func:`train_ppo` hands them to ``reward_fn`` / ``cost_fn``.

    Arrays are ``[T, N, ...]`` (``T`` = ``n_steps`` rounds over ``N`` = ``n_envs`` copies):
    ``obs`` the raw observation features of the state each step started in (not normalised),
    ``actions`` the actions learned from (continuous ones before clipping to the bounds),
    ``next_obs`` the state each step reached (the episode's last observation where it ended, not
    the next episode's first), ``rewards`` the environment's, ``dones`` 1 where an episode ended,
    ``info`` one array per key named in the callable's ``info_keys`` attribute.
    """

    obs: np.ndarray
    actions: np.ndarray
    next_obs: np.ndarray
    rewards: np.ndarray
    dones: np.ndarray
    info: dict[str, np.ndarray]


def _info_keys(*fns: Any) -> tuple[str, ...]:
    keys: list[str] = []
    for fn in fns:
        for key in getattr(fn, "info_keys", ()) if fn is not None else ():
            if not isinstance(key, str):
                raise SymlearnError(f"info_keys must be strings, got {key!r}")
            if key not in keys:
                keys.append(key)
    return tuple(keys)


def _signal(value: Any, what: str, shape: tuple[int, int]) -> np.ndarray:
    """``reward_fn``/``cost_fn`` output checked: ``[T, N]`` or ``[T, N, k]``, finite, as float64."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{what} must return an array of numbers, got {type(value).__name__}") from None
    if array.shape[:2] != shape or array.ndim not in (2, 3):
        raise DataError(f"{what} returned shape {array.shape}; expected {shape} or {shape + ('k',)}")
    if not np.isfinite(array).all():
        raise DataError(f"{what} returned NaN or inf")
    return array


def _reported_cost(value: Any) -> float:
    """An ``info["cost"]`` that only gets reported (a learned cost drives training): its sum, NaN
    when it is not numbers -- never an error, since training does not depend on it."""
    try:
        total = float(np.sum(np.asarray(value, dtype=np.float64)))
    except (TypeError, ValueError):
        return math.nan
    return total if math.isfinite(total) else math.nan


@dataclass(frozen=True)
class RolloutBatch:
    """One iteration's steps as :meth:`_Rollouts.collect` returns them and the update learns from
    them. Arrays are ``[T, N, ...]`` as in :class:`Rollout`; :func:`~symlearn.rl.ppo.train_ppo`
    derives new batches from it (``dataclasses.replace``: a ``reward_fn``'s rewards, normalised
    observations)."""

    obs: np.ndarray        # [T, N, obs_dim] features of the state each step started in
    actions: np.ndarray    # [T, N] (Discrete, int64) or [T, N, action_dim] (Box, before clipping)
    rewards: np.ndarray    # [T, N] the rewards learned from
    dones: np.ndarray      # [T, N] 1 where an episode ended
    costs: np.ndarray      # [T, N, k] info["cost"] or cost_fn's (k = 0 before the first cost)
    true_costs: np.ndarray  # [T, N] the environment's info["cost"] summed over constraints; NaN: none
    truncated: tuple[tuple[int, int, np.ndarray], ...]  # (t, env, last observation) of time-limited ends
    last_obs: np.ndarray   # [N, obs_dim] where every copy stands after the last step (to bootstrap)
    rollout: Rollout       # what the reward_fn / cost_fn hooks saw
    episodes: tuple[FinishedEpisode, ...]  # the episodes that ended in this rollout, in step order


class _Rollouts:
    """``n_envs`` environments stepped in turn, each reset as soon as its episode ends."""

    def __init__(self, envs: list[Any], agent: ActorCritic, costs: CostReader, seed: int | None,
                 info_keys: tuple[str, ...] = (), read_costs: bool = True) -> None:
        self.envs, self.agent, self.costs = envs, agent, costs
        self.info_keys, self.read_costs = info_keys, read_costs
        self._shapes: dict[str, tuple[int, ...]] = {}   # per recorded info key, once seen
        first = [env.reset(seed=None if seed is None else seed + i)[0] for i, env in enumerate(envs)]
        self.obs = agent.features(np.stack([np.asarray(o) for o in first]))  # raw features, not normalised
        n = len(envs)
        self.ep_return, self.ep_length = np.zeros(n), np.zeros(n, dtype=np.int64)
        self.ep_cost = np.zeros((n, costs.n or 0))
        self.steps = 0
        self.finished: list[FinishedEpisode] = []
        self.recent_lengths: deque[int] = deque(maxlen=LENGTH_MEMORY)
        spec = getattr(envs[0], "spec", None)
        self.time_limit = getattr(spec, "max_episode_steps", None)  # gymnasium's TimeLimit, when known
        self.reported_seen = False  # an info["cost"] only reported (cost_fn trains) has arrived

    def collect(self, n_steps: int, actor: NumpyActor, rng: np.random.Generator,
                cost_fn: Callable[[Rollout], Any] | None = None) -> RolloutBatch:
        """``n_steps`` rounds of steps. Observations come back as raw :meth:`ActorCritic.features`
        (``obs``, ``next_obs``, ``last_obs`` and the truncated ones); actions are sampled from the
        normalised ones. The costs are every step's ``info["cost"]``, or ``cost_fn``'s verdict on
        the whole rollout at once (one vectorised call instead of one per step)."""
        n_envs, agent = len(self.envs), self.agent
        obs = np.zeros((n_steps, n_envs, agent.obs_dim), dtype=np.float32)
        act_shape = () if agent.discrete else (agent.action_spec["shape"][0],)
        actions = np.zeros((n_steps, n_envs, *act_shape), dtype=np.int64 if agent.discrete else np.float32)
        rewards = np.zeros((n_steps, n_envs))
        dones = np.zeros((n_steps, n_envs))
        reached = np.zeros((n_steps, n_envs, agent.obs_dim), dtype=np.float32)
        costs = np.zeros((n_steps, n_envs, self.costs.n or 0))
        info_arrays: dict[str, np.ndarray] = {}
        self._shapes = {}                 # the arrays are new: their first step takes the slow path
        truncated: list[tuple[int, int, np.ndarray]] = []  # (t, env, last observation) to bootstrap
        ends: list[tuple[int, int]] = []  # (t, env) where an episode ended
        read_costs = self.read_costs
        # with cost_fn, the environment's own info["cost"] (summed) is kept beside it, for reports only
        reported = None if read_costs else np.full((n_steps, n_envs), np.nan)
        unreported = np.zeros((n_steps, n_envs), dtype=bool)  # steps whose info has no "cost"
        for t in range(n_steps):
            obs[t] = self.obs
            actions[t] = actor.sample(agent.normalize(self.obs), rng)
            next_obs = np.empty_like(self.obs)
            for i, env in enumerate(self.envs):
                o, r, term, trunc, info = env.step(agent.env_action(actions[t, i]))
                if not math.isfinite(r):
                    raise DataError(f"the reward is not finite: {r} "
                                    f"(training step {self.steps + t * n_envs + i}, environment copy {i})")
                rewards[t, i] = r
                if read_costs:
                    cost = self.costs.read(info, i, self.steps + t * n_envs + i)
                    if cost is not None:
                        if costs.shape[2] != cost.size:  # the first cost ever: widen the zero-width buffer
                            costs = np.zeros((n_steps, n_envs, cost.size))
                        costs[t, i] = cost
                elif reported is not None:
                    if info.get("cost") is None:
                        unreported[t, i] = True
                    else:
                        reported[t, i] = _reported_cost(info["cost"])
                for key in self.info_keys:
                    self._record(info_arrays, key, info, t, i, n_steps, n_envs)
                reached[t, i] = agent.features(np.asarray(o)[None])[0]
                if not np.isfinite(reached[t, i]).all():
                    raise DataError(f"the observation is not finite (NaN or inf): {np.asarray(o).tolist()} "
                                    f"(training step {self.steps + t * n_envs + i}, environment copy {i})",
                                    hint="an environment must observe finite numbers on every step")
                next_obs[i] = reached[t, i]
                if term or trunc:
                    dones[t, i] = 1.0
                    ends.append((t, i))
                    if trunc and not term:
                        truncated.append((t, i, reached[t, i].copy()))
                    o, _ = env.reset()
                    next_obs[i] = agent.features(np.asarray(o)[None])[0]
            self.obs = next_obs
        rollout = Rollout(obs, actions, reached, rewards, dones, info_arrays)
        if cost_fn is not None:
            costs = _signal(cost_fn(rollout), "cost_fn", (n_steps, n_envs))
            if costs.ndim == 2:
                costs = costs[..., None]
            self.costs.accept(costs.shape[2])
        self._account(rewards, costs, ends, n_steps)
        self.steps += n_steps * n_envs
        if reported is not None:
            # an environment that reports info["cost"] only where it is paid (a step without one
            # costs nothing, as CostReader reads the costs that train): once any step has reported
            # one, the steps without it are 0, not left out of the cost per episode
            self.reported_seen = self.reported_seen or bool((~unreported).any())
            if self.reported_seen:
                reported[unreported] = 0.0
        true_costs = reported if reported is not None else costs.sum(axis=2) if self.costs.seen \
            else np.full((n_steps, n_envs), np.nan)
        return RolloutBatch(obs=obs, actions=actions, rewards=rewards, dones=dones, costs=costs,
                            true_costs=true_costs, truncated=tuple(truncated), last_obs=self.obs.copy(),
                            rollout=rollout, episodes=tuple(self.finished[len(self.finished) - len(ends):]))

    def _record(self, arrays: dict[str, np.ndarray], key: str, info: dict[str, Any], t: int, i: int,
                n_steps: int, n_envs: int) -> None:
        if key not in info:
            raise DataError(f"the environment reports no info[{key!r}] (training step "
                            f"{self.steps + t * n_envs + i}, environment copy {i})",
                            hint="reward_fn/cost_fn name it in info_keys")
        value = np.asarray(info[key])
        if value.shape == self._shapes.get(key):   # every step after the first
            arrays[key][t, i] = value
            return
        if key not in arrays:
            arrays[key] = np.zeros((n_steps, n_envs, *value.shape),
                                   dtype=np.float64 if value.dtype.kind in "fiub" else value.dtype)
        if value.shape != arrays[key].shape[2:]:
            raise DataError(f"info[{key!r}] has shape {value.shape}, earlier steps {arrays[key].shape[2:]} "
                            f"(training step {self.steps + t * n_envs + i}, environment copy {i})")
        arrays[key][t, i] = value
        self._shapes[key] = value.shape

    def _account(self, rewards: np.ndarray, costs: np.ndarray, ends: list[tuple[int, int]], n_steps: int) -> None:
        """Episode returns, lengths and cost sums, per environment in one pass over its segments
        between episode ends (episodes carry over from one rollout to the next)."""
        if self.ep_cost.shape[1] != costs.shape[2]:  # the first costs ever arrived in this rollout
            self.ep_cost = np.zeros((len(self.envs), costs.shape[2]))
        by_env: list[list[int]] = [[] for _ in self.envs]
        for t, i in ends:
            by_env[i].append(t)
        finished: list[tuple[int, int, FinishedEpisode]] = []  # (t, env, episode)
        for i, times in enumerate(by_env):
            starts = [0] + [t + 1 for t in times]
            segments = starts if starts[-1] < n_steps else starts[:-1]
            reward_sums = np.add.reduceat(rewards[:, i], segments)
            cost_sums = np.add.reduceat(costs[:, i], segments, axis=0) if costs.shape[2] else \
                np.zeros((len(segments), 0))
            for j, t in enumerate(times):
                ret = self.ep_return[i] + reward_sums[j]
                length = self.ep_length[i] + (t + 1 - starts[j])
                cost = self.ep_cost[i] + cost_sums[j]
                end_step = self.steps + (t + 1) * len(self.envs)
                finished.append((t, i, FinishedEpisode(float(ret), int(length), cost, end_step)))
                self.ep_return[i], self.ep_length[i], self.ep_cost[i] = 0.0, 0, 0.0
            if starts[-1] < n_steps:  # the unfinished episode carries over
                self.ep_return[i] += reward_sums[-1]
                self.ep_length[i] += n_steps - starts[-1]
                self.ep_cost[i] += cost_sums[-1]
        finished.sort(key=lambda row: (row[0], row[1]))  # in the order the steps happened
        self.finished.extend(row for _, _, row in finished)
        self.recent_lengths.extend(row.length for _, _, row in finished)

    def episode_length(self) -> float | None:
        """The expected episode length: the mean of the last finished ones; before any ended, the
        time limit when the environment declares one, else the longest episode still running (a
        lower bound); ``None`` before a single step."""
        if self.recent_lengths:
            return float(np.mean(self.recent_lengths))
        if self.time_limit:
            return float(self.time_limit)
        longest = int(self.ep_length.max()) if self.ep_length.size else 0
        return float(longest) if longest > 0 else None

    def cost_estimate(self, costs: np.ndarray) -> np.ndarray | None:
        """``J_c`` per constraint from a whole rollout's ``[T, N, k]`` step costs: the cost per step
        times :meth:`episode_length` -- over the episodes that finished, exactly their mean cost
        (a ratio estimate), and defined in every rollout, also one in which no episode ended."""
        length = self.episode_length()
        if length is None or costs.shape[0] * costs.shape[1] == 0:
            return None
        return costs.reshape(-1, costs.shape[2]).mean(axis=0) * length

    def true_cost_estimate(self, true_costs: np.ndarray) -> float:
        """The environment's cost per episode (summed over constraints) from a rollout's ``[T, N]``
        step costs, estimated as :meth:`cost_estimate` does over the steps that reported one;
        NaN where none did."""
        finite = true_costs[np.isfinite(true_costs)]
        estimate = self.cost_estimate(finite.reshape(-1, 1, 1)) if finite.size else None
        return math.nan if estimate is None else float(estimate[0])

    def episode_stats(self, n_costs: int) -> EpisodeStats:
        return episode_stats(self.finished, n_costs)

