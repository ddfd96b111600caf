"""The CLI on users' environments with less common spaces (``tests/support/space_envs.py``)."""

from __future__ import annotations

import json

import gymnasium
import numpy as np
import pytest
from cli_runner import run
from space_envs import (ENDLESS_LINE, FAULTY, GEARED_POINT, LAMP_COUNTER, MATRIX_POINT, OFFSET_WALK, ONE_GUESS,
                        SWITCH_BOARD)

from symlearn.data import record


def _walk(tmp_path, monkeypatch):
    (tmp_path / "offset_walk.py").write_text(OFFSET_WALK)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import offset_walk  # noqa: F401  (registers OffsetWalk-v0)

    # an expert that walks right but never onto the costly cell 5: ids from the spaces' own start
    record(gymnasium.make("OffsetWalk-v0"), lambda cell: 1 if cell < 4 else 0, 4, seed=0).save("walk.jsonl")


def test_learn_icrl_and_train_on_discrete_spaces_that_start_elsewhere(capsys, tmp_path, monkeypatch):
    """A rollout holds a Discrete observation one-hot and a Discrete action as its index; the cost
    reads the spaces' ids (from ``start``), as the demonstrations hold them."""
    _walk(tmp_path, monkeypatch)
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", "--env", "offset_walk:OffsetWalk-v0",
                         "--demos", "walk.jsonl", "--steps", 2048, "--iterations", 1, "-o", "walk.safetensors")
    assert code == 0, err
    assert json.loads(out)["violation_rate"] is not None
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "offset_walk:OffsetWalk-v0",
                         "--cost", "walk.safetensors", "--steps", 1024, "--eval-episodes", 2)
    assert code == 0, err


def test_sampled_discrete_actions_are_the_spaces_ids(tmp_path, monkeypatch):
    """Sampled episodes keep a Discrete action as the environment took it (``start`` added)."""
    from symlearn.rl.episodes import sample_episodes
    from symlearn.rl.ppo import ActorCritic

    _walk(tmp_path, monkeypatch)
    env = gymnasium.make("OffsetWalk-v0")
    policy = ActorCritic.for_spaces(env.observation_space, env.action_space)
    batch = sample_episodes(policy, lambda: gymnasium.make("OffsetWalk-v0"), 3, seed=0)
    taken = batch.actions[batch.mask]
    assert set(np.unique(taken)) <= {-1, 0, 1} and taken.min() == -1


def _switch_board(tmp_path, monkeypatch, kind):
    (tmp_path / "switch_board.py").write_text(SWITCH_BOARD)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import switch_board  # noqa: F401  (registers SwitchBoard-v0)

    env = gymnasium.make("SwitchBoard-v0", kind=kind)
    record(env, "random", 3, seed=0).save("board.npz")
    return json.dumps({"kind": kind})


@pytest.mark.parametrize("kind", ["multi", "binary"])
def test_our_ppo_acts_in_multidiscrete_and_multibinary_spaces(capsys, tmp_path, monkeypatch, kind):
    """train (ppo, ppo-lag on a DNF, sb3-dqn) and learn icrl act in one Discrete of the combinations;
    the demonstrations' recorded actions are read as its ids; a state cost trains sb3-ppo-lag as it is."""
    kwargs = _switch_board(tmp_path, monkeypatch, kind)
    env = ("--env", "switch_board:SwitchBoard-v0", "--env-kwargs", kwargs)
    small = ("--steps", 512, "--n-steps", 64, "--eval-episodes", 1)
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, *small, "-o", "agent.safetensors")
    assert code == 0, err
    assert json.loads(out)["cost"] is not None
    (tmp_path / "wall.dnf").write_text("x > 0.5\n")
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--cost", "wall.dnf", *small)
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--algo", "sb3-dqn", "--steps", 256,
                         "--eval-episodes", 1)
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", *env, "--demos", "board.npz",
                         "--steps", 1024, "--iterations", 1, "-o", "cost.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--algo", "sb3-ppo-lag",
                         "--cost", "cost.safetensors", "--steps", 256, "--eval-episodes", 1)
    assert code == 0, err


def test_joint_actions_refuse_too_many_combinations_with_the_way_out():
    from gymnasium import spaces

    from symlearn.errors import DataError
    from symlearn.recipes.action_spaces import JointDiscreteActions

    class Wide(gymnasium.Env):
        observation_space, action_space = spaces.Discrete(1), spaces.MultiBinary(20)

    with pytest.raises(DataError, match="1048576 combinations") as info:
        JointDiscreteActions(Wide())
    assert "sb3-ppo" in info.value.hint


def _guess(tmp_path, monkeypatch):
    (tmp_path / "one_guess.py").write_text(ONE_GUESS)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import one_guess  # noqa: F401  (registers OneGuess-v0)


@pytest.mark.filterwarnings("ignore:.*Casting input x to numpy array")
def test_a_scalar_observation_is_one_numbered_column(capsys, tmp_path, monkeypatch):
    """A Box of shape () is one column, x0, to learn dnf and to train --cost alike."""
    _guess(tmp_path, monkeypatch)
    record(gymnasium.make("OneGuess-v0"), "random", 6, seed=0).save("guess.npz")
    code, out, err = run(capsys, "--quiet", "learn", "dnf", "--env", "one_guess:OneGuess-v0", "--demos", "guess.npz",
                         "-o", "guess.dnf")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", "one_guess:OneGuess-v0", "--cost",
                         "guess.dnf", "--steps", 256, "--n-steps", 32, "--eval-episodes", 1)
    assert code == 0, err
    assert json.loads(out)["cost_kind"] == "dnf"


@pytest.mark.filterwarnings("ignore:.*Casting input x to numpy array")
@pytest.mark.parametrize("env_id, algos", [("offset_walk:OffsetWalk-v0", ("sb3-ppo", "sb3-ppo-lag", "sb3-dqn")),
                                           ("one_guess:OneGuess-v0", ("sb3-ppo", "sb3-sac-lag"))])
def test_stable_baselines3_on_discrete_spaces_from_another_start_and_scalar_observations(
        capsys, tmp_path, monkeypatch, env_id, algos):
    """stable-baselines3 numbers Discrete spaces from 0 and flattens observations from their second
    dimension; train shows it such spaces as it reads them, and evaluates in the environment's own."""
    pytest.importorskip("stable_baselines3")
    _walk(tmp_path, monkeypatch)
    _guess(tmp_path, monkeypatch)
    for algo in algos:
        code, out, err = run(capsys, "--json", "--quiet", "train", "--env", env_id, "--algo", algo,
                             "--steps", 128, "--n-steps", 32, "--eval-episodes", 1, "-o", f"{algo}.safetensors")
        assert code == 0, (algo, err)
        assert json.loads(out)["cost"] is not None


def test_stable_baselines3_multibinary_actions_reach_the_environment_as_integers(capsys, tmp_path, monkeypatch):
    """SB3 samples MultiBinary actions as floats; train and data record give the environment the
    space's own integers (a float action made its integer counters floats)."""
    pytest.importorskip("stable_baselines3")
    (tmp_path / "lamp_counter.py").write_text(LAMP_COUNTER)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    env = ("--env", "lamp_counter:LampCounter-v0")
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--algo", "sb3-ppo", "--steps", 128,
                         "--n-steps", 32, "--eval-episodes", 1, "-o", "agent.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--quiet", "data", "record", *env, "--policy", "agent.safetensors",
                         "--episodes", 1, "-o", "lamps.npz")
    assert code == 0, err
    from symlearn.data import load

    assert load(tmp_path / "lamps.npz")[0].actions.dtype.kind in "biu"


def test_learn_dnf_on_discrete_states_names_the_ways_out_of_the_cli(capsys, tmp_path, monkeypatch):
    """Without ``--env`` nothing says the ids are one Discrete observation's: refused, naming the ways
    out. (With the ``--env`` of a Discrete observation they are learned as one column, the id, as
    ``train --cost`` reads it: tests/cli/test_user_env_sweep_round4.py.)"""
    _walk(tmp_path, monkeypatch)
    code, out, err = run(capsys, "learn", "dnf", "--demos", "walk.jsonl")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "walk.jsonl" in err and "--domain" in err and "--env" in err and "FeatureMap" not in err
    code, out, err = run(capsys, "learn", "dnf", "--env", "offset_walk:OffsetWalk-v0", "--demos", "walk.jsonl")
    assert code == 0, err


@pytest.mark.parametrize("env_id", ["geared_point:GearedPoint-v0", "Blackjack-v1"])
def test_learn_icrl_reads_recorded_dict_and_tuple_observations_with_discrete_parts(
        capsys, tmp_path, monkeypatch, env_id):
    """record() keeps a Discrete part as one integer column; the policy's view one-hots it: the
    demonstrations are rebuilt and seen through the view (a Dict of a vector and a gear, and
    gymnasium's Blackjack, a Tuple of three Discrete)."""
    (tmp_path / "geared_point.py").write_text(GEARED_POINT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import geared_point  # noqa: F401  (registers GearedPoint-v0)

    record(gymnasium.make(env_id.split(":")[-1]), "random", 3, seed=0).save("demos.npz")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", "--env", env_id, "--demos", "demos.npz",
                         "--steps", 1024, "--iterations", 1, "-o", "cost.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", "--env", env_id, "--cost", "cost.safetensors",
                         "--steps", 256, "--n-steps", 32, "--eval-episodes", 1)
    assert code == 0, err


def test_record_columns_rebuild_the_observation():
    from gymnasium import spaces

    from symlearn.data.flat_observations import observation_columns
    from symlearn.recipes.spaces import from_record_columns, record_columns_width

    space = spaces.Dict({"pos": spaces.Box(-1, 1, (2,)), "gear": spaces.Discrete(3),
                         "arm": spaces.Tuple((spaces.Discrete(2), spaces.Box(0, 1, (), np.float64)))})
    value = space.sample()
    row, names = observation_columns(value)
    assert record_columns_width(space) == len(row) == 5
    rebuilt = from_record_columns(space, row)
    assert space.contains(rebuilt)
    assert np.allclose(spaces.flatten(space, rebuilt), spaces.flatten(space, value))


def test_learn_spec_acts_in_a_discrete_space_from_another_start(capsys, tmp_path, monkeypatch):
    """The tabular update's Q-table columns are 0..n-1; the environment takes start + column."""
    _walk(tmp_path, monkeypatch)
    (tmp_path / "walk_labels.py").write_text("def label(cell, info):\n    return ['end'] if cell == 9 else []\n")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", "--env", "offset_walk:OffsetWalk-v0",
                         "--demos", "walk.jsonl", "--labeling", "walk_labels.py:label", "--q-steps", 500,
                         "--max-iterations", 1)
    assert code == 0, err
    assert json.loads(out)["policy_update"] == "tabular"


def test_learn_spec_with_an_inline_feature_labeling_and_multidiscrete_actions(capsys, tmp_path, monkeypatch):
    """An inline {proposition: condition} reads the environment's feature_names (as a labeling
    file does); the policy acts in the combinations of a MultiDiscrete space, and demonstrations
    replayed for a labeling that reads info map their recorded actions to those ids."""
    kwargs = _switch_board(tmp_path, monkeypatch, "multi")
    env = ("--env", "switch_board:SwitchBoard-v0", "--env-kwargs", kwargs)
    common = ("--demos", "board.npz", "--ppo-steps", 256, "--max-iterations", 1)
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", *env, "--labeling", '{"right": "x > 0.1"}',
                         *common)
    assert code == 0, err
    assert list(json.loads(out)["propositions"]) == ["right"]
    (tmp_path / "board_labels.py").write_text("def label(observation, info):\n"
                                              "    return ['wall'] if info.get('cost') else []\n")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "spec", *env, "--labeling", "board_labels.py:label",
                         *common)
    assert code == 0, err


def test_learn_icrl_cuts_an_endless_environment_at_the_demonstrations_length(capsys, tmp_path, monkeypatch):
    """Without a time limit, sampled episodes would run to the sampler's cap (10,000 steps)
    against demonstrations record() cut at 30: they are cut where the demonstrations were."""
    (tmp_path / "endless_line.py").write_text(ENDLESS_LINE)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import endless_line  # noqa: F401  (registers EndlessLine-v0)

    record(gymnasium.make("EndlessLine-v0"), lambda x: int(x[0] < 0.4), 3, seed=0, max_steps=30).save("line.npz")
    code, out, err = run(capsys, "--json", "learn", "icrl", "--env", "endless_line:EndlessLine-v0",
                         "--demos", "line.npz", "--steps", 512, "--iterations", 1)
    assert code == 0, err
    assert "cut at 30 steps" in err
    doc = json.loads(out)
    assert abs(doc["reward"]) <= 30 and abs(doc["history"][0]["reward"]) <= 30   # at most 1 per step, 30 steps


def test_learn_icrl_says_nothing_of_a_time_limit_the_environment_keeps_itself(capsys, tmp_path, monkeypatch):
    """An environment that truncates its episodes at 30 by itself (none registered) is not said
    to be cut at 30 steps by symlearn: its demonstrations' replay ends there on its own."""
    (tmp_path / "endless_line.py").write_text(ENDLESS_LINE)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import endless_line  # noqa: F401  (registers EndlessLine-v0)

    record(gymnasium.make("EndlessLine-v0", horizon=30), lambda x: int(x[0] < 0.4), 3, seed=0).save("line.npz")
    code, out, err = run(capsys, "--json", "learn", "icrl", "--env", "endless_line:EndlessLine-v0",
                         "--env-kwargs", '{"horizon": 30}', "--demos", "line.npz", "--steps", 512, "--iterations", 1)
    assert code == 0, err
    assert "time limit" not in err and "cut at" not in err


def test_learn_icrl_on_part_of_a_dict_observation_says_how_to_record_the_view(capsys, tmp_path, monkeypatch):
    (tmp_path / "geared_point.py").write_text(GEARED_POINT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import geared_point  # noqa: F401

    env = gymnasium.make("GearedPoint-v0")
    record(env, "random", 2, seed=0, observation=lambda o: o["pos"]).save("part.npz")
    code, out, err = run(capsys, "learn", "icrl", "--env", "geared_point:GearedPoint-v0", "--demos", "part.npz",
                         "--steps", 256, "--iterations", 1)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "part.npz" in err and "Dict of gear, pos" in err and "numeric_observations(env)" in err

    from symlearn.recipes.spaces import numeric_observations

    record(numeric_observations(env), "random", 2, seed=0).save("view.npz")
    code, out, err = run(capsys, "--quiet", "learn", "icrl", "--env", "geared_point:GearedPoint-v0",
                         "--demos", "view.npz", "--steps", 256, "--iterations", 1)
    assert code == 0, err


def test_a_formula_over_more_columns_than_the_unnamed_features_says_what_it_reads(capsys, tmp_path, monkeypatch):
    """x0..x3 learned from a 4-entry observation, while the environment reports 2 unnamed
    info["features"]: the error names both, not only "names no features"."""
    _switch_board(tmp_path, monkeypatch, "multi")
    (tmp_path / "plain_board.py").write_text(SWITCH_BOARD.replace('    feature_names = ("x", "y")\n', "").replace(
        "SwitchBoard-v0", "PlainBoard-v0").replace("return self.p.astype(np.float32), {}",
                                                   'return self.p.astype(np.float32), {"features": self.p.copy()}'
                                                   ).replace('{"cost": float(self.p[0] > 0.5)}',
                                                  '{"cost": float(self.p[0] > 0.5), "features": self.p.copy()}'))
    import plain_board  # noqa: F401

    (tmp_path / "wide.dnf").write_text("x3 > 0.5\n")
    code, out, err = run(capsys, "train", "--env", "plain_board:PlainBoard-v0", "--cost", "wide.dnf", "--steps", 64)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "formula reads x3" in err and 'info["features"] has 2 unnamed column(s), read as x0, x1' in err


@pytest.mark.parametrize("algo", ["ppo", "sb3-ppo"])
def test_a_failing_or_blind_environment_is_one_line_not_an_internal_error(capsys, tmp_path, monkeypatch, algo):
    """An exception in the user's step names their file and line; a NaN observation is refused
    at its step (our PPO would train on it, stable-baselines3 fail inside torch)."""
    if algo.startswith("sb3"):
        pytest.importorskip("stable_baselines3")
    (tmp_path / "faulty.py").write_text(FAULTY)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    small = ("--algo", algo, "--steps", 128, "--n-steps", 32, "--eval-episodes", 1)
    code, out, err = run(capsys, "train", "--env", "faulty:FaultyMotor-v0", *small)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "faulty.py:" in err and "RuntimeError: motor fault" in err
    code, out, err = run(capsys, "train", "--env", "faulty:BlindSensor-v0", *small)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "not finite" in err


def test_a_matrix_observation_learns_dnf_and_icrl_costs_that_train(capsys, tmp_path, monkeypatch):
    """A ``(2, 3)`` Box observation (stored as a multi-dimensional state) is its six entries,
    x0..x5 in row-major order: learn dnf reads them as train --cost does, and a learned neural
    cost gets the rollout's flattened rows back in the space's shape."""
    (tmp_path / "matrix_point.py").write_text(MATRIX_POINT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import matrix_point  # noqa: F401  (registers MatrixPoint-v0)

    record(gymnasium.make("MatrixPoint-v0"), "random", 3, seed=0).save("matrix.npz")
    env = ("--env", "matrix_point:MatrixPoint-v0")
    code, out, err = run(capsys, "--json", "--quiet", "learn", "dnf", *env, "--demos", "matrix.npz",
                         "-o", "matrix.dnf")
    assert code == 0, err
    assert json.loads(out)["features"] == [f"x{i}" for i in range(6)]
    small = ("--steps", 256, "--n-steps", 32, "--eval-episodes", 1)
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--cost", "matrix.dnf", *small)
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "learn", "icrl", *env, "--demos", "matrix.npz",
                         "--steps", 512, "--iterations", 1, "-o", "matrix.safetensors")
    assert code == 0, err
    code, out, err = run(capsys, "--json", "--quiet", "train", *env, "--cost", "matrix.safetensors", *small)
    assert code == 0, err
