"""The environment registry: one name per thing, every entry builds, every gymnasium id works."""

import json
import subprocess
import sys

import gymnasium
import pytest
from gymnasium.utils.env_checker import check_env

from cli_runner import run
from symlearn.envs import registry
from symlearn.envs.constraint_envs import CONSTRAINT_ENVS, constraint_setting
from symlearn.envs.gym_registration import register_gymnasium_envs
from symlearn.envs.logic_domains import DOMAIN_NAMES, logic_domain
from symlearn.envs.registry import ENTRIES, Entry, Factory, Kind
from symlearn.envs.spec_tasks import TASKS, get_task
from symlearn.errors import DataError, UnknownNameError
from symlearn.logic.ltlf import parse, propositions

GYM_IDS = sorted(registry.gym_entries())
# Environments built on an optional engine (the `highway` and `mujoco` extras): skipped where it is absent.
MUJOCO = ("blocked-half-cheetah", "blocked-ant", "blocked-walker2d", "blocked-swimmer", "biased-inverted-pendulum",
          "broken-ant")
DRIVING = ("driving", "driving-velocity", "driving-distance")
_ENGINES = {**{f"symlearn/{name}-v0": "highway" for name in DRIVING}, **{f"symlearn/{name}-v0": "mujoco" for name in MUJOCO}}


def _skip_without_engine(gym_id):
    from symlearn import optional

    engine = _ENGINES.get(gym_id)
    if engine and not optional.available(engine):
        pytest.skip(f"{gym_id} needs the optional engine {engine}")


def test_names_are_unique_and_the_agreed_ones():
    names = [e.name for e in ENTRIES]
    assert len(names) == len(set(names))
    safenav = [f"safenav-{agent}-{task}" for agent in ("point", "car") for task in ("goal", "push")]
    blocks = [f"blockworld-{t}" for t in ("stack2", "place2", "pyramid3", "stack3", "place3")]
    blocks += [f"blocks-place-{k}" for k in range(2, 7)] + [f"blocks-stack-{r}" for r in range(1, 5)]
    assert set(names) == {"hanoi", "junction-lights", "junction-priority", "junction-combined", "gridworld",
                          *(f"{world}-{i}" for world in ("office", "craft") for i in range(1, 5)),
                          "toy-navigation", *safenav, *DRIVING, "blocked-point", "point-circle", *MUJOCO, *blocks}
    assert GYM_IDS == sorted(f"symlearn/{n}-v0" for n in ("junction-lights", "junction-priority",
                                                          "junction-combined", "gridworld", "office", "craft",
                                                          "toy-navigation", *safenav, *DRIVING, "blocked-point",
                                                          "point-circle", *MUJOCO,
                                                          *(b for b in blocks if b.startswith("blockworld-"))))


def test_the_other_tables_are_views_of_the_registry():
    assert DOMAIN_NAMES == registry.names(Kind.RULES)
    assert list(TASKS) == list(registry.names(Kind.SPEC))
    assert list(CONSTRAINT_ENVS) == list(registry.names(Kind.CONSTRAINTS))
    for name, (domain, description) in CONSTRAINT_ENVS.items():
        entry = registry.get(name)
        assert domain == (name if Kind.RULES in entry.kinds else None) and description == entry.description


@pytest.mark.parametrize("name", registry.names(Kind.CONSTRAINTS))
def test_every_constraint_entry_builds_its_setting(name):
    setting = constraint_setting(name)
    assert setting.truth.any() and (setting.logic is not None) == (Kind.RULES in registry.get(name).kinds)


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_every_logic_domain_builds_under_its_own_name(name):
    domain = logic_domain(name)
    assert domain.name == name and domain.truth_path.is_file() and domain.pairs()


@pytest.mark.parametrize("name", registry.names(Kind.SPEC))
def test_every_spec_task_builds_and_its_formula_speaks_of_the_world(name):
    task = get_task(name)
    env = task.make_env()
    assert task.env_name == registry.get(name).gym_name
    assert set(propositions(parse(task.formula))) <= set(env.labeling.propositions)


@pytest.mark.parametrize("entry", [e for e in ENTRIES if e.env], ids=lambda e: e.name)
def test_every_entry_with_an_environment_builds_it(entry):
    _skip_without_engine(entry.gym_id)
    env = entry.make_env()
    assert env.reset(seed=0) is not None
    if Kind.CONTINUOUS in entry.kinds:  # continuous actions; the ground truth and features in info
        _, _, _, _, info = env.step(env.action_space.sample())
        assert info["cost"] in (0.0, 1.0) and len(info["features"]) == len(env.unwrapped.feature_names)
    elif Kind.MACHINE in entry.kinds:  # pick-and-place pixels of a top-down image
        observation, reward, *_ = env.step(env.action_space.sample())
        assert env.observation_space.contains(observation) and reward in (0.0, 1.0)
    else:
        assert env.action_space.n > 1


def test_hanoi_has_no_gymnasium_environment():
    with pytest.raises(DataError, match="hanoi has no gymnasium environment"):
        registry.get("hanoi").make_env()


@pytest.mark.parametrize("gym_id", GYM_IDS)
def test_every_gymnasium_id_makes_resets_and_steps(gym_id):
    _skip_without_engine(gym_id)
    env = gymnasium.make(gym_id)
    obs, info = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert env.observation_space.contains(obs) and isinstance(info, dict)
    assert env.spec.id == gym_id


# Text rendering ("ansi") has no frame rate, so gymnasium's render_fps warning does not apply; the
# MuJoCo robots keep gymnasium's own v5 spaces (unbounded observations, the pendulum's +-3 N force),
# which its checker advises against; every other warning of the checker fails the test.
@pytest.mark.filterwarnings("ignore:.*render fps")
@pytest.mark.filterwarnings("ignore:.*Box observation space (minimum|maximum) value is")
@pytest.mark.filterwarnings("ignore:.*we recommend using a symmetric and normalized space")
@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("gym_id", GYM_IDS)
def test_every_gymnasium_environment_passes_the_env_checker(gym_id):
    _skip_without_engine(gym_id)
    check_env(gymnasium.make(gym_id).unwrapped)


def test_gymnasium_kwargs_reach_the_environment():
    assert gymnasium.make("symlearn/gridworld-v0", stochasticity=0.2).unwrapped.stochasticity == 0.2
    assert gymnasium.make("symlearn/junction-priority-v0").unwrapped.variant == "priority"


def test_registering_twice_is_harmless():
    assert register_gymnasium_envs() == register_gymnasium_envs() == list(registry.gym_entries())


@pytest.mark.parametrize("code", [
    "import symlearn.envs, sys; assert 'gymnasium' not in sys.modules; import gymnasium",
    "import gymnasium, symlearn.envs",
    "import symlearn.envs.registry, gymnasium",
    "import symlearn.envs.junction_env, gymnasium",
])
def test_registered_whatever_the_import_order(code):
    done = subprocess.run([sys.executable, "-c", code + "; gymnasium.make('symlearn/office-v0').reset(seed=0)"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


def test_gymnasium_imports_symlearn_from_a_prefixed_id():
    code = "import gymnasium; gymnasium.make('symlearn.envs:symlearn/junction-lights-v0').reset(seed=0)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


# --- unknown names --------------------------------------------------------------------------------

@pytest.mark.parametrize("lookup, message", [
    (registry.get, "unknown environment 'junction-light'"),
    (logic_domain, "unknown logic domain 'junction-light'"),
    (get_task, "unknown environment/task 'junction-light'"),
    (constraint_setting, "unknown environment 'junction-light'"),
])
def test_unknown_names_raise_a_data_error_listing_the_known_ones(lookup, message):
    with pytest.raises(DataError, match=message) as info:
        lookup("junction-light")
    assert "junction-priority" in info.value.hint or "office-1" in info.value.hint


def test_the_hint_names_the_closest_name_first():
    with pytest.raises(UnknownNameError) as info:
        registry.get("junction-lite")
    assert info.value.hint.startswith("did you mean 'junction-lights'?")
    with pytest.raises(UnknownNameError) as info:  # the junction's former name points to the new one
        logic_domain("traffic-priority")
    assert info.value.hint.startswith("did you mean 'junction-priority'?")
    with pytest.raises(UnknownNameError, match="'gridworld' is no logic domain"):
        logic_domain("gridworld")


def test_names_are_case_insensitive():
    assert registry.get(" Junction-Lights ").name == "junction-lights"
    assert get_task("Office-3").name == "office-3"


def test_a_wrong_row_is_refused():
    with pytest.raises(ValueError, match="without a formula"):
        Entry("x", frozenset({Kind.SPEC}), "", ("spec",), "symlearn/x-v0", Factory("m:f"))
    with pytest.raises(ValueError, match="not 'symlearn/<name>-v<version>'"):
        Entry("x", frozenset({Kind.CONSTRAINTS}), "", ("ml",), "x-v0", Factory("m:f"))


# --- the command line -----------------------------------------------------------------------------

def test_the_cli_lists_every_entry_and_gymnasium_id(capsys):
    code, out, err = run(capsys, "envs", "--json")
    assert code == 0, err
    doc = json.loads(out)
    rows = doc["constraints"] + doc["specs"] + doc["continuous"] + doc["machines"] + doc["subgoals"]
    assert sorted(r["name"] for r in rows) == sorted(registry.names())
    assert {r["name"]: r["gym_id"] for r in rows} == {e.name: e.gym_id for e in ENTRIES}
    assert [r["id"] for r in doc["gymnasium"]] == list(registry.gym_entries())
    junction = next(r for r in doc["constraints"] if r["name"] == "junction-lights")
    assert junction["kinds"] == ["constraints", "rules"] and junction["methods"] == ["logic", "ml"]
    code, text, _ = run(capsys, "envs")
    assert code == 0 and all(name in text for name in registry.names()) and "symlearn/office-v0" in text
