"""An environment that reports ``info["cost"]`` only on the steps that pay it (GearSwitch: a gear
change costs 1.0, no ``"cost"`` key otherwise; never on an episode's first step, never under a
greedy policy). Whether it reports a cost is read from the steps training and evaluation take,
not from the first: the violation rate is a number (0 where evaluation paid nothing), not "n/a",
and ``ppo-lag`` without ``--cost`` trains on it; an environment none of whose steps in the first
rollout reports a cost is still refused, in one line."""

from __future__ import annotations

import json

import pytest
from cli_runner import run
from user_envs import GEAR_SWITCH, PLAIN_ROBOT, write_module

ENV = "gear_lab:GearSwitch-v0"
SMALL = ("--steps", 256, "--n-envs", 1, "--n-steps", 128, "--eval-episodes", 2, "--json")


@pytest.fixture
def inside(tmp_path, monkeypatch):
    write_module(tmp_path, "gear_lab", GEAR_SWITCH)
    write_module(tmp_path, "quiet_lab", PLAIN_ROBOT.replace("PlainRobot-v0", "QuietRobot-v0"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def _trained(capsys, *args):
    code, out, err = run(capsys, "train", "--env", ENV, *args, *SMALL)
    assert code == 0, err
    return json.loads(out)


def test_train_ppo_reports_a_violation_rate(inside, capsys):
    doc = _trained(capsys, "--algo", "ppo")
    # the greedy agent never changes gear: no evaluation step paid, but training's did -- 0, not n/a
    assert doc["violation_rate"] == 0.0 and doc["cost"] == 0.0
    code, out, err = run(capsys, "train", "--env", ENV, "--algo", "ppo", *SMALL[:-1])
    assert code == 0 and "violation rate 0.000" in out and "n/a" not in out, out


def test_ppo_lag_without_cost_trains_on_the_steps_that_report_one(inside, capsys):
    doc = _trained(capsys, "--algo", "ppo-lag")
    assert doc["violation_rate"] is not None and len(doc["multipliers"]) == 1


def test_ppo_lag_without_cost_is_refused_where_no_step_reports_one(inside, capsys):
    for algo in ("ppo-lag", "sb3-ppo-lag"):
        code, _, err = run(capsys, "train", "--env", "quiet_lab:QuietRobot-v0", "--algo", algo,
                           "--steps", 256, "--n-envs", 1, "--n-steps", 128)
        assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
        assert f"--algo {algo} without --cost" in err and "reports none in the first rollout (128 steps)" in err


def test_sb3_ppo_lag_with_a_dnf_cost_and_without_one(inside, capsys):
    pytest.importorskip("stable_baselines3")
    (inside / "rules.dnf").write_text("x > 0.5\n")
    doc = _trained(capsys, "--algo", "sb3-ppo-lag", "--cost", "rules.dnf")
    assert doc["violation_rate"] == 0.0 and doc["cost_kind"] == "dnf"
    doc = _trained(capsys, "--algo", "sb3-ppo-lag")   # the multiplier on the steps that pay the cost
    assert doc["violation_rate"] is not None and len(doc["multipliers"]) == 1


def test_learn_icrl_reports_a_violation_rate(inside, capsys):
    import gymnasium
    import gear_lab  # noqa: F401 -- registers GearSwitch-v0

    from symlearn.data import record

    record(gymnasium.make("GearSwitch-v0"), lambda observation: 1, 3, seed=0).save(inside / "demos.npz")
    code, out, err = run(capsys, "learn", "icrl", "--env", ENV, "--demos", "demos.npz", "--steps", 600,
                         "--iterations", 1, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["violation_rate"] is not None and doc["feasible_reward"] is not None
