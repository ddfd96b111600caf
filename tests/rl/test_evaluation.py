"""The one evaluation loop: any policy callable, seeds per episode, costs read as in training."""

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.rl.evaluation import run_episodes


class Walk:
    """Steps right by the action; reward 1 per step; ``info["cost"]`` (two entries) from ``costs``,
    or none; ends at ``length`` steps, which the reset seed chooses (``3 + seed % 3``)."""

    def __init__(self, costs=lambda t: [t % 2, 1.0], time_limit=True):
        self.costs, self.time_limit, self.seeds = costs, time_limit, []

    def reset(self, seed=None):
        self.seeds.append(seed)
        self.t, self.length = 0, 3 + (seed or 0) % 3
        return np.zeros(1), {}

    def step(self, action):
        self.t += 1
        cost = self.costs(self.t)
        info = {} if cost is None else {"cost": cost}
        return np.full(1, self.t * action), 1.0, self.time_limit and self.t >= self.length, False, info


def test_episodes_are_reset_with_seed_plus_i_and_summed():
    env = Walk()
    stats = run_episodes(env, lambda observation: 1.0, 3, seed=10)
    assert env.seeds == [10, 11, 12]
    assert stats.lengths.tolist() == [4, 5, 3] and stats.returns.tolist() == [4.0, 5.0, 3.0]
    assert stats.costs.tolist() == [[2.0, 4.0], [3.0, 5.0], [2.0, 3.0]]
    assert stats.end_steps.tolist() == [4, 9, 12]


def test_without_info_cost_the_costs_have_no_columns():
    stats = run_episodes(Walk(costs=lambda t: None), lambda observation: 0, 2, seed=0)
    assert stats.costs.shape == (2, 0)


def test_an_endless_episode_stops_at_max_steps():
    stats = run_episodes(Walk(time_limit=False), lambda observation: 0, 1, max_steps=7)
    assert stats.lengths.tolist() == [7]


def test_a_cost_that_changes_width_is_refused_as_in_training():
    with pytest.raises(DataError, match="entries"):
        run_episodes(Walk(costs=lambda t: [1.0] * t), lambda observation: 0, 1, seed=0)
