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


def test_a_bad_cost_names_the_evaluation_episode_and_its_step():
    """Not "environment 0, step 7" (one environment, steps counted over all episodes): the episode
    and the step within it, from 0."""
    calls = iter(range(100))   # episode 0 has 4 steps (seed 1), so the 6th step is episode 1's second
    with pytest.raises(DataError, match=r"not finite: \[nan\] \(evaluation episode 1, step 1\)"):
        run_episodes(Walk(costs=lambda t: float("nan") if next(calls) == 5 else 0.0), lambda observation: 0, 2, seed=1)


def test_the_cost_reader_says_where_the_step_was():
    from symlearn.rl.episode_stats import CostReader, summed_cost

    with pytest.raises(DataError, match=r"\(training step 9, environment copy 1\)"):
        CostReader(None).read({"cost": "1"}, 1, 9)
    with pytest.raises(DataError, match=r"\(episode 2, step 4\)"):
        summed_cost({"cost": []}, where="episode 2, step 4")
