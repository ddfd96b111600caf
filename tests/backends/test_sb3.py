"""stable-baselines3 agents through our wrappers: MaskablePPO on a shield, DQN on a reward machine
with counterfactual experiences. Skipped without the ``sb3`` extra (``pip install 'symlearn[sb3]'``)."""

import gymnasium as gym
import pytest

sb3 = pytest.importorskip("stable_baselines3")
sb3_contrib = pytest.importorskip("sb3_contrib")
torch = pytest.importorskip("torch")

from stable_baselines3 import DQN, PPO  # noqa: E402
from stable_baselines3.common.vec_env import DummyVecEnv  # noqa: E402

from symlearn.backends import RewardMachineWrapper, Shield, task_machine  # noqa: E402
from symlearn.backends.sb3 import counterfactual_callback  # noqa: E402
from symlearn.envs.gridworld import StochasticGridworld, make_gridworld  # noqa: E402
from symlearn.envs.labelled_grid import LabelledGridEnv  # noqa: E402
from symlearn.envs.office_world import TASKS, make_office_world  # noqa: E402
from symlearn.errors import SymlearnError  # noqa: E402


pytestmark = pytest.mark.usefixtures("one_torch_thread")  # tests/backends/conftest.py


def shielded_gridworld():
    # mode="raise": a single forbidden action anywhere in training fails the test.
    return Shield(make_gridworld(0.0), StochasticGridworld(0.0).constraint_mask(), mode="raise")


def test_maskable_ppo_on_a_shield_never_takes_a_forbidden_action():
    env = shielded_gridworld()
    model = sb3_contrib.MaskablePPO("MlpPolicy", env, n_steps=256, batch_size=64, n_epochs=4, seed=0, device="cpu",
                                    policy_kwargs={"net_arch": [32, 32]})
    model.learn(3_000)
    assert model.num_timesteps >= 3_000 and env.interventions == 0
    state, _ = env.reset(seed=1)
    for _ in range(200):
        action, _ = model.predict(state, action_masks=env.action_masks(), deterministic=True)
        state, _, terminated, truncated, _ = env.step(int(action))
        if terminated or truncated:
            break
    assert env.interventions == 0


def test_an_unmasked_agent_meets_the_shield():
    """The same run without masks does try forbidden actions: the test above could fail."""
    model = PPO("MlpPolicy", shielded_gridworld(), n_steps=256, batch_size=64, seed=0, device="cpu",
                policy_kwargs={"net_arch": [32, 32]})
    with pytest.raises(SymlearnError, match="the shield forbids"):
        model.learn(3_000)


def then_task():
    """A 4x4 grid: first ``b`` (bottom right), then ``a`` (top left); 9 steps at best."""
    grid = LabelledGridEnv(4, 4, {(3, 0): {"b"}, (0, 3): {"a"}}, (0, 0), max_steps=40)
    return grid, task_machine("b T a")


def dqn(env, seed=0, **kwargs):
    settings = dict(learning_rate=1e-3, buffer_size=20_000, learning_starts=500, batch_size=64, gamma=0.95,
                    train_freq=1, target_update_interval=250, exploration_fraction=0.3, exploration_final_eps=0.05,
                    policy_kwargs={"net_arch": [64, 64]}, seed=seed, device="cpu")
    settings.update(kwargs)
    policy = "MultiInputPolicy" if isinstance(env.observation_space, gym.spaces.Dict) else "MlpPolicy"
    return DQN(policy, env, **settings)


def test_dqn_with_counterfactual_experiences_learns_a_two_stage_task():
    """Seed 3 is one where plain DQN has not learned the task after these 4000 steps (measured:
    without the callback 3 of seeds 0-5 fail, with it none)."""
    grid, machine = then_task()
    env = RewardMachineWrapper(grid, machine, grid.labeling, observation="discrete", counterfactual=True)
    callback = counterfactual_callback()
    model = dqn(env, seed=3).learn(4_000, callback=callback)
    assert callback.n_added == 4_000  # one other machine state to replay each step for
    observation, _ = env.reset(seed=0)
    for step in range(1, 41):
        action, _ = model.predict(observation, deterministic=True)
        observation, reward, terminated, truncated, info = env.step(int(action))
        if terminated or truncated:
            break
    assert terminated and reward == 1.0 and step == 9  # b, then a, by the shortest path


def test_the_callback_fills_the_buffer_with_experiences_the_machine_agrees_with():
    """Two environments side by side, Dict observations: every added entry is a machine step."""
    world = make_office_world(max_steps=50)
    machine = task_machine(TASKS["office-3"])

    def make():
        return RewardMachineWrapper(make_office_world(max_steps=50), machine, world.labeling, counterfactual=True)

    venv = DummyVecEnv([make, make])
    callback = counterfactual_callback()
    model = dqn(venv, learning_starts=10_000)  # collect only
    model.learn(200, callback=callback)
    buffer = model.replay_buffer
    acting = len(make().acting_states)
    assert buffer.size() * 2 == 200 + callback.n_added
    assert 200 * (acting - 1) - 1 <= callback.n_added <= 200 * acting  # the odd one waits for a partner
    seen = 0
    for slot in range(buffer.size()):
        for k in range(2):
            s, u = int(buffer.observations["env"][slot, k, 0]), int(buffer.observations["rm"][slot, k, 0])
            s2, u2 = int(buffer.next_observations["env"][slot, k, 0]), int(buffer.next_observations["rm"][slot, k, 0])
            expected_u2, expected_r = machine.step(u, world.labeling.label(s2))
            assert (u2, buffer.rewards[slot, k]) == (expected_u2, expected_r)
            ends = u2 in machine.terminal or u2 in machine.accepting
            assert buffer.dones[slot, k] == ends or buffer.timeouts[slot, k]
            assert s2 == world.next_state(s, int(buffer.actions[slot, k, 0]))
            seen += 1
    assert seen == 200 + callback.n_added


def test_the_callback_explains_what_it_needs():
    grid, machine = then_task()
    plain = RewardMachineWrapper(grid, machine, grid.labeling, observation="discrete")
    with pytest.raises(SymlearnError, match="counterfactual=True"):
        dqn(plain, learning_starts=10).learn(20, callback=counterfactual_callback())
    grid, machine = then_task()
    env = RewardMachineWrapper(grid, machine, grid.labeling, observation="discrete", counterfactual=True)
    with pytest.raises(SymlearnError, match="no replay buffer"):
        PPO("MlpPolicy", env, n_steps=64, device="cpu").learn(64, callback=counterfactual_callback())
    with pytest.raises(SymlearnError, match="optimize_memory_usage"):
        dqn(env, optimize_memory_usage=True, replay_buffer_kwargs={"handle_timeout_termination": False}).learn(
            20, callback=counterfactual_callback())


def test_maskable_ppo_on_a_shield_built_from_asp_rules():
    """``Shield(env, hypothesis)`` under MaskablePPO: every step decided by the rules, none broken."""
    from symlearn.envs.junction_env import JunctionEnv
    from symlearn.envs.logic_domains import logic_domain
    from symlearn.logic.asp import Hypothesis, Program

    domain = logic_domain("junction-priority")
    hypothesis = Hypothesis.from_lp(domain.truth_path, background=Program.from_text(domain.background()))
    env = Shield(JunctionEnv("priority"), hypothesis, mode="raise")
    model = sb3_contrib.MaskablePPO("MlpPolicy", env, n_steps=256, batch_size=64, n_epochs=4, seed=0, device="cpu",
                                    policy_kwargs={"net_arch": [32, 32]})
    model.learn(1_024)
    assert model.num_timesteps >= 1_024 and env.interventions == 0
    observation, _ = env.reset(seed=1)
    violations = 0
    for _ in range(50):
        action, _ = model.predict(observation, action_masks=env.action_masks(), deterministic=True)
        observation, _, terminated, truncated, info = env.step(int(action))
        violations += info["violation"]
        if terminated or truncated:
            break
    assert violations == 0
