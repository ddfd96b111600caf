"""SUMO-backed junction demonstrations: same shape as the native expert, checked against the rules.

The SUMO tests skip when the ``sumo`` extra (eclipse-sumo + traci) is not installed; the
missing-engine test runs everywhere.
"""

import pytest

from symlearn import optional
from symlearn.envs.sumo_junction import SumoSettings, _road_path, sumo_demonstrations, sumo_expert_episodes
from symlearn.envs.traffic_model import ACTIONS, JunctionState, TrafficJunction
from symlearn.errors import MissingDependencyError, ModelError

needs_sumo = pytest.mark.skipif(not optional.available("sumo"), reason="SUMO (eclipse-sumo, traci) not installed")

N_EPISODES = 15


def test_missing_sumo_is_a_clear_error(monkeypatch):
    monkeypatch.setattr(optional, "available", lambda name: False)
    with pytest.raises(MissingDependencyError, match="needs sumo") as info:
        sumo_expert_episodes(TrafficJunction("lights"), 2, seed=0)
    assert "symlearn[sumo]" in info.value.hint


def test_jumped_cells_are_filled_in_along_the_road():
    model = TrafficJunction("lights")
    assert _road_path(model, (3, 2), (3, 2)) == []
    assert _road_path(model, (3, 1), (3, 3)) == ["north", "north"]
    assert _road_path(model, (3, 2), (4, 3)) == ["north", "east"]  # a right turn passes the junction cell


def test_timing_must_fit_the_grid_step():
    with pytest.raises(ModelError, match="must divide"):
        SumoSettings(cell_length=20.0, speed=10.0, sim_step=0.3).steps_per_cell


@pytest.fixture(scope="module", params=["lights", "priority"])
def run(request):
    if not optional.available("sumo"):
        pytest.skip("SUMO (eclipse-sumo, traci) not installed")
    model = TrafficJunction(request.param)
    return model, sumo_demonstrations(model, N_EPISODES, seed=0)


@needs_sumo
def test_episodes_are_drives_across_the_grid(run):
    model, result = run
    assert len(result.episodes) == N_EPISODES
    for episode in result.episodes:
        assert episode
        first, _ = episode[0]
        assert first.cell in model.entries()
        for (state, action), (following, _) in zip(episode, episode[1:]):
            assert model.next_cell(state.cell, action) == following.cell  # one cell per move, no jumps
        last, action = episode[-1]
        assert model.next_cell(last.cell, action) is None  # the episode ends by leaving the grid
        assert model.road_of(last.cell) in ("east", "west", "north", "south")


@needs_sumo
def test_states_and_actions_are_the_models(run):
    model, result = run
    for episode in result.episodes:
        for state, action in episode:
            assert isinstance(state, JunctionState) and action in ACTIONS
            model.state_index(state)  # raises for a state outside the model
            if model.has_lights:
                assert state.light in (0, 1) and not state.car_on_right
            else:
                assert state.light is None


@needs_sumo
def test_observations_vary(run):
    model, result = run
    seen = {(s.light, s.car_on_right) for episode in result.episodes for s, _ in episode}
    if model.has_lights:
        assert {light for light, _ in seen} == {0, 1}
    else:
        assert {flag for _, flag in seen} == {False, True}
    assert {a for episode in result.episodes for _, a in episode} >= {"zero", "east"}  # cars wait and drive


@needs_sumo
def test_sumo_mostly_obeys_the_ground_truth(run):
    model, result = run
    pairs = [pair for episode in result.episodes for pair in episode]
    broken = [(s, a) for s, a in pairs if not model.is_allowed(s, a)]
    assert len(result.violations) == len(broken)  # every breach is reported, none dropped
    assert result.allowed_fraction == pytest.approx(1 - len(broken) / len(pairs))
    print(f"{model.variant}: {len(pairs)} pairs, allowed fraction {result.allowed_fraction:.4f}, "
          f"violations {dict(result.violation_counts)}, {result.episodes_per_second:.1f} episodes/s")
    assert result.allowed_fraction >= 0.95


@needs_sumo
def test_same_seed_same_episodes():
    model = TrafficJunction("priority")
    first = sumo_expert_episodes(model, 4, seed=3)
    assert len(first) == 4
    assert first == sumo_expert_episodes(model, 4, seed=3)


@needs_sumo
def test_max_steps_cuts_episodes():
    episodes = sumo_expert_episodes(TrafficJunction("lights"), 5, seed=1, max_steps=3)
    assert len(episodes) == 5 and all(1 <= len(e) <= 3 for e in episodes)
