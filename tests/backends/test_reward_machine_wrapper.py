"""The reward-machine wrapper: observations, rewards, shaping, termination, counterfactual experiences."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from symlearn.backends import RewardMachineWrapper, task_machine
from symlearn.envs.labelled_grid import LabelledGridEnv
from symlearn.envs.office_world import TASKS, make_office_world
from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.grounding.labeling import Labeling
from symlearn.logic.automata.reward_machine import RewardMachine, task_potential

UP, RIGHT, DOWN, LEFT = range(4)


def corridor(width=4, objects=None, **kwargs):
    """A 1-row grid: start on the left, ``b`` in the middle, ``a`` at the right end."""
    objects = {(width - 1, 0): {"a"}, (1, 0): {"b"}} if objects is None else objects
    return LabelledGridEnv(width, 1, objects, (0, 0), **kwargs)


def wrap(formula="F a", env=None, **kwargs):
    env = corridor() if env is None else env
    return RewardMachineWrapper(env, task_machine(formula), env.labeling, **kwargs)


@pytest.mark.filterwarnings("ignore:.*is different from the unwrapped version")
@pytest.mark.parametrize("mode", ["dict", "tuple", "discrete", "flat"])
def test_passes_the_gymnasium_checker_in_every_observation_mode(mode):
    check_env(wrap("(a T b) & G !n", make_office_world(), observation=mode), skip_render_check=True)


def test_observation_forms_join_the_machine_state():
    machine = task_machine("F a")
    u_count = machine.n_states
    obs = {mode: wrap(observation=mode).reset(seed=0)[0] for mode in ("dict", "tuple", "discrete", "flat")}
    assert obs["dict"] == {"env": 0, "rm": 0} and obs["tuple"] == (0, 0) and obs["discrete"] == 0
    env = wrap(observation="discrete")
    env.reset(seed=0)
    observation, *_ = env.step(RIGHT)
    assert observation == 1 * u_count + 0 and env.observation_space.n == 4 * u_count
    flat = wrap(observation="flat")
    flat.reset(seed=0)
    vector, *_ = flat.step(RIGHT)
    assert vector.dtype == np.float32 and vector.shape == (4 + u_count,)
    assert vector[:4].tolist() == [0, 1, 0, 0] and vector[4:].tolist() == [1] + [0] * (u_count - 1)
    assert flat.augment(3, 1).tolist()[4:] == [0, 1]


def test_rm_state_and_labels_in_info_follow_the_machine():
    env = wrap("b T a")
    machine = env.machine
    _, info = env.reset(seed=0)
    assert info["rm_state"] == machine.initial and info["rm_label"] == []
    word, states = [], [machine.initial]
    for action in (RIGHT, RIGHT, RIGHT):
        _, _, _, _, info = env.step(action)
        word.append(set(info["rm_label"]))
        assert info["rm_previous_state"] == states[-1]
        states.append(info["rm_state"])
    assert word == [{"b"}, set(), {"a"}]
    assert states == machine.run([set(), *word])[0][1:]  # reset reads the start cell's (empty) label


def test_reset_reads_the_label_of_the_first_observation():
    env = corridor(objects={(0, 0): {"a"}})
    wrapped = RewardMachineWrapper(env, task_machine("F a"), env.labeling)
    _, info = wrapped.reset(seed=0)
    assert info["rm_state"] in wrapped.machine.accepting


@pytest.mark.parametrize("mode, expected", [("replace", [0.0, 0.0, 1.0]), ("add", [-1.0, -1.0, 0.0])])
def test_the_machine_reward_replaces_or_adds_to_the_environment_reward(mode, expected):
    env = corridor()
    paying = gym.wrappers.TransformReward(env, lambda r: r - 1.0)  # the grid itself pays nothing
    wrapped = RewardMachineWrapper(paying, task_machine("F a"), env.labeling, reward=mode)
    wrapped.reset(seed=0)
    steps = [wrapped.step(RIGHT) for _ in range(3)]
    assert [s[1] for s in steps] == expected
    assert [s[4]["env_reward"] for s in steps] == [-1.0] * 3
    assert [s[4]["rm_reward"] for s in steps] == [0.0, 0.0, 1.0]


def test_run_time_shaping_equals_a_machine_compiled_with_shaping():
    gamma = 0.9
    shaped_at_run_time = wrap("b T a", shaping=gamma)
    env = corridor()
    compiled = RewardMachineWrapper(env, task_machine("b T a", shaping=True, gamma=gamma), env.labeling)
    for wrapped in (shaped_at_run_time, compiled):
        wrapped.reset(seed=0)
    potential = task_potential(shaped_at_run_time.machine)
    assert potential == list(compiled.machine.potential)
    rewards = []
    for action in (LEFT, RIGHT, RIGHT, RIGHT):
        a = shaped_at_run_time.step(action)
        b = compiled.step(action)
        assert a[1] == pytest.approx(b[1]) and a[2] == b[2]
        u, u2 = a[4]["rm_previous_state"], a[4]["rm_state"]
        plain = shaped_at_run_time.machine.step(u, frozenset(a[4]["rm_label"]))[1]
        assert a[1] == pytest.approx(plain + gamma * potential[u2] - potential[u])
        rewards.append(a[1])
    assert rewards[0] < 0 < rewards[1]  # waiting is charged, progress (reaching b) is paid
    assert a[2]  # and "a" after "b" completes the task


def test_a_shaped_machine_refuses_shaping_twice_and_shaping_needs_a_discount():
    env = corridor()
    with pytest.raises(ModelError, match="shaped already"):
        RewardMachineWrapper(env, task_machine("F a", shaping=True), env.labeling, shaping=0.9)
    for bad in (True, 0.0, 1.5, "0.9"):
        with pytest.raises(SymlearnError, match="discount"):
            wrap(shaping=bad)
    with pytest.raises(ModelError, match="one finite number per machine state"):
        wrap(shaping=0.9, potential=[1.0])


def test_acceptance_ends_the_episode_unless_told_otherwise():
    # "F a & G !n": acceptance is not absorbing (stepping on n later still fails the task).
    env = corridor(5, {(1, 0): {"a"}, (2, 0): {"n"}})
    ending = RewardMachineWrapper(env, task_machine("F a & G !n"), env.labeling)
    ending.reset(seed=0)
    _, reward, terminated, _, info = ending.step(RIGHT)
    assert terminated and reward == 1.0 and info["rm_state"] in ending.machine.accepting
    going_on = RewardMachineWrapper(corridor(5, {(1, 0): {"a"}, (2, 0): {"n"}}), task_machine("F a & G !n"),
                                    env.labeling, terminate_on_accept=False)
    going_on.reset(seed=0)
    assert going_on.step(RIGHT)[2] is False
    _, _, terminated, _, info = going_on.step(RIGHT)  # onto the decoration: the rejecting sink
    assert terminated and info["rm_state"] in going_on.machine.terminal
    assert info["rm_state"] not in going_on.machine.accepting


def test_environment_termination_and_truncation_pass_through():
    env = wrap(env=corridor(max_steps=2))
    env.reset(seed=0)
    assert env.step(LEFT)[3] is False
    assert env.step(LEFT)[3] is True


@pytest.mark.parametrize("mode", ["dict", "discrete", "flat"])
def test_counterfactual_experiences_agree_with_the_machine(mode):
    world = make_office_world()
    env = RewardMachineWrapper(world, task_machine(TASKS["office-1"]), world.labeling, observation=mode,
                               counterfactual=True, shaping=0.95)
    machine = env.machine
    rng = np.random.default_rng(0)
    wrapped_observation, _ = env.reset(seed=0)
    previous = world.state_of(world.start)
    seen_real = 0
    for _ in range(300):
        action = int(rng.integers(4))
        wrapped_observation, reward, terminated, truncated, info = env.step(action)
        observation = world.next_state(previous, action)
        assert _same(wrapped_observation, env.augment(observation, info["rm_state"]))
        experiences = info["crm_experiences"]
        assert [e.machine_state for e in experiences] == env.acting_states
        label = world.labeling.label(observation)
        for e in experiences:
            u2, r = machine.step(e.machine_state, label)
            r += 0.95 * env.potential[u2] - env.potential[e.machine_state]
            assert e.next_machine_state == u2 and e.reward == pytest.approx(r) and e.action == action
            assert _same(e.observation, env.augment(previous, e.machine_state))
            assert _same(e.next_observation, env.augment(observation, u2))
            assert e.terminated == (u2 in machine.terminal or u2 in machine.accepting)
            if e.machine_state == info["rm_previous_state"]:  # the real transition is one of them
                seen_real += 1
                assert e.reward == reward and e.terminated == terminated and e.next_machine_state == info["rm_state"]
        again = env.counterfactual_experiences(previous, action, observation, 0.0, False)
        assert len(again) == len(experiences) and all(_same(a, b) for a, b in zip(again, experiences))
        previous = observation
        if terminated or truncated:
            env.reset()
            previous = world.state_of(world.start)
    assert seen_real == 300


def _same(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return np.array_equal(a, b)


def test_acting_states_leave_out_the_states_where_an_episode_ends():
    env = wrap("F a")
    assert env.acting_states == [u for u in env.machine.states
                                 if u not in env.machine.terminal and u not in env.machine.accepting]
    assert len(env.acting_states) == 1
    decorated = corridor(objects={(3, 0): {"a"}, (2, 0): {"n"}})
    assert (len(wrap("F a & G !n", decorated, terminate_on_accept=False).acting_states)
            == len(wrap("F a & G !n", decorated).acting_states) + 1)  # acceptance goes on


def test_bad_settings_are_reported():
    env = corridor()
    machine = task_machine("F a")
    with pytest.raises(SymlearnError, match="reward mode"):
        RewardMachineWrapper(env, machine, env.labeling, reward="multiply")
    with pytest.raises(SymlearnError, match="observation mode"):
        RewardMachineWrapper(env, machine, env.labeling, observation="image")
    with pytest.raises(ModelError, match="RewardMachine"):
        RewardMachineWrapper(env, machine.dfa, env.labeling)
    with pytest.raises(DataError, match="'z'"):
        RewardMachineWrapper(env, task_machine("F z"), env.labeling)
    with pytest.raises(SymlearnError, match="callable"):
        RewardMachineWrapper(env, machine, {"a": 1})
    boxed = gym.wrappers.TransformObservation(
        env, lambda o: np.array([o], np.float32), gym.spaces.Box(0, 3, (1,), np.float32))
    with pytest.raises(SymlearnError, match="Discrete observation space"):
        RewardMachineWrapper(boxed, machine, lambda o: set(), observation="discrete")
    stringly = RewardMachineWrapper(env, machine, lambda o: "a")
    with pytest.raises(DataError, match="set of proposition names"):
        stringly.reset(seed=0)


def test_any_environment_and_a_plain_callable_labeling():
    """A Box-observation environment (no Labeling object): the label comes from a callable."""
    env = gym.wrappers.TransformObservation(
        corridor(), lambda o: np.array([o], np.float32), gym.spaces.Box(0, 3, (1,), np.float32))
    wrapped = RewardMachineWrapper(env, task_machine("F a"), lambda o: {"a"} if o[0] >= 3 else set(),
                                   observation="flat")
    wrapped.reset(seed=0)
    rewards = [wrapped.step(RIGHT)[1] for _ in range(3)]
    assert rewards == [0.0, 0.0, 1.0]
    labeling = Labeling({3: {"a"}})
    wrapped = RewardMachineWrapper(corridor(), RewardMachine.from_formula("F a"), labeling)
    wrapped.reset(seed=0)
    assert [wrapped.step(RIGHT)[1] for _ in range(3)] == [0.0, 0.0, 1.0]


def test_our_tabular_q_learning_runs_on_the_product_and_keeps_a_shield_s_mask():
    """observation="discrete" makes the product a tabular task; a shield's mask passes through."""
    from symlearn.backends import Shield
    from symlearn.rl.q_learning import q_learning

    grid = LabelledGridEnv(4, 4, {(3, 0): {"b"}, (0, 3): {"a"}}, (0, 0), max_steps=40)
    no_down = np.zeros((16, 4), bool)
    no_down[:, DOWN] = True
    env = RewardMachineWrapper(Shield(grid, no_down), task_machine("b T a"), grid.labeling,
                               observation="discrete")
    _, info = env.reset(seed=0)
    assert info["action_mask"].tolist() == [1, 1, 0, 1]
    result = q_learning(env, 300, learning_rate=1.0, discount=0.9, epsilon=0.2, seed=0)
    state, _ = env.reset(seed=0)
    for step in range(1, 41):
        state, reward, terminated, _, info = env.step(int(np.argmax(result.q_values[state])))
        if terminated:
            break
    assert terminated and reward == 1.0 and step == 9
