"""CRM Q-learning: learns optimal behaviour for reward machines, for every machine state at once."""

import numpy as np
import pytest

from symlearn.backends.reward_machine import task_machine
from symlearn.envs.spec_experts import solve_task, state_labels, successor_table
from symlearn.envs.spec_tasks import get_task
from symlearn.errors import ModelError
from symlearn.logic.ltlf import holds, parse
from symlearn.rl.crm_q_learning import MachineTables, crm_q_learning, label_ids, policy_entropy, sample_episodes


def _corridor(n=6):
    succ = np.array([[max(s - 1, 0), min(s + 1, n - 1)] for s in range(n)])
    labels = [frozenset()] * n
    labels[0] = frozenset({"a"})
    labels[-1] = frozenset({"b"})
    return succ, labels


def test_label_ids_number_distinct_labels():
    ids, distinct = label_ids([frozenset(), frozenset({"a"}), frozenset()])
    assert ids.tolist() == [0, 1, 0] and distinct == [frozenset(), frozenset({"a"})]


def test_machine_tables_reward_and_end_of_episode():
    succ, labels = _corridor()
    ids, distinct = label_ids(labels)
    tables = MachineTables.compile(task_machine("F b & G !a"), distinct)
    u0 = tables.initial
    b, a = distinct.index(frozenset({"b"})), distinct.index(frozenset({"a"}))
    assert tables.reward[u0, b] == 1.0 and tables.done[u0, b]
    assert tables.reward[u0, a] == 0.0 and tables.done[u0, a]  # the task can no longer be done


def test_corridor_ordered_task_needs_both_ends():
    # "a T b": go to the left end first although b is closer on the right
    succ, labels = _corridor()
    start = 3
    result = crm_q_learning(succ, labels, task_machine("a T b"), start, n_steps=20_000, horizon=30, seed=0)
    path = sample_episodes(result, 1, seed=0, greedy=True)[0]
    assert path.tolist() == [3, 2, 1, 0, 1, 2, 3, 4, 5]


def test_shaping_rewards_do_not_end_episodes():
    """A shaped machine pays for progress; only completing (or failing) the task ends an episode."""
    succ, labels = _corridor()
    distinct = label_ids(labels)[1]
    machine = task_machine("a T b", shaping=True)
    tables = MachineTables.compile(machine, distinct)
    a = distinct.index(frozenset({"a"}))
    u0 = tables.initial
    assert tables.reward[u0, a] > 0 and not tables.done[u0, a]  # progress is paid, the task goes on
    result = crm_q_learning(succ, labels, machine, 3, n_steps=20_000, horizon=30, seed=0)
    path = sample_episodes(result, 1, seed=0, greedy=True)[0]
    assert path.tolist() == [3, 2, 1, 0, 1, 2, 3, 4, 5]


def test_every_machine_state_learns_from_counterfactual_experience():
    """Values of machine states the agent never occupies at the start cell match exact values."""
    task = get_task("office-2")
    env = task.make_env()
    exact = solve_task(env, task.formula)
    learned = crm_q_learning(successor_table(env), state_labels(env), task_machine(task.formula),
                             env.state_of(env.start), n_steps=150_000, horizon=env.max_steps, seed=1)
    s0 = env.state_of(env.start)
    for u in range(exact.tables.n_states):
        v_exact = exact.q_values[s0, u].max()
        if v_exact > 0:  # machine states from which the task can still be done
            assert learned.q_values[s0, u].max() == pytest.approx(v_exact, abs=1e-6), u
    assert learned.start_machine_state == exact.start_machine_state


def test_greedy_policy_solves_office_task_optimally():
    task = get_task("office-3")
    env = task.make_env()
    exact = solve_task(env, task.formula)
    result = crm_q_learning(successor_table(env), state_labels(env), task_machine(task.formula),
                            env.state_of(env.start), n_steps=150_000, horizon=env.max_steps, seed=0)
    formula = parse(task.formula)
    paths = sample_episodes(result, 10, seed=3, greedy=True)
    optimal_steps = round(np.log(exact.q_values[exact.start, exact.start_machine_state].max()) / np.log(0.99)) + 1
    for path in paths:
        assert holds(formula, [env.labeling.label(s) for s in path])
        assert len(path) - 1 == optimal_steps
    assert 0.0 <= policy_entropy(result, paths) < 0.5


def test_true_specification_gives_a_random_policy():
    succ, labels = _corridor()
    result = crm_q_learning(succ, labels, task_machine("true"), 2, n_steps=5_000, horizon=20, seed=0)
    paths = sample_episodes(result, 5, seed=0)
    assert all(len(p) == 21 for p in paths)  # nothing ends the episode early
    assert policy_entropy(result, paths) > 0.9


def test_bad_tables_are_reported():
    succ, labels = _corridor()
    with pytest.raises(ModelError, match="outside"):
        crm_q_learning(succ + 10, labels, task_machine("F b"), 0)
    with pytest.raises(ModelError, match="labels"):
        crm_q_learning(succ, labels[:-1], task_machine("F b"), 0)
    with pytest.raises(ModelError, match="start state"):
        crm_q_learning(succ, labels, task_machine("F b"), 99)
