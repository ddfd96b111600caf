"""A fresh sweep of users' environments and domain folders at the CLI's defaults (docs/BENCHMARKS.md,
issue 25: "A sweep of users' modules, gymnasium's toy text and MiniGrid at the CLI's defaults"): one
test per failure it found."""

from __future__ import annotations

import csv
import json

import gymnasium
import numpy as np
import pytest
from cli_runner import run
from space_envs import ENDLESS_LINE, MATRIX_POINT, OFFSET_WALK

from symlearn.backends.dnf_cost import DnfRolloutCost
from symlearn.logic import dnf


def _walk(tmp_path, monkeypatch):
    """The OffsetWalk module (Discrete(8, start=2) observations) and 4 walks that keep off cell 5."""
    from symlearn.data import record

    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import offset_walk  # noqa: F401  (registers OffsetWalk-v0)

    record(gymnasium.make("OffsetWalk-v0"), lambda cell: 1 if cell < 4 else 0, 4, seed=0).save("walk.jsonl")


def test_a_dnf_cost_reads_a_discrete_observation_as_its_id(capsys, tmp_path, monkeypatch):
    """The policy sees a Discrete observation one-hot; the rule ``cell == 5`` reads the id. Before,
    ``train --cost`` stopped with 'expected 1 features (cell), got 8' (the one-hot columns)."""
    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    (tmp_path / "walk.dnf").write_text("cell == 5\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "offset_walk:OffsetWalk-v0", "--cost",
                         "walk.dnf", "--features", "cell", "--steps", 1024, "--eval-episodes", 2, "--log", "run.csv")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["learned_cost"] == doc["cost"], doc   # the rule is the environment's own info["cost"]
    rows = list(csv.DictReader(open(tmp_path / "run.csv")))
    # a random walk from cell 2 steps on cell 5 in most episodes: the rollout's cost sees it
    assert float(rows[0]["learned_cost_0"]) > 0, rows[0]


def test_the_rollout_cost_of_a_discrete_observation_space_from_another_start():
    rule = dnf.parse("cell == 5")
    space = gymnasium.spaces.Discrete(8, start=2)
    cost = DnfRolloutCost(rule, ("cell",), source="observation", observation_space=space)
    ids = np.array([[2, 5], [5, 9]])
    one_hot = np.eye(8, dtype=np.float32)[ids - 2]   # [T, N, 8], as the rollout holds them

    class Rollout:
        next_obs = one_hot

    assert cost(Rollout()).tolist() == [[0.0, 1.0], [1.0, 0.0]]


def test_learn_pdfa_reads_matrix_observations_as_their_entries(capsys, tmp_path, monkeypatch):
    """A (2, 1) Box observation is stored as a 2-D state per step; `learn dnf` reads its entries
    x0, x1, and so does `learn pdfa` now (before: 'the demonstrations hold image states'). Pictures
    (H, W, C) are still refused, naming `learn rm`."""
    from symlearn.data import Demonstrations, Trajectory

    monkeypatch.chdir(tmp_path)
    rng = np.random.default_rng(0)
    runs = []
    for _ in range(12):   # dwell at (0, 0), move, dwell at (1, 1)
        path = [np.zeros(2)] * 8 + [np.full(2, t / 6) for t in range(1, 6)] + [np.ones(2)] * 8
        states = np.asarray(path) + rng.normal(0, 0.005, (len(path), 2))
        runs.append(Trajectory(states=states.reshape(-1, 2, 1), actions=np.zeros(len(path) - 1, dtype=np.int64)))
    Demonstrations(runs).save("column.npz")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "pdfa", "--demos", "column.npz", "-o", "plan.json")
    assert code == 0, err
    centres = [g["centre"] for g in json.loads(out)["subgoals"].values()]
    assert any(np.allclose(c, [1, 1], atol=0.05) for c in centres), out   # where the runs end (the start is no goal)

    pictures = [Trajectory(states=rng.integers(0, 255, (6, 4, 4, 3), dtype=np.uint8)) for _ in range(2)]
    Demonstrations(pictures).save("video.npz")
    code, out, err = run(capsys, "learn", "pdfa", "--demos", "video.npz")
    assert code == 2 and "pictures (4, 4, 3)" in err and "learn rm" in err and len(err.strip().splitlines()) == 1, err


def test_train_says_when_evaluation_episodes_of_an_endless_environment_were_cut(capsys, tmp_path, monkeypatch):
    """No time limit and never done: each greedy evaluation episode runs to the evaluation loop's
    cap. Before, the return (a sum over 100,000 steps) was reported as an episode's without a word."""
    (tmp_path / "endless_line.py").write_text(ENDLESS_LINE)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "endless_line:EndlessLine-v0", "--steps", 512,
                         "--eval-episodes", 1)
    assert code == 0, err
    [warning] = json.loads(out)["warnings"]
    assert "1 of the 1 evaluation episodes ran 100,000 steps" in warning and "max_episode_steps" in warning
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "endless_line:EndlessLine-v0", "--env-kwargs",
                         '{"horizon": 30}', "--steps", 512, "--eval-episodes", 1)
    assert code == 0 and json.loads(out)["warnings"] == [], out   # a limit of its own: nothing to say


def test_learn_icrl_on_demonstrations_without_rewards_reports_the_experts_reward_as_unknown(capsys, tmp_path,
                                                                                           monkeypatch):
    """A hand-written JSONL file need not hold rewards; before, the expert's reward was reported
    as 0.00 (the missing rewards summed as zeros) beside the policy's."""
    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    walks = [json.dumps({"states": [2, 3, 4, 4], "actions": [1, 1, 0]})] * 4
    (tmp_path / "walk.jsonl").write_text('{"symlearn": "demonstrations", "format_version": 1}\n' + "\n".join(walks))
    code, out, err = run(capsys, "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0", "--demos", "walk.jsonl",
                         "--steps", 1024, "--iterations", 1)
    assert code == 0, err
    assert "(expert n/a)" in out, out
    code, out, err = run(capsys, "--json", "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0", "--demos",
                         "walk.jsonl", "--steps", 1024, "--iterations", 1)
    assert code == 0 and json.loads(out)["expert_reward"] is None, err


def _warehouse_with_features(folder):
    """The warehouse folder with a feature map (x, y, carry of every state id) and no labeling."""
    from warehouse_domain import expert_demonstrations, states, write_warehouse

    write_warehouse(folder, labeling=False)
    rows = [[i, [4.0, 3.0, 1.0] if s == "done" else [float(s[0][0]), float(s[0][1]), float(s[2])]]
            for i, s in enumerate(states())]
    (folder / "features.json").write_text(json.dumps({"symlearn": "feature-map", "format_version": 1,
                                                      "names": ["x", "y", "carry"], "table_by_state": rows}))
    with open(folder / "domain.toml", "a") as toml:
        toml.write('features = "features.json"\n')
    expert_demonstrations(20, seed=0).save(folder.parent / "deliveries.jsonl")


def test_learn_spec_in_a_domain_folder_reads_a_feature_labeling_through_its_feature_map(capsys, tmp_path,
                                                                                       monkeypatch):
    """A domain's states are ids; a feature labeling (`carry > 0.5`) reads each id's features from
    the folder's feature map. Before, a feature labeling in domain.toml stopped `learn spec` with
    'state: expected 3 features (x, y, carry), got shape (1,)', blamed on the demonstrations, and
    `--labeling '{...}'` with --domain read the object as a file name."""
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "warehouse"
    _warehouse_with_features(folder)
    labels = '{"loaded": "carry > 0.5", "at_drop": "x > 2.5 & y > 1.5"}'
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", "--domain", "warehouse", "--demos",
                         "deliveries.jsonl", "--labeling", labels, "--max-iterations", 2, "-o", "spec.ltl")
    assert code == 0, err
    doc = json.loads(out)
    assert set(doc["propositions"]) == {"loaded", "at_drop"} and doc["formula"] != "true", doc

    # the same labeling saved in the folder (as learn spec wrote it) is the folder's own
    (folder / "labeling.json").write_text((tmp_path / "spec.labeling.json").read_text())
    with open(folder / "domain.toml", "a") as toml:
        toml.write('labeling = "labeling.json"\n')
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", "--domain", "warehouse", "--demos",
                         "deliveries.jsonl", "--max-iterations", 2)
    assert code == 0 and json.loads(out)["formula"] == doc["formula"], err


def test_a_domain_without_a_labeling_names_the_flags_that_give_one(capsys, tmp_path, monkeypatch):
    """Before, the hint named the Python API's keywords (labeling=, propositions='learn') and the
    message was located in the demonstrations file."""
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "warehouse"
    _warehouse_with_features(folder)
    code, out, err = run(capsys, "learn", "spec", "--domain", "warehouse", "--demos", "deliveries.jsonl")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "--props learn" in err and "--labeling" in err and "propositions=" not in err, err
    assert "deliveries.jsonl" not in err, err


def test_a_feature_labeling_in_a_folder_without_features_is_one_line_naming_it(capsys, tmp_path, monkeypatch):
    from warehouse_domain import write_warehouse

    monkeypatch.chdir(tmp_path)
    folder = write_warehouse(tmp_path / "warehouse", labeling=False)
    (folder / "labels.json").write_text(json.dumps({
        "symlearn": "labeling", "format_version": 1, "kind": "features",
        "features": {"symlearn": "feature-map", "format_version": 1, "names": ["x", "y"]},
        "propositions": [{"name": "east", "meaning": "", "when": "x > 2"}]}))
    with open(folder / "domain.toml", "a") as toml:
        toml.write('labeling = "labels.json"\n')
    code, out, err = run(capsys, "domain", "check", "warehouse")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "labels.json" in err and "features" in err, err


def test_a_dnf_learned_from_the_numeric_view_of_a_picture_observation_trains_there(capsys, tmp_path, monkeypatch):
    """MiniGrid observes Dict(direction, image, mission): `data record` stores the numeric view the
    policy reads (direction=0.., image[0..]); `learn dnf` learns over those columns. Before, `train
    --cost` on the same environment refused the formula ("uses feature 'direction=0', which the
    environment does not provide"): it read only the Dict's named scalars."""
    pytest.importorskip("minigrid")
    from symlearn.recipes.spaces import numeric_observations

    import minigrid  # noqa: F401  (registers the MiniGrid ids)
    from symlearn.data import record

    monkeypatch.chdir(tmp_path)
    env = numeric_observations(gymnasium.make("MiniGrid-Empty-5x5-v0"))
    demos = record(env, lambda observation: 0, 2, seed=0, max_steps=12)   # turns left on the spot
    demos.metadata["feature_names"] = list(env.column_names)
    demos.save("turning.npz")
    code, out, err = run(capsys, "--quiet", "learn", "dnf", "--env", "minigrid:MiniGrid-Empty-5x5-v0", "--demos",
                         "turning.npz", "-o", "turning.dnf")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "minigrid:MiniGrid-Empty-5x5-v0", "--cost",
                         "turning.dnf", "--steps", 512, "--eval-episodes", 1, "--log", "run.csv")
    assert code == 0, err
    rows = list(csv.DictReader(open(tmp_path / "run.csv")))
    # the first policy moves about: it leaves the turning robot's states, which the formula forbids
    assert float(rows[0]["learned_cost_0"]) > 0, rows[0]


def test_the_log_of_plain_ppo_on_a_learned_cost_does_not_call_the_environments_cost_learned(capsys, tmp_path,
                                                                                          monkeypatch):
    """Under --algo ppo a learned cost is a penalty in the reward; the episodes' cost the log has
    is the environment's info["cost"]. Before, it was written as learned_cost_0. The rule here
    (`cell == 9`, the goal, once per episode at most) is not the environment's cost (cell 5)."""
    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    (tmp_path / "goal.dnf").write_text("cell == 9\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    for algo, log in (("ppo", "plain.csv"), ("ppo-lag", "lagrangian.csv")):
        code, out, err = run(capsys, "--quiet", "train", "--env", "offset_walk:OffsetWalk-v0", "--cost", "goal.dnf",
                             "--features", "cell", "--algo", algo, "--steps", 1024, "--eval-episodes", 1, "--log", log)
        assert code == 0, err
    plain = list(csv.DictReader(open(tmp_path / "plain.csv")))
    assert "learned_cost_0" not in plain[0] and float(plain[0]["mean_cost_0"]) > 1, plain[0]
    lagrangian = list(csv.DictReader(open(tmp_path / "lagrangian.csv")))
    assert all(float(row["learned_cost_0"]) <= 1 for row in lagrangian), lagrangian


def test_data_record_of_matrix_observations_to_jsonl_is_refused_before_recording(capsys, tmp_path, monkeypatch):
    """Before, the episodes were run first and the refusal called a (2, 3) matrix 'image states'."""
    (tmp_path / "matrix_point.py").write_text(MATRIX_POINT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    code, out, err = run(capsys, "data", "record", "--env", "matrix_point:MatrixPoint-v0", "--policy", "random",
                         "-o", "demos.jsonl")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "(2, 3)" in err and "demos.npz" in err and "image" not in err, err
    assert not (tmp_path / "demos.jsonl").exists()


def test_learn_icrl_cost_inputs_of_a_discrete_observation_are_its_one_hot_entries(capsys, tmp_path, monkeypatch):
    """The networks read a Discrete observation one-hot. Before, its width was taken as 1:
    `--cost-inputs all` gave the cost one input, the indicator of the first state, and the report
    called it by the observation's name."""
    _walk(tmp_path, monkeypatch)
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0",
                         "--demos", "walk.jsonl", "--cost-inputs", "all", "--steps", 1024, "--iterations", 1)
    assert code == 0, err
    inputs = json.loads(out)["cost_inputs"]
    assert inputs["selection"]["candidates"] == list(range(8)), inputs   # cells 2..9
    assert all(name.startswith("x=") for name in inputs["names"]), inputs
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0",
                         "--demos", "walk.jsonl", "--cost-inputs", "x=5,x=6", "--steps", 1024, "--iterations", 1)
    assert code == 0, err
    assert json.loads(out)["cost_inputs"]["selection"]["candidates"] == [3, 4], out


def test_learn_icrl_on_a_camera_keeps_every_pixel_rather_than_eliminate_them_one_at_a_time(capsys, tmp_path,
                                                                                          monkeypatch):
    """768 candidate inputs whose split entries alone fell short of all of them: the input
    selection eliminated them one at a time, O(d^2) cross-validations (killed after 300 s); now it
    keeps them all, and the text report names the 12 largest shares."""
    from camera_floor_env import CAMERA_FLOOR, waiting_expert

    from symlearn.data import Demonstrations, record

    (tmp_path / "camera_floor.py").write_text(CAMERA_FLOOR)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import camera_floor  # noqa: F401  (registers CameraFloor-v0)

    runs = [t for seed in range(6) for t in record(gymnasium.make("CameraFloor-v0"), waiting_expert(), 1, seed=seed)]
    Demonstrations(runs).save("camera.npz")
    code, out, err = run(capsys, "learn", "icrl", "--env", "camera_floor:CameraFloor-v0", "--demos", "camera.npz",
                         "--steps", 1024, "--iterations", 1)
    assert code == 0, err
    [line] = [line for line in out.splitlines() if "cost inputs" in line]
    assert "756 more" in line, line


OLD_STYLE_RESET = """
import gymnasium as gym
import numpy as np


class OldStyle(gym.Env):
    observation_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
    action_space = gym.spaces.Discrete(3)

    def reset(self, seed=None):   # the pre-0.26 gym API: no options
        self.t = 0
        return np.zeros(2, np.float32), {}

    def step(self, action):
        self.t += 1
        return np.zeros(2, np.float32), 0.0, False, self.t >= 10, {}


gym.register("OldStyle-v0", entry_point=OldStyle, disable_env_checker=True)
"""


def test_a_reset_without_options_is_one_line_naming_its_file(capsys, tmp_path, monkeypatch):
    """gymnasium's wrappers call reset(seed=..., options=...); before, such an environment was an
    internal error (TypeError from gymnasium's code, no file of the user's in the traceback)."""
    (tmp_path / "old_style.py").write_text(OLD_STYLE_RESET)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    for args in (("train", "--env", "old_style:OldStyle-v0", "--steps", 256),
                 ("data", "record", "--env", "old_style:OldStyle-v0", "--policy", "random", "-o", "d.npz")):
        code, out, err = run(capsys, *args)
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert "old_style.py:10:" in err and "options" in err, err   # the line of def reset


OLD_GYM_API = """
import gymnasium as gym
import numpy as np


class OldGym(gym.Env):
    observation_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
    action_space = gym.spaces.Discrete(3)

    def __init__(self, returns="step"):
        self.returns = returns

    def reset(self, seed=None, options=None):
        self.t = 0
        observation = np.zeros(2, np.float32)
        return observation if self.returns == "reset" else (observation, {})

    def step(self, action):
        self.t += 1
        return np.zeros(2, np.float32), 0.0, self.t >= 10, {}   # (observation, reward, done, info)


gym.register("OldGym-v0", entry_point=OldGym, max_episode_steps=20)
"""


@pytest.mark.parametrize("returns, says", [("reset", "reset() returned one ndarray"),
                                           ("step", "step() returned a tuple of 4")])
def test_the_old_gym_apis_returns_are_one_line(capsys, tmp_path, monkeypatch, returns, says):
    """Before: internal errors (an IndexError in record, a broadcast error in our PPO's rollouts,
    an unpacking error in stable-baselines3's), none naming the environment."""
    (tmp_path / "old_gym.py").write_text(OLD_GYM_API)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    for command in (["train", "--steps", 256], ["train", "--algo", "sb3-ppo", "--steps", 256],
                    ["data", "record", "--policy", "random", "-o", "d.npz"]):
        code, out, err = run(capsys, *command, "--env", "old_gym:OldGym-v0", "--env-kwargs",
                             json.dumps({"returns": returns}))
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert says in err and "old_gym:OldGym-v0" in err, err
