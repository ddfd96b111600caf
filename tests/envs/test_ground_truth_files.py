"""The bundled background knowledge and truth*.lp files agree with the Python ground truth."""

import pytest

from symlearn.envs.logic_domains import DOMAIN_NAMES, logic_domain
from symlearn.errors import ModelError
from symlearn.logic.asp import Hypothesis, Program, answer_sets


def _truth(domain):
    return Hypothesis.from_lp(domain.truth_path, background=Program.from_file(domain.bk_path))


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
        program = Program.from_file(domain.bk_path) + " ".join(facts)
        assert len(answer_sets(program)) == 1


def _pairs_of(models, domain):
    actions = {"move", "go"}
    state_predicates = {"at", "tls0", "tls1", "carOnTheRight"}
    found = set()
    for model in models:
        atoms = sorted(str(s) for s in model)
        state = tuple(sorted(a + "." for a in atoms if a.split("(")[0] in state_predicates))
        action = tuple(a + "." for a in atoms if a.split("(")[0] in actions)
        found.add(state + action)
    return found


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_space_file_generates_exactly_the_domain_pairs(name):
    domain = logic_domain(name)
    expected = {tuple(sorted(f[:-1])) + (f[-1],) for f, _ in domain.pairs()}
    models = answer_sets(Program.from_file(domain.bk_path) + Program.from_file(domain.space_path))
    assert len(models) == len(expected)
    assert _pairs_of(models, domain) == expected


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_truth_forbids_exactly_the_invalid_pairs(name):
    domain = logic_domain(name)
    forbidden = _truth(domain).forbidden_interpretations(Program.from_file(domain.space_path))
    expected = {tuple(sorted(f[:-1])) + (f[-1],) for f, ok in domain.pairs() if not ok}
    assert _pairs_of(forbidden, domain) == expected  # interpretations come back as atom strings


def test_unknown_domain():
    with pytest.raises(ModelError, match="unknown logic domain"):
        logic_domain("chess")
