"""Constraint sets over a domain model as environment masks: closure, unavailable ids, id order."""

import numpy as np
import pytest

from symlearn.backends import Shield, closed_mask, env_mask
from symlearn.backends.masks import observed_ids
from symlearn.envs.gridworld import StochasticGridworld, make_gridworld
from symlearn.errors import ModelError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import restrict


def chain():
    """0 -> 1 -> 2 (absorbing "exit", observed by no environment); action 0 stays, 1 moves on."""
    P = np.zeros((3, 2, 3))
    for s in range(3):
        P[s, 0, s] = 1.0
        P[s, 1, min(s + 1, 2)] = 1.0
    return TabularMDP(P, np.zeros((3, 2)), [1, 0, 0], [False, False, True], ("start", "middle", "exit"))


def test_closure_spreads_to_pairs_that_enter_an_empty_state():
    mdp = chain()
    forbidden = np.zeros((3, 2), bool)
    forbidden[1] = True  # nothing allowed in the middle
    np.testing.assert_array_equal(closed_mask(mdp, forbidden, close=False), forbidden)
    closed = closed_mask(mdp, forbidden)
    assert closed[0].tolist() == [False, True]  # moving into the middle is forbidden now
    np.testing.assert_array_equal(closed, restrict(mdp, forbidden).forbidden)


def test_unavailable_ids_are_never_forbidden_and_do_not_empty_a_state():
    mdp = chain()
    unavailable = np.zeros((3, 2), bool)
    unavailable[1, 0] = True  # the middle has one real action only
    forbidden = np.zeros((3, 2), bool)
    forbidden[1] = True
    closed = closed_mask(mdp, forbidden, unavailable)
    assert closed[1].tolist() == [False, True] and closed[0].tolist() == [False, True]
    assert not (closed & unavailable).any()


def test_env_mask_cuts_to_the_observed_ids_after_closing_the_whole_model():
    mdp = chain()
    forbidden = np.zeros((3, 2), bool)
    forbidden[2] = True  # the exit state is terminal: the closure does not spread from it
    forbidden[1, 0] = True
    mask = env_mask(mdp, forbidden, 2)
    assert mask.shape == (2, 2) and mask.tolist() == [[False, False], [True, False]]
    np.testing.assert_array_equal(env_mask(mdp, forbidden, ["start", "middle"]), mask)
    mask[0, 0] = True  # a copy: the caller may change it
    assert not env_mask(mdp, forbidden, 2)[0, 0]


def test_the_order_of_observation_ids_is_checked_by_name():
    mdp = chain()
    forbidden = np.zeros((3, 2), bool)
    with pytest.raises(ModelError, match="first difference at id 0"):
        env_mask(mdp, forbidden, ["middle", "start"])
    with pytest.raises(ModelError, match="cannot use a mask"):
        observed_ids(mdp, 4)
    with pytest.raises(ModelError, match="cannot use a mask"):
        observed_ids(mdp, 0)
    with pytest.raises(ModelError, match="do not start"):
        observed_ids(mdp, ["start", "middle", "exit", "beyond"])
    assert observed_ids(mdp, ("start", "middle", "exit")) == 3


def test_wrong_shapes_and_values_are_model_errors():
    mdp = chain()
    with pytest.raises(ModelError, match="forbidden mask must have shape"):
        closed_mask(mdp, np.zeros((2, 2), bool))
    with pytest.raises(ModelError, match="unavailable mask must have shape"):
        closed_mask(mdp, np.zeros((3, 2), bool), np.zeros((3, 3), bool))
    with pytest.raises(ModelError, match="boolean"):
        closed_mask(mdp, np.full((3, 2), 0.5))


def test_a_closed_gridworld_mask_shields_an_agent():
    """The gridworld's constraint set is already closed; as a shield it blocks the forbidden cells."""
    grid = StochasticGridworld(0.0)
    mdp = grid.to_tabular()
    truth = grid.constraint_mask()
    mask = env_mask(mdp, truth, mdp.state_names)
    np.testing.assert_array_equal(mask, truth)
    env = Shield(make_gridworld(0.0), mask, mode="raise")
    state, info = env.reset(seed=0)
    assert info["action_mask"].tolist() == (~mask[state]).astype(int).tolist()
