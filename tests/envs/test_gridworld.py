import numpy as np
import pytest

from symlearn.data import record
from symlearn.envs.gridworld import ACTIONS, StochasticGridworld, make_gridworld
from symlearn.errors import SymlearnError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import sample_rollouts


def test_layout_and_model():
    env = StochasticGridworld(0.2)
    mdp = env.to_tabular()
    assert (mdp.n_states, mdp.n_actions) == (49, 4)
    assert mdp.terminal.tolist() == [s == env.goal_state for s in range(49)]
    assert env.forbidden_states.sum() == 12
    # toy-text model and the tabular model agree
    again = TabularMDP.from_gymnasium(make_gridworld(0.2))
    np.testing.assert_allclose(again.transitions, mdp.transitions)
    # a move in open space: intended cell with 1 - p, each of the 4 neighbours with p / 4
    s = env.cell_state((1, 3))
    row = mdp.transitions[s, ACTIONS.index("up")]
    assert row[env.cell_state((0, 3))] == pytest.approx(0.8 + 0.05)
    assert row[env.cell_state((1, 4))] == pytest.approx(0.05)
    # rewards: -1 per step, +1 for entering the goal
    before_goal = env.cell_state((5, 6))
    p_goal = 0.8 + 0.2 / 3  # r5c6 sits on the edge: three neighbours, one of them the goal
    assert mdp.rewards[before_goal, ACTIONS.index("down")] == pytest.approx(p_goal * 1 + (1 - p_goal) * -1)


def test_steps_follow_the_model_statistically():
    env = StochasticGridworld(0.4)
    s = env.cell_state((2, 2))
    counts = np.zeros(env.n_states)
    env.reset(seed=0)
    for _ in range(4000):
        env._state = s
        nxt, *_ = env.step(ACTIONS.index("right"))
        counts[nxt] += 1
    np.testing.assert_allclose(counts / 4000, env.to_tabular().transitions[s, 1], atol=0.03)


def test_violation_flag_and_episode_end():
    env = StochasticGridworld(0.0)
    env.reset(seed=0)
    s, reward, *_ , info = env.step(ACTIONS.index("right"))  # r6c0 -> r6c1, next to the block
    assert not info["violation"] and reward == -1
    _, _, _, _, info = env.step(ACTIONS.index("right"))  # into the block
    assert info["violation"]
    wrapped = make_gridworld(0.0)
    policy = env.expert_policy()
    demos = record(wrapped, lambda s: int(policy[s]), 3, seed=0)
    assert all(len(t) == 15 and t.total_reward() == -12 for t in demos)  # 14 steps, last one +1


def test_constraint_mask_marks_moves_into_the_block():
    env = StochasticGridworld(0.0)
    mask = env.constraint_mask()
    assert mask[env.cell_state((6, 1)), ACTIONS.index("right")]
    assert not mask[env.cell_state((6, 1)), ACTIONS.index("up")]
    assert mask[env.cell_state((2, 3)), ACTIONS.index("down")]
    assert not mask[env.goal_state].any()


@pytest.mark.parametrize("p", [0.0, 0.3, 0.5])
def test_expert_never_chooses_a_forbidden_move_and_rarely_slips_in(p):
    env = StochasticGridworld(p)
    policy = env.expert_policy()
    start_states = ~env.forbidden_states
    assert not env.constraint_mask()[np.arange(49)[start_states], policy[start_states]].any()
    rollouts = sample_rollouts(env.to_tabular(), np.eye(4)[policy], 300, 200, np.random.default_rng(0))
    assert (rollouts.states[:, -1] == -1).all() or rollouts.length.max() <= 200
    assert rollouts.fraction_in(env.forbidden_states).mean() < 0.05
    assert (rollouts.states.max(axis=1) >= 0).all()
    assert np.mean([env.goal_state in row for row in rollouts.states]) > 0.95


def test_maxent_expert_is_a_distribution_over_valid_moves():
    env = StochasticGridworld(0.0)
    pi = env.maxent_expert_policy()
    np.testing.assert_allclose(pi.sum(axis=1), 1.0)
    outside = ~env.forbidden_states
    assert (pi[outside][env.constraint_mask()[outside]] == 0).all()


def test_bad_input():
    with pytest.raises(SymlearnError, match="stochasticity"):
        StochasticGridworld(1.5)
    with pytest.raises(SymlearnError, match="outside"):
        StochasticGridworld(0.0, start=(9, 0))
    with pytest.raises(SymlearnError, match="cannot be forbidden"):
        StochasticGridworld(0.0, forbidden=[(6, 0)])
    env = StochasticGridworld(0.0)
    env.reset(seed=0)
    with pytest.raises(SymlearnError, match="not available"):
        env.step(7)
    with pytest.raises(SymlearnError, match="outside the gridworld"):
        env.state_name(49)


def test_text_map():
    env = StochasticGridworld(0.0, shape=(2, 3), start=(0, 0), goal=(1, 2), forbidden=[(1, 1)])
    assert env.render_text() == "S . .\n. X G"
