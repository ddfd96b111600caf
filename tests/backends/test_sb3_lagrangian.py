"""stable-baselines3 on a user's environment with a learned cost: the cost wrappers, the
multiplier callback, and policy files in safetensors + JSON. Skipped without the ``sb3`` extra."""

import numpy as np
import pytest

sb3 = pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

from point_robot_env import PointRobot  # noqa: E402  (tests/support: a user's environment)
from stable_baselines3 import PPO  # noqa: E402
from stable_baselines3.common.vec_env import DummyVecEnv  # noqa: E402

from symlearn.backends.dnf_cost import FormulaCost  # noqa: E402
from symlearn.backends.lagrangian import (  # noqa: E402
    FeatureVectorWrapper,
    LagrangianReward,
    SharedMultipliers,
    StepCostWrapper,
)
from symlearn.backends.sb3 import check_action_space, lagrangian_callback, load_policy, save_policy  # noqa: E402
from symlearn.errors import DataError, ModelError, SymlearnError  # noqa: E402
from symlearn.logic.dnf import parse  # noqa: E402
from symlearn.rl.ppo import LagrangianConfig  # noqa: E402

HAZARD = parse("x > 0.4 & x < 0.6 & y < 0.6")   # exactly the robot's true hazard


pytestmark = pytest.mark.usefixtures("one_torch_thread")  # tests/backends/conftest.py


def dnf_step_cost(names=("x", "y")):
    formula = FormulaCost(HAZARD, names)

    def cost(observation, action, next_observation, info):
        return formula(np.asarray(info["features"], dtype=np.float64).reshape(1, -1))[0][0]
    return cost


def lagrangian_robot(multipliers, **kwargs):
    return LagrangianReward(StepCostWrapper(FeatureVectorWrapper(PointRobot(**kwargs), ("x", "y")), dnf_step_cost()),
                            multipliers, cost_key="learned_cost")


def test_the_learner_sees_r_minus_lambda_c_of_the_learned_cost_and_the_true_cost_stays():
    multipliers = SharedMultipliers(fixed=[2.5])
    env = lagrangian_robot(multipliers, named_features=True)   # names only as dict keys
    env.reset(seed=0)
    seen_cost = 0
    for _ in range(10):   # straight to the right along y ~ 0.1: through the hazard
        _, reward, _, _, info = env.step(np.array([0.1, 0.0], dtype=np.float32))
        assert info["learned_cost"].tolist() == [info["cost"]]   # the formula is the truth here
        assert reward == pytest.approx(info["env_reward"] - 2.5 * info["cost"])
        seen_cost += info["cost"]
    assert seen_cost >= 1


def test_the_multiplier_callback_raises_lambda_while_the_agent_breaks_the_limit():
    multipliers = SharedMultipliers(LagrangianConfig(cost_limit=0.0, update="gradient", lr=0.5, init=0.0), 1)
    venv = DummyVecEnv([lambda: lagrangian_robot(multipliers)] * 2)
    callback = lagrangian_callback(multipliers, cost_key="learned_cost")
    model = PPO("MlpPolicy", venv, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu",
                policy_kwargs={"net_arch": [16, 16]})
    model.learn(512, callback=callback)
    assert len(multipliers.history) == 4   # one update per rollout of 2 x 64 steps
    costs = [h["cost"][0] for h in multipliers.history]
    lambdas = [h["multipliers"][0] for h in multipliers.history]
    assert max(costs) > 0 and lambdas[-1] > 0
    # gradient ascent on J_c - limit: each step adds lr times the estimated cost
    assert lambdas[0] == pytest.approx(0.5 * costs[0])


def test_a_neural_cost_as_a_step_cost():
    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    robot = PointRobot()
    cost = NeuralCost.for_env(robot, FeatureNetwork([0], 0, 1, (8,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([1.0])
    env = StepCostWrapper(robot, lambda s, a, s2, info: cost(np.asarray(s)[None]))
    observation, _ = env.reset(seed=0)
    _, _, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    assert info["learned_cost"].tolist() == pytest.approx(cost(observation[None]).tolist())
    assert "cost" in info   # the environment's own stays
    bad = StepCostWrapper(PointRobot(), lambda *args: float("nan"))
    bad.reset(seed=0)
    with pytest.raises(DataError, match="not finite"):
        bad.step(np.zeros(2, dtype=np.float32))


def test_policies_round_trip_through_safetensors_and_refuse_other_spaces(tmp_path):
    env = PointRobot()
    model = PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(64)
    path = save_policy(model, tmp_path / "agent.safetensors", {"env": "robot"})
    assert path.exists() and path.with_suffix(".json").exists() and not list(tmp_path.glob("*.zip"))
    again = load_policy(path, PointRobot())
    observations = np.random.default_rng(0).uniform(0, 1, size=(20, 2)).astype(np.float32)
    assert np.allclose(model.predict(observations, deterministic=True)[0],
                       again.predict(observations, deterministic=True)[0])
    with pytest.raises(ModelError, match="trained for actions"):
        load_policy(path, PointRobot(discrete=True))


def test_an_algorithm_that_cannot_act_in_the_space_is_one_line():
    with pytest.raises(SymlearnError, match="DQN acts only in Discrete action spaces.*use sb3-ppo or sb3-sac"):
        check_action_space("dqn", PointRobot().action_space)
    check_action_space("dqn", PointRobot(discrete=True).action_space)
    with pytest.raises(SymlearnError, match="SAC acts only in Box"):
        check_action_space("sac", PointRobot(discrete=True).action_space)


def test_dqn_with_counterfactual_experiences_on_a_users_environment_and_a_machine_file(tmp_path):
    """A reward machine written as text (as `learn rm` or a user writes it), read back, run on the
    user's robot with a labeling function of the user's own: every step is replayed for the other
    machine state, with the machine's reward."""
    from stable_baselines3 import DQN

    from symlearn.backends import RewardMachineWrapper, task_machine
    from symlearn.backends.sb3 import counterfactual_callback
    from symlearn.logic.automata.reward_machine import RewardMachine

    path = tmp_path / "task.rm"
    path.write_text(task_machine("m T g").to_text())   # first the upper half, then the goal
    machine = RewardMachine.from_text(path.read_text(), source=str(path))

    def labeling(observation):   # the user's propositions: in the upper half, near the goal
        x, y = (float(v) for v in np.asarray(observation, dtype=np.float32))
        return ({"m"} if y > 0.5 else set()) | ({"g"} if x > 0.75 and y > 0.75 else set())

    env = RewardMachineWrapper(PointRobot(discrete=True), machine, labeling, observation="flat", counterfactual=True)
    callback = counterfactual_callback()
    model = DQN("MlpPolicy", env, learning_starts=100, buffer_size=5_000, seed=0, device="cpu",
                policy_kwargs={"net_arch": [32, 32]})
    model.learn(600, callback=callback)
    acting = len(env.acting_states)
    assert acting == 2 and callback.n_added == 600   # one other machine state to replay each step for
    buffer = model.replay_buffer
    n_env = 2   # the robot's (x, y); then the one-hot machine state
    for slot in range(buffer.size()):
        u = int(np.argmax(buffer.observations[slot, 0, n_env:]))
        u2 = int(np.argmax(buffer.next_observations[slot, 0, n_env:]))
        label = labeling(buffer.next_observations[slot, 0, :n_env])
        expected_u2, expected_reward = machine.step(u, frozenset(label))
        assert (u2, float(buffer.rewards[slot, 0])) == (expected_u2, expected_reward)
