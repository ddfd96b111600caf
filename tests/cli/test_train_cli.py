"""``symlearn train``: PPO / PPO-Lagrangian from the command line, a DNF cost, pruning, model files."""

import json

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
    assert "x > 5" in doc["pruned"]
    pruned = load_dnf(tmp_path / "toy.pruned.dnf")
    assert "x > 5" not in str(pruned) and set(map(str, pruned.conjunctions)) == set(doc["kept"])
    assert agent.exists() and agent.with_suffix(".json").exists()


def test_plain_ppo_on_a_gymnasium_id(capsys):
    code, out, err = run(capsys, "train", "--env", "CartPole-v1", "--algo", "ppo", "--steps", 1024,
                         "--eval-episodes", 1, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["multipliers"] is None and doc["return"] > 0


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
    for algo in ("ppo-lag", "ppo"):
        code, out, err = run(capsys, "train", "--env", "blocked-point", "--algo", algo, "--cost", path,
                             "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "--json")
        assert code == 0, err
        doc = json.loads(out)
        assert doc["cost_kind"] == "neural" and doc["steps"] == 256
        assert (doc["multipliers"] is not None) == (algo == "ppo-lag")
    # a cost learned in another observation space is refused in one line naming the file
    code, _, err = run(capsys, "train", "--env", "toy-navigation", "--cost", path, "--steps", 256)
    assert code == 2 and "cost.safetensors" in err and "Traceback" not in err
    code, _, err = run(capsys, "train", "--env", "blocked-point", "--cost", path, "--prune")
    assert code == 2 and "--prune" in err
