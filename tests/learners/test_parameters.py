"""The estimator protocol of every learner works as scikit-learn's, without importing scikit-learn."""

import subprocess
import sys

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import ParameterGrid

from symlearn.learners.base import Learner


class Inner(Learner):
    def __init__(self, depth=3, weights=None):
        self.depth = depth
        self.weights = weights


class Outer(Learner):
    def __init__(self, inner=None, rate=0.1, name="x"):
        self.inner = inner
        self.rate = rate
        self.name = name


def test_get_and_set_params_reach_nested_learners():
    outer = Outer(inner=Inner(depth=5), rate=0.5)
    assert outer.get_params(deep=False) == {"inner": outer.inner, "name": "x", "rate": 0.5}
    deep = outer.get_params()
    assert deep["inner__depth"] == 5 and deep["inner__weights"] is None
    assert outer.set_params(rate=0.2, inner__depth=7) is outer
    assert outer.rate == 0.2 and outer.inner.depth == 7
    with pytest.raises(ValueError, match="invalid parameter 'speed' for Outer"):
        outer.set_params(speed=1)


def test_sklearn_clone_and_grids_accept_a_learner():
    outer = Outer(inner=Inner(weights=np.arange(3)), name="y")
    twin = clone(outer)
    assert twin is not outer and twin.inner is not outer.inner
    assert twin.name == "y" and np.array_equal(twin.inner.weights, np.arange(3))
    settings = [clone(outer).set_params(**p) for p in ParameterGrid({"rate": [0.1, 1.0], "inner__depth": [1, 2]})]
    assert sorted((s.rate, s.inner.depth) for s in settings) == [(0.1, 1), (0.1, 2), (1.0, 1), (1.0, 2)]


def test_repr_shows_what_differs_from_the_defaults():
    assert repr(Inner()) == "Inner()"
    assert repr(Inner(depth=4)) == "Inner(depth=4)"
    assert repr(Inner(weights=np.zeros(2))) == "Inner(weights=array([0., 0.]))"


def test_importing_the_learners_does_not_import_sklearn():
    code = ("import sys, symlearn.learners.base, symlearn.learners.trees;"
            "print('sklearn' in sys.modules, 'scipy' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.split() == ["False", "False"], done.stderr
