"""Specification learning with a PPO policy update: float observations, a feature labeling."""

from __future__ import annotations

import json

import torch
from cli_runner import run
from line_env import Line

from symlearn.data import record
from symlearn.grounding import FeatureLabeling
from symlearn.learners.temporal.spec_from_demos import SpecLearner
from symlearn.logic.ltlf import holds, parse

CONDITIONS = {"right_end": "x > 0.85", "left_end": "x < 0.15"}


def _demos():
    labeling = FeatureLabeling(["x"], CONDITIONS)
    return labeling, record(Line(), lambda obs: 1, 8, seed=0, labeler=labeling)  # always right


def _words(demos):
    return [[frozenset(s) for s in t.labels] for t in demos]


def test_ppo_policy_update_on_float_observations():
    torch.set_num_threads(1)
    labeling, demos = _demos()
    learner = SpecLearner(labeling=labeling, ppo_steps=6_000, n_eval=20, random_state=0).fit(demos, Line)
    assert learner.world_.route == "ppo"
    assert all(holds(learner.formula_, w) for w in _words(demos))
    assert "right_end" in str(learner.formula_) or "left_end" in str(learner.formula_)
    assert learner.success_rate(learner.formula_) >= 0.8  # the product-trained PPO policy meets it
    assert learner.history_[0].nominal_rate < 0.8  # random walks did not


def test_cli_feature_labeling_named_by_the_environment(capsys, tmp_path):
    """A plain {proposition: condition} file; the names come from the env's feature_names."""
    _, demos = _demos()
    demos_path, labels_path = tmp_path / "demos.jsonl", tmp_path / "labels.json"
    demos.save(demos_path)
    labels_path.write_text(json.dumps(CONDITIONS))
    code, out, err = run(capsys, "learn", "spec", "--env", "line_env:Line-v0", "--demos", demos_path,
                         "--labeling", labels_path, "--ppo-steps", 2_000, "--max-iterations", 1, "--json",
                         "-o", tmp_path / "line.ltl")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["policy_update"] == "ppo" and set(doc["propositions"]) == {"right_end", "left_end"}
    assert doc["iterations"] == 1 and all(holds(parse(doc["formula"]), w) for w in _words(demos))
    saved = json.loads((tmp_path / "line.labeling.json").read_text())  # a feature labeling is saved
    assert saved["kind"] == "features"


def test_the_environment_state_key_hook_keys_the_q_table():
    import gymnasium as gym

    from symlearn.learners.temporal.spec_env_world import EnvWorld
    from symlearn.logic.ltlf import parse

    class Keyed(gym.Wrapper):
        def state_key(self, observation):
            return ("cell", int(observation))

    env = Keyed(gym.make("FrozenLake-v1", is_slippery=False))
    world = EnvWorld(env, lambda obs, info: ["goal"] if obs == 15 else [], q_steps=3_000, horizon=40)
    assert world.route == "tabular"
    result = world.train(parse("F goal"), seed=0)
    assert result.q and all(key[0] == "cell" for key in result.q)
    assert all("goal" in world.word(t)[-1] for t in world.policy_traces(result, 5, seed=1))
