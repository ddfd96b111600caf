"""The logic domains as nominal tabular MDPs (symlearn.envs.logic_mdp)."""

import numpy as np
import pytest

from symlearn.envs.logic_mdp import LogicMDP, logic_mdp
from symlearn.errors import DataError, ModelError

NAMES = ["hanoi", "junction-lights", "junction-priority", "junction-combined"]


@pytest.fixture(scope="module", params=NAMES)
def lm(request) -> LogicMDP:
    return logic_mdp(request.param)


def test_shapes_and_stochastic_rows(lm):
    mdp = lm.mdp
    S, A = mdp.n_states, mdp.n_actions
    assert mdp.transitions.shape == (S, A, S)
    assert lm.unavailable.shape == lm.truth_forbidden.shape == (S, A)
    assert len(lm.states) == S and len(lm.actions) == A
    assert np.all(mdp.transitions >= 0)
    np.testing.assert_allclose(mdp.transitions.sum(axis=2), 1.0, atol=1e-12)
    assert mdp.initial.shape == (S,) and mdp.initial.sum() == pytest.approx(1.0)
    assert not (mdp.initial > 0)[mdp.terminal].any()  # nobody starts in an exit / at the goal


def test_terminal_states_are_absorbing_and_no_pairs(lm):
    mdp = lm.mdp
    terminal = np.flatnonzero(mdp.terminal)
    assert terminal.size >= 1
    for t in terminal:
        assert np.all(mdp.transitions[t, :, t] == 1.0)
        assert lm.unavailable[t].all()
        assert all(lm.pair(int(t), a) is None for a in range(mdp.n_actions))


def test_ids_and_pairs_round_trip(lm):
    available = np.argwhere(~lm.unavailable)
    assert len(available) > 0
    for s, a in available:
        state, action = lm.pair(int(s), int(a))
        assert lm.ids(state, action) == (s, a)
    # mask <-> pairs_of: every available pair, in id order
    everything = lm.pairs_of(np.ones_like(lm.unavailable))
    assert len(everything) == len(available)
    np.testing.assert_array_equal(lm.mask(everything), ~lm.unavailable)
    with pytest.raises(ModelError):
        lm.ids("no such state", lm.actions[0])
    with pytest.raises(ModelError):
        lm.facts(*np.argwhere(lm.unavailable)[0])


def test_pairs_of_the_domain_are_exactly_the_available_ids(lm):
    domain_pairs = list(lm.logic.state_actions())
    if lm.name == "hanoi":  # the goal configuration is the end of the game: no pair of the MDP
        goal = lm.logic.model.goal_state()
        domain_pairs = [(s, a) for s, a in domain_pairs if s != goal]
    assert len(domain_pairs) == int((~lm.unavailable).sum())
    np.testing.assert_array_equal(lm.mask(domain_pairs), ~lm.unavailable)


def test_truth_mask_is_the_domain_truth(lm):
    assert not (lm.truth_forbidden & lm.unavailable).any()
    for s, a in np.argwhere(~lm.unavailable):
        state, action = lm.pair(int(s), int(a))
        assert lm.truth_forbidden[s, a] == (not lm.logic.is_allowed(state, action))


@pytest.mark.parametrize("name", ["hanoi", "junction-lights", "junction-priority"])
def test_truth_mask_equals_the_ground_truth_rules(name):
    lm = logic_mdp(name)
    np.testing.assert_array_equal(lm.rule_mask(lm.logic.truth_path.read_text()), lm.truth_forbidden)


def test_expert_demonstrations_obey_the_truth_and_end_at_a_goal(lm):
    demos = lm.expert_demonstrations(12, seed=3)
    assert len(demos) == 12
    mdp = lm.mdp
    for trajectory in demos:
        states, actions = list(map(int, trajectory.states)), list(map(int, trajectory.actions))
        assert len(states) == len(actions) + 1
        assert mdp.initial[states[0]] > 0
        assert mdp.terminal[states[-1]] and not mdp.terminal[states[:-1]].any()
        for t, (s, a) in enumerate(zip(states, actions)):
            assert not lm.unavailable[s, a] and not lm.truth_forbidden[s, a]
            assert mdp.transitions[s, a, states[t + 1]] > 0  # a possible step of the nominal MDP
    again = lm.expert_demonstrations(12, seed=3)
    assert [list(t.states) for t in again] == [list(t.states) for t in demos]


def test_bad_demonstration_count():
    with pytest.raises(DataError):
        logic_mdp("hanoi").expert_demonstrations(0)


def test_sizes_of_the_bundled_domains():
    hanoi = logic_mdp("hanoi")
    assert (hanoi.mdp.n_states, hanoi.mdp.n_actions) == (60, 6)
    assert int((~hanoi.unavailable).sum()) == 216 - 2  # minus the 2 moves of the goal configuration
    lights = logic_mdp("junction-lights")
    assert (lights.mdp.n_states, lights.mdp.n_actions) == (54, 5)
