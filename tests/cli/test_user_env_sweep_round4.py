"""A fourth sweep of users' environments at the CLI's defaults (docs/BENCHMARKS.md, issue 25,
"Fourth sweep of users' environments"): kinds no earlier sweep wrote -- a required ``render_mode``,
``Sequence``/``Graph`` observations, a ``Discrete(5, start=2)`` observation returned as
``np.int64`` with a two-entry ``info["cost"]``, a scalar ``Box`` observation returned as a Python
float. One test per failure."""

from __future__ import annotations

import json

import numpy as np
from cli_runner import run

#: a point whose constructor requires ``render_mode`` and ``speed`` (no defaults)
NEEDY = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Needy(gym.Env):
    metadata = {"render_modes": ["ansi"]}

    def __init__(self, render_mode, speed):
        self.render_mode, self.speed = render_mode, speed
        self.observation_space = spaces.Box(-1, 1, (2,), np.float64)
        self.action_space = spaces.Box(-1, 1, (2,), np.float64)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.p = np.zeros(2)
        return self.p.copy(), {}

    def step(self, action):
        self.p = np.clip(self.p + self.speed * np.asarray(action), -1, 1)
        return self.p.copy(), 0.0, False, False, {"cost": float(self.p[1] > 0.6)}


gym.register("Needy-v0", entry_point=Needy, max_episode_steps=5)
'''

#: observations of no fixed size: a ``Sequence`` that grows by one entry a step, and a ``Graph``
UNSIZED = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Growing(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Sequence(spaces.Box(0, 1, (2,), np.float32))
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return (np.zeros(2, np.float32),), {}

    def step(self, action):
        self.t += 1
        return tuple(np.full(2, 0.1 * i, np.float32) for i in range(self.t + 1)), 0.0, self.t >= 3, False, {}


class Network(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Graph(spaces.Box(0, 1, (2,)), spaces.Discrete(2))
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return self.observation_space.sample(), {}

    def step(self, action):
        return self.observation_space.sample(), 0.0, True, False, {}


gym.register("Growing-v0", entry_point=Growing)
gym.register("Network-v0", entry_point=Network)
'''

#: a ladder of rungs 2..6: ``Discrete(5, start=2)`` observed as ``np.int64``, two actions (down,
#: up), and ``info["cost"]`` a vector of two constraints (rung 5; a second that never pays)
LADDER = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Ladder(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Discrete(5, start=2)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.s = np.int64(2)
        return self.s, {}

    def step(self, action):
        self.s = np.int64(min(6, max(2, self.s + (1 if int(action) == 1 else -1))))
        return self.s, float(self.s == 6), bool(self.s == 6), False, {"cost": np.array([float(self.s == 5), 0.0])}


gym.register("Ladder-v0", entry_point=Ladder, max_episode_steps=20)
'''

#: a scalar ``Box(())`` observation returned as a Python float, two actions, 10 steps
SCALAR_WALK = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class ScalarWalk(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(-5.0, 5.0, (), np.float64)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.x, self.t = 0.0, 0
        return np.float64(self.x), {}

    def step(self, action):
        self.x = float(np.clip(self.x + (0.5 if action else -0.5), -5, 5))
        self.t += 1
        return np.float64(self.x), -abs(self.x - 2), False, self.t >= 10, {"cost": float(self.x > 3)}


gym.register("ScalarWalk-v0", entry_point=ScalarWalk)
'''


def _module(tmp_path, monkeypatch, name, source):
    (tmp_path / f"{name}.py").write_text(source)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))


def test_a_missing_constructor_argument_hint_names_only_what_is_missing(capsys, tmp_path, monkeypatch):
    """``--env-kwargs '{"speed": 0.1}'`` for ``__init__(self, render_mode, speed)``: the hint read the
    keys of gymnasium's "with kwargs ({'speed': 0.1})" as missing too, and said "give render_mode and
    speed in --env-kwargs '{"speed": ..., "render_mode": ..., "speed": ...}'" (a key twice)."""
    _module(tmp_path, monkeypatch, "needy", NEEDY)
    record = ("data", "record", "--env", "needy:Needy-v0", "--policy", "random", "--episodes", 1, "-o", "d.npz")
    code, _, err = run(capsys, *record, "--env-kwargs", '{"speed": 0.1}')
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "give render_mode in --env-kwargs '{\"speed\": 0.1, \"render_mode\": null}'" in err, err
    code, _, err = run(capsys, *record)
    assert code == 2 and "'{\"render_mode\": null, \"speed\": ...}'" in err, err
    # the suggested kwargs work
    code, _, err = run(capsys, *record, "--env-kwargs", '{"speed": 0.1, "render_mode": null}')
    assert code == 0, err


def test_observations_of_no_fixed_size_are_refused_before_anything_runs(capsys, tmp_path, monkeypatch):
    """A ``Sequence`` observation was recorded as a vector while its length stayed 1, then stopped
    mid-recording with "the observation's entries changed between steps" (hint: "an observation space
    keeps its keys and shapes", which a Sequence need not); ``train`` said "no numeric part" with a
    FlattenObservation hint that does not apply."""
    _module(tmp_path, monkeypatch, "unsized", UNSIZED)
    for env, kind in (("unsized:Growing-v0", "Sequence"), ("unsized:Network-v0", "Graph")):
        code, _, err = run(capsys, "data", "record", "--env", env, "--policy", "random", "--episodes", 2,
                           "-o", "d.npz")
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert kind in err and "no fixed size" in err and "ObservationWrapper" in err, err
        assert not (tmp_path / "d.npz").exists()
        code, _, err = run(capsys, "train", "--env", env, "--steps", 64)
        assert code == 2 and kind in err and "no fixed size" in err, err

    from gymnasium import spaces

    from symlearn.recipes.spaces import variable_size_parts
    nested = spaces.Dict({"pos": spaces.Box(0, 1, (2,)), "seen": spaces.Sequence(spaces.Discrete(3))})
    assert variable_size_parts(nested) == ["seen"]
    assert variable_size_parts(spaces.Box(0, 1, (2,))) == []


def test_learn_dnf_reads_the_ids_of_a_discrete_observation_as_train_does(capsys, tmp_path, monkeypatch):
    """``data record`` stores a ``Discrete`` observation as ids; ``learn dnf --env`` refused them as
    "discrete states" (hint: a Python ``record(..., observation=...)``), though ``train --cost`` reads
    a Discrete observation by its id. Now one column, the id, named as train names it."""
    _module(tmp_path, monkeypatch, "ladder", LADDER)
    code, _, err = run(capsys, "data", "record", "--env", "ladder:Ladder-v0", "--policy", "random",
                       "--episodes", 6, "-o", "ladder.jsonl")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "learn", "dnf", "--env", "ladder:Ladder-v0", "--demos", "ladder.jsonl",
                         "-o", "ladder.dnf")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == ["x0"], doc
    (low, high), = [leaf["x0"] for leaf in doc["leaves"]][:1]
    assert 2 <= low and high <= 6, doc    # bounds in ids (2..6), not in one-hot entries
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "ladder:Ladder-v0", "--cost", "ladder.dnf",
                         "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
    assert code == 0, err
    # without --env there is nothing to say the ids are one observation's: still refused, the hint says so
    code, _, err = run(capsys, "learn", "dnf", "--demos", "ladder.jsonl")
    assert code == 2 and "--env" in err, err


def test_sb3_lagrangian_keeps_one_multiplier_per_entry_of_a_vector_cost(capsys, tmp_path, monkeypatch):
    """``info["cost"] = np.array([c1, c2])``: ``--algo ppo-lag`` keeps two multipliers; ``sb3-ppo-lag``
    made one and stopped with "info['cost'] has 2 entries for 1 multiplier(s)"."""
    _module(tmp_path, monkeypatch, "ladder", LADDER)
    for algo in ("sb3-ppo-lag", "ppo-lag"):
        code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "ladder:Ladder-v0", "--algo", algo,
                             "--steps", 256, "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1)
        assert code == 0, (algo, err)
        assert len(json.loads(out)["multipliers"]) == 2, (algo, out)


def test_the_lagrangian_reward_says_a_cost_keeps_its_length():
    import gymnasium
    import pytest

    from symlearn.backends.lagrangian import LagrangianReward, SharedMultipliers
    from symlearn.errors import DataError

    class Env(gymnasium.Env):
        observation_space = gymnasium.spaces.Box(0, 1, (1,))
        action_space = gymnasium.spaces.Discrete(2)

        def reset(self, *, seed=None, options=None):
            return np.zeros(1, np.float32), {}

        def step(self, action):
            return np.zeros(1, np.float32), 0.0, False, False, {"cost": [1.0, 0.0, 0.0]}

    env = LagrangianReward(Env(), SharedMultipliers(n_costs=2, fixed=[1.0, 1.0]))
    env.reset()
    with pytest.raises(DataError, match="3 entries for 2") as caught:
        env.step(0)
    assert "one multiplier each" in str(caught.value.hint)


def test_learn_spec_on_a_scalar_box_observation(capsys, tmp_path, monkeypatch):
    """A ``Box(())`` observation with two actions takes the PPO route; it was refused as "a PPO policy
    update needs array observations (a Box), not Box(-5.0, 5.0, (), float64)". Where no formula was
    scored, the stop line said "below threshold" with gain 0."""
    _module(tmp_path, monkeypatch, "scalar_walk", SCALAR_WALK)
    code, _, err = run(capsys, "data", "record", "--env", "scalar_walk:ScalarWalk-v0", "--policy", "random",
                       "--episodes", 4, "-o", "walk.jsonl")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "learn", "spec", "--env", "scalar_walk:ScalarWalk-v0", "--demos",
                         "walk.jsonl", "--labeling", '{"far": "x0 > 3"}', "--ppo-steps", 128, "--max-iterations", 1)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["policy_update"] == "ppo" and doc["stopped_because"], doc
    if doc["stopped_because"] != "gain below threshold":
        assert "below threshold" not in err, err


#: a corridor of cells 1..6 (``Discrete(6, start=1)``) with its toy-text model ``P`` keyed by those
#: ids; actions left, right, jump (+2); cell 4 is lava
CORRIDOR = '''
import gymnasium as gym
from gymnasium import spaces


class Corridor(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Discrete(6, start=1)
        self.action_space = spaces.Discrete(3)
        self.P = {s: {a: [(1.0, min(6, max(1, s + (-1, 1, 2)[a])), float(s + (-1, 1, 2)[a] >= 6),
                           s + (-1, 1, 2)[a] >= 6)] for a in range(3)} for s in range(1, 7)}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.s = 1
        return self.s, {}

    def step(self, action):
        _, self.s, reward, done = self.P[self.s][int(action)][0]
        return self.s, reward, done, False, {"cost": float(self.s == 4)}


gym.register("Corridor-v0", entry_point=Corridor, max_episode_steps=30)
'''


def test_learn_constraints_in_a_toy_text_world_whose_ids_start_at_one(capsys, tmp_path, monkeypatch):
    """``P`` keyed by the observation space's ids 1..6: ``learn constraints --env`` stopped with
    ``internal error: KeyError: 0`` (the model was read at 0..5). Now read by id, the demonstrations'
    ids too, and the forbidden pairs named by the ids: stepping into the lava from 3 (right), 2
    (jump) and 5 (left)."""
    import gymnasium

    from symlearn.data import record
    from symlearn.mdp import TabularMDP

    _module(tmp_path, monkeypatch, "corridor", CORRIDOR)
    import corridor  # noqa: F401  (registers Corridor-v0)

    record(gymnasium.make("Corridor-v0"), lambda s: 2 if s == 3 else 1, 4, seed=0).save("walk.jsonl")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "constraints", "--env", "corridor:Corridor-v0",
                         "--demos", "walk.jsonl", "-o", "rules.json")
    assert code == 0, err
    forbidden = {tuple(pair) for pair in json.load(open(tmp_path / "rules.json"))["forbidden"]}
    assert {("3", "1"), ("2", "2"), ("5", "0")} <= forbidden, forbidden

    # the same ids as one DNF column: the expert jumps 3 -> 5 over the lava, which is no path
    # through 4 (the gap was closed as "crossed by a demonstrated step", calling 4 safe)
    code, out, err = run(capsys, "--json", "learn", "dnf", "--env", "corridor:Corridor-v0", "--demos", "walk.jsonl",
                         "-o", "cells.dnf")
    assert code == 0, err
    from symlearn.logic import dnf
    rule = dnf.parse((tmp_path / "cells.dnf").read_text())
    assert rule.evaluate([[1.0], [3.0], [4.0], [5.0], [6.0]], ["x0"]).tolist() == [False, False, True, False, False]
    # and no rule is a slab between two ids (x0 > 3 & x0 < 4 holds at no id: it forbids nothing)
    from symlearn.learners.trees.one_class_tree import _holds_at_a_whole_number
    assert all(_holds_at_a_whole_number(c) for c in rule.conjunctions), str(rule)

    mdp = TabularMDP.from_gymnasium(gymnasium.make("Corridor-v0"))
    assert mdp.state_names == ("1", "2", "3", "4", "5", "6") and mdp.initial[0] == 1.0
    assert mdp.transitions[mdp.state_index("3"), 1, mdp.state_index("4")] == 1.0


def test_a_model_without_an_entry_is_one_line_naming_the_state():
    import gymnasium
    import pytest

    from symlearn.errors import ModelError
    from symlearn.mdp import TabularMDP

    class Holey(gymnasium.Env):
        observation_space = gymnasium.spaces.Discrete(2)
        action_space = gymnasium.spaces.Discrete(1)
        P = {0: {0: [(1.0, 1, 0.0, True)]}}

        def reset(self, *, seed=None, options=None):
            return 0, {}

    with pytest.raises(ModelError, match="no entry for state 1, action 0"):
        TabularMDP.from_gymnasium(Holey())


#: a throttle in ``Box(0, 10, (1,))`` observing ``MultiBinary(3)``; the reward is best at 8
THROTTLE = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Throttle(gym.Env):
    def __init__(self):
        self.observation_space = spaces.MultiBinary(3)
        self.action_space = spaces.Box(0.0, 10.0, (1,), np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.t = 0
        return np.array([1, 0, 0], np.int8), {}

    def step(self, action):
        a = float(np.asarray(action).reshape(-1)[0])
        self.t += 1
        return (np.array([self.t % 2, a > 5, a > 9], np.int8), -abs(a - 8.0), False, self.t >= 8,
                {"cost": float(a > 9)})


gym.register("Throttle-v0", entry_point=Throttle)
'''


def test_ppo_starts_inside_an_action_box_that_excludes_zero(capsys, tmp_path, monkeypatch):
    """``Box(0, 10)`` actions: a new policy's mean was 0, the lower bound, and stayed there (greedy
    return -63.8 after 4,096 steps: 8 steps of -8). It now starts at the box's centre with a spread
    in the box's units; boxes around 0 start as before."""
    import gymnasium
    import torch

    from symlearn.rl.ppo import ActorCritic

    _module(tmp_path, monkeypatch, "throttle", THROTTLE)
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "throttle:Throttle-v0", "--steps", 256,
                         "--n-envs", 2, "--n-steps", 64, "--eval-episodes", 1, "-o", "agent.safetensors")
    assert code == 0, err
    assert json.loads(out)["return"] > -40, out
    loaded = ActorCritic.load(tmp_path / "agent.safetensors")   # the centred bias is a saved weight
    assert 3 < float(loaded.act(np.array([1, 0, 0]), deterministic=True)[0]) < 7

    obs = gymnasium.spaces.Box(-1, 1, (2,))
    for low, high, mean in ((0.0, 10.0, 5.0), (-4.0, -2.0, -3.0), (-2.0, 2.0, 0.0)):
        torch.manual_seed(0)
        agent = ActorCritic.for_spaces(obs, gymnasium.spaces.Box(low, high, (1,)), log_std_init=-1.0)
        act = float(agent.act(np.zeros(2, np.float32), deterministic=True)[0])
        assert abs(act - mean) < 0.1, (low, high, act)
        spread = float(agent.log_std.detach().exp()[0])
        assert abs(spread - np.exp(-1.0) * (1.0 if low < 0 < high else (high - low) / 2)) < 1e-5


TUPLE_ACTIONS = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Lever(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Box(-1, 1, (2,), np.float32)
        self.action_space = spaces.Tuple((spaces.Discrete(2), spaces.Box(-1, 1, (1,), np.float32)))

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return np.zeros(2, np.float32), {}

    def step(self, action):
        return np.zeros(2, np.float32), 0.0, True, False, {}


gym.register("Lever-v0", entry_point=Lever)
'''


def test_data_record_refuses_composite_actions_in_one_line(capsys, tmp_path, monkeypatch):
    """``Tuple(Discrete(2), Box(...))`` actions: ``internal error: ValueError: setting an array element
    with a sequence`` after the first episode; ``train`` already said what to do."""
    _module(tmp_path, monkeypatch, "lever", TUPLE_ACTIONS)
    code, _, err = run(capsys, "data", "record", "--env", "lever:Lever-v0", "--policy", "random", "-o", "d.npz")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "Tuple(" in err and "ActionWrapper" in err and "internal error" not in err, err
    assert not (tmp_path / "d.npz").exists()


NO_INFO = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class NoInfo(gym.Env):
    def __init__(self, where="reset"):
        self.where = where
        self.observation_space = spaces.Box(-1, 1, (2,), np.float32)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return np.zeros(2, np.float32), (None if self.where == "reset" else {})

    def step(self, action):
        return np.zeros(2, np.float32), 0.0, True, False, (None if self.where == "step" else {})


gym.register("NoInfo-v0", entry_point=NoInfo, disable_env_checker=True)
'''


def test_an_info_that_is_none_is_named_as_such(capsys, tmp_path, monkeypatch):
    """``return observation, None`` from ``reset``: "reset() returned a tuple of 2, not (observation,
    info)" -- two values, as asked; the info was the matter."""
    _module(tmp_path, monkeypatch, "no_info", NO_INFO)
    for where, says in (("reset", "reset() returned (observation, None)"), ("step", "step() returned info as None")):
        code, _, err = run(capsys, "data", "record", "--env", "no_info:NoInfo-v0", "--env-kwargs",
                           json.dumps({"where": where}), "--policy", "random", "-o", "d.npz")
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert says in err and "dict" in err, err


def test_a_library_warning_repeated_by_every_environment_copy_is_printed_once():
    """highway-env's "roundabout-v0 is out of date" came once per environment copy: 5 times in a
    ``train``. The one-line format prints a text once per command (what Python's showwarning
    writes is the format's text; pytest records warnings itself, so the format is called here)."""
    import warnings

    from symlearn.cli.main import _one_line_warnings

    old = "\x1b[33mWARN: The environment roundabout-v0 is out of date.\x1b[0m"
    with _one_line_warnings(debug=False):
        printed = [warnings.formatwarning(old, DeprecationWarning, "registration.py", 512) for _ in range(3)]
        printed.append(warnings.formatwarning("another", UserWarning, "x.py", 1))
    assert printed == ["warning: WARN: The environment roundabout-v0 is out of date.\n", "", "",
                       "warning: another\n"], printed
    with _one_line_warnings(debug=False):   # the next command prints it again
        assert warnings.formatwarning(old, DeprecationWarning, "registration.py", 512).startswith("warning:")


LAZY_SPACES = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Lazy(gym.Env):
    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.observation_space = spaces.Box(-1, 1, (2,), np.float32)
        self.action_space = spaces.Discrete(2)
        return np.zeros(2, np.float32), {}

    def step(self, action):
        return np.zeros(2, np.float32), 0.0, True, False, {}


gym.register("Lazy-v0", entry_point=Lazy, disable_env_checker=True)
'''


def test_spaces_set_only_in_reset_are_one_line_naming_the_class(capsys, tmp_path, monkeypatch):
    """``observation_space``/``action_space`` assigned in ``reset``: ``internal error: AttributeError:
    'Lazy' object has no attribute 'observation_space'`` from every command."""
    _module(tmp_path, monkeypatch, "lazy", LAZY_SPACES)
    for command in (("train", "--steps", 64), ("data", "record", "--policy", "random", "-o", "d.npz")):
        code, _, err = run(capsys, *command[:2 if command[0] == "data" else 1], "--env", "lazy:Lazy-v0",
                           *command[2 if command[0] == "data" else 1:])
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert "lazy.py:" in err and "observation_space or action_space" in err and "__init__" in err, err


STEP_FEATURES = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class StepFeatures(gym.Env):
    feature_names = ("speed",)

    def __init__(self):
        self.observation_space = spaces.Box(-1, 1, (2,), np.float32)
        self.action_space = spaces.Box(-1, 1, (2,), np.float32)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.p = np.zeros(2, np.float32)
        return self.p.copy(), {}

    def step(self, action):
        a = np.clip(np.asarray(action, np.float32), -1, 1) * 0.1
        self.p = np.clip(self.p + a, -1, 1).astype(np.float32)
        speed = float(np.linalg.norm(a))
        return self.p.copy(), 0.0, False, False, {"features": {"speed": speed}, "cost": float(speed > 0.12)}


gym.register("StepFeatures-v0", entry_point=StepFeatures, max_episode_steps=10)
'''


def test_features_reported_by_step_only_are_named_as_the_matter(capsys, tmp_path, monkeypatch):
    """``info["features"]`` after ``step`` but not after ``reset``: "1 feature names (speed) for 2
    columns of the observation" with the hint ``--features a,b,...``, pointing away from the fix."""
    _module(tmp_path, monkeypatch, "step_features", STEP_FEATURES)
    (tmp_path / "fast.dnf").write_text("speed > 0.12\n")
    for command in (("train", "--cost", "fast.dnf", "--steps", 64),
                    ("data", "record", "--states", "features", "--policy", "random", "-o", "d.npz")):
        head = 2 if command[0] == "data" else 1
        code, _, err = run(capsys, *command[:head], "--env", "step_features:StepFeatures-v0", *command[head:])
        assert code == 2 and len(err.strip().splitlines()) == 1, err
        assert "after step but not after reset" in err and "--features" not in err, err


TEXT_WORLD = '''
import gymnasium as gym
from gymnasium import spaces


class Words(gym.Env):
    def __init__(self):
        self.observation_space = spaces.Text(8)
        self.action_space = spaces.Discrete(2)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        return "a", {}

    def step(self, action):
        return "b" if action else "a", 0.0, True, False, {}


gym.register("Words-v0", entry_point=Words)
'''


def test_a_text_observation_is_recorded_and_a_feature_labeling_names_the_way_that_works(capsys, tmp_path,
                                                                                       monkeypatch):
    """``Text`` observations record as symbols; a feature labeling over them was refused with the
    hint "give --features a,b,...", which cannot name text. ``train`` says it needs numbers."""
    _module(tmp_path, monkeypatch, "words", TEXT_WORLD)
    env = ("--env", "words:Words-v0")
    code, _, err = run(capsys, "data", "record", *env, "--policy", "random", "--episodes", 3, "-o", "w.npz")
    assert code == 0, err
    code, _, err = run(capsys, "learn", "spec", *env, "--demos", "w.npz", "--labeling", '{"b": "x0 > 0"}')
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "FILE.py:function" in err and "give --features" not in err, err
    code, _, err = run(capsys, "train", *env, "--steps", 64)
    assert code == 2 and "no numeric part" in err and "symbols" in err, err
