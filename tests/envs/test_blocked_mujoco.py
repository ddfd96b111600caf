"""Blocked MuJoCo: x first in the observation, the same dynamics as the bare v5 robot, the
benchmark's rewards, the wall's cost exactly at the wall, the broken ant's dead legs, bad input."""

import json

import numpy as np
import pytest

pytest.importorskip("mujoco")
# the bare HalfCheetah-v5 built as a reference repeats MuJoCo's notice about gymnasium's model file
pytestmark = pytest.mark.filterwarnings("ignore:MuJoCo. compiler attribute:RuntimeWarning")

import gymnasium as gym  # noqa: E402

from symlearn.envs import blocked_mujoco as bm  # noqa: E402
from symlearn.envs.blocked_mujoco_tasks import TASKS  # noqa: E402
from symlearn.errors import DataError, MissingDependencyError  # noqa: E402

# factory, task row, extra kwargs of the bare robot that match the factory's defaults
FACTORIES = {
    "half-cheetah": (bm.make_blocked_half_cheetah, {}),
    "ant": (bm.make_blocked_ant, {"include_cfrc_ext_in_observation": False}),
    "broken-ant": (bm.make_broken_ant, {"include_cfrc_ext_in_observation": False}),
    "walker2d": (bm.make_blocked_walker2d, {}),
    "swimmer": (bm.make_blocked_swimmer, {}),
    "inverted-pendulum": (bm.make_biased_inverted_pendulum, {}),
}


def _task(name):
    return TASKS["ant" if name == "broken-ant" else name]


def _bare(name):
    task = _task(name)
    return gym.make(task.gym_id, **task.robot_kwargs, **FACTORIES[name][1]).unwrapped


def _expected_reward(name, reward, info, obs):
    if name in ("ant", "broken-ant"):  # distance from the origin instead of forward speed
        return info["distance_from_origin"] + info["reward_survive"] + info["reward_ctrl"] + info["reward_contact"]
    if name == "inverted-pendulum":  # the benchmark's: 1 left of -0.01, 0.1 right of 0, linear between
        return reward * (1.0 if obs[0] <= -0.01 else 0.1 if obs[0] >= 0 else 0.1 + 0.9 * -obs[0] / 0.01)
    return reward - info["reward_forward"] + abs(info["reward_forward"])


@pytest.mark.parametrize("name", FACTORIES)
def test_observation_layout_dynamics_and_reward_match_the_bare_robot(name):
    env, bare = FACTORIES[name][0](max_episode_steps=6), _bare(name)
    obs, info = env.reset(seed=3)
    bare_obs, _ = bare.reset(seed=3)
    names = env.unwrapped.observation_names
    assert env.unwrapped is env and names[0] == "x" and len(names) == obs.shape[0] == env.observation_space.shape[0]
    assert np.array_equal(obs, bare_obs) and info["cost"] == float(env.is_unsafe(obs))
    rng = np.random.default_rng(0)
    for step in range(1, 7):
        action = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = env.step(action)
        if name == "broken-ant":
            action[4:] = 0.0  # what the robot receives
        bare_obs, bare_reward, bare_terminated, _, bare_info = bare.step(action)
        assert np.array_equal(obs, bare_obs) and terminated == bare_terminated  # v5's dynamics and termination
        assert obs[0] == env.unwrapped.robot.data.qpos[0] == info["features"][0]
        assert reward == pytest.approx(_expected_reward(name, bare_reward, bare_info, bare_obs), abs=1e-9)
        assert info["cost"] == float(env.is_unsafe(obs)) and info["violation"] == env.is_unsafe(obs)
        if terminated:
            break
    assert terminated or (step == 6 and truncated)


BOUNDARY = {"half-cheetah": 0.05, "ant": 0.05, "walker2d": 0.05, "swimmer": 0.05, "inverted-pendulum": 1e-3}


@pytest.mark.parametrize("name", BOUNDARY)
def test_the_cost_switches_at_the_wall(name):
    env, task = FACTORIES[name][0](), _task(name)
    env.reset(seed=0)
    robot = env.unwrapped.robot
    qpos, qvel = robot.data.qpos.copy(), np.zeros_like(robot.data.qvel)
    outward = -1.0 if task.side == "below" else 1.0  # toward the forbidden side
    for offset, unsafe in ((outward * BOUNDARY[name], True), (-outward * BOUNDARY[name], False)):
        qpos[0] = task.wall + offset
        env.set_state(qpos, qvel)
        obs, _, _, _, info = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
        assert info["cost"] == float(unsafe) and info["violation"] == unsafe == env.is_unsafe(obs)
    # exactly at the wall is allowed; the next float outward is not; vectorised over a batch
    width = env.observation_space.shape[0]
    batch = np.zeros((3, width))
    batch[:, 0] = [task.wall, np.nextafter(task.wall, outward * np.inf), np.nextafter(task.wall, -outward * np.inf)]
    assert env.is_unsafe(batch).tolist() == [False, True, False]
    assert env.is_unsafe(batch[1]) is True and bm.make_blocked(name, wall=task.wall + outward).is_unsafe(batch[1]) is False


@pytest.mark.parametrize("name", ["half-cheetah", "walker2d", "swimmer"])
def test_running_backward_pays_like_running_forward(name):
    env = FACTORIES[name][0]()
    env.reset(seed=0)
    qpos, qvel = env.unwrapped.robot.data.qpos.copy(), np.zeros_like(env.unwrapped.robot.data.qvel)
    qvel[0] = -1.0  # sliding backward
    env.set_state(qpos, qvel)
    _, reward, _, _, info = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    assert info["x_velocity"] < -0.1 and info["reward_forward"] < 0  # v5 would charge for this step
    assert reward == pytest.approx(abs(info["reward_forward"]) + info["reward_ctrl"] + info.get("reward_survive", 0.0))


def test_the_ant_is_paid_for_its_distance_either_way():
    env = bm.make_blocked_ant()
    env.reset(seed=0)
    qpos, qvel = env.unwrapped.robot.data.qpos.copy(), np.zeros(14)
    rewards = []
    for x in (-2.0, 2.0):
        qpos[:2] = x, 0.0
        env.set_state(qpos, qvel)
        _, reward, _, _, info = env.step(np.zeros(8, dtype=np.float32))
        assert info["reward_survive"] == 1.0 and info["distance_from_origin"] == pytest.approx(2.0, abs=0.05)
        rewards.append(reward)
    assert rewards[0] == pytest.approx(rewards[1], abs=0.05) and min(rewards) > 2.9


def test_the_pendulum_is_paid_left_of_its_start():
    env = bm.make_biased_inverted_pendulum()
    env.reset(seed=0)
    paid = {}
    for x in (-0.02, -0.005, 0.005):
        env.set_state([x, 0.0], [0.0, 0.0])
        _, paid[x], terminated, _, _ = env.step(np.zeros(1, dtype=np.float32))
        assert not terminated
    assert paid[-0.02] == 1.0 and paid[0.005] == pytest.approx(0.1) and paid[-0.005] == pytest.approx(0.55, abs=1e-3)
    env.set_state([-0.02, 0.5], [0.0, 0.0])  # the pole beyond 0.2 rad: v5 ends the episode, pays nothing
    _, reward, terminated, _, _ = env.step(np.zeros(1, dtype=np.float32))
    assert terminated and reward == 0.0


def test_the_broken_ants_disabled_legs_do_nothing():
    broken, whole = bm.make_broken_ant(), bm.make_blocked_ant()
    assert broken.observation_space == whole.observation_space and broken.action_space == whole.action_space
    assert broken.observation_names == whole.observation_names
    broken.reset(seed=0)
    state = broken.unwrapped.robot.data.qpos.copy(), broken.unwrapped.robot.data.qvel.copy()
    base = np.full(8, 0.5, dtype=np.float32)

    def after(env, changes):
        env.reset(seed=0)
        env.set_state(*state)
        action = base.copy()
        for index, value in changes.items():
            action[index] = value
        obs = env.step(action)[0]
        assert action[4] == changes.get(4, 0.5)  # the caller's action is left as given
        return obs

    reference = after(broken, {})
    for index in (4, 5, 6, 7):  # hip_2, ankle_2, hip_3, ankle_3: two legs
        assert np.array_equal(after(broken, {index: -1.0}), reference)
    for index in (0, 2):  # a working leg moves the ant, and the whole ant's leg 2 moves it
        assert not np.array_equal(after(broken, {index: -1.0}), reference)
    assert not np.array_equal(after(whole, {4: -1.0}), after(whole, {}))


def test_the_ants_contact_forces_can_be_kept():
    env = bm.make_blocked_ant(contact_forces=True)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (107,) == (len(env.observation_names),) and env.observation_names[29] == "cfrc_torso_rx"


@pytest.mark.parametrize("kwargs, message", [
    ({"wall": float("nan")}, "wall must be finite"),
    ({"wall": "left"}, "wall must be a number"),
    ({"max_episode_steps": 0}, "max_episode_steps must be an integer of at least 1"),
    ({"max_episode_steps": 2.5}, "max_episode_steps must be an integer"),
    ({"contact_forces": "yes"}, "contact_forces must be true or false"),
    ({"disabled_actuators": [8]}, r"disabled_actuators must be action indices in 0\.\.7"),
    ({"exclude_current_positions_from_observation": True}, "keeps the root's position in the observation"),
])
def test_bad_arguments(kwargs, message):
    with pytest.raises(DataError, match=message):
        bm.make_broken_ant(**kwargs)


def test_unknown_task_and_missing_mujoco(monkeypatch):
    with pytest.raises(DataError, match="unknown blocked MuJoCo task 'hopper'"):
        bm.make_blocked("hopper")
    from symlearn import optional

    monkeypatch.setattr(optional, "available", lambda name: name != "mujoco")
    with pytest.raises(MissingDependencyError, match="needs mujoco") as info:
        bm.make_blocked_swimmer()
    assert "symlearn[mujoco]" in info.value.hint


def test_registered_with_gymnasium_and_the_registry():
    from symlearn.envs.gym_registration import register_gymnasium_envs
    from symlearn.recipes.environments import resolve_env

    assert "symlearn/blocked-swimmer-v0" in register_gymnasium_envs()
    env = gym.make("symlearn/blocked-swimmer-v0", wall=0.3)
    assert env.unwrapped.wall == 0.3 and env.unwrapped.task.name == "swimmer"
    target = resolve_env("blocked-ant", '{"wall": -2, "contact_forces": true}')
    assert target.make().wall == -2.0
    with pytest.raises(DataError, match="unknown --env-kwargs key 'wal' for blocked-ant") as info:
        resolve_env("blocked-ant", json.dumps({"wal": -2}))
    assert info.value.hint.startswith("did you mean 'wall'?")


@pytest.mark.slow
@pytest.mark.parametrize("task", ["half-cheetah", "inverted-pendulum"])
def test_blocked_mujoco_benchmark_plumbing(tmp_path, task, monkeypatch):
    """benchmarks/icrl_blocked_mujoco.py --smoke: expert, two methods and evaluation end to end."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "icrl_blocked_mujoco.py"
    monkeypatch.syspath_prepend(str(path.parent))  # its sibling icrl_common, as when run as a script
    spec = importlib.util.spec_from_file_location("icrl_blocked_mujoco", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    out = tmp_path / "run.json"
    document = module.main(["--smoke", "--task", task, "--methods", "mce-icrl,gacl", "--learner",
                            '{"reset_actor": "last"}', "--json", str(out)])
    run = document["runs"][0]
    assert json.loads(out.read_text())["benchmark"] == "icrl_blocked_mujoco"
    for method in ("mce-icrl", "gacl"):
        assert len(run[method]["history"]) == 2 and 0 <= run[method]["violation_rate"] <= 1
        assert set(run[method]["targets"]) == {"violation_rate <= 0.1", "reward >= 0.5 x expert"}
        # "last" with 2 iterations: only the second phase starts from a fresh actor, and the
        # record says so (reset_actor="auto" decides per run, so the runs must keep it)
        assert run[method]["actor_resets"] == [2]
    assert set(document["summary"]) == {"expert", "unconstrained", "mce-icrl", "gacl"}
