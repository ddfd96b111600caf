"""A shield built directly on ASP rules (clingo decides each new state-action pair)."""

import pytest

from symlearn.backends.rules import rules_allowed
from symlearn.backends.shield import Shield
from symlearn.envs.junction_env import JunctionEnv
from symlearn.envs.logic_domains import logic_domain
from symlearn.errors import SymlearnError
from symlearn.logic.asp import Hypothesis, Program
from symlearn.rl.q_learning import q_learning


def _shielded(variant: str, rules_path) -> Shield:
    domain = logic_domain(f"junction-{variant}")
    env = JunctionEnv(variant)
    model = env.model
    hypothesis = Hypothesis.from_lp(rules_path, background=Program.from_text(domain.background()))
    atoms = [model.action_fact(None, a).rstrip(".") for a in model.actions]
    states = model.states()
    return Shield(env, rules_allowed(hypothesis, atoms),
                  state_of=lambda observation: model.state_facts(states[int(observation)]), seed=0)


def test_truth_rules_as_a_shield_give_no_violations():
    domain = logic_domain("junction-priority")
    shielded = _shielded("priority", domain.truth_path)
    result = q_learning(shielded, 60, seed=0)
    assert result.violations.sum() == 0
    plain = q_learning(JunctionEnv("priority"), 60, seed=0)
    assert plain.violations.sum() > 0


def test_masks_agree_with_the_ground_truth_in_every_state():
    domain = logic_domain("junction-lights")
    shielded = _shielded("lights", domain.truth_path)
    model = shielded.env.model
    for i, state in enumerate(model.states()):
        for a, action in enumerate(model.actions):
            assert shielded.allowed(model.state_facts(state), a) == model.is_allowed(state, action)


def test_unknown_action_index_is_an_error():
    allowed = rules_allowed(Hypothesis([":- go(west)."]), ["go(zero)"])
    assert allowed("at(1,1).", 0) is True
    with pytest.raises(SymlearnError, match="no ASP atom"):
        allowed("at(1,1).", 3)


def test_a_hypothesis_is_taken_as_it_is_when_the_environment_gives_the_translation():
    """``Shield(env, hypothesis)``: the facts from info['state_facts'], the atoms from env.action_atoms."""
    domain = logic_domain("junction-lights")
    hypothesis = Hypothesis.from_lp(domain.truth_path, background=Program.from_text(domain.background()))
    env = JunctionEnv("lights")
    shielded = Shield(env, hypothesis, seed=0)
    model = env.model
    observation, info = shielded.reset(seed=0)
    for _ in range(30):
        state = model.states()[int(observation)]
        assert info["action_mask"].tolist() == [int(model.is_allowed(state, a)) for a in model.actions]
        observation, _, terminated, truncated, info = shielded.step(int(shielded.rng.integers(5)))
        assert not info["violation"]
        if terminated or truncated:
            observation, info = shielded.reset()


def test_a_hypothesis_without_its_translation_is_refused_at_construction():
    from symlearn.envs.gridworld import make_gridworld

    rules = Hypothesis([":- go(west)."])
    with pytest.raises(SymlearnError, match="action atom of every action"):
        Shield(make_gridworld(0.0), rules)
    with pytest.raises(SymlearnError, match="2 action atoms for 4 actions"):
        Shield(make_gridworld(0.0), rules, action_atoms=["go(north)", "go(west)"])
    with pytest.raises(SymlearnError, match="apply to ASP rules"):
        Shield(make_gridworld(0.0), lambda s, a: True, action_atoms=["go(north)"] * 4)
    # atoms given, but the environment reports no facts and no state_of says how to get them
    shielded = Shield(make_gridworld(0.0), rules, action_atoms=["go(north)", "go(east)", "go(south)", "go(west)"])
    with pytest.raises(SymlearnError, match=r"no info\['state_facts'\]"):
        shielded.reset(seed=0)
    with_facts = Shield(make_gridworld(0.0), rules, action_atoms=["go(north)", "go(east)", "go(south)", "go(west)"],
                        state_of=lambda observation: ["at(1,1)."])
    assert with_facts.reset(seed=0)[1]["action_mask"].tolist() == [1, 1, 1, 0]


def test_a_mask_on_continuous_observations_is_refused_at_construction():
    import gymnasium as gym
    import numpy as np

    with pytest.raises(SymlearnError, match="needs integer observations"):
        Shield(gym.make("CartPole-v1"), np.zeros((10, 2), bool))
    failing = Shield(gym.make("CartPole-v1"), lambda state, action: state["speed"] < 1)  # no names in an array
    with pytest.raises(SymlearnError, match="constraints failed on state .*IndexError"):
        failing.reset(seed=0)
