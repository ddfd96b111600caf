"""The environment resolver: bundled names, gymnasium ids and a user's module:EnvId alike."""

from __future__ import annotations

import json
import sys

import pytest
from user_envs import PLAIN_ROBOT, POINT_ROBOT, careful_expert, write_module

from symlearn.envs.registry import ENTRIES, Kind
from symlearn.errors import DataError, SymlearnError, UnknownNameError
from symlearn.recipes.environments import parse_env_kwargs, parse_feature_names, resolve_env


@pytest.fixture
def user_folder(tmp_path, monkeypatch):
    """A folder with the user's modules, as the current directory (dropped from sys.modules after)."""
    write_module(tmp_path, "my_point_robot", POINT_ROBOT)
    write_module(tmp_path, "my_plain_robot", PLAIN_ROBOT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield tmp_path
    for name in ("my_point_robot", "my_plain_robot", "my_broken", "my_silent"):
        sys.modules.pop(name, None)


def test_a_users_module_is_imported_and_its_id_made(user_folder):
    target = resolve_env("my_point_robot:PointRobot-v0", '{"wall": 0.2}')
    assert not target.bundled and target.gym_id == "PointRobot-v0" and target.kwargs == {"wall": 0.2}
    env = target.make()
    assert env.unwrapped.wall == 0.2
    assert target.feature_names(env) == ("px", "py")
    assert target.features(env).source == "info"
    assert target.reports_cost(env)
    assert not target.has_expert and not target.trains_expert
    with pytest.raises(DataError, match="has no expert: give your demonstrations with --demos"):
        target.expert_demonstrations(3)


def test_names_from_features_flag_are_counted_against_the_observation(user_folder):
    target = resolve_env("my_plain_robot:PlainRobot-v0")
    assert target.feature_names() is None  # nothing names its columns
    assert not target.reports_cost()       # and it has no ground truth: n/a, never 0
    assert target.feature_names(override="a,b") == ("a", "b")
    with pytest.raises(DataError, match=r"3 feature names \(a, b, c\) for 2 columns of the observation"):
        target.feature_names(override="a,b,c")
    with pytest.raises(DataError, match="--features names 'a' twice"):
        target.feature_names(override="a,a")


@pytest.mark.parametrize("name, kwargs, message", [
    ("my_point_robot:PointRobot-v9", None, "module 'my_point_robot' did not register the gymnasium id 'PointRobot-v9'"),
    ("my_point_robot:PointRobot-v0", '{"wal": 1}', "unknown --env-kwargs key 'wal' for PointRobot-v0"),
    ("my_point_robot:PointRobot-v0", '{"wall": 1, "wall": 2}', 'key "wall" appears twice'),
    ("my_point_robot:PointRobot-v0", "[1]", "--env-kwargs must be a JSON object"),
    ("my_point_robot:PointRobot-v0", "{wall: 1}", "not JSON"),
    ("my_point_robot:PointRobot-v0", "[" * 40 + "]" * 40, "nested more than 32 levels deep"),
    ("no_such_module_here:X-v0", None, "no module named 'no_such_module_here'"),
    ("toy-navigaton", None, "unknown environment 'toy-navigaton'"),
    ("CartPol-v1", None, "unknown environment 'CartPol-v1'"),
    ("toy-navigation", '{"sped": 1}', "unknown --env-kwargs key 'sped' for toy-navigation"),
    (":X-v0", None, "write module:EnvId"),
])
def test_every_bad_name_is_one_clear_error(user_folder, name, kwargs, message):
    with pytest.raises(SymlearnError) as info:
        resolve_env(name, kwargs)
    assert message in str(info.value)


def test_hints_say_what_was_meant(user_folder, tmp_path, monkeypatch):
    with pytest.raises(UnknownNameError) as info:
        resolve_env("my_point_robot:PointRobot-v1")
    assert "did you mean my_point_robot:PointRobot-v0?" in info.value.hint
    with pytest.raises(DataError) as info:
        resolve_env("my_point_robot:PointRobot-v0", '{"wal": 1}')
    assert info.value.hint.startswith("did you mean 'wall'?") and "horizon" in info.value.hint
    with pytest.raises(UnknownNameError) as info:
        resolve_env("CartPol-v1")
    assert "did you mean 'CartPole-v1'?" in info.value.hint
    # an id its package registers on import, named without the package (highway-v0, which
    # highway_env registers): the installed package is named. A package of this test's own, so
    # that no other test can have imported it (and registered the id) first
    (tmp_path / "zorkworld_env").mkdir()
    (tmp_path / "zorkworld_env" / "__init__.py").write_text("")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(UnknownNameError) as info:
        resolve_env("zorkworld-v0")
    assert "did you mean zorkworld_env:zorkworld-v0?" in info.value.hint
    with pytest.raises(UnknownNameError) as info:  # a name close to no registered id (other tests register some)
        resolve_env("Qqqxjz-v0")
    assert "named package:ID (e.g. qqqxjz:Qqqxjz-v0)" in info.value.hint


def test_an_id_its_installed_package_registers_on_import_resolves_without_the_package(tmp_path, monkeypatch):
    """MiniGrid-Empty-5x5-v0 without minigrid: (gymnasium's own make needs the package imported
    first): the installed package that registers the id is imported, as for package:ID. A
    package of this test's own, so that no other test has imported it first."""
    (tmp_path / "zorkland_env").mkdir()
    (tmp_path / "zorkland_env" / "__init__.py").write_text(
        "import gymnasium as gym\n"
        "gym.register('Zorkland-v0', entry_point='gymnasium.envs.classic_control:CartPoleEnv', max_episode_steps=5)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    target = resolve_env("Zorkland-v0")
    assert target.gym_id == "Zorkland-v0"
    env = target.make()
    assert env.reset(seed=0)[0].shape == (4,)
    env.close()
    # a misspelt id of that package is still refused, with the package:ID hint
    with pytest.raises(UnknownNameError) as info:
        resolve_env("Zorklandd-v7")
    assert "did you mean 'Zorkland-v0'?" in info.value.hint


@pytest.mark.parametrize("name, hint", [
    ("my_point_robot.py:PointRobot-v0", "run from its folder with --env my_point_robot:..."),
    ("/home/me/lab/my_point_robot.py:PointRobot-v0", "run from /home/me/lab with --env my_point_robot:..."),
    ("./my_point_robot:PointRobot-v0", "--env my_point_robot:..."),
])
def test_a_file_path_for_the_module_says_to_name_the_module(user_folder, name, hint):
    """``my_robot.py:MyRobot-v0`` run from the folder that holds my_robot.py: the old message ("no
    module named 'my_robot.py'; run from the folder that holds my_robot.py") told the user to do
    what they had done."""
    with pytest.raises(UnknownNameError) as info:
        resolve_env(name)
    assert "--env takes a module's name, not a file" in str(info.value) and hint in info.value.hint
    with pytest.raises(UnknownNameError) as info:
        resolve_env("Gridlabs-Maze-v3")  # as an id a package registers only when imported
    assert "gridlabs:Gridlabs-Maze-v3" in info.value.hint


def test_a_module_that_fails_is_named_with_its_own_error(user_folder):
    write_module(user_folder, "my_broken", "import numpy\nraise RuntimeError('calibration file missing')\n")
    with pytest.raises(DataError) as info:
        resolve_env("my_broken:Robot-v0")
    assert "importing module 'my_broken' failed: RuntimeError: calibration file missing" in info.value.message
    assert info.value.file.endswith("my_broken.py") and info.value.line == 2
    write_module(user_folder, "my_silent", "x = 1\n")
    with pytest.raises(UnknownNameError, match="did not register") as info:
        resolve_env("my_silent:Robot-v0")
    assert "gymnasium.register" in info.value.hint


def test_a_value_of_the_wrong_type_fails_when_built_in_one_line(user_folder):
    target = resolve_env("my_point_robot:PointRobot-v0", '{"horizon": "long"}')
    env = target.make()  # builds: the wrong type only shows when stepped
    env.reset(seed=0)
    with pytest.raises(TypeError):
        env.step(env.action_space.sample())


def test_gymnasium_ids_and_bundled_names_resolve_alike():
    cartpole = resolve_env("CartPole-v1", '{"max_episode_steps": 20}')
    assert cartpole.gym_id == "CartPole-v1" and not cartpole.bundled
    assert cartpole.make().spec.max_episode_steps == 20
    toy = resolve_env("symlearn/toy-navigation-v0")
    assert toy.entry.name == "toy-navigation" and toy.has_expert
    assert resolve_env("symlearn.envs:symlearn/toy-navigation-v0").entry.name == "toy-navigation"
    assert resolve_env("TOY-Navigation").entry.name == "toy-navigation"


def test_a_bundled_expert_records_in_the_kwargs_variant():
    demos = resolve_env("blocked-point", '{"wall": -4.0}').expert_demonstrations(2, seed=1)
    assert len(demos) == 2
    with pytest.raises(DataError, match="drives the default environment only"):
        resolve_env("safenav-point-goal", '{"agent": "car"}').expert_demonstrations(1)


def test_every_registry_entry_says_what_it_has():
    """The registry is the one table: experts, features and kinds are fields, not name matching."""
    for entry in ENTRIES:
        if Kind.SPEC in entry.kinds or Kind.SUBGOALS in entry.kinds or Kind.MACHINE in entry.kinds:
            assert entry.expert is not None, entry.name
        if Kind.SUBGOALS in entry.kinds:
            assert entry.feature_names() and entry.env is None
    assert resolve_env("blocks-place-3").feature_names()[:3] == ("red_x", "red_y", "red_z")
    assert resolve_env("safenav-car-goal").feature_names()[:2] == ("a_x", "a_y")


def test_strict_json_helpers():
    assert parse_env_kwargs(None) == {} and parse_env_kwargs({"a": 1}) == {"a": 1}
    with pytest.raises(DataError, match="NaN is not a JSON number"):
        parse_env_kwargs('{"a": NaN}')
    assert parse_feature_names(" x, y ") == ("x", "y")
    with pytest.raises(DataError, match="every name must be non-empty"):
        parse_feature_names("x,,y")


def test_a_careful_expert_is_recorded_on_a_users_environment(user_folder):
    from symlearn.data import record

    env = resolve_env("my_point_robot:PointRobot-v0").make()
    demos = record(env, careful_expert(), 3, seed=0)
    assert len(demos) == 3 and json.loads(json.dumps(demos.metadata))["env"] == "PointRobot-v0"


def test_widths_of_a_users_subclassed_spaces():
    """A user's own space classes derived from gymnasium's count as their bases (the class name
    was compared before, so a ``Box`` subclass of shape () had no width and a ``Discrete``
    subclass no default feature)."""
    import gymnasium

    from symlearn.recipes.environments import _feature_width, observation_width

    class Gauge(gymnasium.spaces.Box):
        pass

    class Dial(gymnasium.spaces.Discrete):
        pass

    class Env:
        observation_space = Gauge(low=0.0, high=1.0, shape=())

    assert observation_width(Env()) == 1 and _feature_width(Env()) == 1
    Env.observation_space = Dial(5)
    assert observation_width(Env()) is None and _feature_width(Env()) == 1
