"""Q-learning with counterfactual experiences for reward machines (CRM, Toro Icarte et al.).

The agent acts in the product of environment state ``s`` and machine state ``u``. Every real
transition ``s -a-> s'`` is replayed for *every* machine state ``u``: the machine reads the
label of ``s'`` from ``u`` and yields ``(u', r)``, and ``Q[s, u, a]`` is updated towards
``r + gamma * max Q[s', u']`` (zero when that step ends the episode). So a machine state learns
from transitions the agent made while it was in another one.

The environment is given as a deterministic successor table ``successors[s, a] -> s'`` (what
:meth:`LabelledGridEnv.next_state` computes) plus the label of every state, which lets many
episodes run side by side as numpy arrays. An episode ends when the machine enters an
accepting state from a non-accepting one (the task was just completed), when it falls into a
non-accepting absorbing state (the task can no longer be completed), or at the horizon. Ends
are read from the machine's states, not its rewards: a shaped machine pays positive rewards
for progress, which must not end the episode.

>>> import numpy as np
>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.automata.reward_machine import RewardMachine
>>> from symlearn.logic.guards import Guard
>>> succ = np.array([[0, 1], [0, 2], [1, 2]])        # a 3-cell corridor: left, right
>>> labels = [frozenset(), frozenset(), frozenset({"goal"})]
>>> g = Guard.var("goal")
>>> rm = RewardMachine.from_dfa(DFA({"goal"}, 2, 0, [1], {0: [(~g, 0), (g, 1)], 1: [(Guard.true(), 1)]}))
>>> result = crm_q_learning(succ, labels, rm, start=0, n_steps=2_000, horizon=10, seed=0)
>>> int(result.greedy_action(0, result.start_machine_state))   # go right
1
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from symlearn.errors import ModelError

__all__ = ["MachineTables", "CRMResult", "crm_q_learning", "label_ids", "sample_episodes", "policy_entropy"]


def label_ids(state_labels: Sequence[frozenset[str]]) -> tuple[np.ndarray, list[frozenset[str]]]:
    """Number the distinct labels: ``ids[s]`` indexes ``distinct``."""
    distinct: dict[frozenset[str], int] = {}
    ids = np.array([distinct.setdefault(frozenset(lab), len(distinct)) for lab in state_labels], dtype=np.int64)
    return ids, list(distinct)


@dataclass(frozen=True)
class MachineTables:
    """A reward machine tabulated over the distinct labels of an environment.

    ``next_u[u, l]``, ``reward[u, l]``, ``done[u, l]`` (the episode ends) and ``completed[u, l]``
    (the task was just completed) for machine state ``u`` reading label number ``l``.
    """

    next_u: np.ndarray
    reward: np.ndarray
    done: np.ndarray
    completed: np.ndarray
    initial: int
    accepting: frozenset[int]

    @property
    def n_states(self) -> int:
        return self.next_u.shape[0]

    @classmethod
    def compile(cls, machine, labels: Sequence[frozenset[str]]) -> MachineTables:
        n_u, n_l = machine.n_states, len(labels)
        next_u = np.zeros((n_u, n_l), dtype=np.int64)
        reward = np.zeros((n_u, n_l))
        completed = np.zeros((n_u, n_l), dtype=bool)
        dead = np.zeros((n_u, n_l), dtype=bool)
        accepting = machine.accepting
        dead_states = {q for q in machine.terminal if q not in accepting}
        for u in range(n_u):
            for j, label in enumerate(labels):
                target, r = machine.step(u, label)
                next_u[u, j], reward[u, j] = target, r
                completed[u, j] = target in accepting and u not in accepting
                dead[u, j] = target in dead_states
        return cls(next_u, reward, completed | dead, completed, int(machine.initial), frozenset(accepting))


@dataclass
class CRMResult:
    """Learned action values ``q_values[s, u, a]`` and what is needed to run the policy."""

    q_values: np.ndarray
    tables: MachineTables
    successors: np.ndarray
    labels: np.ndarray  # label id of every environment state
    start: int
    horizon: int
    steps: int
    episodes: int
    history: list[float] = field(default_factory=list)  # completion rate per chunk of training

    @property
    def start_machine_state(self) -> int:
        return int(self.tables.next_u[self.tables.initial, self.labels[self.start]])

    def greedy_action(self, s: int, u: int) -> int:
        return int(np.argmax(self.q_values[s, u]))

    def action_probabilities(self, s: np.ndarray, u: np.ndarray, tolerance: float = 1e-6) -> np.ndarray:
        """Uniform over the actions whose value is within ``tolerance`` of the best (``(K, A)``)."""
        return _tie_uniform(self.q_values[s, u], tolerance)


def _tie_uniform(q: np.ndarray, tolerance: float) -> np.ndarray:
    best = q.max(axis=-1, keepdims=True)
    near = q >= best - tolerance * np.maximum(1.0, np.abs(best))
    return near / near.sum(axis=-1, keepdims=True)


def _check(successors: np.ndarray, state_labels: Sequence, start: int) -> np.ndarray:
    succ = np.asarray(successors)
    if succ.ndim != 2 or not np.issubdtype(succ.dtype, np.integer):
        raise ModelError("successors must be an integer (S, A) table of next states")
    n = succ.shape[0]
    if succ.min() < 0 or succ.max() >= n:
        raise ModelError(f"successor table points outside the {n} states")
    if len(state_labels) != n:
        raise ModelError(f"{len(state_labels)} state labels for {n} states")
    if not 0 <= int(start) < n:
        raise ModelError(f"start state {start} is not one of 0..{n - 1}")
    return succ.astype(np.int64)


def crm_q_learning(
    successors: np.ndarray,
    state_labels: Sequence[frozenset[str]],
    machine,
    start: int,
    *,
    n_steps: int = 100_000,
    n_envs: int = 64,
    horizon: int = 200,
    discount: float = 0.99,
    learning_rate: float = 1.0,
    epsilon: float = 0.1,
    optimistic: float = 1.0,
    seed: int | None = None,
) -> CRMResult:
    """Train ``Q[s, u, a]`` for ``machine`` on the environment by CRM Q-learning.

    ``n_steps`` real transitions are made by ``n_envs`` epsilon-greedy episodes run side by
    side; each is replayed for all machine states. Values start at ``optimistic`` (at least
    the largest reward) so untried actions look attractive and get explored. A learning rate of
    1 is exact for deterministic dynamics and rewards, which is what this module assumes.
    """
    succ = _check(successors, state_labels, start)
    if not 0 < discount <= 1 or not 0 < learning_rate <= 1 or not 0 <= epsilon <= 1:
        raise ModelError("need 0 < discount <= 1, 0 < learning_rate <= 1, 0 <= epsilon <= 1")
    ids, distinct = label_ids(state_labels)
    tables = MachineTables.compile(machine, distinct)
    rng = np.random.default_rng(seed)
    n_s, n_a = succ.shape
    n_u = tables.n_states
    q = np.full((n_s, n_u, n_a), float(optimistic))
    all_u = np.arange(n_u)[None, :]
    rows = np.arange(n_envs)
    u_start = int(tables.next_u[tables.initial, ids[start]])

    s = np.full(n_envs, int(start))
    u = np.full(n_envs, u_start)
    t = np.zeros(n_envs, dtype=np.int64)
    episodes, completed, history = 0, 0, []
    chunk_eps = chunk_done = 0
    n_rounds = max(1, int(n_steps) // n_envs)
    for round_ in range(n_rounds):
        values = q[s, u]
        noisy = values + rng.random(values.shape) * 1e-9  # random tie-breaking
        a = np.where(rng.random(n_envs) < epsilon, rng.integers(0, n_a, n_envs), noisy.argmax(axis=1))
        s2 = succ[s, a]
        l2 = ids[s2]
        nu = tables.next_u[:, l2].T  # (K, U): counterfactual next machine state for every u
        r = tables.reward[:, l2].T
        d = tables.done[:, l2].T
        target = r + discount * np.where(d, 0.0, q[s2[:, None], nu].max(axis=-1))
        idx = (s[:, None], all_u, a[:, None])
        q[idx] += learning_rate * (target - q[idx])
        # the real machine state moves on
        ended = d[rows, u]
        completed_now = tables.completed[u, l2]
        u = nu[rows, u]
        s = s2
        t += 1
        reset = ended | (t >= horizon)
        if reset.any():
            n_reset = int(reset.sum())
            episodes += n_reset
            chunk_eps += n_reset
            hits = int((completed_now & reset).sum())
            completed += hits
            chunk_done += hits
            s[reset], u[reset], t[reset] = int(start), u_start, 0
        if (round_ + 1) % max(1, n_rounds // 20) == 0:
            history.append(chunk_done / chunk_eps if chunk_eps else 0.0)
            chunk_eps = chunk_done = 0
    return CRMResult(q, tables, succ, ids, int(start), int(horizon), n_rounds * n_envs, episodes, history)


def sample_episodes(result: CRMResult, n: int, *, seed: int | None = None, greedy: bool = False,
                    epsilon: float = 0.0, tolerance: float = 1e-6) -> list[np.ndarray]:
    """State sequences of ``n`` episodes of the learned policy (first state included).

    The policy picks uniformly among the best actions (``greedy`` breaks ties at random too,
    so the two differ only when ``tolerance`` makes near-ties count). Episodes end like in
    training: on completion, on a dead machine state, or at the horizon.
    """
    rng = np.random.default_rng(seed)
    tables, succ, ids = result.tables, result.successors, result.labels
    n_a = succ.shape[1]
    s = np.full(n, result.start)
    u = np.full(n, result.start_machine_state)
    alive = np.ones(n, dtype=bool)
    paths = [[result.start] for _ in range(n)]
    tol = 0.0 if greedy else tolerance
    for _ in range(result.horizon):
        if not alive.any():
            break
        probs = _tie_uniform(result.q_values[s, u], max(tol, 1e-12))
        cum = probs.cumsum(axis=1)
        a = (rng.random((n, 1)) < cum).argmax(axis=1)
        if epsilon > 0:
            a = np.where(rng.random(n) < epsilon, rng.integers(0, n_a, n), a)
        s2 = succ[s, a]
        l2 = ids[s2]
        ended = tables.done[u, l2]
        u = tables.next_u[u, l2]
        for k in np.flatnonzero(alive):
            paths[k].append(int(s2[k]))
        s = s2
        alive &= ~ended
    return [np.asarray(p, dtype=np.int64) for p in paths]


def policy_entropy(result: CRMResult, paths: Sequence[np.ndarray], tolerance: float = 1e-6) -> float:
    """Mean entropy of the action distribution along ``paths``, divided by ``log |A|`` (1 = uniform)."""
    tables, ids = result.tables, result.labels
    n_a = result.successors.shape[1]
    total, count = 0.0, 0
    for path in paths:
        u = result.start_machine_state
        for i in range(len(path) - 1):
            p = _tie_uniform(result.q_values[path[i], u], tolerance)
            nz = p[p > 0]
            total += float(-(nz * np.log(nz)).sum() / np.log(n_a))
            count += 1
            u = int(tables.next_u[u, ids[path[i + 1]]])
    return total / count if count else 0.0
