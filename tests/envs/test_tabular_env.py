"""TabularEnv: a gymnasium environment over any TabularMDP (and over a user's Domain)."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from symlearn.envs.tabular_env import TabularEnv
from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP
from symlearn.rl.q_learning import q_learning


def chain(slip: float = 0.0) -> TabularMDP:
    """start -> middle -> goal (terminal); action 0 = forward (slips back with ``slip``), 1 = stay."""
    P = np.zeros((3, 2, 3))
    P[0, 0, 1], P[0, 0, 0] = 1.0 - slip, slip
    P[1, 0, 2], P[1, 0, 1] = 1.0 - slip, slip
    P[0, 1, 0] = P[1, 1, 1] = 1.0
    P[2, :, 2] = 1.0
    R = np.array([[-1.0, -2.0], [10.0, -2.0], [0.0, 0.0]])
    return TabularMDP(P, R, [1, 0, 0], [False, False, True], ("start", "middle", "goal"), ("forward", "stay"))


def test_reset_and_step_follow_the_model():
    env = TabularEnv(chain(), violations=np.array([[False, True], [False, False], [False, False]]))
    assert env.observation_space.n == 3 and env.action_space.n == 2
    state, info = env.reset(seed=0)
    assert state == 0 and info == {"state_name": "start"}
    state, reward, terminated, truncated, info = env.step(1)
    assert (state, reward, terminated, truncated) == (0, -2.0, False, False)
    assert info == {"state_name": "start", "action_name": "stay", "violation": True}
    state, reward, terminated, truncated, info = env.step(np.int64(0))
    assert (state, reward, terminated, truncated, info["violation"]) == (1, -1.0, False, False, False)
    state, reward, terminated, truncated, info = env.step(0)
    assert (state, reward, terminated, truncated, info["state_name"]) == (2, 10.0, True, False, "goal")


def test_no_violation_key_without_a_mask():
    env = TabularEnv(chain())
    env.reset(seed=0)
    assert "violation" not in env.step(0)[4]


def test_terminal_and_truncation():
    env = TabularEnv(chain(), max_steps=3)
    env.reset(seed=0)
    outcomes = [env.step(1)[2:4] for _ in range(3)]
    assert outcomes == [(False, False), (False, False), (False, True)]
    with pytest.raises(SymlearnError, match="no episode is running"):
        env.step(0)  # after truncation the episode is over
    env.reset()
    env.step(0)
    # entering the terminal state on the very last step is termination, not truncation
    env = TabularEnv(chain(), max_steps=2)
    env.reset(seed=0)
    env.step(0)
    assert env.step(0)[2:4] == (True, False)
    with pytest.raises(SymlearnError, match="reset"):
        env.step(0)


def test_seeding_reproduces_episodes():
    def episode(env, seed):
        states = [env.reset(seed=seed)[0]]
        for _ in range(20):
            state, _, terminated, truncated, _ = env.step(0)
            states.append(state)
            if terminated or truncated:
                break
        return states

    env = TabularEnv(chain(slip=0.5), max_steps=20)
    runs = {seed: episode(env, seed) for seed in range(8)}
    assert all(episode(TabularEnv(chain(slip=0.5), max_steps=20), seed) == runs[seed] for seed in runs)
    assert len({tuple(r) for r in runs.values()}) > 1  # slips really are random


def test_initial_distribution_is_sampled():
    P = np.zeros((3, 1, 3))
    P[:, 0, 2] = 1.0
    mdp = TabularMDP(P, np.zeros((3, 1)), [0.5, 0.5, 0.0], [False, False, True])
    env = TabularEnv(mdp)
    starts = {env.reset(seed=seed)[0] for seed in range(30)}
    assert starts == {0, 1}


@pytest.mark.filterwarnings("ignore:.*not having a spec:UserWarning")  # built directly, not by gymnasium.make
def test_passes_gymnasium_check_env():
    check_env(TabularEnv(chain(slip=0.2)), skip_render_check=True)
    env = TabularEnv(chain(), render_mode="ansi")
    check_env(env)
    env.reset(seed=0)
    assert env.render().startswith("state 0 (start)")


def test_accepts_a_domain_and_round_trips_the_model():
    mdp = chain()

    class Wrapper:  # anything with a .mdp, as a Domain or a bundled LogicMDP
        def __init__(self, model):
            self.mdp = model

    env = TabularEnv(Wrapper(mdp))
    assert TabularMDP.from_gymnasium(env) is mdp


def test_bad_input_is_a_symlearn_error():
    with pytest.raises(ModelError, match="needs a TabularMDP"):
        TabularEnv(np.zeros((3, 2, 3)))
    with pytest.raises(ModelError, match="shape"):
        TabularEnv(chain(), violations=np.zeros((3, 3), bool))
    with pytest.raises(ModelError, match="boolean"):
        TabularEnv(chain(), violations=np.zeros((3, 2)))
    with pytest.raises(SymlearnError, match="max_steps"):
        TabularEnv(chain(), max_steps=0)
    with pytest.raises(SymlearnError, match="render mode"):
        TabularEnv(chain(), render_mode="human")
    env = TabularEnv(chain())
    with pytest.raises(SymlearnError, match="reset"):
        env.step(0)
    env.reset(seed=0)
    for bad in (2, -1, 0.5, True):
        with pytest.raises(ModelError, match="outside"):
            env.step(bad)


def test_q_learning_counts_violations_in_the_env():
    # "stay" in the start is flagged: an agent that explores breaks it, a greedy one learns to go on
    violations = np.array([[False, True], [False, False], [False, False]])
    result = q_learning(TabularEnv(chain(), violations=violations, max_steps=10), 50, epsilon=0.3, seed=0)
    assert result.violations.sum() > 0
    assert result.greedy_policy()[:2].tolist() == [0, 0]
