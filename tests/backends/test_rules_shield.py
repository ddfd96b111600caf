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
