"""Demonstrations read against a TabularMDP: checked once, even through a wrapping learner."""

import warnings

import numpy as np

from symlearn.mdp import TabularMDP
from symlearn.mdp.episodes import tabular_episodes


def _line() -> TabularMDP:
    P = np.zeros((3, 1, 3))
    P[0, 0, 1] = P[1, 0, 2] = P[2, 0, 2] = 1
    return TabularMDP(P, np.zeros((3, 1)), [1, 0, 0], [False, False, True])


def test_checked_episodes_pass_through_and_warn_once():
    mdp = _line()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        episodes = tabular_episodes([([0, 2], [0])], mdp)  # 0 -> 2 has probability zero
        again = tabular_episodes(episodes, mdp)
    assert again == episodes and again[0] is episodes[0]
    assert [str(w.message) for w in caught] == [
        "1 demonstrated step(s) have probability zero under the model (treated as noise and kept)"]
