import numpy as np
import pytest

from symlearn.envs.traffic_model import ACTIONS, JunctionState, TrafficJunction
from symlearn.errors import ModelError


@pytest.fixture(scope="module")
def lights():
    return TrafficJunction("lights")


@pytest.fixture(scope="module")
def priority():
    return TrafficJunction("priority")


def test_state_and_pair_counts(lights, priority):
    for model in (lights, priority):
        assert len(model.states()) == 50 and len(set(model.states())) == 50
        assert len(list(model.state_actions())) == 250
    # lights: per phase 4 road ends x 3 + 4 approaches x (3 green | 2 red, two of each) + junction 5
    assert lights.allowed_mask().sum() == 2 * (4 * 3 + 2 * 3 + 2 * 2 + 5)
    # priority, no car on the right: 8 arm cells x 2 (stand, drive on) + junction 2 (stand, east);
    # with a car on the right: stand still on the 9 road cells
    assert priority.allowed_mask().sum() == (8 * 2 + 2) + 9


def test_geometry(lights):
    assert lights.road_of((3, 3)) == "zero"
    assert [lights.road_of(c) for c in [(3, 4), (3, 1), (5, 3), (1, 3), (2, 2), (0, 3)]] == \
        ["north", "south", "east", "west", None, None]
    assert [lights.before_junction(c) for c in [(3, 4), (3, 2), (4, 3), (2, 3), (3, 5), (3, 3)]] == \
        ["north", "south", "east", "west", None, None]
    assert lights.next_cell((3, 5), "north") is None
    assert lights.next_cell((3, 5), "east") == (4, 5)
    assert lights.next_cell((2, 2), "zero") == (2, 2)
    assert sorted(lights.entries()) == [(1, 3), (3, 1), (3, 5), (5, 3)]


@pytest.mark.parametrize("state, action, broken", [
    (JunctionState(1, 1, light=0), "zero", ["off_road"]),
    (JunctionState(3, 4, light=1), "east", ["leaves_road"]),
    (JunctionState(3, 5, light=0), "north", []),           # driving off the map at a road end
    (JunctionState(3, 4, light=0), "south", ["red_light"]),  # north approach, phase 0 = N/S red
    (JunctionState(3, 4, light=1), "south", []),
    (JunctionState(2, 3, light=1), "east", ["red_light"]),
    (JunctionState(2, 3, light=0), "east", []),
    (JunctionState(2, 3, light=1), "west", []),              # two-way: backing off is fine
    (JunctionState(3, 3, light=1), "west", []),              # the junction itself has no light
    (JunctionState(4, 3, light=1), "zero", []),
])
def test_lights_ground_truth(lights, state, action, broken):
    assert lights.violations(state, action) == broken
    assert lights.is_allowed(state, action) == (not broken)


@pytest.mark.parametrize("state, action, broken", [
    (JunctionState(5, 5), "zero", ["off_road"]),
    (JunctionState(1, 3), "east", []),
    (JunctionState(1, 3), "west", ["wrong_way"]),            # leaves the map against the flow
    (JunctionState(2, 3), "north", ["leaves_road", "wrong_way"]),
    (JunctionState(3, 3), "north", ["wrong_way"]),          # the junction only exits east
    (JunctionState(3, 3), "east", []),
    (JunctionState(3, 4), "south", []),
    (JunctionState(3, 2), "north", []),
    (JunctionState(3, 2), "south", ["wrong_way"]),
    (JunctionState(5, 3), "east", []),
    (JunctionState(3, 2, car_on_right=True), "north", ["priority"]),
    (JunctionState(3, 2, car_on_right=True), "zero", []),
])
def test_priority_ground_truth(priority, state, action, broken):
    assert priority.violations(state, action) == broken


def test_facts(lights, priority):
    assert lights.example_facts(JunctionState(3, 2, light=1), "north") == ["at(3,2).", "tls1.", "go(north)."]
    assert priority.example_facts(JunctionState(3, 2, car_on_right=True), "zero") == \
        ["at(3,2).", "carOnTheRight.", "go(zero)."]
    assert priority.example_facts(JunctionState(3, 2), "zero") == ["at(3,2).", "go(zero)."]


def test_bad_input(lights):
    with pytest.raises(ModelError, match="unknown junction variant"):
        TrafficJunction("roundabout")
    with pytest.raises(ModelError, match="strictly inside"):
        TrafficJunction("lights", size=5, junction=(1, 3))
    with pytest.raises(ModelError, match="unknown action"):
        lights.is_allowed(JunctionState(3, 3, light=0), "up")
    with pytest.raises(ModelError, match="light phase"):
        lights.is_allowed(JunctionState(3, 4), "south")
    with pytest.raises(ModelError, match="not a state"):
        lights.state_index(JunctionState(9, 9, light=0))


@pytest.mark.parametrize("variant", ["lights", "priority"])
def test_expert_drives_through_by_the_rules(variant):
    model = TrafficJunction(variant)
    rng = np.random.default_rng(7)
    for _ in range(30):
        episode = model.expert_episode(rng)
        assert episode, "an episode has at least one step"
        cell = episode[0][0].cell
        assert cell in model.entries()
        for state, action in episode:
            assert state.cell == cell and model.is_allowed(state, action)
            assert action in ACTIONS
            cell = model.next_cell(cell, action)
        if len(episode) < 40:
            assert cell is None  # left the map at a road end


def test_larger_grid_keeps_the_semantics():
    model = TrafficJunction("lights", size=7, junction=(4, 4))
    assert model.road_of((4, 7)) == "north" and model.before_junction((4, 5)) == "north"
    assert not model.is_allowed(JunctionState(4, 5, light=0), "south")
    assert len(model.states()) == 98
