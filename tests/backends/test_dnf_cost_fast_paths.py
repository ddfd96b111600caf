"""The cost wrapper's per-step paths (bound evaluator, one-row counting) agree with batch
evaluation and batch counting of the same points."""

from __future__ import annotations

import numpy as np
import pytest

from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
from symlearn.envs.toy_navigation import ToyNavigationEnv
from symlearn.errors import DataError
from symlearn.logic.dnf import parse

RULES = parse("x < 0.1\ny > 0.95\nx > 0.3 & x < 0.6 & y > 0.3 & y < 0.6\nx >= 0.5 & y < 0.2\nx > 2")


def test_one_row_counting_equals_batch_counting():
    rng = np.random.default_rng(0)
    X = np.round(rng.random((500, 2)), 1)                                   # ties on the thresholds too
    fires = RULES.evaluate(X, ["x", "y"], per_conjunction=True)
    batch, steps = RuleStats(RULES, ["x", "y"]), RuleStats(RULES, ["x", "y"])
    batch.count(fires)
    for row in fires:
        steps.count(row[None, :])
    assert np.array_equal(batch.evaluated, steps.evaluated) and np.array_equal(batch.fired, steps.fired)


@pytest.mark.parametrize("per_rule", [False, True])
@pytest.mark.parametrize("track", [False, True])
def test_wrapper_costs_and_stats_match_batch_evaluation(per_rule, track):
    env = DnfCostWrapper(ToyNavigationEnv(), RULES, ["x", "y"], per_rule=per_rule, track=track)
    env.reset(seed=1)
    rng = np.random.default_rng(1)
    points, costs = [], []
    for _ in range(300):
        _, _, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2))
        points.append(info["features"])
        costs.append(info["cost"])
        if terminated or truncated:
            env.reset()
    fires = RULES.evaluate(np.array(points), ["x", "y"], per_conjunction=True)
    want = fires.astype(float) if per_rule else fires.any(axis=1).astype(float)
    assert np.array_equal(np.array(costs, dtype=float), want)
    expected = RuleStats(RULES, ["x", "y"])
    if track:
        expected.count(fires)
    assert np.array_equal(env.stats.evaluated, expected.evaluated) and np.array_equal(env.stats.fired, expected.fired)


def test_wrapper_refuses_non_finite_features():
    env = DnfCostWrapper(ToyNavigationEnv(), RULES, ["x", "y"], source=lambda obs, info: [np.inf, 0.0], track=False)
    env.reset(seed=0)
    with pytest.raises(DataError, match="finite"):
        env.step(np.zeros(2))
