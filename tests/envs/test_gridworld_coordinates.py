"""The gridworld's coordinate adapter: the observation, the ground-truth cost, and the expert."""

import numpy as np
import pytest

from symlearn.data import record
from symlearn.envs.gridworld import StochasticGridworld
from symlearn.envs.gridworld_coordinates import CoordinateGridworld, expert_demonstrations
from symlearn.rl.episodes import sample_episodes
from symlearn.rl.episode_metrics import episode_metrics


def test_observations_are_coordinates_and_the_cost_marks_forbidden_cells():
    env = CoordinateGridworld(0.0)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs) and obs.tolist() == [6.0, 0.0] and info["cost"] == 0.0
    # right from the start: (6, 1) is free, (6, 2) is forbidden (the block reaches the bottom row)
    obs, reward, terminated, _, info = env.step(1)
    assert obs.tolist() == [6.0, 1.0] and reward == -1.0 and info["cost"] == 0.0 and not terminated
    obs, _, _, _, info = env.step(np.int64(1))
    assert obs.tolist() == [6.0, 2.0] and info["cost"] == 1.0 and info["violation"]
    assert env.is_unsafe(np.array([[6.2, 2.4], [2.0, 2.0], [5.0, 4.0]])).tolist() == [True, False, True]
    assert env.state_of(np.array([9.0, -3.0])) == 6 * 7 + 0  # clipped to the grid


def test_expert_demonstrations_match_the_cell_world_and_never_violate_when_deterministic():
    env = CoordinateGridworld(0.0)
    demos = expert_demonstrations(env, 3, seed=4)
    grid = StochasticGridworld(0.0)
    expert = grid.expert_policy()
    cells = record(grid, lambda s: int(expert[s]), 3, seed=4, max_steps=grid.max_steps)
    for coords, ids in zip(demos, cells):
        assert env.state_of(np.asarray(coords.states)).tolist() == list(ids.states)
        assert list(coords.actions) == list(ids.actions)
    batch = sample_episodes(lambda obs, rng: expert[env.state_of(obs)], lambda: CoordinateGridworld(0.0), 5, seed=0)
    metrics = episode_metrics(batch)
    assert metrics.violation_rate == 0.0 and metrics.reward < 0  # a detour around the block


def test_stochasticity_is_checked():
    with pytest.raises(Exception, match="stochasticity"):
        CoordinateGridworld(1.5)
