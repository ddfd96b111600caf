"""Features that are settings of an episode (learners/episode_settings.py) and the warnings the
one-class tree and the sub-goal PDFA give about them."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory
from symlearn.learners.episode_settings import episode_settings
from symlearn.learners.subgoals import SubgoalPDFALearner


def test_constant_within_and_different_between():
    a = np.array([[0.0, 1.0, 5.0], [1.0, 1.0, 5.0], [2.0, 1.0, 5.0]])
    b = np.array([[3.0, 2.0, 5.0], [2.0, 2.0, 5.0]])
    assert episode_settings([a, b]) == [1]  # column 2 is constant everywhere: no setting, just a constant
    assert episode_settings([a]) == []  # one episode: nothing to compare
    with_nan = np.array([[0.0, np.nan, 5.0], [1.0, 2.0, 5.0]])
    assert episode_settings([a, with_nan]) == [1]  # an unobserved value does not break the constant
    assert episode_settings([a, b, np.array([[9.0, 9.0, 9.0]])]) == [1]  # a one-row episode says nothing


def _walks(rng, n=12):
    """A walker going from 0 to 1 on x, dwelling at 0.5 and at 1, with a goal height drawn per
    episode (constant within it)."""
    runs = []
    for _ in range(n):
        goal = rng.uniform(0, 1)
        xs = [*np.linspace(0, 0.5, 10), *[0.5] * 12, *np.linspace(0.5, 1, 10), *[1.0] * 12]
        states = [[x, goal] for x in xs]
        runs.append(Trajectory(states=states, actions=[0] * (len(states) - 1)))
    return Demonstrations(runs)


def test_the_pdfa_learner_names_the_setting_and_the_subsets_that_leave_it_out():
    demos = _walks(np.random.default_rng(0))
    with pytest.warns(UserWarning, match=r"feature\(s\) x1 of subset all are constant within every demonstration"):
        learner = SubgoalPDFALearner().fit(demos)
    assert "--subsets 'all=0'" in learner.warnings_[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert SubgoalPDFALearner(subsets={"walk": [0]}).fit(demos).warnings_ == []
