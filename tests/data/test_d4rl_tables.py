"""D4RL transition tables: split into episodes at terminals | timeouts, written and read back exactly."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from symlearn.data import Demonstrations, Trajectory, load
from symlearn.data.d4rl_format import HEADER, to_table
from symlearn.data.files import detect
from symlearn.errors import DataError, LimitExceededError

from demo_strategies import PROPS, finite, info_dicts, state_columns

h5py = pytest.importorskip("h5py")
ROUND_TRIP = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@st.composite
def transition_demos(draw):
    """Demonstrations a D4RL table can hold: array states, array actions in every trajectory, the
    final state everywhere or nowhere."""
    state_kind = draw(st.sampled_from(["discrete", "vector", "image"]))
    shape = {"discrete": None, "vector": draw(st.sampled_from([(), (3,)])), "image": (2, 2, 3)}[state_kind]
    dtype = {"discrete": None, "vector": draw(st.sampled_from([np.float32, np.float64, np.int64])),
             "image": np.uint8}[state_kind]
    action_kind = draw(st.sampled_from(["discrete", "vector"]))
    closing = draw(st.sampled_from([0, 1]))  # states beyond the last action
    with_rewards, with_labels = draw(st.booleans()), draw(st.booleans())
    trajectories = []
    for _ in range(draw(st.integers(1, 4))):
        n_actions = draw(st.integers(1, 5))
        n = n_actions + closing
        states = draw(state_columns(state_kind, n, shape, dtype))
        if action_kind == "vector":
            actions = draw(hnp.arrays(np.float64, (n_actions, 2), elements=finite))
        else:
            actions = draw(st.lists(st.integers(0, 5), min_size=n_actions, max_size=n_actions))
        rewards = draw(st.lists(finite, min_size=n_actions, max_size=n_actions)) if with_rewards else None
        labels = draw(st.lists(st.frozensets(PROPS, max_size=3), min_size=n, max_size=n)) if with_labels else None
        info = draw(info_dicts) | draw(st.fixed_dictionaries({}, optional={"terminated": st.booleans(),
                                                                           "partial": st.booleans()}))
        trajectories.append(Trajectory(states, actions, rewards, labels, info))
    return Demonstrations(trajectories, metadata=draw(info_dicts))


@ROUND_TRIP
@given(transition_demos(), st.sampled_from(["t.hdf5", "t.h5", "t.npz"]))
def test_round_trip_through_a_d4rl_table_is_exact(tmp_path, demos, name):
    path = tmp_path / name
    demos.save(path, format="d4rl")
    assert detect(path) == ("d4rl-npz" if name.endswith(".npz") else "d4rl-hdf5")
    assert load(path) == demos


def _table(**columns):
    n = len(columns["observations"])
    columns.setdefault("actions", np.arange(n) % 3)
    columns.setdefault("rewards", np.linspace(0, 1, n, dtype=np.float32))
    return columns


def _write(tmp_path, name, columns):
    path = tmp_path / name
    if name.endswith(".npz"):
        np.savez(path, **columns)
    else:
        with h5py.File(path, "w") as handle:
            for key, value in columns.items():
                handle[key] = value
            handle["infos/qpos"] = np.zeros((len(columns["observations"]), 3))
            handle["metadata/algorithm"] = "SAC"  # a string D4RL keeps beside the arrays: not read
    return path


@pytest.mark.parametrize("name", ["plain.hdf5", "plain.npz"])
def test_episodes_split_at_terminals_and_timeouts_the_rest_flagged_partial(tmp_path, name):
    observations = np.arange(20, dtype=np.float32).reshape(10, 2)
    terminals = np.zeros(10, dtype=bool)
    timeouts = np.zeros(10, dtype=bool)
    terminals[2], timeouts[5], terminals[7] = True, True, True  # rows 8, 9: an episode the file cut
    demos = load(_write(tmp_path, name, _table(observations=observations, terminals=terminals, timeouts=timeouts,
                                               next_observations=observations + 100)))
    assert [len(t) for t in demos] == [4, 4, 3, 3]  # rows + the closing next observation
    assert [t.n_actions for t in demos] == [3, 3, 2, 2]
    assert [t.info for t in demos] == [{"terminated": True, "truncated": False},
                                       {"terminated": False, "truncated": True},
                                       {"terminated": True, "truncated": False},
                                       {"terminated": False, "truncated": True, "partial": True}]
    np.testing.assert_array_equal(demos[1].states, np.vstack([observations[3:6], observations[5] + 100]))
    assert demos[0].states.dtype == np.float32 and demos[0].rewards.dtype == np.float64
    assert demos.metadata == {"source_format": "d4rl"}
    # without next_observations an episode is its rows, with an action in every state
    demos = load(_write(tmp_path, name, _table(observations=observations, terminals=terminals.astype(np.float32))))
    assert [len(t) for t in demos] == [3, 5, 2]  # no timeouts column: 3..7 is one episode
    assert all(t.n_actions == len(t) for t in demos)
    # writing back what was read keeps the episode ends
    demos.save(tmp_path / "again.hdf5")
    assert [t.info for t in load(tmp_path / "again.hdf5")] == [t.info for t in demos]


def test_header_less_table_matches_what_was_written(tmp_path):
    demos = Demonstrations([Trajectory(np.eye(4)[:k + 1], np.arange(k) % 2, np.ones(k),
                                       info={"terminated": k % 2 == 0, "truncated": k % 2 == 1}) for k in (1, 2, 3)])
    arrays = to_table(demos)
    del arrays[HEADER]
    np.savez(tmp_path / "bare.npz", **arrays)
    again = load(tmp_path / "bare.npz")
    assert list(again) == list(demos) and again.metadata == {"source_format": "d4rl"}


def test_what_a_d4rl_table_cannot_hold_is_refused(tmp_path):
    symbols = Demonstrations([Trajectory(["a", "b"], [0])])
    with pytest.raises(DataError, match="array observations"):
        symbols.save(tmp_path / "s.hdf5")
    with pytest.raises(DataError, match="no actions"):
        Demonstrations([Trajectory([0, 1])]).save(tmp_path / "s.hdf5")
    with pytest.raises(DataError, match="final state and some do not"):
        Demonstrations([Trajectory([0, 1], [0]), Trajectory([0, 1], [0, 1])]).save(tmp_path / "s.hdf5")
    with pytest.raises(DataError, match="trajectory 1 has no action"):
        Demonstrations([Trajectory([0, 1], [0]), Trajectory([0], [])]).save(tmp_path / "s.npz", format="d4rl")
    with pytest.raises(DataError, match="a D4RL table is an .npz or .hdf5"):
        symbols.save(tmp_path / "s.jsonl", format="d4rl")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("name", ["bad.hdf5", "bad.npz"])
@pytest.mark.parametrize("change, message", [
    (lambda c: c.pop("terminals"), "has no 'terminals': not a D4RL table"),
    (lambda c: c.update(actions=c["actions"][:-1]), "'actions' has 5 rows, 'observations' has 6"),
    (lambda c: c.update(terminals=np.array([0, 0, 2, 0, 0, 1])), "'terminals' row 2 is 2"),
    (lambda c: c.update(rewards=np.zeros((6, 2))), r"'rewards' has shape \(6, 2\)"),
    (lambda c: c.update(next_observations=np.zeros((6, 3))), "'next_observations' has shape"),
    (lambda c: c.update(observations=np.full((6, 2), np.nan)), r"episode 0 \(rows 0..5\): states hold a non-finite"),
])
def test_malformed_tables_name_the_file(tmp_path, name, change, message):
    columns = _table(observations=np.zeros((6, 2)), terminals=np.eye(6, dtype=bool)[5])
    change(columns)
    with pytest.raises(DataError, match=f"{name}: {message}"):
        load(_write(tmp_path, name, columns))


def test_hdf5_strings_objects_and_huge_declarations_are_refused_before_reading(tmp_path, monkeypatch):
    path = tmp_path / "t.hdf5"
    with h5py.File(path, "w") as handle:
        handle["observations"] = np.zeros((3, 2))
        handle["actions"] = np.array(["up", "up", "down"], dtype=h5py.string_dtype())
        handle["terminals"] = np.array([0, 0, 1], dtype=bool)
    with pytest.raises(DataError, match="'/actions' has dtype .*no strings, variable-length or object"):
        load(path)
    with h5py.File(path, "w") as handle:
        handle.create_dataset("observations", shape=(2**32, 4), dtype="f8", chunks=(1024, 4))  # nothing written
        handle["actions"] = np.zeros(3)
        handle["terminals"] = np.zeros(3, dtype=bool)
    with pytest.raises(LimitExceededError, match=r"declared size \(dataset '/observations'.*128 GB"):
        load(path)
    with h5py.File(path, "w") as handle:
        handle["observations"] = np.zeros((3, 2))
        handle["actions"] = h5py.ExternalLink("/etc/elsewhere.h5", "/actions")
        handle["terminals"] = np.zeros(3, dtype=bool)
    with pytest.raises(DataError, match="'/actions' is a link to another file"):
        load(path)
    np.savez(tmp_path / "o.npz", observations=np.array([object()] * 3), actions=np.zeros(3), terminals=np.ones(3))
    with pytest.raises(DataError, match="member 'observations' has dtype"):
        load(tmp_path / "o.npz")


def test_a_hand_edited_header_is_caught(tmp_path):
    demos = Demonstrations([Trajectory([0, 1], [0]), Trajectory([2, 3], [1])])
    arrays = to_table(demos)
    arrays["timeouts"][:] = False  # the two episodes now run together
    np.savez(tmp_path / "e.npz", **arrays)
    with pytest.raises(DataError, match="2 trajectories described, the rows hold 1"):
        load(tmp_path / "e.npz")
    arrays = to_table(demos)
    arrays[HEADER] = np.frombuffer(json.dumps({"symlearn": "other"}).encode(), dtype=np.uint8)
    np.savez(tmp_path / "h.npz", **arrays)
    with pytest.raises(DataError, match="not a symlearn D4RL header"):
        load(tmp_path / "h.npz")


def test_cli_converts_to_and_from_d4rl(tmp_path, run_cli):
    demos = Demonstrations([Trajectory(np.eye(4)[:3], [1, 0], [0.5, 1.0], [[], ["a"], ["a", "b"]], {"seed": 1})],
                           metadata={"env": "x"})
    demos.save(tmp_path / "d.npz")
    for args in (("d.npz", "t.npz", "--to", "d4rl"), ("t.npz", "t.hdf5"), ("t.hdf5", "back.jsonl")):
        done = run_cli("data", "convert", *args, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
    assert detect(tmp_path / "t.npz") == "d4rl-npz"
    assert load(tmp_path / "back.jsonl") == demos
    done = run_cli("data", "info", "t.hdf5", cwd=tmp_path)
    assert done.returncode == 0 and "t.hdf5 (d4rl-hdf5): 1 trajectories, 3 steps" in done.stdout
    (tmp_path / "junk.hdf5").write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 40)
    done = run_cli("data", "validate", "junk.hdf5", cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "junk.hdf5: not a readable HDF5 file" in done.stderr


def test_an_hdf5_bomb_is_refused_in_one_line_without_reading(tmp_path):
    """4 GB declared in a file of a few KB; with the size limit lifted, the row counts still stop
    it before a byte is read (the child stays far below the 4 GB)."""
    from hostile import check

    with h5py.File(tmp_path / "bomb.hdf5", "w") as handle:
        handle.create_dataset("observations", shape=(2**29,), dtype="f8", chunks=(2**16,), compression="gzip")
        handle["actions"] = np.zeros(3)
        handle["terminals"] = np.zeros(3, dtype=bool)
    assert (tmp_path / "bomb.hdf5").stat().st_size < 100_000
    check(["data", "info", "bomb.hdf5"], cwd=tmp_path, timeout=60, memory_mb=1024, names="bomb.hdf5",
          contains=["SYMLEARN_MAX_ARRAY_MB", "4 GB"])
    result = check(["data", "convert", "bomb.hdf5", "out.npz"], cwd=tmp_path, timeout=60, memory_mb=1024,
                   env={"SYMLEARN_MAX_ARRAY_MB": "0"}, names="bomb.hdf5", contains="'actions' has 3 rows",
                   outputs=[tmp_path / "out.npz"])
    assert result.max_rss_mb < 400


def test_mutated_tables_and_minari_files_never_crash_the_reader(tmp_path):
    """300 seeded mutants of a D4RL HDF5 table, a D4RL NPZ table and a Minari-shaped HDF5 file
    (bytes flipped, inserted, deleted, truncated; NPZ members rewritten), read in a child with
    1 GB: each is read or refused with a SymlearnError, nothing else."""
    from hostile import run_python

    code = f"""
import json, random
from pathlib import Path
import h5py, numpy as np
from fuzz_inputs import TEXT_MUTATIONS, npz_mutants
from symlearn.data import Demonstrations, Trajectory, load
from symlearn.errors import SymlearnError

folder = Path({str(tmp_path)!r})
demos = Demonstrations([Trajectory(np.arange(8.0).reshape(4, 2), [0, 1, 0], [1.0, 0.0, 2.0], info={{"terminated": True}}),
                        Trajectory(np.ones((3, 2)), [1, 1], [0.5, 0.5], labels=None)], metadata={{"env": "x"}})
demos.save(folder / "t.hdf5")
demos.save(folder / "t.npz", format="d4rl")
with h5py.File(folder / "main_data.hdf5", "w") as handle:
    for i, t in enumerate(demos):
        handle[f"episode_{{i}}/observations"] = t.states
        handle[f"episode_{{i}}/actions"] = t.actions
        handle[f"episode_{{i}}/rewards"] = t.rewards
        handle[f"episode_{{i}}/terminations"] = np.eye(t.n_actions, dtype=bool)[-1]
        handle[f"episode_{{i}}/truncations"] = np.zeros(t.n_actions, dtype=bool)
        handle[f"episode_{{i}}"].attrs["seed"] = i
assert len(load(folder / "main_data.hdf5")) == 2
rng = random.Random(7)
seeds = [(name, (folder / name).read_bytes()) for name in ("t.hdf5", "t.npz", "main_data.hdf5")]
crashes, outcomes = [], {{"read": 0, "refused": 0}}
for i in range(300):
    name, data = seeds[i % 3]
    if name.endswith(".npz") and rng.random() < 0.7:
        mutation, mutated = npz_mutants(data, rng)
    else:
        mutation = rng.choice(["flip", "flip", "insert", "delete", "truncate"])
        mutated = TEXT_MUTATIONS[mutation](data, rng)
    target = folder / "work" / str(i) / name
    target.parent.mkdir(parents=True)
    target.write_bytes(mutated)
    try:
        load(target)
        outcomes["read"] += 1
    except SymlearnError:
        outcomes["refused"] += 1
    except Exception as exc:
        crashes.append([name, mutation, f"{{type(exc).__name__}}: {{exc}}"])
print(json.dumps({{"crashes": crashes, "outcomes": outcomes}}))
"""
    result = run_python(code, cwd=tmp_path, timeout=120, memory_mb=1024)
    assert result.returncode == 0, result.describe()
    report = json.loads(result.stdout.strip().splitlines()[-1])
    assert not report["crashes"], json.dumps(report["crashes"], indent=1)
    assert report["outcomes"]["refused"] > 50
