"""``symlearn learn icrl``: a short run end to end, and the bad input of issue 12 as one-line errors."""

import json

import numpy as np
import pytest

from cli_runner import run
from dict_lift_env import lift_demonstrations
from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.blocked_point import expert_demonstrations

MODULE = "symlearn.cli.learn_icrl_command"


@pytest.fixture(autouse=True)
def icrl_registered(monkeypatch):
    """The command until ``learn_command.LEARN_SUBCOMMANDS`` lists it."""
    from symlearn.cli import learn_command

    if MODULE not in learn_command.LEARN_SUBCOMMANDS:
        monkeypatch.setattr(learn_command, "LEARN_SUBCOMMANDS", (*learn_command.LEARN_SUBCOMMANDS, MODULE))


def test_short_run_writes_the_cost_and_reports_the_metrics(capsys, tmp_path):
    out = tmp_path / "cost.safetensors"
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--n-demos", 3, "--steps", 2048,
                            "--iterations", 2, "--cost-inputs", "x,y", "--env-kwargs", '{"wall": -4.0}',
                            "-o", out, "--log", tmp_path / "icrl.csv", "--json")
    assert code == 0, err
    doc = json.loads(stdout)
    rows = (tmp_path / "icrl.csv").read_text().splitlines()
    assert rows[0].startswith("iteration,") and "violation_rate" in rows[0] and len(rows) == 3
    for key in ("reward", "violation_rate", "feasible_reward", "recovery_auc", "iterations", "seconds"):
        assert key in doc
    assert doc["iterations"] == 2 and 0 <= doc["violation_rate"] <= 1 and 0 <= doc["recovery_auc"] <= 1
    assert out.is_file() and out.with_suffix(".json").is_file() and doc["files"] == [str(out),
                                                                                        str(out.with_suffix(".json"))]
    from symlearn.envs.blocked_point import BlockedPoint
    from symlearn.learners.neural import NeuralCost

    cost = NeuralCost.load(out, BlockedPoint())
    # the inputs read: those the selection kept of the candidates x, y (which, at this budget,
    # depends on the nominal policy; it changed with MCE-ICRL's default beta)
    assert set(cost.phi.obs_dims) <= {0, 1} and list(cost.phi.obs_dims) == doc["cost_inputs"]["entries"]
    assert len(cost.lambdas) == len(doc["lambda"])
    assert doc["expert_cost"]["episodes"] == 3 and cost.expert_level == pytest.approx(doc["expert_cost"]["mean"])


def _save(tmp_path, states, name="demos.npz"):
    path = tmp_path / name
    Demonstrations([Trajectory(states=states, actions=np.zeros((len(states) - 1, 2)))]).save(path)
    return path


def _refused(capsys, *args, match):
    code, stdout, err = run(capsys, "learn", "icrl", *args)
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert match in err, err
    return err


def test_demonstrations_of_another_observation_shape(capsys, tmp_path):
    path = _save(tmp_path, np.zeros((5, 3)))
    err = _refused(capsys, "--env", "blocked-point", "--demos", path, match="shape (3,), the space's is (4,)")
    assert str(path) in err


def test_nan_observations(capsys, tmp_path):
    path = _save(tmp_path, np.zeros((5, 4)))
    with np.load(path, allow_pickle=False) as archive:
        arrays = {k: archive[k] for k in archive.files}
    arrays["states"] = arrays["states"].astype(np.float64)
    arrays["states"][2, 1] = np.nan
    np.savez(path, **arrays)
    err = _refused(capsys, "--env", "blocked-point", "--demos", path, match="non-finite value (nan) at step 2")
    assert str(path) in err


def test_unknown_env_kwargs_key_and_bad_json(capsys):
    _refused(capsys, "--env", "blocked-point", "--env-kwargs", '{"wal": -3}', match="unknown --env-kwargs key 'wal'")
    _refused(capsys, "--env", "blocked-point", "--env-kwargs", '{"wall": ', match="not JSON")
    _refused(capsys, "--env", "blocked-point", "--env-kwargs", '{"wall": 99}', match="wall must be")
    _refused(capsys, "--env", "blocked-point", "--env-kwargs", '{"wall": "left"}', match="'wall' of blocked-point must be a number")
    _refused(capsys, "--env", "blocked-point", "--env-kwargs", '[1]', match="must be a JSON object")


@pytest.mark.parametrize("beta", ["0", "-0.5", "nan"])
def test_beta_must_be_positive(capsys, beta):
    _refused(capsys, "--env", "blocked-point", "--beta", beta, match="--beta must be a number > 0")


def test_other_refusals(capsys, tmp_path):
    _refused(capsys, "--env", "blocked-point", "-o", tmp_path / "cost.pt", match="must end in .safetensors")
    _refused(capsys, "--env", "blocked-pont", match="did you mean 'blocked-point'")
    _refused(capsys, "--env", "gridworld", match="no environment for neural ICRL")
    _refused(capsys, "--env", "blocked-point", "--expert-steps", 0, match="--expert-steps must be at least 1")
    _refused(capsys, "--env", "blocked-point", "--method", "gacl", "--lambda-lr", 0.1,
             match="for --method mce-icrl, me-icrl or vme-icrl")
    _refused(capsys, "--env", "blocked-point", "--method", "me-icrl", "--cost-sparsity", 0.1,
             match="for --method mce-icrl only")
    _refused(capsys, "--env", "blocked-point", "--cost-sparsity", "nan", match="--cost-sparsity must be a number >= 0")
    _refused(capsys, "--env", "blocked-point", "--select-inputs", 0.6, match="--select-inputs must be a number in [0, 0.5]")
    _refused(capsys, "--env", "blocked-point", "--lambda-lr", -1, match="--lambda-lr must be a number > 0")
    _refused(capsys, "--env", "blocked-point", "--cost-inputs", "x,z", match="unknown observation entry 'z'")
    assert not (tmp_path / "cost.pt").exists()


def test_demonstrations_without_actions(capsys, tmp_path):
    path = tmp_path / "states.npz"
    Demonstrations([Trajectory(states=np.zeros((5, 4)))]).save(path)
    _refused(capsys, "--env", "blocked-point", "--demos", path, match="needs actions")


@pytest.mark.parametrize("method", ["mce-icrl", "me-icrl", "gacl"])
def test_recorded_expert_demonstrations_are_accepted(capsys, tmp_path, method):
    path = tmp_path / "expert.npz"
    expert_demonstrations(2, seed=1).save(path)
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--demos", path, "--steps", 2048,
                            "--iterations", 1, "--method", method, "--json")
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["iterations"] == 1 and doc["method"] == method and doc["recovery_auc"] is not None
    # no --cost-inputs: the entries BlockedPoint declares its constraint to be about are the candidates
    inputs = doc["cost_inputs"]
    assert inputs["from"] == "declared features" and inputs["selection"]["candidates"] == [0, 1]
    assert inputs["entries"] == inputs["selection"]["selected"] and set(inputs["names"]) <= {"x", "y"}


def test_all_cost_inputs_sparsity_and_the_baselines_multiplier_step(capsys):
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--n-demos", 2, "--steps", 1024,
                            "--iterations", 1, "--cost-inputs", "all", "--select-inputs", 0, "--cost-sparsity", 0.05,
                            "--json")
    assert code == 0, err
    inputs = json.loads(stdout)["cost_inputs"]
    assert inputs["names"] == ["x", "y", "vx", "vy"] and inputs["from"] == "given" and len(inputs["shares"]) == 4
    assert inputs["selection"] is None
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--n-demos", 2, "--steps", 1024,
                            "--iterations", 1, "--method", "vme-icrl", "--lambda-lr", 0.5)
    assert code == 0, err
    assert "cost inputs (declared features, selected): " in stdout


def test_without_a_scripted_expert_a_lagrangian_expert_is_trained_and_cached(capsys, tmp_path):
    """PointCircle has no scripted expert but a ground-truth cost: PPO-Lagrangian makes the
    demonstrations, cached under --expert-cache; the second run reads them instead of training."""
    args = ("learn", "icrl", "--env", "point-circle", "--n-demos", 2, "--expert-steps", 1024, "--steps", 1024,
            "--iterations", 1, "--expert-cache", tmp_path, "--json")
    code, stdout, err = run(capsys, *args)
    assert code == 0, err
    assert "no scripted expert: PPO-Lagrangian" in err
    cached = list(tmp_path.glob("point-circle_s0_1024_*.npz"))
    assert len(cached) == 1
    first = json.loads(stdout)["expert_reward"]
    stamp = cached[0].stat().st_mtime_ns
    code, stdout, err = run(capsys, *args)
    assert code == 0, err
    assert cached[0].stat().st_mtime_ns == stamp and json.loads(stdout)["expert_reward"] == first


def test_demonstrations_of_a_dict_observing_environment(capsys, tmp_path, monkeypatch):
    """``record`` keeps a Dict observation as feature states; learn icrl reads them through the
    same flat view as the environment (before: an internal TypeError from a dict)."""
    lift_demonstrations(tmp_path, monkeypatch, 4)
    code, out, err = run(capsys, "learn", "icrl", "--env", "lift_lab:DictLift-v0", "--demos", "lift.jsonl",
                         "--steps", 600, "--iterations", 1, "--json")
    assert code == 0, err
    assert json.loads(out)["reward"] is not None


def test_a_users_environment_named_by_feature_names_only(capsys, tmp_path, monkeypatch):
    """A user's environment with ``feature_names`` (one per observation entry) but no
    ``observation_names``: the report names the cost's inputs (before: by column index), says
    where the demonstrations came from, and the cost file's provenance records it."""
    import gymnasium

    from user_envs import POINT_ROBOT, careful_expert

    (tmp_path / "named_lab.py").write_text(POINT_ROBOT.replace("PointRobot-v0", "NamedRobot-v0"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import named_lab  # noqa: F401 -- registers NamedRobot-v0

    from symlearn.data import record

    record(gymnasium.make("NamedRobot-v0", horizon=20), careful_expert(), 4, seed=0).save(tmp_path / "demos.npz")
    code, out, err = run(capsys, "learn", "icrl", "--env", "named_lab:NamedRobot-v0", "--env-kwargs",
                         '{"horizon": 20}', "--demos", "demos.npz", "--steps", 600, "--iterations", 1,
                         "-o", "cost.safetensors")
    assert code == 0, err
    assert "warning" not in err, err  # recorded in the environment --env names
    line = next(line for line in out.splitlines() if "cost inputs" in line)
    read = line.split(":", 1)[1].split(",")
    assert read and all(entry.split()[0] in ("px", "py") for entry in read), line
    assert "  learned from demos.npz" in out, out
    config = json.loads((tmp_path / "cost.json").read_text())["config"]
    assert config["provenance"]["demonstrations"] == "demos.npz"
    assert config["provenance"]["learner"] == "NeuralMCEICRL"


def test_demonstrations_recorded_in_another_environment_get_a_warning(capsys, tmp_path, monkeypatch):
    """learn icrl reads its --demos through recipes.experts.demonstrations, so a file recorded in
    another environment than --env is read with one warning line (the same check as learn dnf)."""
    import gymnasium

    from user_envs import PLAIN_ROBOT, POINT_ROBOT, careful_expert

    (tmp_path / "here_lab.py").write_text(POINT_ROBOT.replace("PointRobot-v0", "HereRobot-v0"))
    (tmp_path / "there_lab.py").write_text(PLAIN_ROBOT.replace("PlainRobot-v0", "ThereRobot-v0"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import here_lab  # noqa: F401 -- registers HereRobot-v0

    from symlearn.data import record

    record(gymnasium.make("HereRobot-v0", horizon=10), careful_expert(), 2, seed=0).save(tmp_path / "demos.npz")
    code, out, err = run(capsys, "learn", "icrl", "--env", "there_lab:ThereRobot-v0", "--demos", "demos.npz",
                         "--steps", 200, "--iterations", 1, "--select-inputs", 0)
    assert code == 0, err
    warning = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warning) == 1 and "HereRobot-v0" in warning[0] and "there_lab:ThereRobot-v0" in warning[0], err


def test_a_wall_nobody_tuned_on_is_recovered_at_the_defaults(capsys):
    """Issue 25's BlockedPoint target at a wall position nobody tuned on (-2; seed 0, where the
    current-sample cost update ended with the cost higher on the allowed side: AUC 0.0): recovery
    AUC >= 0.9 and violation <= 0.05 with no flag but the wall (about 15 s)."""
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "blocked-point", "--env-kwargs", '{"wall": -2}',
                            "--json", "-q")
    assert code == 0, err
    doc = json.loads(stdout)
    assert doc["recovery_auc"] >= 0.9 and doc["violation_rate"] <= 0.05


def test_cost_memory_belongs_to_mce_icrl(capsys):
    _refused(capsys, "--env", "blocked-point", "--method", "me-icrl", "--cost-memory", "current",
             match="--cost-memory is a setting of --method mce-icrl, not me-icrl")


def test_unnamed_observation_entries_are_x0_x1_as_learn_dnf_names_them(capsys, tmp_path, monkeypatch):
    """The tests' rover names nothing: --cost-inputs reads x0, x1 and the report names them so."""
    import gymnasium as gym
    import rover_env

    from symlearn.data import record

    monkeypatch.chdir(tmp_path)
    record(gym.make("Rover-v0"), rover_env.expert, 2, seed=0).save("rover.npz")
    code, stdout, err = run(capsys, "learn", "icrl", "--env", "rover_env:Rover-v0", "--demos", "rover.npz",
                            "--steps", 1024, "--iterations", 1, "--cost-inputs", "x0,x1", "--json")
    assert code == 0, err
    inputs = json.loads(stdout)["cost_inputs"]
    assert inputs["entries"] == [0, 1] and inputs["names"] == ["x0", "x1"]
    code, _, err = run(capsys, "learn", "icrl", "--env", "rover_env:Rover-v0", "--demos", "rover.npz",
                       "--cost-inputs", "speed")
    assert code == 2 and "x0..x3" in err


def test_names_of_info_features_that_are_not_the_observation_name_no_cost_input(capsys, tmp_path, monkeypatch):
    """A cart observing (vel, pos) with info["features"] {"pos", "vel"}: those names are not the
    observation's entries, so --cost-inputs pos is refused (it read the velocity before) and the
    report calls the entries x0, x1."""
    import sys

    import gymnasium as gym
    from user_envs import SWAPPED_CART

    from symlearn.data import record

    (tmp_path / "swapped_cart.py").write_text(SWAPPED_CART)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import swapped_cart  # noqa: F401 -- registers SwappedCart-v0

    try:
        record(gym.make("SwappedCart-v0"), lambda o: np.array([1.0], np.float32), 2, seed=0).save("cart.npz")
        code, _, err = run(capsys, "learn", "icrl", "--env", "swapped_cart:SwappedCart-v0", "--demos", "cart.npz",
                           "--cost-inputs", "pos")
        assert code == 2 and "unknown observation entry 'pos'" in err and "x0..x1" in err, err
        code, out, err = run(capsys, "learn", "icrl", "--env", "swapped_cart:SwappedCart-v0", "--demos", "cart.npz",
                             "--steps", 512, "--iterations", 1, "--cost-inputs", "x1", "--json")
        assert code == 0, err
        assert json.loads(out)["cost_inputs"]["names"] == ["x1"]
    finally:
        sys.modules.pop("swapped_cart", None)
        gym.registry.pop("SwappedCart-v0", None)


def test_a_cost_with_every_lambda_at_zero_is_warned_about():
    """A fresh conveyor arm (issue 24, seed 2) ended with "lambda 0, 0, 0, 0" and no other sign that
    the cost is 0 everywhere; the report now says so in a warning line."""
    from symlearn.cli.learn_icrl_command import _render, lambda_warnings

    assert lambda_warnings([0.0, 0.5]) == []
    [warning] = lambda_warnings([0.0, 0.0, 0.0])
    assert "0 everywhere" in warning and "constrains nothing" in warning
    doc = {"method": "mce-icrl", "env": "e", "iterations": 1, "seconds": 1.0, "reward": 0.0, "expert_reward": None,
           "violation_rate": None, "feasible_reward": None, "recovery_auc": None, "recovery_iou": None,
           "lambda": [0.0], "cost_inputs": {"names": ["x"], "entries": [0], "shares": [1.0], "from": "all",
                                            "selection": False}, "files": [], "warnings": [warning]}
    assert f"warning: {warning}" in _render(doc).splitlines()


def test_a_zero_cost_whose_inputs_do_not_separate_names_that_cause():
    """boost_rover (issue 24, second pass): the constraint is about an action and the cost's inputs
    (x, battery) tell the demonstrations' states from the nominal policy's at a held-out AUC of
    0.66; the warning says so and names --cost-inputs, not another seed."""
    from symlearn.cli.learn_icrl_command import lambda_warnings

    inputs = {"names": ["x0", "x1"], "selection": {"all_candidates_auc": 0.66}}
    [warning] = lambda_warnings([0.0, 0.0], inputs)
    assert "0 everywhere" in warning and "AUC 0.66" in warning and "--cost-inputs" in warning
    assert "x0, x1" in warning and "another --seed" not in warning
    [separable] = lambda_warnings([0.0], {"names": ["x"], "selection": {"all_candidates_auc": 0.99}})
    assert "another --seed" in separable
    assert lambda_warnings([0.0, 0.1], inputs) == []
    assert "another --seed" in lambda_warnings([0.0], {"names": ["x"], "selection": False})[0]


def test_a_cost_that_is_zero_in_effect_is_warned_about_too():
    """boost_rover with the dual step's fix: lambda 0 / 0 / 0.00016 / 0.00004, a charge of 0.0003 on
    the policy's episodes against the 2.7 of reward they earn over the expert -- 0 in effect, warned
    like a cost with every lambda at 0; a cost that charges the policy more than 1 % of that is not."""
    from symlearn.cli.learn_icrl_command import lambda_warnings, negligible_charge

    doc = {"lambda": [0.0, 0.0, 0.00016, 0.00004], "reward": 8.89, "expert_reward": 6.21,
           "history": [{"policy_features": [0.03, 0.04, 1.6, 0.29]}]}
    charge, gap = negligible_charge(doc)
    assert charge < 0.001 and abs(gap - 2.68) < 1e-9
    [warning] = lambda_warnings(doc["lambda"], {"names": ["x0", "x1"], "selection": {"all_candidates_auc": 0.66}},
                                (charge, gap))
    assert "0 in effect" in warning and "constrains nothing" in warning and "AUC 0.66" in warning
    assert negligible_charge({**doc, "lambda": [0.0, 0.0, 0.1, 0.0]}) is None     # 0.16 > 1 % of 2.68
    assert negligible_charge({**doc, "reward": 6.0}) is None                       # no gap over the expert
    assert negligible_charge({**doc, "expert_reward": None}) is None
    assert negligible_charge({**doc, "lambda": [0.0] * 4}) is None                 # every lambda 0: the other warning
