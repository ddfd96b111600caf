"""A limit of 0 with a slack (LagrangianConfig.zero_limit_slack): a rollout without cost lowers the
multiplier, one with a cost step still raises it; without the slack it can only rise."""

import numpy as np
import pytest

from symlearn.errors import SymlearnError
from symlearn.rl.ppo import LagrangianConfig, Multipliers
from symlearn.rl.ppo.multipliers import zero_limit_targets


def _run(slack: float, rule: str, costs: list[float], resolution: float = 0.2) -> list[float]:
    m = Multipliers(LagrangianConfig(cost_limit=0.0, update=rule, lr=0.1, init=1.0, zero_limit_slack=slack), 1)
    return [float(m.update([c], [resolution])[0]) for c in costs]


@pytest.mark.parametrize("rule", ["adam", "gradient", "pid"])
def test_at_limit_zero_a_cost_free_stretch_lowers_the_multiplier_only_with_the_slack(rule):
    costs = [3.0] * 5 + [0.0] * 40   # an exploring agent's violations, then a safe (over-cautious) agent
    exact = _run(0.0, rule, costs)
    slack = _run(0.5, rule, costs)
    # exact 0: a cost of 0 is no error, the multiplier never comes down
    assert exact[-1] >= max(exact[:5]) - 1e-9
    # with the slack it does, while staying non-negative
    assert slack[-1] < slack[4] and min(slack) >= 0.0


def test_one_cost_step_in_a_rollout_still_raises_the_multiplier():
    # resolution 0.2: one cost step in the rollout shows as J_c = 0.2, over the target 0.1
    values = _run(0.5, "gradient", [0.2] * 3)
    assert values[0] > 1.0 and values[2] > values[1]


def test_targets_move_only_zero_limits_and_only_with_a_resolution():
    limits = np.array([0.0, 1.5])
    assert zero_limit_targets(limits, 0.5, [0.4, 0.4]).tolist() == [0.2, 1.5]
    assert zero_limit_targets(limits, 0.5, None).tolist() == [0.0, 1.5]
    assert zero_limit_targets(limits, 0.0, [0.4, 0.4]).tolist() == [0.0, 1.5]
    m = Multipliers(LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.1, init=1.0), 1)
    assert float(m.update([0.0], [0.2])[0]) == 1.0   # the default: the exact limit


def test_the_slack_is_checked():
    assert LagrangianConfig(cost_limit=0.0).zero_limit_slack == 0.0
    for bad in (-0.1, 1.5, True):
        with pytest.raises(SymlearnError, match="zero_limit_slack"):
            LagrangianConfig(cost_limit=0.0, zero_limit_slack=bad)
