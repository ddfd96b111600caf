"""Office and craft worlds: layout, dynamics, labels, exact model."""

from collections import deque

import numpy as np
import pytest

from symlearn.envs.craft_world import RESOURCES, make_craft_world
from symlearn.envs.office_world import TASKS, make_office_world
from symlearn.errors import ModelError

UP, RIGHT, DOWN, LEFT = range(4)


def shortest(env, start, goals, avoid=frozenset()):
    """BFS over cells; returns the number of moves to the nearest goal cell."""
    seen, queue = {start}, deque([(start, 0)])
    while queue:
        s, d = queue.popleft()
        if s in goals:
            return d
        for a in range(4):
            t = env.next_state(s, a)
            if t not in seen and t not in avoid:
                seen.add(t)
                queue.append((t, d + 1))
    return None


def test_office_walls_and_doors():
    env = make_office_world()
    s = lambda x, y: env.state_of((x, y))  # noqa: E731
    assert env.next_state(s(2, 1), RIGHT) == s(3, 1)      # door between the first two rooms
    assert env.next_state(s(2, 0), RIGHT) == s(2, 0)      # wall beside the door
    assert env.next_state(s(1, 2), UP) == s(1, 3)         # door upwards
    assert env.next_state(s(0, 2), UP) == s(0, 2)         # wall
    assert env.next_state(s(0, 0), LEFT) == s(0, 0)       # edge of the grid
    assert env.next_state(s(4, 5), UP) == s(4, 6)
    assert env.next_state(s(5, 5), UP) == s(5, 5)


def test_office_labels_and_tasks():
    env = make_office_world()
    state, info = env.reset()
    assert env.cell_of(state) == (2, 1) and info["labels"] == []
    lab = env.labeling
    assert set(lab.propositions) == set("abcdefgn")
    assert len(lab.states_where("n")) == 6 and len(lab.states_where("f")) == 2
    state, _, terminated, truncated, info = env.step(LEFT)
    assert info["labels"] == ["a"] and not terminated and not truncated
    assert set(TASKS) == {"office-1", "office-2", "office-3", "office-4"}


def test_office_tasks_are_achievable_without_decorations():
    env = make_office_world()
    plants = set(env.labeling.states_where("n"))
    start = env.state_of((2, 1))
    coffee = set(env.labeling.states_where("f"))
    office = set(env.labeling.states_where("g"))
    to_coffee = shortest(env, start, coffee, plants)
    assert to_coffee is not None and to_coffee > 0
    from_coffee = min(shortest(env, c, office, plants) for c in coffee)
    assert from_coffee is not None


def test_office_exact_model_matches_steps():
    env = make_office_world()
    mdp = env.to_tabular()
    rng = np.random.default_rng(0)
    state, _ = env.reset()
    for _ in range(200):
        action = int(rng.integers(4))
        expected = mdp.successors(state, action)
        state, *_ = env.step(action)
        assert expected == {state: 1.0}


def test_episode_truncates_and_bad_action():
    env = make_office_world(max_steps=3)
    env.reset()
    assert [env.step(UP)[3] for _ in range(3)] == [False, False, True]
    with pytest.raises(ModelError, match="not one of 0..3"):
        env.step(7)


def test_craft_world_is_seeded():
    one, two, other = make_craft_world(seed=1), make_craft_world(seed=1), make_craft_world(seed=2)
    assert one.objects == two.objects and one.objects != other.objects
    counts = {r: len(one.labeling.states_where(r)) for r in RESOURCES}
    assert counts == {r: 5 for r in RESOURCES}
    assert one.state_of(one.start) not in {s for r in RESOURCES for s in one.labeling.states_where(r)}
    with pytest.raises(ModelError, match="do not fit"):
        make_craft_world(size=2, per_resource=1)
