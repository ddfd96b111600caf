"""PPO-Lagrangian's stall rule (``LagrangianConfig(reset_actor="auto")``, :mod:`symlearn.rl.ppo.stall`):
a fresh actor when the policy stays over its limit while the multiplier keeps rising."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from symlearn.errors import SymlearnError
from symlearn.rl.ppo import LagrangianConfig, LagrangianStall, PPOConfig, train_ppo


def _feed(rule: LagrangianStall, estimates, multipliers, returns=None) -> list[tuple[int, str]]:
    verdicts = []
    returns = returns or [float("nan")] * len(estimates)
    for i, (e, m, r) in enumerate(zip(estimates, multipliers, returns, strict=True), start=1):
        verdict = rule.update(i, None if e is None else np.array([e]), np.array([m]), r)
        if verdict:
            verdicts.append((i, verdict))
    return verdicts


def test_a_flat_cost_under_a_rising_heavy_multiplier_resets_and_keeps_a_fresh_actor_that_does_no_worse():
    rule = LagrangianStall(100, np.array([0.0]))   # window: 10 updates
    lambdas = [0.1 * i for i in range(1, 101)]
    # the window must start at lambda >= 1 (iteration 10), so the first reset is at iteration 19; a window
    # later (29) the fresh actor is judged, no worse, and kept; the next window resets again, and that is the last
    assert _feed(rule, [400.0] * 100, lambdas) == [(19, "reset"), (30, "reset")]
    assert rule.resets == [19, 30] and rule.restored == []


def test_a_fresh_actor_that_does_worse_is_replaced_by_the_old_one_and_no_more_are_tried():
    rule = LagrangianStall(100, np.array([0.0]))
    lambdas = [0.1 * i for i in range(1, 101)]
    # the old actor earns 500 at a cost of 50; after the reset the fresh one earns 9 at a cost of 45
    estimates = [50.0] * 19 + [45.0] * 81
    returns = [500.0] * 19 + [9.0] * 81
    assert _feed(rule, estimates, lambdas, returns) == [(19, "reset"), (29, "restore")]
    assert rule.restored == [29]


@pytest.mark.parametrize("case, estimates, lambdas", [
    ("the cost falls", [400.0 * 0.97 ** i for i in range(100)], [0.1 * i for i in range(1, 101)]),
    ("within the limit now and then", [0.0 if i % 5 == 0 else 400.0 for i in range(100)],
     [1.0 + 0.1 * i for i in range(100)]),
    ("the multiplier does not rise", [400.0] * 100, [2.0] * 100),
    ("the multiplier is light", [400.0] * 100, [0.009 * i for i in range(100)]),
    ("no update", [None] * 100, [0.1 * i for i in range(1, 101)]),
    ("a floor far below the peak", [400.0] * 10 + [14.0] * 90, [0.1 * i for i in range(1, 101)]),
])
def test_no_reset_where_the_policy_is_not_stuck(case, estimates, lambdas):
    rule = LagrangianStall(100, np.array([0.0]))
    assert _feed(rule, estimates, lambdas) == [], case


def test_never_in_the_last_third_of_the_run():
    rule = LagrangianStall(30, np.array([0.0]))    # window 8 updates; the last third starts after iteration 20
    estimates, lambdas = [400.0] * 30, [0.0] * 21 + [1.0 + 0.1 * i for i in range(9)]
    assert _feed(rule, estimates, lambdas) == []


def test_reset_actor_takes_auto_or_never():
    assert LagrangianConfig(cost_limit=0).reset_actor == "never"   # off by default: measured (module doc)
    with pytest.raises(SymlearnError, match="reset_actor"):
        LagrangianConfig(cost_limit=0, reset_actor="always")


def _run(reset_actor: str):
    from symlearn.envs.toy_navigation import ToyNavigationEnv

    # every step costs 1: the limit 0 is out of reach, the multiplier rises without end
    class AlwaysCosts(ToyNavigationEnv):
        def step(self, action):
            observation, reward, terminated, truncated, info = super().step(action)
            return observation, reward, terminated, truncated, {**info, "cost": 1.0}

    config = PPOConfig(seed=0, n_envs=2, n_steps=32, batch_size=64, n_epochs=1)
    return train_ppo(AlwaysCosts, 64 * 30, config, LagrangianConfig(cost_limit=0.0, reset_actor=reset_actor))


def test_training_resets_the_actor_and_keeps_the_critics():
    auto, never = _run("auto"), _run("never")
    resets = [h.iteration for h in auto.history if h.actor_reset]
    assert 1 <= len(resets) <= 2 and resets[0] <= 20 and not any(h.actor_reset for h in never.history)
    # up to the reset both runs are the same run; after it the actors differ
    first = resets[0] - 1
    assert [h.mean_return for h in auto.history[:first]] == [h.mean_return for h in never.history[:first]]
    assert not torch.equal(auto.policy.actor[0].weight, never.policy.actor[0].weight)
