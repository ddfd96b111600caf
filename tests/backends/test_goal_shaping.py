"""Goal-distance shaping Psi(u) = gamma ** d(u) (thesis eqs. 7.6-7.7) and the properties it lists."""

import math

import pytest

from symlearn.backends.goal_shaping import goal_distances, goal_potential, shape
from symlearn.errors import ModelError
from symlearn.logic.automata import RewardMachine

GAMMA = 0.9


def _chain():
    """0 -a-> 1 -b-> 2 -c-> 3 (goal); 2 -back-> 1 moves away; 0 -dead-> 4 never reaches the goal."""
    return RewardMachine({"a", "b", "c", "back", "dead"}, 5, 0, {
        0: [("a & !dead", 1, 0.0), ("dead & !a", 4, 0.0)], 1: [("b", 2, 0.0)],
        2: [("c & !back", 3, 1.0), ("back & !c", 1, 0.0)]},
        terminal=[3], accepting=[3])


def test_distances_and_potential():
    rm = _chain()
    assert goal_distances(rm) == [3, 2, 1, 0, math.inf]
    assert goal_potential(rm, GAMMA) == pytest.approx([GAMMA ** 3, GAMMA ** 2, GAMMA, 1.0, 0.0])


def test_moving_closer_pays_nothing():
    shaped = shape(_chain(), GAMMA)
    assert shaped.step(0, {"a"}) == (1, pytest.approx(0.0))
    assert shaped.step(1, {"b"}) == (2, pytest.approx(0.0))


def test_staying_is_slightly_negative_and_moving_away_more():
    shaped = shape(_chain(), GAMMA)
    for u, d in ((0, 3), (1, 2), (2, 1)):
        state, stay = shaped.step(u, set())
        assert state == u and stay == pytest.approx((GAMMA - 1) * GAMMA ** d) and stay < 0
    _, away = shaped.step(2, {"back"})
    _, stay = shaped.step(2, set())
    assert away == pytest.approx((GAMMA ** 2 - 1) * GAMMA) and away < stay < 0


def test_reaching_the_goal_pays_one_and_the_goal_is_terminal():
    shaped = shape(_chain(), GAMMA)
    assert shaped.step(2, {"c"}) == (3, pytest.approx(1.0))
    assert shaped.step(3, {"a"}) == (3, 0.0)
    # the return of the shortest route is the sparse one: everything before the goal pays 0
    states, rewards = shaped.run([{"a"}, {"b"}, {"c"}])
    assert states == [0, 1, 2, 3] and rewards == pytest.approx([0.0, 0.0, 1.0])


def test_dead_state_costs_its_potential():
    shaped = shape(_chain(), GAMMA)
    assert shaped.step(0, {"dead"}) == (4, pytest.approx(-GAMMA ** 3))


def test_potential_recorded_and_json_round_trip():
    shaped = shape(_chain(), GAMMA)
    assert shaped.gamma == GAMMA and shaped.potential[3] == 1.0
    again = RewardMachine.from_json(shaped.to_json())
    assert again == shaped


def test_bad_gamma_and_double_shaping_refused():
    with pytest.raises(ModelError, match="gamma"):
        shape(_chain(), 1.0)
    with pytest.raises(ModelError, match="shaped already"):
        shape(shape(_chain(), GAMMA), GAMMA)
