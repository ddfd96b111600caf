"""``symlearn train``: PPO / PPO-Lagrangian from the command line, a DNF cost, pruning, model files."""

import importlib.util
import json

import numpy as np
import pytest

from cli_runner import run
from symlearn.envs.toy_navigation import UNSAFE_DNF
from symlearn.logic.dnf import load as load_dnf
from symlearn.logic.dnf import parse


def test_ppo_lag_on_a_dnf_cost_with_pruning(capsys, tmp_path):
    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF + "\nx > 5\n")  # a rule no agent can ever fire (x lies in [0, 1])
    agent = tmp_path / "agent.safetensors"
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, "--prune", "--steps", 2048,
                         "--eval-episodes", 2, "-o", agent, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert {"return", "cost", "violation_rate", "pruned", "seconds"} <= set(doc)
    assert 0 <= doc["violation_rate"] <= 1 and len(doc["multipliers"]) == 1
    assert isinstance(doc["actor_resets"], list)   # iterations whose actor was renewed (LagrangianConfig.reset_actor)
    assert "x > 5" in doc["pruned"]
    pruned = load_dnf(tmp_path / "toy.pruned.dnf")
    assert "x > 5" not in str(pruned) and set(map(str, pruned.conjunctions)) == set(doc["kept"])
    assert agent.exists() and agent.with_suffix(".json").exists()


def test_plain_ppo_is_the_default_without_a_cost_and_an_unreported_cost_is_null(capsys):
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--steps", 512, "--n-envs", 2, "--n-steps", 64,
                         "--eval-episodes", 1, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["algo"] == "ppo" and doc["multipliers"] is None and doc["return"] > 0
    assert doc["cost"] is None and doc["violation_rate"] is None and doc["cost_kind"] is None
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--steps", 128, "--n-envs", 1, "--n-steps", 128,
                         "--eval-episodes", 1)
    assert code == 0, err
    assert "ground-truth cost n/a per episode, violation rate n/a" in out


def test_the_greedy_evaluation_reports_what_the_learned_cost_charges(capsys, tmp_path):
    """An agent trained on a learned cost is evaluated on it too (summed over rules, per episode):
    where the environment reports no info["cost"] it is the only sign that the agent kept, or
    broke, the constraint it was trained on. A formula true everywhere charges every step."""
    rules = tmp_path / "everywhere.dnf"
    rules.write_text("x0 > -100\n")
    small = ("--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 2)
    for algo in ("ppo-lag", "ppo", "sb3-ppo-lag"):
        code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", rules, "--algo", algo, *small,
                             "--json")
        assert code == 0, err
        doc = json.loads(out)
        assert doc["cost"] is None   # CartPole reports none
        assert doc["learned_cost"] == pytest.approx(doc["return"])   # 1 per step, as CartPole's reward
        assert doc["cost_limit"] == (None if algo == "ppo" else 0.0)
        # a Lagrangian whose greedy agent still pays more than the limit says so, whatever its multiplier
        kept = [w for w in doc["warnings"] if "does not keep --cost-limit 0" in w]
        assert len(kept) == (0 if algo == "ppo" else 1), doc["warnings"]
        assert all("--depth-weight 3" in w for w in kept)   # a DNF cost: the depth-shaped cost is named
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", rules, *small)
    assert code == 0, err
    assert "per episode (limit 0), ground-truth cost n/a per episode" in out and "learned cost " in out
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", *small, "--json")
    assert code == 0 and json.loads(out)["learned_cost"] is None, err
    never = tmp_path / "never.dnf"
    never.write_text("x0 > 100\n")
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", never, *small, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["learned_cost"] == 0 and doc["warnings"] == []


ROBOT = "point_robot_env:HazardRobot-v0"   # tests/support/point_robot_env.py, a user's module
HAZARD = "x > 0.4 & x < 0.6 & y < 0.6\n"


def test_a_user_module_trains_ppo_lag_on_a_dnf_and_on_its_own_cost(capsys, tmp_path):
    rules = tmp_path / "hazard.dnf"
    rules.write_text(HAZARD)
    small = ("--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 2, "--json")
    code, out, err = run(capsys, "train", "--env", ROBOT, "--cost", rules, *small)
    assert code == 0, err
    doc = json.loads(out)   # ppo-lag is the default with a cost; the true cost is the environment's
    assert (doc["algo"], doc["cost_kind"], len(doc["multipliers"])) == ("ppo-lag", "dnf", 1)
    assert doc["cost"] is not None and 0 <= doc["violation_rate"] <= 1 and doc["steps"] == 256
    code, out, err = run(capsys, "train", "--env", ROBOT, "--algo", "ppo-lag", *small)   # info["cost"]
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_kind"] is None and doc["multipliers"] is not None and doc["cost"] is not None
    # names only in a dict info["features"], and environment keyword arguments
    code, out, err = run(capsys, "train", "--env", ROBOT, "--env-kwargs", '{"named_features": true, "max_steps": 20}',
                         "--cost", rules, "--prune", *small)
    assert code == 0, err
    assert json.loads(out)["kept"] + json.loads(out)["pruned"] == ["x > 0.4 & x < 0.6 & y < 0.6"]


def test_a_dnf_cost_needs_feature_names(capsys, tmp_path):
    rules = tmp_path / "pole.dnf"
    rules.write_text("pole_angle > 0.1\n")
    code, _, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", rules, "--steps", 128)
    assert code == 2 and "--features" in err and str(rules) in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", rules, "--features",
                         "cart_x,cart_v,pole_angle,pole_v", "--steps", 128, "--n-envs", 1, "--n-steps", 128,
                         "--eval-episodes", 1, "--json")
    assert code == 0, err
    assert json.loads(out)["cost_kind"] == "dnf" and json.loads(out)["cost"] is None
    code, _, err = run(capsys, "train", "--env", "CartPole-v1", "--cost", rules, "--features", "pole_angle,b",
                       "--steps", 128)
    _one_line(code, err, "4")   # two names for four observation entries
    code, _, err = run(capsys, "train", "--env", ROBOT, "--cost", rules, "--features", "x,x", "--steps", 128)
    _one_line(code, err, "twice")
    code, _, err = run(capsys, "train", "--env", ROBOT, "--features", "x,y", "--steps", 128)
    _one_line(code, err, "--features", "--cost")


def _one_line(code, err, *needles):
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for needle in needles:
        assert needle in err, (needle, err)


@pytest.mark.parametrize("flags, needle", [
    (("--steps", 0), "--steps must be between 1"),
    (("--steps", "1e20"), "--steps must be between 1"),
    (("--steps", "2.5"), "--steps must be a whole number"),
    (("--cost-limit", -1, "--algo", "ppo-lag"), "--cost-limit must be a finite number >= 0"),
    (("--cost-limit", "nan"), "--cost-limit must be a finite number >= 0"),
    (("--multiplier-init", -0.5), "--multiplier-init must be a number in [0, 1e6]"),
    (("--multiplier-init", "inf"), "--multiplier-init must be a number in [0, 1e6]"),
    (("--multiplier-init", "1e300"), "--multiplier-init must be a number in [0, 1e6]"),
    (("--reward-scale-floor", 0), "--reward-scale-floor must be a number in (0, 1]"),
    (("--reward-scale-floor", "nan"), "--reward-scale-floor must be a number in (0, 1]"),
    (("--reward-scale-floor", 2), "--reward-scale-floor must be a number in (0, 1]"),
    (("--algo", "sb3-ppo-lag", "--reward-scale-floor", "1"), "--reward-scale-floor is an option of our PPO"),
    (("--cost-scale-floor", 0), "--cost-scale-floor must be a number in (0, 1]"),
    (("--cost-scale-floor", "inf"), "--cost-scale-floor must be a number in (0, 1]"),
    (("--algo", "sb3-ppo-lag", "--cost-scale-floor", "1"), "--cost-scale-floor is an option of our PPO"),
    (("--zero-limit-slack", -0.1), "--zero-limit-slack must be a number in [0, 1]"),
    (("--zero-limit-slack", "nan"), "--zero-limit-slack must be a number in [0, 1]"),
    (("--algo", "sb3-ppo-lag", "--zero-limit-slack", "0.25"), "--zero-limit-slack is an option of our PPO"),
    (("--n-envs", 0), "--n-envs must be between 1"),
    (("--n-envs", 100, "--n-steps", 100_000), "steps per rollout"),
    (("--n-steps", "1e12"), "--n-steps must be between 1"),
    (("--algo", "ppo-lag"), "reports none"),                    # CartPole has no info["cost"]
    (("--algo", "sb3-sac"), "acts only in Box action spaces"),
    (("-o", "agent.zip"), "never stable-baselines3's pickled .zip"),
    (("--env-kwargs", '{"gravity": 1}'), "unknown --env-kwargs key 'gravity'"),
    (("--env-kwargs", "[1]"), "must be a JSON object"),
    (("--algo", "sb3-ppo", "--normalize-values"), "--normalize-values is an option of our PPO"),
    (("--algo", "sb3-ppo", "--reset-actor", "never"), "--reset-actor is an option of our PPO"),
    (("--depth-weight", 3), "--depth-weight shapes a DNF cost"),
    (("--depth-weight", -1), "--depth-weight must be a finite number >= 0"),
    (("--depth-weight", "inf"), "--depth-weight must be a finite number >= 0"),
])
def test_bad_numbers_and_choices_are_one_line(capsys, flags, needle):
    _one_line(*run(capsys, "train", "--env", "CartPole-v1", *flags)[::2], needle)


def test_bad_input_is_one_line(capsys, tmp_path):
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--cost-limit", -1)
    assert code == 2 and "--cost-limit" in err
    code, _, err = run(capsys, "train", "--env", "nowhere-v9")
    assert code == 2 and "Traceback" not in err
    rules = tmp_path / "bad.dnf"
    parse("speed > 1").save(rules)
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules)
    assert code == 2 and "speed" in err and str(rules) in err
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--prune")
    assert code == 2 and "--cost" in err


def test_ppo_options_reach_the_trainer_and_the_model_file(capsys, tmp_path):
    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF)
    agent = tmp_path / "agent.safetensors"
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, "--steps", 256,
                         "--n-envs", 2, "--n-steps", 64, "--advantage-scale", "returns", "--multiplier-update", "adam",
                         "--normalize-observations", "--normalize-values", "--eval-episodes", 1, "-o", agent, "--json")
    assert code == 0, err
    assert json.loads(out)["steps"] == 256
    training = json.loads(agent.with_suffix(".json").read_text())
    text = json.dumps(training)
    for needle in ('"advantage_scale": "returns"', '"update": "adam"', '"normalize_observations": true',
                   '"normalize_values": true', '"n_envs": 2', '"n_steps": 64'):
        assert needle in text, needle
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--n-envs", 0)
    assert code == 2 and "--n-envs" in err


def test_log_csv_has_a_row_per_iteration_with_true_and_learned_cost(capsys, tmp_path):
    import csv

    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF)
    log = tmp_path / "logs" / "run.csv"
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, "--steps", 512,
                         "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "--log", log,
                         "--cost-estimate", "episodes", "--json")
    assert code == 0, err
    with open(log, newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [int(r["iteration"]) for r in rows] == [1, 2, 3, 4]
    assert {"steps", "mean_return", "true_cost", "learned_cost_0", "multipliers_0", "cost_estimate_0"} <= set(rows[0])
    # 200-step episodes end in the fourth 2 x 64-step rollout: "episodes" updated nothing before it
    assert [r["cost_estimate_0"] == "" for r in rows] == [True, True, True, False]
    assert all(float(r["true_cost"]) >= 0 for r in rows)  # the toy reports its own cost beside the learned one
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--log", tmp_path)
    assert code == 2 and "is a directory" in err and "Traceback" not in err


@pytest.mark.skipif(not importlib.util.find_spec("stable_baselines3"), reason="needs the sb3 extra")
def test_sb3_runs_log_the_columns_of_our_ppo(capsys, tmp_path):
    """--log with a stable-baselines3 learner: one row per rollout (PPO) or per 1,000 steps (SAC),
    the environment's own reward (not r - lambda c), the learned and the true cost per episode that
    ended, and the multiplier the Lagrangian callback moved."""
    import csv

    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF)
    log = tmp_path / "ppo.csv"
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--algo", "sb3-ppo-lag", "--cost", rules,
                         "--steps", 1024, "--n-envs", 2, "--n-steps", 128, "--eval-episodes", 1, "--log", log,
                         "--json")
    assert code == 0, err
    rows = list(csv.DictReader(log.open()))
    assert [int(r["steps"]) for r in rows] == [256, 512, 768, 1024]
    assert {"mean_return", "mean_length", "learned_cost_0", "true_cost", "multipliers_0"} <= set(rows[0])
    ended = [r for r in rows if r["episodes"] != "0"]
    assert ended and all(r["mean_length"] == "200.0" for r in ended)   # the toy's episodes run 200 steps
    # the return is the toy's own (its rewards lie in [-1, 1] per step plus the goal), not r - lambda c
    assert all(float(r["mean_return"]) > -201 for r in ended)
    assert float(rows[-1]["multipliers_0"]) == pytest.approx(json.loads(out)["multipliers"][0])
    # the toy reports its ground truth beside the learned formula: both are counted, never negative
    assert all(float(r["learned_cost_0"]) >= 0 and float(r["true_cost"]) >= 0 for r in ended)
    log = tmp_path / "sac.csv"
    code, out, err = run(capsys, "train", "--env", ROBOT, "--algo", "sb3-sac", "--steps", 2000, "--n-envs", 1,
                         "--eval-episodes", 1, "--log", log)
    assert code == 0, err
    rows = list(csv.DictReader(log.open()))
    assert [int(r["steps"]) for r in rows] == [1000, 2000] and "multipliers_0" not in rows[0]


def _saved_cost(tmp_path, env_name: str):
    """A small learned cost over BlockedPoint's x (random weights, lambda 1), saved as ICRL saves it."""
    import gymnasium as gym
    import torch

    import symlearn.envs  # noqa: F401  (registers the gymnasium ids)
    from symlearn.envs.registry import get
    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    env = gym.make(get(env_name).gym_id)
    cost = NeuralCost.for_env(env, FeatureNetwork([0], 0, 1, (8,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([1.0])
    path = tmp_path / "cost.safetensors"
    cost.save(path)
    return path


def test_a_learned_neural_cost_trains_a_fresh_agent(capsys, tmp_path):
    path = _saved_cost(tmp_path, "blocked-point")
    sb3 = ("sb3-ppo-lag",) if importlib.util.find_spec("stable_baselines3") else ()
    for algo in ("ppo-lag", "ppo", *sb3):
        code, out, err = run(capsys, "train", "--env", "blocked-point", "--algo", algo, "--cost", path,
                             "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "--json")
        assert code == 0, err
        doc = json.loads(out)
        assert doc["cost_kind"] == "neural" and doc["steps"] == 256
        assert (doc["multipliers"] is not None) == algo.endswith("ppo-lag")
    # a cost learned in another observation space is refused in one line naming the file
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--cost", path, "--steps", 256)
    assert code == 2 and "cost.safetensors" in err and "Traceback" not in err
    code, _, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, "--prune")
    assert code == 2 and "--prune" in err


def test_a_neural_cost_holds_the_agent_to_its_experts_level_by_default(capsys, tmp_path):
    """A sigmoid cost charges every state something, so limit 0 is out of reach: the default limit
    is what the file records the cost charges its demonstrations; --cost-limit overrides it; a file
    with no record keeps 0 and says why that cannot be kept."""
    from symlearn.learners.neural import NeuralCost

    path = _saved_cost(tmp_path, "blocked-point")
    small = ("--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "--json")
    code, out, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, *small)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_limit"] == 0 and doc["cost_limit_from"] == "default"
    assert any("out of reach" in w and "--cost-limit" in w for w in doc["warnings"])
    cost = NeuralCost.load(path)
    cost.provenance["expert_cost"] = {"mean": 12.5, "min": 3.0, "max": 20.0, "episodes": 4, "mean_length": 100.0}
    cost.save(path)
    code, out, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, *small)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_limit"] == 12.5 and doc["cost_limit_from"] == "expert"
    assert not any("out of reach" in w for w in doc["warnings"])
    assert abs(doc["multipliers"][0] - 1.0) <= 0.2 + 1e-9   # the expert level is the cost's floor: from 1
    code, out, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, "--cost-limit", 3, *small)
    assert code == 0, err
    doc = json.loads(out)
    assert (doc["cost_limit"], doc["cost_limit_from"]) == (3, "--cost-limit")
    assert doc["multipliers"][0] <= 0.2 + 1e-9   # a budget the user gives: from 0
    code, out, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, "--cost-limit", 0, *small)
    assert code == 0, err
    warned = [w for w in json.loads(out)["warnings"] if "out of reach" in w]
    assert warned and "pay 12.5 per episode" in warned[0] and "older" not in warned[0]
    from symlearn.cli.train_command import _limit_kept

    class Args:   # an agent that paid 40 against the level of 12.5 the limit was taken from
        algo, cost_limit, cost_limit_from = "ppo-lag", 12.5, "expert"

    class Neural:
        kind, expert_level = "neural", 12.5

    said = _limit_kept(Args, Neural, {"learned_cost": 40.0, "steps": 256})
    assert "does not keep its limit, the expert's level of 12.5 per episode" in said and "pay 40" in said


def test_a_neural_cost_of_zero_everywhere_is_named_as_such(capsys, tmp_path):
    """`learn icrl` can end with every lambda at 0 (issue 24: a fresh conveyor arm, seed 2): the cost
    is 0 everywhere and charges its demonstrations 0, so the default limit is 0. `train` said "a
    learned neural cost charges every state something, so --cost-limit 0 is out of reach" to a user
    who gave no --cost-limit; it now says the cost constrains nothing."""
    from symlearn.learners.neural import NeuralCost

    path = _saved_cost(tmp_path, "blocked-point")
    cost = NeuralCost.load(path)
    cost.set_lambdas([0.0])
    cost.provenance["expert_cost"] = {"mean": 0.0, "min": 0.0, "max": 0.0, "episodes": 4, "mean_length": 100.0}
    cost.save(path)
    code, out, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, "--steps", 256, "--n-envs", 2,
                         "--n-steps", 64, "--eval-episodes", 1, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_limit"] == 0 and doc["cost_limit_from"] == "expert"
    assert not any("charges every state something" in w for w in doc["warnings"]), doc["warnings"]
    assert any("0 everywhere" in w and "constrained nothing" in w for w in doc["warnings"]), doc["warnings"]


def test_stable_baselines3_learners_on_a_user_module(capsys, tmp_path):
    pytest.importorskip("stable_baselines3")
    from point_robot_env import PointRobot

    from symlearn.backends.sb3 import load_policy

    rules = tmp_path / "hazard.dnf"
    rules.write_text(HAZARD)
    agent = tmp_path / "agent.safetensors"
    small = ("--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 2, "--json")
    code, out, err = run(capsys, "train", "--env", ROBOT, "--algo", "sb3-ppo-lag", "--cost", rules, "-o", agent, *small)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_kind"] == "dnf" and len(doc["multipliers"]) == 1 and doc["cost"] is not None
    assert doc["files"] == [str(agent), str(agent.with_suffix(".json"))]
    assert load_policy(agent, PointRobot()).predict(np.zeros(2, dtype=np.float32))[0].shape == (2,)
    two = tmp_path / "two.dnf"
    two.write_text(HAZARD + "x > 5\n")   # a rule no agent can fire
    for algo, n in (("sb3-ppo", None), ("sb3-ppo-lag", 2)):   # plain: both rules subtracted, lambda 1
        code, out, err = run(capsys, "train", "--env", ROBOT, "--algo", algo, "--cost", two, "--per-rule", "--prune",
                             *small)
        assert code == 0, err
        doc = json.loads(out)
        assert doc["pruned"] == ["x > 5"] and (doc["multipliers"] is None if n is None else len(doc["multipliers"]) == n)
    code, out, err = run(capsys, "train", "--env", ROBOT, "--env-kwargs", '{"discrete": true}', "--algo", "sb3-dqn",
                         *small)
    assert code == 0, err
    assert json.loads(out)["multipliers"] is None
    code, out, err = run(capsys, "train", "--env", ROBOT, "--algo", "sb3-sac-lag", "--steps", 160, "--n-envs", 1,
                         "--eval-episodes", 1, "--json")   # without --cost: the environment's info["cost"]
    assert code == 0, err
    doc = json.loads(out)
    assert doc["cost_kind"] is None and len(doc["multipliers"]) == 1 and doc["cost"] is not None
    # 160 steps are less than SAC's 1,000-step update window: the multiplier never moved, and it says so
    assert any("the multiplier was never updated: 160 steps are fewer than one update window of 1,000" in w
               for w in doc["warnings"]), doc["warnings"]
    code, _, err = run(capsys, "train", "--env", ROBOT, "--algo", "sb3-dqn", "--steps", 64)
    _one_line(code, err, "DQN acts only in Discrete action spaces")


def test_observations_nothing_can_read_are_one_line_and_tuples_are_flattened(capsys):
    """A Tuple of Discrete parts is seen through the numeric view (one-hot, flattened) and trains;
    an observation with no numeric part at all is refused in one line."""
    pytest.importorskip("stable_baselines3")
    import gymnasium as gym

    class Pair(gym.Env):
        observation_space = gym.spaces.Tuple((gym.spaces.Discrete(3), gym.spaces.Discrete(2)))
        action_space = gym.spaces.Discrete(2)

        def reset(self, *, seed=None, options=None):
            return (0, 0), {}

        def step(self, action):
            return (0, 0), 0.0, True, False, {}

    class Words(Pair):
        observation_space = gym.spaces.Text(5)

        def reset(self, *, seed=None, options=None):
            return "hello", {}

        def step(self, action):
            return "hello", 0.0, True, False, {}

    for name, entry in (("TestPairObservation-v0", Pair), ("TestWordsObservation-v0", Words)):
        if name not in gym.registry:
            gym.register(name, entry_point=entry)
    code, out, err = run(capsys, "train", "--env", "TestPairObservation-v0", "--algo", "sb3-ppo", "--steps", 64,
                         "--eval-episodes", 1)
    assert code == 0, err
    code, _, err = run(capsys, "train", "--env", "TestWordsObservation-v0", "--algo", "sb3-ppo", "--steps", 64)
    _one_line(code, err, "has no numeric part")


def test_stable_baselines3_absent_is_one_line_naming_the_extra(capsys, monkeypatch):
    from symlearn import optional

    monkeypatch.setattr(optional, "available", lambda name: False)
    code, _, err = run(capsys, "train", "--env", "CartPole-v1", "--algo", "sb3-ppo", "--steps", 64)
    _one_line(code, err, "symlearn[sb3]")


OUTSIDE = '''
import gymnasium as gym
import numpy as np


class Line(gym.Env):
    """A walk on [0, 1]: reward for going right, cost past `edge`."""

    feature_names = ("pos",)

    def __init__(self, edge=0.8):
        self.edge = edge
        self.observation_space = gym.spaces.Box(0.0, 1.0, shape=(1,), dtype=np.float32)
        self.action_space = gym.spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos, self.t = 0.0, 0
        return np.array([self.pos], np.float32), {"cost": 0.0}

    def step(self, action):
        self.pos = min(max(self.pos + (0.1 if action else -0.1), 0.0), 1.0)
        self.t += 1
        return (np.array([self.pos], np.float32), self.pos, False, self.t >= 20,
                {"cost": float(self.pos > self.edge)})


gym.register("Line-v0", entry_point=Line)
'''


def test_a_module_outside_the_repository_from_the_current_directory(run_cli, tmp_path):
    """`python -m symlearn` in a user's folder: their module is importable from there."""
    (tmp_path / "my_line.py").write_text(OUTSIDE)
    (tmp_path / "edge.dnf").write_text("pos > 0.7\n")
    result = run_cli("train", "--env", "my_line:Line-v0", "--env-kwargs", '{"edge": 0.7}', "--cost", "edge.dnf",
                     "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 2, "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    doc = json.loads(result.stdout)
    assert (doc["algo"], doc["cost_kind"]) == ("ppo-lag", "dnf") and doc["cost"] is not None


def test_a_depth_weighted_dnf_cost_charges_deep_violations_more(capsys, tmp_path):
    """--depth-weight: the learned cost of the log is 1 + W x depth per unsafe step (more than the
    binary count of the same run), the ground truth stays info["cost"], SB3 agents read it too."""
    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF + "\n")
    rows = {}
    for weight in (0, 3):
        log = tmp_path / f"w{weight}.csv"
        code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, "--depth-weight", weight,
                             "--steps", 1024, "--n-steps", 256, "--eval-episodes", 1, "--log", log, "--json")
        assert code == 0, err
        assert json.loads(out)["cost_kind"] == "dnf"
        import csv

        rows[weight] = list(csv.DictReader(log.open()))
    # same seed, same first rollout (256 steps a copy: every 200-step episode ends in it): the
    # shaped cost is the binary one plus the depth term
    first0, first3 = float(rows[0][0]["learned_cost_0"]), float(rows[3][0]["learned_cost_0"])
    assert first0 > 0 and first3 > first0
    assert rows[0][0]["true_cost"] == rows[3][0]["true_cost"]
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, "--depth-weight", 3,
                         "--algo", "sb3-ppo-lag", "--steps", 256, "--n-steps", 64, "--eval-episodes", 1, "--json")
    assert code == 0, err


def test_the_multipliers_start_where_multiplier_init_says(capsys, tmp_path):
    """One iteration of Adam moves a multiplier by about --multiplier-lr: started at 5, it ends near 5."""
    rules = tmp_path / "toy.dnf"
    rules.write_text(UNSAFE_DNF)
    log = tmp_path / "run.csv"
    for init in (0, 5):
        code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules,
                             "--multiplier-init", init, "--steps", 128, "--n-envs", 1, "--n-steps", 128,
                             "--eval-episodes", 1, "--log", log, "--json")
        assert code == 0, err
        assert abs(json.loads(out)["multipliers"][0] - init) <= 0.1 + 1e-9


def test_sb3_training_leaves_no_folder_in_the_temporary_directory(capsys, tmp_path, monkeypatch):
    """SB3's default logger makes an empty ``SB3-<date>`` folder in the temporary directory on every
    ``learn``; ours has no folder, so a sweep of SB3 runs leaves the temporary directory as it was."""
    import tempfile

    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.delenv("SB3_LOGDIR", raising=False)
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--algo", "sb3-ppo", "--steps", 256,
                         "--n-envs", 1, "--n-steps", 128, "--eval-episodes", 1, "--json")
    assert code == 0, err
    assert json.loads(out)["steps"] == 256
    assert list(scratch.iterdir()) == []


def test_a_learned_dnfs_false_alarm_floor_is_added_to_a_positive_budget(capsys, tmp_path):
    """`learn dnf --validation` records in the rule file how often the formula fires on held-out
    expert states; `train --cost` adds that per episode (the file's false-alarm floor) to a positive
    --cost-limit, keeps limit 0 as it is unless --false-alarm-floor add, and --false-alarm-floor none
    gives the limit as written (issue 24: a SafeNav formula charges the expert 19-36 per episode, so
    a budget of 25 on it was out of every policy's reach)."""
    from symlearn.learners.validation import rule_file_validation

    rules = tmp_path / "toy.dnf"
    # what learn dnf --validation writes: 30 of 300 held-out states in 3 episodes -> 10 per episode
    rules.write_text("# unsafe set of toy-navigation\n"
                     "# validation: 30 of 300 held-out expert states unsafe (10.0%; 3 demonstrations held out, "
                     "12 learned from)\n" + UNSAFE_DNF)
    recorded = rule_file_validation(rules.read_text())
    assert (recorded.forbidden, recorded.n_held_out, recorded.per_demonstration) == (30, 3, 10.0)
    small = ("--steps", 128, "--n-envs", 1, "--n-steps", 128, "--eval-episodes", 1, "--json")

    def trained(*flags):
        code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", rules, *flags, *small)
        assert code == 0, err
        return json.loads(out)

    doc = trained("--cost-limit", 5)
    assert (doc["cost_limit"], doc["cost_limit_from"], doc["cost_limit_given"], doc["false_alarm_floor"]) \
        == (15, "validation", 5, 10)
    assert doc["multipliers"][0] <= 0.1 + 1e-9    # a budget: from 0, as before
    doc = trained("--cost-limit", 5, "--false-alarm-floor", "none")
    assert (doc["cost_limit"], doc["cost_limit_from"], doc["false_alarm_floor"]) == (5, "--cost-limit", 10)
    doc = trained()
    assert (doc["cost_limit"], doc["cost_limit_from"]) == (0, "default")   # a hard limit stays hard
    doc = trained("--false-alarm-floor", "add")
    assert (doc["cost_limit"], doc["cost_limit_from"], doc["cost_limit_given"]) == (10, "validation", 0)
    assert abs(doc["multipliers"][0] - 1.0) <= 0.1 + 1e-9   # still the hard constraint: from 1
    doc = trained("--cost-limit", 5, "--per-rule")   # a cost per rule is in other units than the floor
    assert doc["cost_limit"] == 5 and doc["cost_limit_from"] == "--cost-limit"

    plain = tmp_path / "plain.dnf"
    plain.write_text(UNSAFE_DNF)
    doc = json.loads(run(capsys, "train", "--env", "toy-navigation", "--cost", plain, "--cost-limit", 5, *small)[1])
    assert (doc["cost_limit"], doc["cost_limit_from"], doc["false_alarm_floor"]) == (5, "--cost-limit", None)
    code, out, err = run(capsys, "train", "--env", "toy-navigation", "--cost", plain, "--false-alarm-floor", "add",
                         *small)
    assert code != 0 and "records none" in err and "--validation" in err


def test_a_validation_line_below_the_rules_or_inconsistent_is_not_read_as_the_floor(tmp_path):
    from symlearn.errors import DataError
    from symlearn.learners.validation import rule_file_validation

    line = "# validation: 3 of 30 held-out expert states unsafe (10.0%; 1 demonstration held out, 4 learned from)\n"
    assert rule_file_validation(line + "x > 1\n").per_demonstration == 3
    assert rule_file_validation("x > 1\n" + line) is None     # a user's comment among the rules
    with pytest.raises(DataError, match="inconsistent"):
        rule_file_validation(line.replace("3 of 30", "31 of 30"))


def test_an_unkept_dnf_limit_names_the_false_alarm_floor_it_left_out():
    """The warning of an agent over its limit says how the file's floor would enter the limit:
    dropping ``--false-alarm-floor none`` at a budget, ``add`` at limit 0."""
    import argparse

    from symlearn.cli.train_command import _limit_kept

    class Dnf:
        kind, expert_level = "dnf", None

    args = argparse.Namespace(algo="ppo-lag", cost_limit=5.0, cost_limit_given=5.0, cost_limit_from="--cost-limit",
                              false_alarm_floor=10.0, false_alarm_floor_mode="none", depth_weight=0.0)
    said = _limit_kept(args, Dnf, {"learned_cost": 40.0, "steps": 256})
    assert "flags 10 states of an unseen expert episode" in said and "without --false-alarm-floor none" in said
    args.cost_limit = args.cost_limit_given = 0.0
    args.cost_limit_from, args.false_alarm_floor_mode = "default", "auto"
    assert "--false-alarm-floor add allows them" in _limit_kept(args, Dnf, {"learned_cost": 40.0, "steps": 256})
    args.cost_limit, args.cost_limit_from, args.false_alarm_floor_mode = 10.0, "validation", "add"
    assert "its limit, 0 plus the formula's false-alarm floor of 10" in _limit_kept(
        args, Dnf, {"learned_cost": 40.0, "steps": 256})
