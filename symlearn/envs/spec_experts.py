"""Exact experts for the specification tasks: value iteration on environment x task automaton.

The task formula becomes a minimal DFA and a reward machine (reward 1 on reaching acceptance);
value iteration over the product of the deterministic grid and the machine gives optimal
action values. The expert then acts uniformly at random among the optimal actions, so its
demonstrations differ where several shortest solutions exist, and an episode ends the moment
the task is done.

>>> demos = expert_demonstrations("office-1", 3, seed=0)
>>> len(demos), all(demos.metadata["satisfied"])
(3, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from symlearn.errors import DataError, ModelError

DISCOUNT = 0.99


def successor_table(env) -> np.ndarray:
    """``succ[s, a]``: the next state of a deterministic tabular environment."""
    n_s, n_a = int(env.observation_space.n), int(env.action_space.n)
    return np.array([[env.next_state(s, a) for a in range(n_a)] for s in range(n_s)], dtype=np.int64)


def state_labels(env, labeling=None) -> list[frozenset[str]]:
    labeling = env.labeling if labeling is None else labeling
    return [labeling.label(s) for s in range(int(env.observation_space.n))]


@dataclass
class ProductSolution:
    """Optimal ``q_values[s, u, a]`` of a task; the same shape as a CRM result."""

    q_values: np.ndarray
    tables: object
    successors: np.ndarray
    labels: np.ndarray
    start: int
    horizon: int
    iterations: int

    @property
    def start_machine_state(self) -> int:
        return int(self.tables.next_u[self.tables.initial, self.labels[self.start]])


def solve_task(env, formula, *, labeling=None, discount: float = DISCOUNT, tol: float = 1e-10,
               max_iterations: int = 100_000) -> ProductSolution:
    """Exact optimal values of ``formula`` in ``env`` by value iteration on the product."""
    from symlearn.logic.automata.reward_machine import RewardMachine
    from symlearn.rl.crm_q_learning import MachineTables, label_ids

    succ = successor_table(env)
    ids, distinct = label_ids(state_labels(env, labeling))
    tables = MachineTables.compile(RewardMachine.from_formula(formula), distinct)
    lab_next = ids[succ]  # (S, A)
    nu = tables.next_u[:, lab_next]  # (U, S, A)
    r = tables.reward[:, lab_next]
    live = ~tables.done[:, lab_next]
    v = np.zeros((tables.n_states, succ.shape[0]))  # V[u, s]
    for it in range(1, max_iterations + 1):
        q = r + discount * live * v[nu, succ[None]]
        new_v = q.max(axis=-1)
        if np.max(np.abs(new_v - v)) < tol:
            v = new_v
            break
        v = new_v
    return ProductSolution(np.transpose(q, (1, 0, 2)).copy(), tables, succ, ids, env.state_of(env.start),
                           int(env.max_steps), it)


def expert_demonstrations(task, n: int, seed: int | None = 0, *, env=None):
    """``n`` demonstrations of the optimal expert for ``task`` (a name or :class:`SpecTask`).

    Each trajectory holds the visited states, the actions and the environment labels.
    ``metadata["satisfied"]`` says, per trajectory, whether it satisfies the task formula.
    """
    from symlearn.data import Demonstrations, Trajectory
    from symlearn.envs.spec_tasks import SpecTask, get_task
    from symlearn.logic.ltlf import holds, parse

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise DataError(f"the number of expert demonstrations must be a positive integer, got {n!r}")
    task = task if isinstance(task, SpecTask) else get_task(task)
    env = task.make_env() if env is None else env
    solution = solve_task(env, task.formula)
    if solution.q_values[solution.start, solution.start_machine_state].max() <= 0:
        raise ModelError(f"task {task.name} cannot be completed in this environment")
    rng = np.random.default_rng(seed)
    formula = parse(task.formula)
    trajectories, satisfied = [], []
    for _ in range(int(n)):
        states, actions = _expert_episode(solution, rng)
        labels = [sorted(env.labeling.label(s)) for s in states]
        satisfied.append(bool(holds(formula, labels)))
        trajectories.append(Trajectory(states, actions, labels=labels))
    meta = {"task": task.name, "formula": task.formula, "policy": "optimal expert (product value iteration)",
            "seed": seed, "satisfied": satisfied}
    return Demonstrations(trajectories, metadata=meta)


def _expert_episode(solution: ProductSolution, rng: np.random.Generator) -> tuple[list[int], list[int]]:
    tables, succ, ids = solution.tables, solution.successors, solution.labels
    s, u = solution.start, solution.start_machine_state
    states, actions = [s], []
    for _ in range(solution.horizon):
        q = solution.q_values[s, u]
        best = np.flatnonzero(q >= q.max() - 1e-9)
        a = int(rng.choice(best))
        s2 = int(succ[s, a])
        done = bool(tables.done[u, ids[s2]])
        u = int(tables.next_u[u, ids[s2]])
        s = s2
        states.append(s)
        actions.append(a)
        if done:
            break
    return states, actions
