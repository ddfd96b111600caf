import gymnasium as gym
import numpy as np
import pytest

from symlearn.errors import ModelError
from symlearn.mdp import TabularMDP


def chain(n=4):
    """A corridor: action 0 stays, action 1 moves right; the last state is the goal."""
    P = np.zeros((n, 2, n))
    for s in range(n):
        P[s, 0, s] = 1
        P[s, 1, min(s + 1, n - 1)] = 1
    initial = np.eye(n)[0]
    return TabularMDP(P, np.zeros((n, 2)), initial, np.zeros(n, bool),
                      state_names=[f"c{s}" for s in range(n)], action_names=["stay", "right"])


def test_construction_and_names():
    mdp = chain()
    assert (mdp.n_states, mdp.n_actions) == (4, 2)
    assert mdp.state_index("c2") == 2 and mdp.action_index("right") == 1
    assert mdp.successors(1, 1) == {2: 1.0}
    with pytest.raises(ValueError):
        mdp.transitions[0, 0, 0] = 0.5  # read-only


def test_goal_conditioning():
    mdp = chain().with_goal("c3", goal_reward=1.0)
    assert mdp.goals == (3,) and mdp.terminal[3]
    assert mdp.rewards[2, 1] == 1.0 and mdp.rewards[2, 0] == 0.0 and mdp.rewards[3].sum() == 0
    assert mdp.successors(3, 1) == {3: 1.0}


def test_reward_on_transitions_is_averaged():
    P = np.zeros((2, 1, 2))
    P[0, 0] = [0.25, 0.75]
    P[1, 0, 1] = 1
    R = np.zeros((2, 1, 2))
    R[0, 0, 1] = 4.0
    mdp = TabularMDP(P, R, [1, 0], [False, True])
    assert mdp.rewards[0, 0] == pytest.approx(3.0)


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(transitions=np.ones((2, 1, 2))), "sum to 2, not 1"),
        (dict(transitions=np.ones((2, 1, 3)) / 3), r"shape \(S, A, S\)"),
        (dict(rewards=np.zeros((3, 1))), "rewards must have shape"),
        (dict(rewards=np.full((2, 1), np.nan)), "rewards must be finite"),
        (dict(initial=[0.5, 0.2]), "probability vector"),
        (dict(terminal=[True]), "boolean vector of length 2"),
        (dict(state_names=["a", "a"]), "state names must be unique"),
        (dict(action_names=["a", "b"]), "2 action names for 1 actions"),
        (dict(goals=(5,)), "goal states must be in 0..1"),
    ],
)
def test_invalid_models_are_refused(change, message):
    base = dict(transitions=np.array([[[0.0, 1.0]], [[0.0, 1.0]]]), rewards=np.zeros((2, 1)),
                initial=[1.0, 0.0], terminal=[False, True])
    base.update(change)
    with pytest.raises(ModelError, match=message):
        TabularMDP(**base)


def test_from_gymnasium_frozen_lake():
    env = gym.make("FrozenLake-v1", is_slippery=True)
    mdp = TabularMDP.from_gymnasium(env, action_names=["left", "down", "right", "up"])
    assert (mdp.n_states, mdp.n_actions) == (16, 4)
    holes_and_goal = {5, 7, 11, 12, 15}
    assert set(np.flatnonzero(mdp.terminal)) == holes_and_goal
    assert mdp.initial[0] == 1.0
    # slippery: the intended move and both perpendicular ones, a third each
    assert mdp.successors(0, 2) == pytest.approx({0: 1 / 3, 4: 1 / 3, 1: 1 / 3})
    assert mdp.rewards[14, 2] == pytest.approx(1 / 3)
    assert mdp.successors(5, 0) == {5: 1.0}


def test_from_gymnasium_needs_a_model():
    with pytest.raises(ModelError, match="does not expose its transition model"):
        TabularMDP.from_gymnasium(gym.make("CartPole-v1"))


class _StartsAnywhere(gym.Env):
    """Gymnasium's toy-text model ``P`` without ``initial_state_distrib``: starts in 1 or 2."""

    observation_space, action_space = gym.spaces.Discrete(3), gym.spaces.Discrete(1)
    P = {s: {0: [(1.0, s, 0.0, False)]} for s in range(3)}

    def __init__(self, start=None):
        self.start = start

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return (int(self.np_random.integers(1, 3)) if self.start is None else self.start), {}

    def step(self, action):
        return 0, 0.0, False, False, {}


def test_from_gymnasium_reads_a_missing_start_distribution_off_the_resets():
    mdp = TabularMDP.from_gymnasium(_StartsAnywhere())
    assert mdp.initial[0] == 0 and mdp.initial[1] > 0 and mdp.initial[2] > 0 and mdp.initial.sum() == 1
    with pytest.raises(ModelError, match="reset\\(\\) returned 7, not a state 0..2"):
        TabularMDP.from_gymnasium(_StartsAnywhere(start=7))


def test_from_gymnasium_uses_an_environments_own_model():
    from symlearn.envs.office_world import make_office_world

    mdp = TabularMDP.from_gymnasium(make_office_world())
    assert (mdp.n_states, mdp.n_actions) == (108, 4) and mdp.action_names == ("up", "right", "down", "left")
    renamed = TabularMDP.from_gymnasium(make_office_world(), action_names=["n", "e", "s", "w"])
    assert renamed.action_names == ("n", "e", "s", "w")


def test_a_name_says_which_world_and_derived_models_keep_it():
    from symlearn.learners.constraints.constraint_file import world_name

    named = TabularMDP(chain().transitions, np.zeros((4, 2)), np.eye(4)[0], np.zeros(4, bool), name="corridor")
    assert named.with_goal(3).name == named.make_absorbing([2]).name == "corridor"
    assert world_name(named) == "corridor" and world_name(chain()) is None and chain().name is None
    for bad in ("", "  ", 3):
        with pytest.raises(ModelError, match="name"):
            TabularMDP(chain().transitions, np.zeros((4, 2)), np.eye(4)[0], np.zeros(4, bool), name=bad)
