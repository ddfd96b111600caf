"""Blocked HalfCheetah: x in the observation, the direction-free reward, the wall's cost."""

import numpy as np
import pytest

pytest.importorskip("mujoco")
pytestmark = pytest.mark.filterwarnings("ignore:MuJoCo:RuntimeWarning")  # the v5 model's deprecation notice

from symlearn.envs.blocked_mujoco import OBSERVATION_NAMES, make_blocked_half_cheetah  # noqa: E402
from symlearn.errors import DataError  # noqa: E402


def test_observation_reward_and_cost():
    env = make_blocked_half_cheetah(wall=-3.0, max_episode_steps=30)
    obs, info = env.reset(seed=0)
    assert obs.shape == (18,) == (len(OBSERVATION_NAMES),) and info["cost"] == 0.0
    assert abs(obs[0] - info.get("x_position", obs[0])) < 1e-9 or abs(obs[0]) < 0.2
    rng = np.random.default_rng(0)
    steps = 0
    while True:
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 6).astype(np.float32))
        steps += 1
        assert obs[0] == pytest.approx(info["x_position"])
        forward = env.unwrapped._forward_reward_weight * abs(info["x_velocity"])
        assert reward == pytest.approx(forward + info["reward_ctrl"]) and reward >= info["reward_ctrl"]
        assert info["cost"] == float(info["x_position"] < -3.0)
        if terminated or truncated:
            break
    assert steps == 30 and truncated
    assert env.is_unsafe(np.array([[-3.5] + [0.0] * 17, [2.0] + [0.0] * 17])).tolist() == [True, False]
    env.close()


def test_a_cheetah_placed_behind_the_wall_is_unsafe():
    env = make_blocked_half_cheetah(wall=-3.0, max_episode_steps=10)
    env.reset(seed=1)
    sim = env.unwrapped
    qpos, qvel = sim.data.qpos.copy(), sim.data.qvel.copy()
    qpos[0] = -3.5  # the root's x, behind the wall
    sim.set_state(qpos, qvel)
    obs, _, _, _, info = env.step(np.zeros(6, dtype=np.float32))
    assert obs[0] < -3.0 and info["cost"] == 1.0 and info["violation"] and env.is_unsafe(obs)
    qpos[0] = 0.0
    sim.set_state(qpos, qvel * 0)
    obs, _, _, _, info = env.step(np.zeros(6, dtype=np.float32))
    assert info["cost"] == 0.0 and not env.is_unsafe(obs)
    env.close()


def test_bad_arguments():
    with pytest.raises(DataError, match="max_episode_steps"):
        make_blocked_half_cheetah(max_episode_steps=0)
    with pytest.raises(DataError, match="wall"):
        make_blocked_half_cheetah(wall=float("nan"))


@pytest.mark.slow
def test_half_cheetah_benchmark_plumbing(tmp_path):
    """benchmarks/icrl_blocked_half_cheetah.py --smoke: expert, MCE-ICRL and evaluation end to end."""
    import importlib.util
    import json
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "icrl_blocked_half_cheetah.py"
    spec = importlib.util.spec_from_file_location("icrl_blocked_half_cheetah", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    out = tmp_path / "hc.json"
    document = module.main(["--smoke", "--json", str(out)])
    run = document["runs"][0]
    assert json.loads(out.read_text())["benchmark"] == "icrl_blocked_half_cheetah"
    assert len(run["mce-icrl"]["history"]) == 2 and 0 <= run["mce-icrl"]["violation_rate"] <= 1
    assert set(run["targets"]) == {"violation_rate <= 0.1", "reward >= 0.5 x expert"}
