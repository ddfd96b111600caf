"""The bundled background knowledge and truth*.lp files agree with the Python ground truth."""

import pytest

from symlearn.envs.asp_constants import set_constants
from symlearn.envs.hanoi_model import HanoiModel
from symlearn.envs.logic_domains import DOMAIN_NAMES, LogicDomain, logic_domain
from symlearn.envs.traffic_model import TrafficJunction
from symlearn.errors import DataError, ModelError
from symlearn.logic.asp import Hypothesis, Program, answer_sets


def _background(domain):
    # the model's sizing of bk.lp (the combined junction is 7 x 7), located at bk.lp for errors
    return Program.from_text(domain.background(), source=str(domain.bk_path))


def _truth(domain):
    return Hypothesis.from_lp(domain.truth_path, background=_background(domain))


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_truth_file_classifies_every_pair_like_the_model(name):
    domain = logic_domain(name)
    truth = _truth(domain)
    disagreements = []
    for state, action in domain.state_actions():
        state_facts = " ".join(domain.state_facts(state))
        action_atom = domain.action_fact(state, action).rstrip(".")
        by_rules = truth.allowed(state_facts, action_atom)
        if by_rules != domain.is_allowed(state, action):
            disagreements.append((state_facts, action_atom, by_rules))
    assert not disagreements, disagreements[:5]


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_each_context_has_exactly_one_answer_set(name):
    # the learner's fast path relies on it; sample every 7th pair to stay quick
    domain = logic_domain(name)
    for facts, _ in domain.pairs()[::7]:
        program = _background(domain) + " ".join(facts)
        assert len(answer_sets(program)) == 1


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_space_file_generates_exactly_the_domain_pairs(name):
    domain = logic_domain(name)
    models = answer_sets(_background(domain) + Program.from_file(domain.space_path))
    decoded = [domain.decode(model) for model in models]
    assert len(decoded) == len(set(decoded)) == len(list(domain.state_actions()))
    assert set(decoded) == set(domain.state_actions())


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_truth_forbids_exactly_the_invalid_pairs(name):
    domain = logic_domain(name)
    expected = [(s, a) for s, a in domain.state_actions() if not domain.is_allowed(s, a)]
    assert domain.forbidden_pairs(domain.truth_path) == expected


def test_forbidden_pairs_of_a_single_rule():
    domain = logic_domain("junction-priority")
    forbidden = domain.forbidden_pairs([":- go(west)."])
    assert len(forbidden) == 50 and all(a == "west" for _, a in forbidden)
    assert domain.forbidden_pairs(":- go(west), carOnTheRight.") == [(s, a) for s, a in forbidden if s.car_on_right]


def test_decode_rejects_a_non_pair():
    domain = logic_domain("hanoi")
    with pytest.raises(ModelError, match="no state-action pair"):
        domain.decode(["at(0,0,0)", "move(0,1)", "on(1,2)"])


def test_unknown_domain_lists_the_known_ones():
    with pytest.raises(DataError, match="unknown logic domain 'chess'") as info:
        logic_domain("chess")
    assert "junction-lights" in info.value.hint


@pytest.mark.parametrize("folder, model_factory, files", [
    ("traffic", lambda: TrafficJunction("lights", size=7, junction=(4, 4)), ("space_lights.lp", "truth_lights.lp")),
    ("traffic", lambda: TrafficJunction("priority", size=7, junction=(3, 5)),
     ("space_priority.lp", "truth_priority.lp")),
    ("hanoi", lambda: HanoiModel(4, 3), ("space.lp", "truth.lp")),
    ("hanoi", lambda: HanoiModel(2, 4), ("space.lp", "truth.lp")),
])
def test_resized_background_agrees_with_the_resized_model(folder, model_factory, files):
    model = model_factory()
    space, truth = files
    domain = LogicDomain("resized", folder, "bk.lp", space, "bias.las", truth, model, "resized")
    models = answer_sets(Program.from_text(domain.background()) + Program.from_file(domain.space_path))
    assert sorted(domain.decode(m) for m in models) == sorted(model.state_actions())
    expected = [(s, a) for s, a in model.state_actions() if not model.is_allowed(s, a)]
    assert domain.forbidden_pairs(domain.truth_path) == expected


def test_set_constants_refuses_a_missing_constant():
    with pytest.raises(ModelError, match="#const size 0 times"):
        set_constants("col(1..5).", {"size": 7})
