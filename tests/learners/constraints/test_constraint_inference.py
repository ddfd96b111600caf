import warnings

import numpy as np
import pytest

from symlearn.data import Demonstrations, Trajectory, record
from symlearn.envs.gridworld import ACTIONS, StochasticGridworld
from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.learners.constraints.mce_icrl import MCEICRL, MEICRL
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.rl.tabular import restrict, sample_rollouts


def maxent_demos(env, n, seed):
    pi = env.maxent_expert_policy()
    rng = np.random.default_rng(seed)
    return record(env, lambda s: int(rng.choice(4, p=pi[s])), n, seed=seed, max_steps=200)


def expert_demos(env, n, seed):
    policy = env.expert_policy()
    return record(env, lambda s: int(policy[s]), n, seed=seed, max_steps=200)


# --- maximum-likelihood constraint inference --------------------------------------------------
@pytest.mark.parametrize("seed", [0, 1])
def test_ml_inference_recovers_the_block_in_a_deterministic_gridworld(seed):
    env = StochasticGridworld(0.0)
    demos = maxent_demos(env, 30, seed)
    learner = MLConstraintInference(horizon=30, rationality=3, min_visitation=1e-4).fit(demos, env.to_tabular())
    entries = env.constraint_mask() & ~env.forbidden_states[:, None]
    assert (learner.constraints_ & entries).sum() == entries.sum()  # every move into the block
    assert not (learner.constraints_ & learner.demonstrated_).any()
    # the block is unreachable from the start in the restricted model
    reach = np.zeros(49, bool)
    frontier = [env.start_state]
    reach[env.start_state] = True
    P = env.to_tabular().transitions
    while frontier:
        s = frontier.pop()
        for a in np.flatnonzero(~learner.constraints_[s]):
            for t in np.flatnonzero(P[s, a]):
                if not reach[t]:
                    reach[t] = True
                    frontier.append(t)
    assert not (reach & env.forbidden_states).any() and reach[env.goal_state]
    # constraints were added in order of decreasing likelihood gain
    visits = [step.visitation for step in learner.history_]
    assert learner.stopped_because_ == "min_visitation" and visits[-1] >= 1e-4
    assert len(learner.history_) >= entries.sum()


def test_ml_inference_with_the_sparse_inferred_reward():
    env = StochasticGridworld(0.0)
    demos = maxent_demos(env, 30, 0)
    learner = MLConstraintInference(reward="sparse", horizon=30, rationality=3).fit(demos, env.to_tabular())
    entries = env.constraint_mask() & ~env.forbidden_states[:, None]
    assert (learner.constraints_ & entries).sum() >= entries.sum() - 1
    assert learner.goals_ == (env.goal_state,)


def test_ml_inference_stops_after_max_iterations_and_calls_generalize():
    env = StochasticGridworld(0.0)
    demos = expert_demos(env, 2, 0)
    calls = []

    def generalize(forbidden, seen):
        calls.append(int(forbidden.sum()))
        extra = np.zeros_like(forbidden)
        extra[env.cell_state((0, 0))] = True  # a rule that forbids a whole corner state
        return extra

    learner = MLConstraintInference(horizon=20, max_iterations=3, generalize=generalize).fit(demos, env.to_tabular())
    assert learner.stopped_because_ == "max_iterations" and len(learner.history_) == 3 and len(calls) == 3
    assert learner.constraints_[env.cell_state((0, 0))].all() and learner.empty_states_[env.cell_state((0, 0))]
    assert learner.history_[0].n_generalized >= 4


def test_ml_inference_closes_the_set_in_a_stochastic_gridworld():
    env = StochasticGridworld(0.3)
    demos = expert_demos(env, 10, 0)
    learner = MLConstraintInference(horizon=30, rationality=3, max_iterations=40).fit(demos, env.to_tabular())
    again = restrict(env.to_tabular(), learner.constraints_, protected=learner.demonstrated_)
    np.testing.assert_array_equal(again.forbidden, learner.constraints_)  # already closed


# --- MCE-ICRL and ME-ICRL ----------------------------------------------------------------------
def violation_rate(env, policy, seed=123):
    rollouts = sample_rollouts(env.to_tabular(), policy, 1000, 200, np.random.default_rng(seed))
    return float(rollouts.fraction_in(env.forbidden_states).mean())


def test_mce_icrl_forbids_no_state_the_expert_heads_for_but_keeps_the_cells_it_slipped_into():
    """With slips (p = 0.3) the expert's own route gets multipliers above the threshold too (the
    entropy-regularised policy visits it more often than the demonstrations); the binary reading
    leaves out the states it heads for, and only those: the block keeps every cell the raw
    multipliers mark, although the expert was carried into some of it."""
    from symlearn.learners.constraints.mce_icrl import deliberate_moves
    from symlearn.mdp.episodes import tabular_episodes

    env = StochasticGridworld(0.3)
    demos = expert_demos(env, 30, 0)
    learner = MCEICRL(n_iterations=150).fit(demos, env.to_tabular())
    raw = learner.lambda_ > learner.threshold
    episodes = tabular_episodes(demos, env.to_tabular())
    visited = np.zeros(env.n_states, dtype=bool)
    for e in episodes:
        visited[e.states] = True
    assert visited[env.forbidden_states].any()  # the dynamics carried the expert into the block
    headed, moves = deliberate_moves(env.to_tabular(), episodes)
    assert np.array_equal(headed, learner.headed_for_) and not headed[env.forbidden_states].any()
    assert (raw & headed).any()  # route cells with a multiplier above the threshold...
    assert not (learner.constraint_map_ & headed).any()  # ...are not read as forbidden
    assert np.array_equal(learner.constraint_map_[env.forbidden_states], raw[env.forbidden_states])
    assert not (learner.forbidden_ & moves).any()  # no move the expert made on purpose is forbidden
    assert np.array_equal(learner.constraint_map_, raw & ~headed)


def test_mce_icrl_stops_when_the_excess_stalls():
    """With slips the demonstrations' feature counts are not exactly reachable: the excess settles
    and the multipliers only grow; the loop stops there (stop_reason_ "stalled") instead of at the cap."""
    env = StochasticGridworld(0.3)
    demos = expert_demos(env, 30, 0)
    stalled = MCEICRL().fit(demos, env.to_tabular())
    capped = MCEICRL(patience=None).fit(demos, env.to_tabular())
    assert stalled.stop_reason_ == "stalled" and stalled.n_iter_ < capped.n_iter_ == 300
    assert capped.stop_reason_ == "max_iterations" and not stalled.converged_
    assert min(h.excess for h in stalled.history_) <= 1.1 * min(h.excess for h in capped.history_)
    assert stalled.constraint_map_[env.forbidden_states].mean() >= 0.9  # the block is still found
    assert MCEICRL(n_iterations=1000, tol=10.0).fit(demos, env.to_tabular()).stop_reason_ == "converged"
    with pytest.raises(SymlearnError, match="patience"):
        MCEICRL(patience=0).fit(demos, env.to_tabular())


def test_mce_icrl_learns_the_block_without_noise():
    env = StochasticGridworld(0.0)
    learner = MCEICRL(n_iterations=150).fit(expert_demos(env, 20, 0), env.to_tabular())
    assert violation_rate(env, learner.policy_) < 0.01
    assert learner.constraint_map_[env.forbidden_states].mean() > 0.5
    nominal = violation_rate(env, MCEICRL(n_iterations=1).fit(expert_demos(env, 2, 0), env.to_tabular()).policy_)
    assert nominal > 0.1  # without learned costs the agent walks through the block
    assert (learner.lambda_ >= 0).all() and learner.cost_.shape == (49, 4)
    excess = [step.excess for step in learner.history_]
    assert excess[-1] < 0.2 * excess[0]


@pytest.mark.parametrize("p", [0.3, pytest.param(0.5, marks=pytest.mark.slow)])
def test_mce_icrl_beats_me_icrl_on_violations_under_stochastic_dynamics(p):
    env = StochasticGridworld(p)
    demos = expert_demos(env, 50, 1)
    mce = MCEICRL(n_iterations=150).fit(demos, env.to_tabular())
    me = MEICRL(n_iterations=150).fit(demos, env.to_tabular())
    mce_rate, me_rate = violation_rate(env, mce.policy_), violation_rate(env, me.policy_)
    assert mce_rate < 0.08
    assert me_rate > 2 * mce_rate


def test_mce_icrl_with_state_action_features_and_known_constraints():
    env = StochasticGridworld(0.0)
    demos = expert_demos(env, 5, 0)
    learner = MCEICRL(features="state_action", n_iterations=50,
                      known_constraints=env.constraint_mask()).fit(demos, env.to_tabular())
    assert learner.lambda_.shape == (49 * 4,)
    assert (learner.policy_[env.constraint_mask() & ~env.forbidden_states[:, None]] == 0).all()


# --- bad input ---------------------------------------------------------------------------------
def test_states_outside_the_environment():
    env = StochasticGridworld(0.0)
    demos = Demonstrations([Trajectory([42, 35, 99], [0, 0])])
    for learner in (MLConstraintInference(), MCEICRL()):
        with pytest.raises(DataError, match=r"demonstration 0: states: step 2: state 99 is outside the environment \(0..48\)"):
            learner.fit(demos, env.to_tabular())


def test_actions_not_available():
    env = StochasticGridworld(0.0)
    demos = Demonstrations([Trajectory([42, 35], [7])])
    with pytest.raises(DataError, match="action 7 is outside the environment"):
        MLConstraintInference().fit(demos, env.to_tabular())
    with pytest.raises(DataError, match="unknown action 'jump'"):
        MCEICRL().fit([(np.array([42, 35]), np.array(["jump"]))], env.to_tabular())
    with pytest.raises(DataError, match="has no actions"):
        MCEICRL().fit(Demonstrations([Trajectory([42, 35])]), env.to_tabular())


def test_demonstrations_that_break_the_given_constraints():
    env = StochasticGridworld(0.0)
    into_block = [env.start_state, env.cell_state((6, 1)), env.cell_state((6, 2))]
    bad = Demonstrations([Trajectory(into_block, [1, 1], rewards=[-1, -1])])
    with pytest.raises(DataError, match=r"demonstration 0, step 1: state 43, action 1 breaks the given constraints \(1 violating"):
        MLConstraintInference(known_constraints=env.constraint_mask()).fit(bad, env.to_tabular())
    with pytest.raises(DataError, match="breaks the given constraints"):
        MCEICRL(known_constraints=env.constraint_mask()).fit(bad, env.to_tabular())
    noisy = expert_demos(env, 3, 0) + bad
    with pytest.warns(UserWarning, match="1 demonstrated step"):
        learner = MLConstraintInference(known_constraints=env.constraint_mask(),
                                        on_violation="warn", horizon=20).fit(noisy, env.to_tabular())
    assert not learner.constraints_[env.cell_state((6, 1)), ACTIONS.index("right")]  # noise is kept allowed


def test_impossible_steps_are_counted_as_noise():
    env = StochasticGridworld(0.0)
    jump = Demonstrations([Trajectory([env.start_state, env.cell_state((0, 0)), env.cell_state((0, 1))], [0, 1])])
    with pytest.warns(UserWarning, match="1 demonstrated step"):
        MLConstraintInference(horizon=10, max_iterations=1).fit(jump, env.to_tabular())


def test_bad_settings():
    env = StochasticGridworld(0.0)
    demos = expert_demos(env, 1, 0)
    with pytest.raises(SymlearnError, match="unknown features"):
        MCEICRL(features="pixels").fit(demos, env.to_tabular())
    with pytest.raises(ModelError, match="features must have shape"):
        MCEICRL(features=np.ones((3, 3, 3))).fit(demos, env.to_tabular())
    with pytest.raises(SymlearnError, match="unknown reward"):
        MLConstraintInference(reward="dense").fit(demos, env.to_tabular())
    with pytest.raises(DataError, match="no demonstrations"):
        MLConstraintInference().fit([], env.to_tabular())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        MLConstraintInference(horizon=5, max_iterations=1).fit(demos, env)  # an env with to_tabular() works


def test_reach_scores_leave_out_the_states_a_rule_abiding_agent_never_reaches():
    from symlearn.learners.constraints.constraint_metrics import reach_scores
    from symlearn.mdp import TabularMDP

    # a chain 0 -> 1 -> 2 (action 0: forward, action 1: stay); the truth forbids 0's forward move,
    # so 1 and 2 are unreachable from 0, and a rule that forbids staying in 1 is invisible there
    P = np.zeros((3, 2, 3))
    P[0, 0, 1] = P[1, 0, 2] = P[2, 0, 2] = 1.0
    for s in range(3):
        P[s, 1, s] = 1.0
    mdp = TabularMDP(P, np.zeros((3, 2)), [1.0, 0.0, 0.0], [False, False, False])
    truth = np.array([[True, False], [False, False], [False, False]])
    learned = truth | np.array([[False, False], [False, True], [False, False]])
    scores = reach_scores(learned, truth, mdp, np.ones((3, 2), bool))
    assert scores == {"reach_fpr": 0.0, "reach_fnr": 0.0, "reach_pairs": 2, "unreachable": 4}
