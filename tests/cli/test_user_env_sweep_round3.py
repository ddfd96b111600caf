"""A third sweep of users' environments and gymnasium's own at the CLI's defaults: modules nobody
had written before (a dict ``info["features"]`` whose key order changes, ``Discrete(3, start=-1)``
actions with stable-baselines3, pictures, toy-text worlds under SB3, ...). One test per failure."""

from __future__ import annotations

import json

import gymnasium
import numpy as np
import pytest
from cli_runner import run

#: a point whose float64 observation is ``(x, y, speed)``, named by ``feature_names``, and whose
#: ``info["features"]`` is a dict of the same numbers with its keys in a random order per step
#: (as a dict built from a set or by several code paths comes); right of ``x = 0.5`` costs 1
SHUFFLED_FEATURES = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class ShuffledFeatures(gym.Env):
    feature_names = ("x", "y", "speed")

    def __init__(self):
        self.observation_space = spaces.Box(-np.inf, np.inf, (3,), np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float64)

    def _obs(self):
        return np.array([self.p[0], self.p[1], self.speed], dtype=np.float64)

    def _info(self, cost=0.0):
        keys = ["x", "y", "speed"] if self.np_random.random() < 0.5 else ["speed", "y", "x"]
        values = dict(zip(self.feature_names, self._obs()))
        return {"features": {k: float(values[k]) for k in keys}, "cost": np.float64(cost)}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.speed = self.np_random.uniform(-0.9, -0.5, 2), 0.0
        return self._obs(), self._info()

    def step(self, action):
        a = np.clip(np.asarray(action, dtype=np.float64), -1, 1) * 0.1
        self.p = np.clip(self.p + a, -1, 1)
        self.speed = float(np.linalg.norm(a))
        return self._obs(), float(a[0]), False, False, self._info(float(self.p[0] > 0.5))


gym.register("ShuffledFeatures-v0", entry_point="shuffled_features:ShuffledFeatures", max_episode_steps=20)
'''

#: a painter on a line: ``Discrete(3, start=-1)`` actions (-1 left, 0 paint, 1 right) checked by
#: the environment, an ``int32`` Box observation ``(position, painted)``, a ``render_mode``
#: argument and a namespaced id; standing at the far end costs 1
PAINTER = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Painter(gym.Env):
    metadata = {"render_modes": ["ansi"], "render_fps": 4}

    def __init__(self, render_mode=None, length=9):
        self.render_mode, self.length = render_mode, length
        self.observation_space = spaces.Box(0, length, (2,), np.int32)
        self.action_space = spaces.Discrete(3, start=-1)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.pos, self.painted, self.t = 0, 0, 0
        return np.array([self.pos, self.painted], np.int32), {}

    def step(self, action):
        if not self.action_space.contains(action):
            raise ValueError(f"action {action!r} outside {self.action_space}")
        a = int(action)
        self.pos = int(np.clip(self.pos + a, 0, self.length))
        self.painted = min(self.length, self.painted + (a == 0))
        self.t += 1
        return (np.array([self.pos, self.painted], np.int32), float(a == 0), False, self.t >= 10,
                {"cost": float(self.pos >= self.length - 1)})

    def render(self):
        return "." * self.pos + "P"


gym.register("paint/Painter-v1", entry_point=Painter)
'''

#: a uint8 camera picture ``(12, 12, 3)`` of a dot moved by ``Discrete(5)`` actions (stable-
#: baselines3 trains on it channels-first); the right edge costs 1
CAMERA = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Camera(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(0, 255, (12, 12, 3), np.uint8)
        self.action_space = spaces.Discrete(5)

    def _obs(self):
        picture = np.zeros((12, 12, 3), np.uint8)
        picture[self.p[0], self.p[1]] = (255, 200, 0)
        return picture

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.t = np.array([0, 0]), 0
        return self._obs(), {}

    def step(self, action):
        move = [(0, 0), (0, 1), (1, 0), (0, -1), (-1, 0)][int(action)]
        self.p = np.clip(self.p + move, 0, 11)
        self.t += 1
        return self._obs(), float(self.p[0]), False, self.t >= 8, {"cost": float(self.p[1] > 8)}


gym.register("Camera-v0", entry_point=Camera)
'''

#: a scalar observation (``Box`` of shape ``()``) and one step per episode: guess the number shown
#: (always 0.3, so that every episode is the same one)
SCALAR_GUESS = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class ScalarGuess(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(-1.0, 1.0, (), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.x = np.float32(0.3)
        return np.asarray(self.x), {}

    def step(self, action):
        guess = float(np.asarray(action).reshape(-1)[0])
        return np.asarray(np.float32(0.0)), -abs(self.x - guess), True, False, {"cost": float(guess > 0.8)}


gym.register("ScalarGuess-v0", entry_point=ScalarGuess)
'''


def _module(tmp_path, monkeypatch, name, source):
    (tmp_path / f"{name}.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))


def test_learn_dnf_reads_a_dict_of_features_by_the_names_the_environment_declares(capsys, tmp_path, monkeypatch):
    """``feature_names`` = (x, y, speed), the observation those numbers, ``info["features"]`` the
    same dict with its keys in another order: refused before as "names the columns of its
    info["features"] (speed=0, y=-0.5, x=-0.9 after reset), which are not its observation"."""
    _module(tmp_path, monkeypatch, "shuffled_features", SHUFFLED_FEATURES)
    from symlearn.data import record

    import shuffled_features  # noqa: F401  (registers ShuffledFeatures-v0)
    record(gymnasium.make("ShuffledFeatures-v0"), "random", 6, seed=0).save("demos.npz")
    code, out, err = run(capsys, "--json", "learn", "dnf", "--env", "shuffled_features:ShuffledFeatures-v0",
                         "--demos", "demos.npz", "-o", "rules.dnf")
    assert code == 0, err
    assert set(json.loads(out)["features"]) == {"x", "y", "speed"}
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "shuffled_features:ShuffledFeatures-v0",
                         "--cost", "rules.dnf", "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err


def test_a_dnf_cost_wrapper_reads_a_dict_of_features_by_name(tmp_path, monkeypatch):
    """``DnfCostWrapper`` (docs/GUIDE.md, "In Python") turned a dict ``info["features"]`` into an
    array and raised ``TypeError: float() argument must be ... not 'dict'``."""
    from symlearn.backends.dnf_cost import DnfCostWrapper, DnfRolloutCost
    from symlearn.logic import dnf

    _module(tmp_path, monkeypatch, "shuffled_features", SHUFFLED_FEATURES)
    import shuffled_features  # noqa: F401

    env = DnfCostWrapper(gymnasium.make("ShuffledFeatures-v0"), dnf.parse("speed > 0.1"), ("x", "y", "speed"))
    env.reset(seed=0)
    for _ in range(6):   # whatever order the keys come in, the rule reads the speed
        info = env.step(np.array([1.0, 1.0]))[-1]
        assert info["cost"] == 1.0, info
        info = env.step(np.zeros(2))[-1]
        assert info["cost"] == 0.0, info

    # a rollout holds the dicts as they came (train_ppo records info["features"] per step)
    rows = np.empty((2, 1), dtype=object)
    rows[0, 0] = np.asarray({"speed": 0.2, "y": 0.0, "x": -0.5}, dtype=object)
    rows[1, 0] = np.asarray({"x": 0.9, "y": 0.0, "speed": 0.0}, dtype=object)

    class Rollout:
        info = {"features": rows}

    cost = DnfRolloutCost(dnf.parse("speed > 0.1"), ("x", "y", "speed"))
    assert cost(Rollout()).tolist() == [[1.0], [0.0]]


def test_ppo_lag_on_the_environments_cost_reports_the_limit_it_kept(capsys, tmp_path, monkeypatch):
    """``train --algo ppo-lag`` without ``--cost`` trains to a limit of 0 (its warning says
    "--cost-limit 0") but the JSON said ``cost_limit: null``."""
    _module(tmp_path, monkeypatch, "painter", PAINTER)
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "painter:paint/Painter-v1", "--algo",
                         "ppo-lag", "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err
    doc = json.loads(out)
    assert (doc["cost_limit"], doc["cost_limit_from"]) == (0.0, "default")
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "painter:paint/Painter-v1", "--algo",
                         "ppo-lag", "--cost-limit", 2, "--steps", 256, "--n-envs", 2, "--n-steps", 64,
                         "--eval-episodes", 1)
    assert code == 0, err
    doc = json.loads(out)
    assert (doc["cost_limit"], doc["cost_limit_from"]) == (2.0, "--cost-limit")
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "painter:paint/Painter-v1",
                         "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err
    assert json.loads(out)["cost_limit"] is None   # plain PPO keeps no limit


@pytest.mark.parametrize("algo", ["sb3-dqn", "sb3-ppo"])
def test_stable_baselines3_evaluates_on_gymnasiums_toy_text_worlds(capsys, tmp_path, monkeypatch, algo):
    """SB3's ``predict`` gives a Discrete action as a 0-d array; FrozenLake looks its transitions
    up by it (``P[s][a]``) and raised ``TypeError: unhashable type: 'numpy.ndarray'`` in the
    greedy evaluation after training, reported as the environment's fault."""
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "FrozenLake-v1", "--env-kwargs",
                         '{"is_slippery": false}', "--algo", algo, "--steps", 128, "--eval-episodes", 1,
                         "-o", "agent.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "data", "record", "--env", "FrozenLake-v1", "--env-kwargs",
                         '{"is_slippery": false}', "--policy", "agent.safetensors", "--episodes", 1,
                         "-o", "demos.jsonl")
    assert code == 0, err


@pytest.mark.parametrize("module, source, env, algo", [
    ("painter", PAINTER, "painter:paint/Painter-v1", "sb3-dqn"),        # Discrete(3, start=-1) actions
    ("camera", CAMERA, "camera:Camera-v0", "sb3-ppo"),                  # pictures, trained channels-first
    ("scalar_guess", SCALAR_GUESS, "scalar_guess:ScalarGuess-v0", "sb3-sac"),   # a scalar observation
])
def test_data_record_acts_through_the_view_stable_baselines3_trained_on(capsys, tmp_path, monkeypatch, module,
                                                                        source, env, algo):
    """``data record --policy`` of an ``sb3-*`` policy loaded it on the environment's own spaces:
    a ``Discrete(3, start=-1)`` environment got SB3's ids 0..2 (the painter walked right instead of
    painting, silently; one that checks its actions raised), a picture or a scalar observation was
    refused ("trained for observations {'shape': [3, 12, 12]}, the environment's are [12, 12, 3]")."""
    _module(tmp_path, monkeypatch, module, source)
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", env, "--algo", algo, "--steps", 200,
                         "--eval-episodes", 2, "-o", "agent.safetensors")
    assert code == 0, err
    trained = json.loads(out)
    code, out, err = run(capsys, "--json", "--quiet", "--seed", 10_000, "data", "record", "--env", env,
                         "--policy", "agent.safetensors", "--episodes", 2, "-o", "demos.npz")
    assert code == 0, err
    recorded = json.loads(out)
    # the greedy policy from the evaluation's seed: the same episodes as train's evaluation
    assert recorded["return"] == pytest.approx(trained["return"]), (trained, recorded)
    from symlearn.data import load

    actions = np.concatenate([np.asarray(t.actions).reshape(len(t.actions), -1) for t in load("demos.npz")])
    space = gymnasium.make(env.split(":")[1]).action_space
    assert all(space.contains(a.reshape(space.shape).astype(space.dtype) if space.shape else
                              space.dtype.type(a.item())) for a in actions)


def test_a_small_learned_cost_keeps_its_digits_next_to_its_limit():
    """``learned cost 0.00 per episode (limit 0.000224, ...)`` read as kept, while the warning
    below it said the agent pays 0.00271."""
    from symlearn.cli.train_command import _render

    doc = {"env": "e", "algo": "ppo-lag", "steps": 1, "seconds": 0.1, "return": -1.0, "learned_cost": 0.00271,
           "cost_limit": 0.000224, "cost_limit_from": "expert", "cost": None, "violation_rate": None,
           "multipliers": [1.0], "pruned": None, "files": [], "warnings": []}
    text = _render(doc)
    assert "learned cost 0.0027 per episode (limit 0.000224" in text, text
    doc.update(learned_cost=0.0, cost=3.5, violation_rate=0.25)
    assert "learned cost 0.00 per episode" in _render(doc) and "ground-truth cost 3.50" in _render(doc)


@pytest.mark.parametrize("algo", ["ppo", "sb3-ppo"])
def test_a_neural_cost_of_zero_everywhere_is_named_without_a_lagrangian_too(capsys, tmp_path, monkeypatch, algo):
    """docs/GUIDE.md: a cost whose every lambda is 0 constrains nothing, "and so does ``train
    --cost`` with that file" say so; only the Lagrangians did, ``--algo ppo`` (and ``sb3-ppo``,
    ``sb3-sac``: ``r - C``) trained on the reward alone in silence."""
    import torch

    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    _module(tmp_path, monkeypatch, "painter", PAINTER)
    import painter  # noqa: F401

    cost = NeuralCost.for_env(gymnasium.make("paint/Painter-v1"),
                              FeatureNetwork([0], 0, 1, (8,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([0.0])
    cost.save(tmp_path / "zero.safetensors")
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "painter:paint/Painter-v1", "--algo", algo,
                         "--cost", "zero.safetensors", "--steps", 128, "--n-envs", 2, "--n-steps", 64,
                         "--eval-episodes", 1)
    assert code == 0, err
    assert any("0 everywhere" in w and "constrained nothing" in w for w in json.loads(out)["warnings"]), out


#: a grid whose size has no default: ``__init__(self, size)``, given by ``--env-kwargs``
SIZED_GRID = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class SizedGrid(gym.Env):
    def __init__(self, size, hazard=None):
        self.size = size
        self.observation_space = spaces.MultiDiscrete([size, size])
        self.action_space = spaces.Discrete(4)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.t = np.array([0, 0]), 0
        return self.p.copy(), {}

    def step(self, action):
        self.p = np.clip(self.p + [(0, 1), (1, 0), (0, -1), (-1, 0)][int(action)], 0, self.size - 1)
        self.t += 1
        return self.p.copy(), 0.0, False, self.t >= 10, {}


gym.register("SizedGrid-v0", entry_point=SizedGrid)
'''


def test_a_required_constructor_argument_is_named_with_the_flag_that_gives_it(capsys, tmp_path, monkeypatch):
    """Before: "building ... failed: TypeError: ... missing 1 required positional argument: 'size'"
    with the hint "check the environment's parameters"."""
    _module(tmp_path, monkeypatch, "sized_grid", SIZED_GRID)
    code, _, err = run(capsys, "data", "record", "--env", "sized_grid:SizedGrid-v0", "--policy", "random",
                       "-o", "demos.npz")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "give size in --env-kwargs '{\"size\": ...}'" in err, err
    code, _, err = run(capsys, "data", "record", "--env", "sized_grid:SizedGrid-v0", "--env-kwargs", '{"size": 4}',
                       "--policy", "random", "--episodes", 2, "-o", "demos.npz")
    assert code == 0, err


def test_dnf_eval_on_a_demonstrations_file_says_what_it_reads(capsys, tmp_path, monkeypatch):
    """``dnf eval rules.dnf --points demos.npz``: "per-feature arrays must be 1-D: states (804, 3),
    actions (800, 1), __meta__ ()" listed the file's members as if they were features."""
    _module(tmp_path, monkeypatch, "painter", PAINTER)
    code, _, err = run(capsys, "data", "record", "--env", "painter:paint/Painter-v1", "--policy", "random",
                       "--episodes", 2, "-o", "demos.npz")
    assert code == 0, err
    (tmp_path / "rules.dnf").write_text("x0 > 7\n")
    code, _, err = run(capsys, "dnf", "eval", "rules.dnf", "--points", "demos.npz")
    assert code == 2 and "is a demonstrations file, not points" in err and "__meta__" not in err, err


def test_a_neural_cost_on_a_dict_space_names_the_views_that_work():
    """The hint said "flatten dict/tuple spaces with FlattenObservation", which one-hot encodes a
    Discrete part that ``record()`` stores as one column: the demonstrations then no longer fit."""
    from gymnasium import spaces

    from symlearn.errors import DataError
    from symlearn.learners.neural.neural_cost import space_spec

    with pytest.raises(DataError) as caught:
        space_spec(spaces.Dict({"cell": spaces.Discrete(3), "pos": spaces.Box(-1, 1, (2,))}))
    assert "numeric_observations" in caught.value.hint and "FlattenObservation" not in caught.value.hint


def test_a_short_sb3_sac_lagrangian_without_any_cost_is_refused_as_ppo_lag_is(capsys, tmp_path, monkeypatch):
    """``train --algo sb3-sac-lag`` without ``--cost`` on an environment that reports no
    ``info["cost"]``: refused after the first update window (1,000 steps for SAC), so a shorter
    run trained a Lagrangian with nothing to constrain and exited 0; ``ppo-lag`` refuses."""
    pytest.importorskip("stable_baselines3")
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "Pendulum-v1", "--algo", "sb3-sac-lag",
                         "--steps", 200, "--eval-episodes", 1)
    assert code == 2, err
    assert "reports none in the first rollout (200 steps)" in err and "train --algo sb3-sac)" in err, err


@pytest.mark.parametrize("command", [["learn", "icrl"], ["learn", "spec", "--labeling", '{"far": "x0 > 6"}']])
def test_an_environment_without_an_expert_names_the_command_that_records_one(capsys, tmp_path, monkeypatch,
                                                                            command):
    """The hint named only the Python call ``symlearn.data.record(env, policy, n)``, not ``symlearn
    data record``, which a user of the command line has."""
    _module(tmp_path, monkeypatch, "painter", PAINTER)
    code, _, err = run(capsys, *command, "--env", "painter:paint/Painter-v1")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "`symlearn data record --env painter:paint/Painter-v1 --policy AGENT.safetensors -o demos.npz`" in err


#: a point observed as ``(px, py, vx, vy)`` (``observation_names``) whose ``info["features"]`` is the
#: position alone (``feature_names`` = px, py); right of ``px = 0.5`` costs 1
POSITION_FEATURES = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class PositionFeatures(gym.Env):
    observation_names = ("px", "py", "vx", "vy")
    feature_names = ("px", "py")

    def __init__(self):
        self.observation_space = spaces.Box(-1, 1, (4,), np.float32)
        self.action_space = spaces.Box(-1, 1, (2,), np.float32)

    def _obs(self):
        return np.concatenate([self.p, self.v]).astype(np.float32)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.v, self.t = self.np_random.uniform(-0.9, -0.5, 2), np.zeros(2), 0
        return self._obs(), {"features": self.p.copy()}

    def step(self, action):
        self.v = 0.1 * np.clip(action, -1, 1)
        self.p = np.clip(self.p + self.v, -1, 1)
        self.t += 1
        return self._obs(), float(self.v[0]), False, self.t >= 10, {"features": self.p.copy(),
                                                                     "cost": float(self.p[0] > 0.5)}


gym.register("PositionFeatures-v0", entry_point=PositionFeatures)
'''


def test_learn_dnf_next_to_an_env_takes_the_way_out_its_refusal_names(capsys, tmp_path, monkeypatch):
    """Recorded observations (4 columns) of an environment whose ``info["features"]`` is 2 of them:
    refused, with the hint "name the observation's columns with --features a,b,..."; doing so
    was refused in turn ("4 feature names (px, py, vx, vy) for 2 columns of info["features"]")."""
    _module(tmp_path, monkeypatch, "position_features", POSITION_FEATURES)
    env = ("--env", "position_features:PositionFeatures-v0")
    code, _, err = run(capsys, "data", "record", *env, "--policy", "random", "--episodes", 4, "-o", "demos.npz")
    assert code == 0, err
    code, _, err = run(capsys, "learn", "dnf", *env, "--demos", "demos.npz")
    assert code == 2 and "--features px,py,vx,vy" in err and "--inputs px,py" in err, err
    code, _, err = run(capsys, "learn", "dnf", *env, "--demos", "demos.npz", "--features", "px,py,vx,vy",
                       "--inputs", "px,py", "-o", "rules.dnf")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--cost", "rules.dnf", "--steps", 128,
                         "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err


def test_learn_pdfa_reads_the_column_names_recorded_with_the_demonstrations(capsys, tmp_path, monkeypatch):
    """``record()`` names a Dict observation's columns (``arm[0]``, ``goal[1]``) in the file's
    metadata, and ``learn dnf`` reads them; ``learn pdfa --subsets 'arm=arm[0],arm[1]'`` said "no
    feature named 'arm[0]' (features: x0, x1, ...)"."""
    from symlearn.data import Demonstrations, Trajectory

    monkeypatch.chdir(tmp_path)
    rng = np.random.default_rng(0)
    runs = []
    for _ in range(8):   # the arm dwells at (1, 0), then at (1, 1); the goal column stays put
        path = [np.linspace([0, 0], [1, 0], 5), np.tile([1.0, 0.0], (10, 1)), np.linspace([1, 0], [1, 1], 5),
                np.tile([1.0, 1.0], (10, 1))]
        arm = np.concatenate(path) + rng.normal(0, 0.003, (30, 2))
        runs.append(Trajectory(states=np.column_stack([arm, np.full((30, 2), 0.5)])))
    Demonstrations(runs, metadata={"feature_names": ["arm[0]", "arm[1]", "goal[0]", "goal[1]"]}).save("demos.npz")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "pdfa", "--demos", "demos.npz", "--subsets",
                         "arm=arm[0],arm[1]")
    assert code == 0, err
    assert len(json.loads(out)["subgoals"]) == 2, out


#: a Dict observation of MultiBinary, Box and MultiDiscrete parts, ``MultiDiscrete([2, 3])`` actions
#: (seen by our PPO as one Discrete(6)); the level above 0.8 costs 1
SWITCH_ROOM = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class SwitchRoom(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Dict({"switches": spaces.MultiBinary(3),
                                              "level": spaces.Box(0, 1, (1,), np.float32),
                                              "room": spaces.MultiDiscrete([3, 2])})
        self.action_space = spaces.MultiDiscrete([2, 3])

    def _obs(self):
        return {"switches": self.s.copy(), "level": np.array([self.level], np.float32), "room": self.room.copy()}

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.s, self.level, self.room, self.t = np.zeros(3, np.int8), 0.0, np.array([0, 0]), 0
        return self._obs(), {}

    def step(self, action):
        a = np.asarray(action)
        self.s[int(a[1])] = int(a[0])
        self.level = float(np.clip(self.level + 0.1 * (self.s.sum() - 1), 0, 1))
        self.room = np.array([int(a[1]), int(a[0])])
        self.t += 1
        return self._obs(), self.level, False, self.t >= 8, {"cost": float(self.level > 0.8)}


gym.register("SwitchRoom-v0", entry_point=SwitchRoom)
'''


def test_learn_icrl_names_the_entries_of_a_dict_observation_under_joint_actions(capsys, tmp_path, monkeypatch):
    """A Dict observation's view names its entries (``level[0]``, ``room[0]=2``), but under the
    wrapper that makes MultiDiscrete actions one Discrete they were lost (gymnasium's wrappers no
    longer hand attributes on): ``--cost-inputs 'level[0]'`` was "unknown observation entry
    'level[0]' (observation entries: x0..x8)"."""
    _module(tmp_path, monkeypatch, "switch_room", SWITCH_ROOM)
    env = ("--env", "switch_room:SwitchRoom-v0")
    code, _, err = run(capsys, "data", "record", *env, "--policy", "random", "--episodes", 4, "-o", "demos.npz")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", *env, "--demos", "demos.npz",
                         "--cost-inputs", "level[0]", "--steps", 256, "--iterations", 1, "-o", "cost.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--cost", "cost.safetensors", "--steps", 128,
                         "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err


def test_train_cost_given_the_forbidden_pairs_of_learn_constraints_says_what_they_are(capsys, tmp_path, monkeypatch):
    """``learn constraints --env FrozenLake-v1 ... -o rules.json`` then ``train --cost rules.json``
    said only 'not a symlearn dnf (missing "symlearn": "dnf")'."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "rules.json").write_text(json.dumps({"format": "symlearn-constraints", "version": 1, "method": "ml",
                                                     "forbidden": [["6", "0"]]}))
    code, _, err = run(capsys, "train", "--env", "FrozenLake-v1", "--cost", "rules.json", "--steps", 64)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "forbidden state-action pairs `learn constraints` writes" in err and "Shield" in err, err
