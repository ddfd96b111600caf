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


def _env(costly: int):
    """An environment class whose steps cost 1 for the first ``costly`` steps of the whole run (an
    exploring agent's brushes), 0 after (an agent that has become safe)."""
    import gymnasium as gym
    from gymnasium import spaces

    class BrushThenSafe(gym.Env):
        steps = 0   # shared by the copies: the run's step count

        def __init__(self):
            self.observation_space = spaces.Box(-1.0, 1.0, (1,), dtype=np.float32)
            self.action_space = spaces.Discrete(2)

        def reset(self, *, seed=None, options=None):
            super().reset(seed=seed)
            self.t = 0
            return np.zeros(1, dtype=np.float32), {}

        def step(self, action):
            self.t += 1
            BrushThenSafe.steps += 1
            cost = 1.0 if BrushThenSafe.steps <= costly else 0.0
            return np.zeros(1, dtype=np.float32), 0.0, False, self.t >= 16, {"cost": cost}

    return BrushThenSafe


@pytest.mark.parametrize("slack", [0.0, 0.25])
def test_training_passes_the_step_cost_so_a_safe_agent_lowers_its_multiplier(slack):
    pytest.importorskip("torch")
    from symlearn.rl.ppo import PPOConfig, train_ppo

    env = _env(costly=64)
    result = train_ppo(lambda: env(), 64 * 12, PPOConfig(seed=0, n_envs=1, n_steps=64, batch_size=64, n_epochs=1),
                       # the gradient rule: Adam's steps after a violation of 16 are ~lr x 0.25 / 16 down
                       LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.1, zero_limit_slack=slack))
    lambdas = [h.multipliers[0] for h in result.history]
    if slack:   # violations in the first rollout only: the multiplier comes back down
        assert lambdas[-1] < max(lambdas) - 0.2
    else:       # the exact limit: it never comes down
        assert all(b >= a - 1e-12 for a, b in zip(lambdas, lambdas[1:]))
