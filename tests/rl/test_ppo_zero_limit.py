"""A limit of 0 with a slack (LagrangianConfig.zero_limit_slack): rollouts without cost lower the
multiplier, rollouts over the slack still raise it; without the slack it can only rise."""

import numpy as np
import pytest

from symlearn.errors import SymlearnError
from symlearn.rl.ppo import LagrangianConfig, Multipliers
from symlearn.rl.ppo.multipliers import zero_limit_targets


def _run(slack: float, rule: str, costs: list[float]) -> list[float]:
    m = Multipliers(LagrangianConfig(cost_limit=0.0, update=rule, lr=0.1, init=1.0, zero_limit_slack=slack), 1)
    return [float(m.update([c], [1.0])[0]) for c in costs]


@pytest.mark.parametrize("rule", ["adam", "gradient"])
def test_at_limit_zero_a_cost_free_stretch_lowers_the_multiplier_only_with_the_slack(rule):
    # one stochastic brush (0.2 of a step per episode in one rollout), then a safe agent
    costs = [2.0] + [0.0] * 60
    exact = _run(0.0, rule, costs)
    slack = _run(0.25, rule, costs)
    # the exact 0: a cost of 0 is no error, so the multiplier never comes down (Adam's momentum even
    # keeps raising it after the brush)
    assert all(b >= a - 1e-12 for a, b in zip(exact, exact[1:]))
    # with the slack it comes down, to 0 at most
    assert slack[-1] < slack[0] - 0.5 and min(slack) >= 0.0


def test_pid_with_the_slack_ends_lower_than_without():
    costs = [2.0] * 3 + [0.0] * 60
    assert _run(0.25, "pid", costs)[-1] < _run(0.0, "pid", costs)[-1]


def test_rollouts_over_the_slack_still_raise_the_multiplier():
    values = _run(0.25, "gradient", [0.5] * 3)   # half a step per episode: over the slack
    assert values[0] > 1.0 and values[2] > values[1]


def test_targets_move_only_zero_limits_and_only_with_a_step_cost():
    limits = np.array([0.0, 1.5])
    assert zero_limit_targets(limits, 0.25, [2.0, 2.0]).tolist() == [0.5, 1.5]
    assert zero_limit_targets(limits, 0.25, None).tolist() == [0.0, 1.5]
    assert zero_limit_targets(limits, 0.0, [1.0, 1.0]).tolist() == [0.0, 1.5]
    m = Multipliers(LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.1, init=1.0), 1)
    assert float(m.update([0.0], [1.0])[0]) == 1.0   # the default: the exact limit


def test_the_slack_is_checked():
    assert LagrangianConfig(cost_limit=0.0).zero_limit_slack == 0.0
    for bad in (-0.1, 1.5, True):
        with pytest.raises(SymlearnError, match="zero_limit_slack"):
            LagrangianConfig(cost_limit=0.0, zero_limit_slack=bad)
