import numpy as np
import pytest

from symlearn.errors import ModelError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import restrict, sample_rollouts


def corridor(n=5):
    """0 - 1 - ... - n-1 (goal); action 0 left, action 1 right."""
    P = np.zeros((n, 2, n))
    for s in range(n):
        P[s, 0, max(s - 1, 0)] = 1
        P[s, 1, min(s + 1, n - 1)] = 1
    return TabularMDP(P, -np.ones((n, 2)), np.eye(n)[0], np.eye(n)[n - 1].astype(bool))


def test_empty_states_and_transitions_into_them_are_forbidden():
    mdp = corridor()
    mask = np.zeros((5, 2), bool)
    mask[2] = True  # state 2 has no valid action left
    r = restrict(mdp, mask)
    assert r.empty_states.tolist() == [False, False, True, False, False]
    assert r.forbidden[1, 1] and r.forbidden[3, 0]  # both ways into state 2
    # closure cascades: state 1 can still go left, so it is not empty
    assert not r.forbidden[1, 0]


def test_closure_cascades_and_protected_pairs_stop_it():
    mdp = corridor()
    mask = np.zeros((5, 2), bool)
    mask[1, 1] = mask[0, 1] = True  # state 0 can then only go left (stay), state 1 only left
    mask[0, 0] = True  # state 0 empty -> (1, 0) forbidden -> state 1 empty -> (2, 0) forbidden
    r = restrict(mdp, mask)
    assert r.empty_states[:2].all() and r.forbidden[2, 0]
    protected = np.zeros((5, 2), bool)
    protected[2, 0] = True
    r = restrict(mdp, mask, protected=protected)
    assert not r.forbidden[2, 0] and r.kept[2, 0]


def test_goal_is_never_empty():
    mdp = corridor()
    mask = np.zeros((5, 2), bool)
    mask[4] = True
    assert not restrict(mdp, mask).empty_states[4]


def test_bad_mask():
    with pytest.raises(ModelError, match="shape"):
        restrict(corridor(), np.zeros((3, 3), bool))


def test_rollouts_stop_at_the_goal():
    mdp = corridor()
    policy = np.tile([0.0, 1.0], (5, 1))
    r = sample_rollouts(mdp, policy, 10, 50, np.random.default_rng(0))
    assert (r.length == 4).all() and (r.returns() == -4).all()
    assert r.fraction_in(np.eye(5)[2].astype(bool)).tolist() == [0.25] * 10


def test_value_iteration_respects_an_allowed_mask():
    from symlearn.rl.tabular import value_iteration

    mdp = corridor()
    mask = np.zeros((5, 2), bool)
    mask[2, 1] = True  # the way right from state 2 is closed
    free = value_iteration(mdp, discount=0.9)
    closed = value_iteration(mdp, discount=0.9, allowed=restrict(mdp, mask).allowed)
    assert free.policy[2] == 1 and closed.policy[2] == 0
    assert closed.values[0] < free.values[0]
