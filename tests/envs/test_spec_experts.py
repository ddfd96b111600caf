"""Exact experts of the eight specification tasks and the task registry."""

import numpy as np
import pytest

from symlearn.envs.spec_experts import expert_demonstrations, solve_task
from symlearn.envs.spec_tasks import TASKS, get_task
from symlearn.errors import DataError
from symlearn.logic.ltlf import holds, parse


def test_registry_lists_eight_tasks_with_formulas():
    assert sorted(TASKS) == [f"{w}-{i}" for w in ("craft", "office") for i in range(1, 5)]
    row = get_task("Office-3").listing()
    assert row["formula"] == "(f T g) & (e T g) & G !n" and row["states"] == 108 and "n" in row["propositions"]


def test_unknown_task_names_the_known_ones():
    with pytest.raises(DataError, match="unknown environment/task 'ofice-1'") as info:
        get_task("ofice-1")
    assert "office-1" in info.value.hint


@pytest.mark.parametrize("name", sorted(TASKS))
def test_expert_demonstrations_satisfy_the_task_and_are_shortest(name):
    task = get_task(name)
    env = task.make_env()
    demos = expert_demonstrations(task, 4, seed=2, env=env)
    formula = parse(task.formula)
    solution = solve_task(env, task.formula)
    best = solution.q_values[solution.start, solution.start_machine_state].max()
    shortest = round(np.log(best) / np.log(0.99)) + 1  # reward 1 arrives on the last step
    for traj in demos:
        states = [int(s) for s in traj.states]
        assert holds(formula, [env.labeling.label(s) for s in states])
        assert len(states) - 1 == shortest
        assert all(env.next_state(s, int(a)) == t for s, a, t in zip(states, traj.actions, states[1:]))
        # the task is completed on the last step and not before
        assert not holds(formula, [env.labeling.label(s) for s in states[:-1]])


def test_experts_vary_between_equally_short_solutions():
    demos = expert_demonstrations("craft-1", 10, seed=0)
    assert len({tuple(t.states.tolist()) for t in demos}) > 1


def test_expert_count_must_be_positive():
    with pytest.raises(DataError, match="positive integer"):
        expert_demonstrations("office-1", 0)
