"""Q-learning with counterfactual experiences for reward machines (CRM, Toro Icarte et al.).

The agent acts in the product of environment state ``s`` and machine state ``u``. Every real
transition ``s -a-> s'`` is replayed for *every* machine state ``u``: the machine reads the
label of ``s'`` from ``u`` and yields ``(u', r)``, and ``Q[s, u, a]`` is updated towards
``r + gamma * max Q[s', u']`` (zero when that step ends the episode). So a machine state learns
from transitions the agent made while it was in another one.

The environment is given as a deterministic successor table ``successors[s, a] -> s'`` (what
:meth:`LabelledGridEnv.next_state` computes), or with :class:`Dynamics` as transition
probabilities and a start distribution sampled for every episode (a domain folder's
``model.npz``), plus the label of every state, which lets many episodes run side by side as numpy
arrays. An episode ends when the machine enters an
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

__all__ = ["CRMResult", "Dynamics", "MachineTables", "STOCHASTIC_LEARNING_RATE", "crm_q_learning", "label_ids",
           "policy_entropy", "sample_episodes"]


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
    successors: np.ndarray  # (S, A): the next state, or with ``dynamics`` the most likely one
    labels: np.ndarray  # label id of every environment state
    start: int  # the start state, or with several the most likely one
    horizon: int
    steps: int
    episodes: int
    history: list[float] = field(default_factory=list)  # completion rate per chunk of training
    dynamics: Dynamics | None = None  # stochastic moves or several start states (None: deterministic)

    @property
    def start_machine_state(self) -> int:
        return int(self.tables.next_u[self.tables.initial, self.labels[self.start]])

    def step(self, s: np.ndarray, a: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return self.successors[s, a] if self.dynamics is None else self.dynamics.step(s, a, rng)

    def starts(self, n: int, rng: np.random.Generator) -> np.ndarray:
        return np.full(n, self.start) if self.dynamics is None else self.dynamics.starts(n, rng)

    def greedy_action(self, s: int, u: int) -> int:
        return int(np.argmax(self.q_values[s, u]))

    def action_probabilities(self, s: np.ndarray, u: np.ndarray, tolerance: float = 1e-6) -> np.ndarray:
        """Uniform over the actions whose value is within ``tolerance`` of the best (``(K, A)``)."""
        return _tie_uniform(self.q_values[s, u], tolerance)


def _tie_uniform(q: np.ndarray, tolerance: float) -> np.ndarray:
    best = q.max(axis=-1, keepdims=True)
    near = q >= best - tolerance * np.maximum(1.0, np.abs(best))
    return near / near.sum(axis=-1, keepdims=True)


@dataclass(frozen=True)
class Dynamics:
    """Stochastic moves and start states, sampled for many episodes at once: ``cumulative[s, a]``
    is the running sum of ``P(s' | s, a)`` over ``s'``, ``initial`` that of the start states."""

    cumulative: np.ndarray  # (S, A, S)
    initial: np.ndarray  # (S,)

    @classmethod
    def of(cls, transitions: np.ndarray, initial: np.ndarray) -> Dynamics:
        P = np.asarray(transitions, dtype=np.float64)
        start = np.asarray(initial, dtype=np.float64)
        if P.ndim != 3 or P.shape[0] != P.shape[2] or start.shape != (P.shape[0],):
            raise ModelError(f"transitions must be (S, A, S) and the start distribution (S,), got {P.shape} "
                             f"and {start.shape}")
        if (P < 0).any() or not np.allclose(P.sum(axis=2), 1.0) or (start < 0).any() or not np.isclose(start.sum(), 1):
            raise ModelError("every transition row and the start distribution must be probabilities summing to 1")
        cumulative, first = P.cumsum(axis=2), start.cumsum()
        cumulative[..., -1] = first[-1] = 1.0   # rounding must never leave a draw without a state
        return cls(cumulative, first)

    def step(self, s: np.ndarray, a: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return (rng.random((len(s), 1)) < self.cumulative[s, a]).argmax(axis=1)

    def starts(self, n: int, rng: np.random.Generator) -> np.ndarray:
        return (rng.random((n, 1)) < self.initial[None, :]).argmax(axis=1)


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


#: Q-learning's step where moves are stochastic (a deterministic world's is 1, which is exact):
#: half of each sampled target, so a value averages over the successors it has seen. Measured on
#: the warehouse domain with an alarm coming and going (probability 0.2 and 0.5, 3 seeds, two
#: formulas, the spec learner's budgets): 0.5 and 1 gave greedy policies completing the task in
#: every episode; the sample average (1 / updates) kept the early optimistic targets and gave 0.
STOCHASTIC_LEARNING_RATE = 0.5


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
    learning_rate: float | None = None,
    epsilon: float = 0.1,
    optimistic: float = 1.0,
    seed: int | None = None,
    dynamics: Dynamics | None = None,
) -> CRMResult:
    """Train ``Q[s, u, a]`` for ``machine`` on the environment by CRM Q-learning.

    ``n_steps`` real transitions are made by ``n_envs`` epsilon-greedy episodes run side by
    side; each is replayed for all machine states. Values start at ``optimistic`` (at least
    the largest reward) so untried actions look attractive and get explored. ``dynamics``
    (:class:`Dynamics`): moves and start states are sampled from it (a domain with stochastic
    moves or several start states); ``successors`` and ``start`` are then its most likely next
    and start states, used for nothing but the result's description. ``learning_rate`` (None):
    1, exact for deterministic dynamics and rewards; with ``dynamics``
    :data:`STOCHASTIC_LEARNING_RATE`.
    """
    succ = _check(successors, state_labels, start)
    if learning_rate is None:
        learning_rate = 1.0 if dynamics is None else STOCHASTIC_LEARNING_RATE
    if dynamics is not None and dynamics.cumulative.shape[:2] != succ.shape:
        raise ModelError(f"the dynamics are for {dynamics.cumulative.shape[:2]} moves, the successor table "
                         f"for {succ.shape}")
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
    first_u = tables.next_u[tables.initial]   # the machine state after reading a start state's label

    if dynamics is None:
        s = np.full(n_envs, int(start))
        u = np.full(n_envs, u_start)
    else:
        s = dynamics.starts(n_envs, rng)
        u = first_u[ids[s]]
    t = np.zeros(n_envs, dtype=np.int64)
    episodes, completed, history = 0, 0, []
    chunk_eps = chunk_done = 0
    n_rounds = max(1, int(n_steps) // n_envs)
    for round_ in range(n_rounds):
        values = q[s, u]
        noisy = values + rng.random(values.shape) * 1e-9  # random tie-breaking
        a = np.where(rng.random(n_envs) < epsilon, rng.integers(0, n_a, n_envs), noisy.argmax(axis=1))
        s2 = succ[s, a] if dynamics is None else dynamics.step(s, a, rng)
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
            if dynamics is None:
                s[reset], u[reset] = int(start), u_start
            else:
                s[reset] = dynamics.starts(n_reset, rng)
                u[reset] = first_u[ids[s[reset]]]
            t[reset] = 0
        if (round_ + 1) % max(1, n_rounds // 20) == 0:
            history.append(chunk_done / chunk_eps if chunk_eps else 0.0)
            chunk_eps = chunk_done = 0
    return CRMResult(q, tables, succ, ids, int(start), int(horizon), n_rounds * n_envs, episodes, history, dynamics)


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
    if result.dynamics is None:
        s = np.full(n, result.start)
        u = np.full(n, result.start_machine_state)
    else:
        s = result.starts(n, rng)
        u = tables.next_u[tables.initial, ids[s]]
    alive = np.ones(n, dtype=bool)
    paths = [[int(first)] for first in s]
    tol = 0.0 if greedy else tolerance
    for _ in range(result.horizon):
        if not alive.any():
            break
        probs = _tie_uniform(result.q_values[s, u], max(tol, 1e-12))
        cum = probs.cumsum(axis=1)
        a = (rng.random((n, 1)) < cum).argmax(axis=1)
        if epsilon > 0:
            a = np.where(rng.random(n) < epsilon, rng.integers(0, n_a, n), a)
        s2 = result.step(s, a, rng)
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
        u = int(tables.next_u[tables.initial, ids[path[0]]]) if len(path) else result.start_machine_state
        for i in range(len(path) - 1):
            p = _tie_uniform(result.q_values[path[i], u], tolerance)
            nz = p[p > 0]
            total += float(-(nz * np.log(nz)).sum() / np.log(n_a))
            count += 1
            u = int(tables.next_u[u, ids[path[i + 1]]])
    return total / count if count else 0.0
