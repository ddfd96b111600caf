import numpy as np
import pytest

from symlearn.backends import CostWrapper, Shield
from symlearn.envs.gridworld import ACTIONS, StochasticGridworld, make_gridworld
from symlearn.errors import ModelError, SymlearnError
from symlearn.learners.constraints.mce_icrl import state_features

RIGHT = ACTIONS.index("right")
UP = ACTIONS.index("up")


def truth():
    return StochasticGridworld(0.0).constraint_mask()


def test_mask_is_reported_after_reset_and_every_step():
    env = Shield(make_gridworld(0.0), truth())
    _, info = env.reset(seed=0)
    assert info["action_mask"].dtype == np.int8 and info["action_mask"].tolist() == [1, 1, 1, 1]
    _, _, _, _, info = env.step(RIGHT)  # now next to the block: right is forbidden
    assert info["action_mask"].tolist() == [1, 0, 1, 1]
    assert env.action_masks().tolist() == [True, False, True, True]


def test_replace_refuse_and_raise():
    env = Shield(make_gridworld(0.0), truth(), seed=0)
    env.reset(seed=0)
    env.step(RIGHT)
    state, _, _, _, info = env.step(RIGHT)
    assert info["shield"] == "replaced" and info["shield_action"] != RIGHT
    assert not StochasticGridworld(0.0).forbidden_states[state]

    env = Shield(make_gridworld(0.0), truth(), mode="refuse", refusal_reward=-5)
    env.reset(seed=0)
    before, *_ = env.step(RIGHT)
    after, reward, terminated, truncated, info = env.step(RIGHT)
    assert (after, reward, terminated, truncated, info["shield"]) == (before, -5, False, False, "refused")
    assert env.interventions == 1

    env = Shield(make_gridworld(0.0), truth(), mode="raise")
    env.reset(seed=0)
    env.step(RIGHT)
    with pytest.raises(SymlearnError, match="forbids action 1 in state 43"):
        env.step(RIGHT)


class FactHypothesis:
    """Stands in for an ASP hypothesis: allowed(state_facts, action) on symbolic facts."""

    def allowed(self, facts, action):
        return not ("next_to_block_east" in facts and action == RIGHT)


def test_a_rule_set_with_allowed_plugs_in_through_state_of():
    grid = StochasticGridworld(0.0)

    def facts(observation):
        r, c = grid.state_cell(observation)
        return {"next_to_block_east"} if c == 1 and r >= 3 else set()

    env = Shield(make_gridworld(0.0), FactHypothesis(), state_of=facts)
    _, info = env.reset(seed=0)
    _, _, _, _, info = env.step(RIGHT)
    assert info["action_mask"].tolist() == [1, 0, 1, 1]
    env2 = Shield(make_gridworld(0.0), lambda s, a: a != UP)  # a plain callable
    assert env2.reset(seed=0)[1]["action_mask"].tolist() == [0, 1, 1, 1]


def test_dead_end_lets_everything_through_and_says_so():
    env = Shield(make_gridworld(0.0), np.ones((49, 4), bool))
    _, info = env.reset(seed=0)
    assert info["shield_dead_end"] and info["action_mask"].tolist() == [1, 1, 1, 1]


def test_bad_constraints():
    with pytest.raises(ModelError, match=r"shape \(S, A\) with A = 4, S = 49"):
        Shield(make_gridworld(0.0), np.zeros((3, 4), bool))
    with pytest.raises(SymlearnError, match="unknown shield mode"):
        Shield(make_gridworld(0.0), truth(), mode="ignore")
    env = Shield(make_gridworld(0.0), truth())
    env.reset(seed=0)
    with pytest.raises(SymlearnError, match="not available"):
        env.step(9)
    with pytest.raises(SymlearnError, match="either constraints"):
        CostWrapper(make_gridworld(0.0))


def test_cost_from_mask_and_penalty():
    env = CostWrapper(make_gridworld(0.0), truth(), violation_cost=10, penalty=0.5)
    env.reset(seed=0)
    _, reward, _, _, info = env.step(RIGHT)
    assert info["cost"] == 0 and reward == -1
    _, reward, _, _, info = env.step(RIGHT)
    assert info["cost"] == 10 and reward == -1 - 5


def test_cost_from_multipliers():
    grid = StochasticGridworld(0.0)
    lam = np.zeros(49)
    lam[grid.cell_state((6, 1))] = 2.5
    env = CostWrapper.from_multipliers(make_gridworld(0.0), lam, state_features(grid.to_tabular()))
    env.reset(seed=0)
    costs = [env.step(RIGHT)[4]["cost"] for _ in range(2)]
    assert costs == [0.0, 2.5]  # the cost is of the state the action is taken in
    with pytest.raises(ModelError, match="phi must have shape"):
        CostWrapper.from_multipliers(make_gridworld(0.0), lam, np.ones((49, 4, 3)))
    with pytest.raises(ModelError, match="cost must have shape"):
        CostWrapper.from_array(make_gridworld(0.0), np.ones((2, 2)))


def test_wrappers_compose():
    env = CostWrapper(Shield(make_gridworld(0.0), truth()), truth(), violation_cost=10)
    _, info = env.reset(seed=0)
    assert "action_mask" in info
    env.step(RIGHT)
    _, _, _, _, info = env.step(RIGHT)  # the shield replaces it before anything happens
    assert info["shield"] == "replaced" and "action_mask" in info


def test_observations_outside_the_mask_are_reported():
    import gymnasium as gym

    env = Shield(gym.make("FrozenLake-v1"), np.zeros((49, 4), bool), state_of=lambda obs: obs + 100)
    with pytest.raises(SymlearnError, match=r"state 100 is outside the constraint mask \(0..48\)"):
        env.reset(seed=0)
