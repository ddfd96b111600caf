"""ICRL metrics on hand-made episodes and costs whose answers are known."""

import math

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.rl.episodes import EpisodeBatch
from symlearn.learners.neural.icrl_metrics import recovery, sample_around
from symlearn.rl.episode_metrics import episode_metrics


def _batch(rewards, costs, lengths):
    E, T = len(rewards), max(len(r) for r in rewards)
    pad = lambda rows: np.array([list(r) + [0] * (T - len(r)) for r in rows], dtype=float)  # noqa: E731
    mask = np.arange(T)[None, :] < np.array(lengths)[:, None]
    return EpisodeBatch(np.zeros((E, T, 2)), np.zeros((E, T, 2)), pad(rewards), pad(costs), mask)


def test_reward_violation_rate_and_feasible_reward():
    batch = _batch(rewards=[[1, 1, 1, 1], [2, 2, 2]], costs=[[0, 0, 1, 0], [0, 0, 0]], lengths=[4, 3])
    m = episode_metrics(batch)
    assert m.reward == pytest.approx((4 + 6) / 2)
    assert m.violation_rate == pytest.approx((1 / 4 + 0) / 2)  # per episode, then averaged
    assert m.feasible_reward == pytest.approx((2 + 6) / 2)  # reward before the first violating step
    first_step = episode_metrics(_batch([[5, 1]], [[1, 0]], [2]))
    assert first_step.feasible_reward == 0 and first_step.violation_rate == 0.5


def test_padding_is_not_counted():
    batch = _batch(rewards=[[1, 1], [1, 1, 1, 1]], costs=[[0, 0, 9, 9], [0, 0, 0, 0]], lengths=[2, 4])
    assert episode_metrics(batch).violation_rate == 0  # costs beyond an episode's end are padding


def test_metrics_need_steps():
    with pytest.raises(DataError):
        episode_metrics(_batch([[1]], [[0]], [0]))


class _Threshold:
    """A cost that is ``lambda`` beyond x < wall (a perfect one) or the reverse."""

    uses_actions = False

    def __init__(self, wall, reverse=False):
        self.wall, self.reverse, self.lambdas = wall, reverse, np.array([2.0])

    def __call__(self, states, actions=None):
        unsafe = states[:, 0] < self.wall
        return 2.0 * (~unsafe if self.reverse else unsafe)


def _unsafe(states):
    return states[:, 0] < -3


def test_recovery_of_a_perfect_and_of_a_reversed_cost():
    expert = np.column_stack([np.linspace(-2.5, 10, 50), np.zeros(50)])
    perfect = recovery(_Threshold(-3), _unsafe, expert, n=5000)
    assert perfect.auc == 1 and perfect.iou == 1 and 0.05 < perfect.unsafe_share < 0.3
    reverse = recovery(_Threshold(-3, reverse=True), _unsafe, expert, n=5000)
    assert reverse.auc == 0 and reverse.iou == 0
    shifted = recovery(_Threshold(-2), _unsafe, expert, n=5000)  # too cautious: every unsafe state found
    assert shifted.auc > 0.9 and 0.4 < shifted.iou < 1


def test_recovery_without_unsafe_states_has_no_auc():
    expert = np.column_stack([np.linspace(5, 10, 50), np.zeros(50)])
    result = recovery(_Threshold(-3), _unsafe, expert, n=500)
    assert math.isnan(result.auc) and result.as_dict()["auc"] is None


def test_samples_cover_the_widened_box():
    rng = np.random.default_rng(0)
    states = sample_around(np.array([[0.0, 1.0], [4.0, 1.0]]), 4000, 0.25, rng)
    assert states[:, 0].min() < -0.9 and states[:, 0].max() > 4.9 and states[:, 0].min() >= -1.0
    assert np.ptp(states[:, 1]) > 0.4  # a constant entry is widened too


def test_auto_margin_widens_the_box_until_the_unsafe_set_is_in_it():
    # x in [5, 10]: the 0.25 box ends at 3.75, the 2.0 box reaches -5, past the wall at -3
    expert = np.column_stack([np.linspace(5, 10, 50), np.zeros(50)])
    result = recovery(_Threshold(-3), _unsafe, expert, n=2000, margin="auto")
    assert result.margin == 2.0 and result.auc == 1 and 0.01 <= result.unsafe_share <= 0.99
    assert result.as_dict()["margin"] == 2.0
    near = np.column_stack([np.linspace(-2.5, 10, 50), np.zeros(50)])  # already both kinds at 0.25
    assert recovery(_Threshold(-3), _unsafe, near, n=2000, margin="auto").margin == 0.25
