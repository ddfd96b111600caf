"""A DNF formula as the cost of an environment, and pruning by ascending-complexity rule counts."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
from symlearn.errors import DataError, SymlearnError
from symlearn.logic.dnf import parse


class Walk(gym.Env):
    """A point on a line [0, 1] (features: x), moved by +-0.1; x is reported in info."""

    observation_space = gym.spaces.Box(0.0, 1.0, (1,), dtype=np.float64)
    action_space = gym.spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.x = 0.5
        return np.array([self.x]), {"features": [self.x]}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.1 if action else -0.1), 0.0, 1.0))
        return np.array([self.x]), 1.0, False, False, {"features": [self.x], "cost": 0.5}


def test_cost_and_per_rule_cost():
    dnf = parse("x > 0.75\nx < 0.25 & x > 0.1\n")
    env = DnfCostWrapper(Walk(), dnf, ["x"])
    env.reset(seed=0)
    costs = [env.step(1)[4]["cost"] for _ in range(4)]  # 0.6 0.7 0.8 0.9
    assert costs == [0.0, 0.0, 1.0, 1.0]
    per_rule = DnfCostWrapper(Walk(), dnf, ["x"], per_rule=True, penalty=2.0)
    per_rule.reset(seed=0)
    for _ in range(3):
        _, reward, _, _, info = per_rule.step(1)
    assert info["cost"].tolist() == [1.0, 0.0] and reward == 1.0 - 2.0 and info["env_cost"] == 0.5


def test_rule_stats_count_in_ascending_complexity():
    dnf = parse("x > 0.5 & y > 0.5\nx > 0.5\ny > 2")
    stats = RuleStats(dnf, ["x", "y"])
    stats.update(np.array([[0.9, 0.9], [0.9, 0.1], [0.1, 0.1]]))
    # order of evaluation: "x > 0.5" and "y > 2" (1 atom, file order), then the 2-atom rule
    assert stats.evaluated.tolist() == [1, 3, 1]  # the 2-atom rule is only reached where x <= 0.5
    assert stats.fired.tolist() == [0, 2, 0]
    pruned, verdicts = stats.prune(0.1)
    assert str(pruned) == "x > 0.5" and [v.kept for v in verdicts] == [False, True, False]


def test_pruning_keeps_the_rule_an_agent_runs_into():
    """The thesis' toy: a rule the agent's rewarding path crosses fires; rules about corners it
    never visits are evaluated but never fire and are pruned."""
    dnf = parse("x > 0.1 & x < 0.7 & y > 0.3\nx < 0.1\nx > 0.9\ny < 0.1\ny > 0.9")
    stats = RuleStats(dnf, ["x", "y"])
    t = np.linspace(0.1, 0.9, 200)
    diagonal = np.stack([t, t], axis=1)  # straight to the goal, through the unsafe region
    stats.update(diagonal)
    pruned, _ = stats.prune(1e-3)
    assert str(pruned) == "x > 0.1 & x < 0.7 & y > 0.3"


def test_counts_since_a_snapshot_and_reset():
    """Pruning against the trained agent: the counts of the last part of training only."""
    dnf = parse("x > 0.1 & x < 0.7 & y > 0.3\nx < 0.1")
    stats = RuleStats(dnf, ["x", "y"])
    stats.update(np.array([[0.5, 0.5], [0.05, 0.2]]))  # early: the diagonal and a step off the start
    snapshot = stats.snapshot()
    stats.update(np.array([[0.5, 0.2], [0.8, 0.5], [0.8, 0.8]]))  # late: the safe route
    late = stats.since(snapshot)
    assert stats.evaluated.tolist() == [4, 5] and stats.fired.tolist() == [1, 1]
    assert late.evaluated.tolist() == [3, 3] and late.fired.tolist() == [0, 0]
    assert str(stats.prune(1e-3)[0]) == str(dnf) and len(late.prune(1e-3)[0]) == 0
    snapshot[0][:] = 99  # a copy: changing it changes nothing
    assert stats.since(stats.snapshot()).evaluated.tolist() == [0, 0]
    with pytest.raises(SymlearnError, match="another formula"):
        stats.since((np.zeros(3, dtype=np.int64), np.zeros(3, dtype=np.int64)))
    stats.reset()
    assert stats.evaluated.tolist() == [0, 0] and stats.fired.tolist() == [0, 0]


def test_bad_input():
    dnf = parse("z > 1")
    with pytest.raises(DataError, match="feature 'z'"):
        DnfCostWrapper(Walk(), dnf, ["x"])
    env = DnfCostWrapper(Walk(), parse("x > 1"), ["x", "y"])
    env.reset(seed=0)
    with pytest.raises(DataError, match="expected 2 features"):
        env.step(1)
    stats = RuleStats(parse("x > 1"), ["x"])
    with pytest.raises(DataError, match="finite"):
        stats.update(np.array([[np.nan]]))
