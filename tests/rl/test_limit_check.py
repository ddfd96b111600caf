"""A PPO-Lagrangian run whose cost limit stayed out of reach says so (rl/ppo/limit_check.py)."""

import dataclasses
import json

from cli_runner import run

from symlearn.rl.ppo import PPOIteration, limit_warnings

BASE = PPOIteration(iteration=0, steps=0, episodes=1, mean_return=0.0, mean_length=100.0, mean_cost=(1.0,),
                    multipliers=(0.0,), policy_loss=0.0, value_loss=0.0, cost_value_loss=(0.0,), entropy=0.0,
                    approx_kl=0.0, clip_fraction=0.0, explained_variance=0.0, epochs=4.0, stopped_early=False,
                    learning_rate=1e-3, steps_per_second=1.0, seconds=1.0)


def history(multipliers, estimates):
    return [dataclasses.replace(BASE, iteration=i, multipliers=(m,), cost_estimate=(c,))
            for i, (m, c) in enumerate(zip(multipliers, estimates))]


def test_a_rising_heavy_multiplier_above_the_limit_is_warned_about():
    rising = history([2 + i for i in range(12)], [50.0] * 12)
    [warning] = limit_warnings(rising, [25.0])
    assert "stayed above --cost-limit 25 for the last 4 iterations" in warning and "rose from 10 to 13" in warning


def test_runs_that_meet_the_limit_or_barely_pay_are_not():
    met = history([2 + i for i in range(12)], [50.0] * 11 + [20.0])  # the last update saw it within the limit
    light = history([3.5 + 0.01 * i for i in range(12)], [2.0] * 12)  # the README's toy: a creeping 3.5
    falling = history([20 - i for i in range(12)], [50.0] * 12)  # the multiplier already comes down
    short = history([10, 11], [50.0, 50.0])
    assert limit_warnings(met, [25.0]) == limit_warnings(light, [0.0]) == []
    assert limit_warnings(falling, [25.0]) == limit_warnings(short, [25.0]) == []
    assert limit_warnings(history([10 + i for i in range(12)], [50.0] * 12), [25.0], advantage_scale="raw") == []


def test_train_warns_when_the_cost_is_paid_on_every_step(capsys, tmp_path):
    always, never = tmp_path / "always.dnf", tmp_path / "never.dnf"
    always.write_text("x > -10\n")
    never.write_text("x > 100\n")
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", always, "--steps", 6144,
                         "--multiplier-lr", 1)
    assert code == 0, err
    assert "warning: the cost stayed above --cost-limit 0" in out and "out of reach for this cost" in out
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", never, "--steps", 6144,
                         "--multiplier-lr", 1, "--json")
    assert code == 0 and json.loads(out)["warnings"] == []


def _with_scales(runs, reward_scales):
    return [dataclasses.replace(h, return_scales=(s, 1.0)) for h, s in zip(runs, reward_scales)]


def test_a_reward_that_stopped_varying_under_a_broken_limit_is_named():
    """CartPole held left of a line: every episode balances to 500 steps, the reward's return
    scale falls to a fiftieth of its widest, and the cost stays over its limit with the multiplier
    rising but below the heavy threshold: the one warning is about the reward's scale."""
    collapsing = [20.0] * 6 + [20.0 / 2 ** k for k in range(1, 7)]          # ends at 20 / 64
    broken = _with_scales(history([1 + 0.5 * i for i in range(12)], [100.0] * 12), collapsing)
    [warning] = limit_warnings(broken, [0.0])
    assert "vary 64x less than at their widest" in warning and "--reward-scale-floor 1" in warning
    # nothing when the reward still varies, the limit is met at the end, or the floor is raised already
    varied = _with_scales(history([1 + 0.5 * i for i in range(12)], [100.0] * 12), [20.0] * 6 + [5.0] * 6)
    met = _with_scales(history([1 + 0.5 * i for i in range(12)], [100.0] * 11 + [0.0]), collapsing)
    assert limit_warnings(varied, [0.0]) == limit_warnings(met, [0.0]) == []
    assert limit_warnings(broken, [0.0], reward_floor=1.0) == []


def test_the_advice_matches_the_kind_of_cost():
    """A run on the environment's own info["cost"] was told about 'a learned formula that also flags
    the expert' (issue 24, the fresh conveyor arm): the advice now follows what was constrained."""
    rising = history([2 + i for i in range(12)], [50.0] * 12)
    [formula] = limit_warnings(rising, [25.0])                       # the default: a learned formula
    [true_cost] = limit_warnings(rising, [25.0], cost_kind=None)
    [neural] = limit_warnings(rising, [25.0], cost_kind="neural")
    assert "learn dnf --validation" in formula
    assert "formula" not in true_cost and "expert" not in true_cost and "raise --steps" in true_cost
    assert "formula" not in neural and "charges the expert" in neural


ALWAYS_PAID = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class AlwaysPaid(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return np.zeros(1, np.float32), {"cost": 1.0}

    def step(self, action):
        self.t += 1
        return np.zeros(1, np.float32), float(action), False, self.t >= 20, {"cost": 1.0}


gym.register("AlwaysPaid-v0", entry_point=AlwaysPaid)
'''


def test_train_on_the_environments_own_cost_names_no_formula(capsys, tmp_path, monkeypatch):
    (tmp_path / "always_paid.py").write_text(ALWAYS_PAID)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, out, err = run(capsys, "train", "--env", "always_paid:AlwaysPaid-v0", "--algo", "ppo-lag",
                         "--steps", 6144, "--multiplier-lr", 1, "--json")
    assert code == 0, err
    warnings = json.loads(out)["warnings"]
    assert any("out of reach for this cost" in w for w in warnings), warnings
    assert not any("formula" in w or "learn dnf" in w for w in warnings), warnings


def _run(lengths, returns, multipliers):
    return [dataclasses.replace(BASE, iteration=i, mean_length=n, mean_return=r, multipliers=(m,), cost_estimate=(1.0,))
            for i, (n, r, m) in enumerate(zip(lengths, returns, multipliers))]


def test_episodes_ended_early_to_stop_paying_are_warned_about():
    # the traffic task with its start above the speed cap: 150-step episodes became 3-step crashes
    crashing = _run([150] * 6 + [40, 10, 4, 3, 3, 3], [90] * 6 + [30, 8, 3, 1.6, 1.6, 1.6], [1 + i for i in range(12)])
    warnings = limit_warnings(crashing, [0.0])
    [early] = [w for w in warnings if "shorter" in w]
    assert "mean length 150 -> 3 steps" in early and "--cost-limit at least" in early


def test_shorter_episodes_that_earn_more_or_run_unconstrained_are_not():
    # a goal reached sooner: shorter episodes, a higher return
    sooner = _run([150] * 6 + [60, 30, 20, 20, 20, 20], [1] * 6 + [5, 8, 10, 10, 10, 10], [1.0] * 12)
    # the multiplier never on: not the Lagrangian's doing
    unconstrained = _run([150] * 6 + [3] * 6, [90] * 6 + [1] * 6, [0.0] * 12)
    # a little shorter only
    slightly = _run([150] * 6 + [100] * 6, [90] * 6 + [30] * 6, [2.0] * 12)
    for run in (sooner, unconstrained, slightly):
        assert not [w for w in limit_warnings(run, [0.0]) if "shorter" in w]


def _safe_run(returns, estimates, multiplier=2.7):
    return [dataclasses.replace(BASE, iteration=i, mean_return=r, multipliers=(multiplier,), cost_estimate=(c,))
            for i, (r, c) in enumerate(zip(returns, estimates))]


# the no-fly drone of issue 24's second pass, in shape: it pays while exploring, earns ~10 within
# the limit at its best stretch, then keeps clear of the disc and ends at ~3, the cost at 0 throughout
DRONE_RETURNS = [0.0] * 6 + [4.0] * 6 + [10.0] * 12 + [6.0] * 6 + [3.0] * 30
DRONE_COSTS = [3.0] * 12 + [0.0] * 48


def test_a_safe_run_that_gave_up_what_it_earned_within_the_limit_is_warned_about():
    [warning] = limit_warnings(_safe_run(DRONE_RETURNS, DRONE_COSTS), [0.0], cost_kind=None)
    assert "the return fell from 10 (iterations" in warning and "to 3 over the last 20 iterations" in warning
    assert "--cost-scale-floor 1" in warning
    # at a limit of 0 the multiplier cannot come down: the slack that lets it is named too, unless set
    assert "--zero-limit-slack 0.25" in warning
    [slack] = limit_warnings(_safe_run(DRONE_RETURNS, DRONE_COSTS), [0.0], cost_kind=None, zero_slack=0.25)
    assert "gave up" in slack and "--zero-limit-slack" not in slack
    [budget] = limit_warnings(_safe_run(DRONE_RETURNS, DRONE_COSTS), [0.5], cost_kind=None)
    assert "--zero-limit-slack" not in budget


def test_safe_runs_that_kept_their_best_or_never_learned_are_not():
    kept = _safe_run([0.0] * 6 + [4.0] * 6 + [10.0] * 48, DRONE_COSTS)
    never = _safe_run([-5.0] * 60, [0.0] * 60)                         # nothing learned within the limit
    broken = _safe_run(DRONE_RETURNS, [3.0] * 12 + [0.0] * 18 + [2.0] * 30)   # over the limit at the end
    unpriced = _safe_run(DRONE_RETURNS, DRONE_COSTS, multiplier=0.0)   # no Lagrangian at work
    for run in (kept, never, broken, unpriced):
        assert not [w for w in limit_warnings(run, [0.0]) if "gave up" in w]
    # the remedy it names already in use: the warning stays, the advice changes
    [held] = limit_warnings(_safe_run(DRONE_RETURNS, DRONE_COSTS), [0.0], cost_floor=1.0)
    assert "gave up" in held and "--cost-scale-floor" not in held
    # a wobble of a tenth of the run's spread is not a gain given up
    wobble = _safe_run([0.0] * 6 + [-20.0] * 6 + [-19.0] * 12 + [-19.5] * 36, [3.0] * 12 + [0.0] * 48)
    assert not [w for w in limit_warnings(wobble, [0.0]) if "gave up" in w or "ended where it started" in w]


def test_a_safe_run_that_never_earned_more_than_its_start_says_so():
    """The speed cart's seed 1: the cart docks only in episodes that pay the cost (-8 instead of
    -20); the multiplier keeps it safe, and it ends never docking, as it started."""
    returns = [-20.0] * 20 + [-8.0] * 10 + [-20.0] * 30
    costs = [0.0] * 20 + [8.0] * 10 + [0.0] * 30
    [warning] = limit_warnings(_safe_run(returns, costs), [0.0], cost_kind=None)
    assert "the return ended at the lowest the run saw (-20; at most -8, only while the cost was paid)" in warning
    # seed 2: docked while exploring at a cost in its first iterations, never after
    [warning] = limit_warnings(_safe_run([-12.0] * 5 + [-20.0] * 55, [9.0] * 5 + [0.0] * 55), [0.0])
    assert "the lowest the run saw (-20" in warning
