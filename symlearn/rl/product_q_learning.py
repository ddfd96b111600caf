"""Q-learning on the product of a live environment and a reward machine, with counterfactual updates.

:mod:`symlearn.rl.crm_q_learning` needs a successor table; a user's gymnasium environment has
none, only ``reset`` and ``step``. Here the agent acts in the environment itself and the product
state is ``(key(observation), u)``: ``key`` makes the observation hashable (an array by its dtype,
shape and bytes, a dict by its items -- :func:`observation_key`), or is the environment's own
state key when the observation does not identify the state (``state_key(env, observation)``; e.g.
MiniGrid's partial view). Action values are a dict ``key -> Q[u, a]`` that grows as states are
met, so no state space has to be enumerated.

Every real transition ``o -a-> o'`` with label ``l'`` (the labeler's answer for ``o'`` and its
``info``) is replayed for every machine state ``u`` (CRM, Toro Icarte et al.): ``Q[o, u, a]``
moves towards ``r(u, l') + gamma * max Q[o', u'(u, l')]``, zero after ``o'`` when the machine
ends there (the task completed or can no longer be) or the environment *terminated* (a
truncation bootstraps). An episode ends like that, on truncation, or at ``horizon``.

>>> import gymnasium as gym
>>> from symlearn.logic.automata.reward_machine import RewardMachine
>>> env = gym.make("FrozenLake-v1", is_slippery=False)
>>> goal = lambda obs, info, where="": {"goal"} if obs == 15 else set()
>>> result = product_q_learning(env, goal, RewardMachine.from_formula("F goal"), n_steps=4000, horizon=50, seed=0)
>>> words = rollout_words(env, goal, 5, policy=result, horizon=50, seed=1)[0]
>>> all("goal" in w[-1] for w in words)
True
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from symlearn.errors import ModelError
from symlearn.rl.crm_q_learning import MachineTables

__all__ = ["MachineColumns", "ProductQResult", "observation_key", "product_q_learning", "rollout_words"]

Labeler = Callable[..., frozenset]  # labeler(observation, info, where="") -> frozenset of names
StateKey = Callable[[Any, Any], Hashable]  # state_key(env, observation) -> hashable


def observation_key(observation: Any) -> Hashable:
    """A hashable stand-in for an observation: equal observations, equal keys."""
    if isinstance(observation, np.ndarray):
        return (observation.dtype.str, observation.shape, observation.tobytes())
    if isinstance(observation, np.generic):
        return observation.item()
    if isinstance(observation, Mapping):
        return tuple((k, observation_key(v)) for k, v in sorted(observation.items(), key=lambda kv: str(kv[0])))
    if isinstance(observation, (list, tuple)):
        return tuple(observation_key(v) for v in observation)
    try:
        hash(observation)
    except TypeError:
        raise ModelError(f"an observation of type {type(observation).__name__} cannot be used as a table key",
                         hint="give a state_key(env, observation) function") from None
    return observation


class MachineColumns:
    """The reward machine read on one label, for every machine state at once (cached per label)."""

    def __init__(self, machine) -> None:
        self.machine = machine
        self._cache: dict[frozenset, MachineTables] = {}
        self.initial = int(machine.initial)
        self.n_states = int(machine.n_states)

    def __call__(self, label) -> MachineTables:
        label = frozenset(label)
        found = self._cache.get(label)
        if found is None:
            found = self._cache[label] = MachineTables.compile(self.machine, [label])
        return found


@dataclass
class ProductQResult:
    """Action values ``q[key][u, a]`` over the states met, and the machine they belong to."""

    q: dict[Hashable, np.ndarray]
    machine: Any
    n_actions: int
    state_key: StateKey
    steps: int
    episodes: int
    completed: int  # episodes that completed the task while training
    history: list[float] = field(default_factory=list)  # completion rate per chunk of episodes

    def __post_init__(self) -> None:
        self.columns = MachineColumns(self.machine)

    def probabilities(self, key: Hashable, u: int, tolerance: float = 1e-6) -> np.ndarray:
        """Uniform over the best actions (all of them in a state never met)."""
        row = self.q.get(key)
        if row is None:
            return np.full(self.n_actions, 1.0 / self.n_actions)
        values = row[u]
        best = values.max()
        near = values >= best - tolerance * max(1.0, abs(best))
        return near / near.sum()


def _default_key(_env: Any, observation: Any) -> Hashable:
    return observation_key(observation)


def _n_actions(env: Any) -> int:
    n = getattr(env.action_space, "n", None)
    if n is None:
        raise ModelError("tabular product Q-learning needs a Discrete action space",
                         hint="continuous actions go through PPO (policy='ppo')")
    return int(n)


def _action_start(env: Any) -> int:
    """Where a Discrete action space's ids begin (``Discrete(3, start=-1)``: -1); the Q-table's
    columns are ``0..n-1``, the environment takes ``start + column``."""
    return int(getattr(env.action_space, "start", 0) or 0)


def product_q_learning(env: Any, labeler: Labeler, machine, *, n_steps: int = 50_000, horizon: int = 200,
                       discount: float = 0.99, learning_rate: float = 1.0, epsilon: float = 0.1,
                       optimistic: float = 1.0, state_key: StateKey | None = None,
                       seed: int | None = None) -> ProductQResult:
    """Train by CRM Q-learning for ``n_steps`` environment steps (see the module docstring).

    A learning rate of 1 is exact when ``key`` identifies the state and the environment is
    deterministic given it; lower it for stochastic environments. Values start at
    ``optimistic`` (at least the largest reward), which drives exploration of untried actions.
    """
    if not 0 < discount <= 1 or not 0 < learning_rate <= 1 or not 0 <= epsilon <= 1:
        raise ModelError("need 0 < discount <= 1, 0 < learning_rate <= 1, 0 <= epsilon <= 1")
    key_of = state_key or _default_key
    n_a, start = _n_actions(env), _action_start(env)
    columns = MachineColumns(machine)
    n_u = columns.n_states
    rng = np.random.default_rng(seed)
    q: dict[Hashable, np.ndarray] = {}
    all_u = np.arange(n_u)

    def row(key: Hashable) -> np.ndarray:
        found = q.get(key)
        if found is None:
            found = q[key] = np.full((n_u, n_a), float(optimistic))
        return found

    steps = episodes = completed = 0
    chunk = []
    history: list[float] = []
    while steps < n_steps:
        observation, info = env.reset(seed=int(rng.integers(1 << 31)))
        u = int(columns(labeler(observation, info, "reset")).next_u[columns.initial, 0])
        key = key_of(env, observation)
        done_here = False
        for _ in range(horizon):
            values = row(key)
            if rng.random() < epsilon:
                a = int(rng.integers(n_a))
            else:
                here = values[u]
                a = int(rng.choice(np.flatnonzero(here >= here.max() - 1e-12)))
            observation, _reward, terminated, truncated, info = env.step(a + start)
            steps += 1
            tables = columns(labeler(observation, info, f"training step {steps}"))
            next_u, reward, done = tables.next_u[:, 0], tables.reward[:, 0], tables.done[:, 0]
            key2 = key_of(env, observation)
            following = row(key2)
            future = np.where(done | bool(terminated), 0.0, following[next_u].max(axis=1))
            values[all_u, a] += learning_rate * (reward + discount * future - values[all_u, a])
            done_here = bool(tables.completed[u, 0])
            ended = bool(done[u]) or terminated or truncated
            u, key = int(next_u[u]), key2
            if ended:
                break
        episodes += 1
        completed += done_here
        chunk.append(done_here)
        if len(chunk) == 20:
            history.append(float(np.mean(chunk)))
            chunk = []
    return ProductQResult(q, machine, n_a, key_of, steps, episodes, completed, history)


def rollout_words(env: Any, labeler: Labeler, n: int, *, policy: ProductQResult | None = None,
                  horizon: int = 200, seed: int | None = None) -> tuple[list[list[frozenset]], float]:
    """Label words of ``n`` episodes (first observation included) of ``policy`` (uniform over its
    best actions) or, without one, of uniformly random actions (the action space's samples when
    it is not discrete); and the policy's mean action entropy along them divided by ``log |A|``
    (1 for random actions).

    With a policy, an episode also ends where its machine ends (as in training)."""
    rng = np.random.default_rng(seed)
    discrete = getattr(env.action_space, "n", None) is not None
    n_a = _n_actions(env) if policy is not None or discrete else 0
    start = _action_start(env) if discrete else 0
    if not discrete:  # random continuous actions: the action space's own seeded sampler
        env.action_space.seed(int(rng.integers(1 << 31)))
    words, total, count = [], 0.0, 0
    for episode in range(n):
        observation, info = env.reset(seed=int(rng.integers(1 << 31)))
        label = frozenset(labeler(observation, info, f"rollout {episode}, step 0"))
        word = [label]
        u = None
        if policy is not None:
            u = int(policy.columns(label).next_u[policy.columns.initial, 0])
        for t in range(horizon):
            if policy is None:
                a = int(rng.integers(n_a)) if discrete else env.action_space.sample()
                total += 1.0
            else:
                probs = policy.probabilities(policy.state_key(env, observation), u)
                a = int(rng.choice(n_a, p=probs))
                nz = probs[probs > 0]
                total += float(-(nz * np.log(nz)).sum() / np.log(n_a)) if n_a > 1 else 0.0
            count += 1
            observation, _reward, terminated, truncated, info = env.step(a + start if discrete else a)
            label = frozenset(labeler(observation, info, f"rollout {episode}, step {t + 1}"))
            word.append(label)
            ended = terminated or truncated
            if policy is not None:
                tables = policy.columns(label)
                ended = ended or bool(tables.done[u, 0])
                u = int(tables.next_u[u, 0])
            if ended:
                break
        words.append(word)
    return words, (total / count if count else 0.0)
