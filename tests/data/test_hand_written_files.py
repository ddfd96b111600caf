"""Demonstration files written by other tools (plain numpy, json, h5py), as docs/FORMATS.md
describes them, read back with nothing dropped, truncated or wrapped."""

import json

import numpy as np
import pytest

from symlearn.data import Trajectory, load
from symlearn.errors import DataError
from tests.support.cli_runner import run


def header(**fields):
    return json.dumps({"symlearn": "demonstrations", "format_version": 1, **fields})


def test_jsonl_float32_column_written_as_short_decimals_reads_back_exactly(tmp_path):
    # numpy prints float32 0.1 as "0.1": its nearest float32 is the value that was written
    states = np.random.default_rng(0).normal(size=(4, 2)).astype(np.float32)
    rows = [[float(str(x)) for x in row] for row in states]
    path = tmp_path / "f32.jsonl"
    path.write_text(header(state_kind="vector", state_dtype="float32") + "\n" + json.dumps({"states": rows}) + "\n")
    got = load(path)[0].states
    assert got.dtype == np.float32 and np.array_equal(got, states)


@pytest.mark.parametrize("dtype, values", [("float32", [[1e39]]), ("float16", [[70000.0]]), ("int8", [300]),
                                           ("int64", [[0.5]])])
def test_jsonl_values_beyond_the_declared_dtype_are_refused(tmp_path, dtype, values):
    kind = "vector" if isinstance(values[0], list) else "discrete"
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind=kind, state_dtype=dtype) + "\n" + json.dumps({"states": values}) + "\n")
    with pytest.raises(DataError, match=f"do not fit the header dtype {dtype}") as info:
        load(path)
    assert "d.jsonl:2:" in str(info.value)


def test_jsonl_without_dtype_gives_whole_number_lines_the_common_dtype(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="vector") + "\n" + json.dumps({"states": [[0, 1], [1, 2]]}) + "\n"
                    + json.dumps({"states": [[0.5, 1], [1, 2]]}) + "\n")
    demos = load(path)
    assert [t.states.dtype for t in demos] == [np.float64, np.float64]
    assert demos[0].states.tolist() == [[0.0, 1.0], [1.0, 2.0]]


def test_jsonl_disagreeing_trajectories_name_the_line(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="discrete", action_kind="discrete") + "\n\n"
                    + json.dumps({"states": [0, 1], "actions": [1]}) + "\n"
                    + json.dumps({"states": [0, 3], "actions": [2], "rewards": [1]}) + "\n")
    with pytest.raises(DataError, match="trajectory 1 has rewards") as info:
        load(path)
    assert str(info.value).startswith(f"{path}:4:")


def test_jsonl_flat_integers_under_a_vector_header_get_a_hint(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="vector", state_dtype="int64") + "\n" + json.dumps({"states": [1, 2]}) + "\n")
    with pytest.raises(DataError, match="header says vector") as info:
        load(path)
    assert "state_kind discrete" in info.value.hint


def test_jsonl_crlf_bom_unicode_and_no_final_newline(tmp_path):
    lines = [header(state_kind="features", action_kind="symbol", metadata={"source": "mon outil"}),
             json.dumps({"states": [{"x": 0.5, "porte": True}, {"x": 1e300, "porte": False}],
                         "actions": ["droite→"], "labels": [[], ["été"]], "info": {"ü": None}}, ensure_ascii=False)]
    path = tmp_path / "d.jsonl"
    path.write_bytes(("\ufeff" + "\r\n".join(lines)).encode("utf-8"))
    (t,) = load(path)
    assert t.states[1] == {"x": 1e300, "porte": False} and t.actions == ("droite→",)
    assert t.labels[1] == {"été"} and t.info == {"ü": None}


def test_uint64_ids_beyond_int64_are_refused_not_wrapped():
    with pytest.raises(DataError, match="beyond int64"):
        Trajectory(np.array([2**63 + 5, 3], dtype=np.uint64))
    with pytest.raises(DataError, match="beyond int64"):
        Trajectory([2**63])
    assert Trajectory(np.array([2**63 - 1], dtype=np.uint64)).states.tolist() == [2**63 - 1]


def npz(path, meta, **arrays):
    np.savez(path, __meta__=json.dumps({"symlearn": "demonstrations", "format_version": 1, **meta}), **arrays)
    return path


def test_npz_without_flags_keeps_its_actions_and_rewards(tmp_path):
    # the flags are a writer's detail: a hand-written __meta__ without them must not drop the columns
    states = np.arange(20, dtype=np.float32).reshape(10, 2)
    actions = np.linspace(0, 1, 8).reshape(8, 1)
    path = npz(tmp_path / "d.npz", {"state_kind": "vector", "action_kind": "vector"}, lengths=np.array([4, 6]),
               states=states, actions=actions, action_lengths=np.array([3, 5]), rewards=np.ones(8, np.float32))
    demos = load(path)
    assert demos.has_actions and demos.has_rewards
    assert np.array_equal(demos[1].actions, actions[3:]) and demos[1].rewards.tolist() == [1.0] * 5
    assert demos[0].info == {}  # no 'info' member: every trajectory's info is empty


def test_npz_action_lengths_and_kinds_may_be_left_out(tmp_path):
    path = npz(tmp_path / "d.npz", {}, lengths=np.array([3, 2]), states=np.arange(10.0).reshape(5, 2),
               actions=np.array([0, 1, 0, 1, 1]), label_names=np.array(["a"]),
               labels=np.array([[1], [0], [0], [1], [1]], dtype=np.uint8))
    demos = load(path)
    assert [t.n_actions for t in demos] == [3, 2] and demos.action_kind == "discrete"
    assert demos[1].labels == (frozenset({"a"}), frozenset({"a"}))
    path = npz(tmp_path / "e.npz", {}, lengths=np.array([3, 2]), states=np.array(list("abcde")),
               actions=np.array(["x", "y", "z"]))
    demos = load(path)
    assert demos.state_kind == "symbol" and [t.actions for t in demos] == [("x", "y"), ("z",)]


def test_npz_flag_false_with_its_member_or_actions_of_no_length_are_refused(tmp_path):
    states = np.arange(10.0).reshape(5, 2)
    path = npz(tmp_path / "d.npz", {"has_actions": False}, lengths=np.array([3, 2]), states=states,
               actions=np.zeros(5))
    with pytest.raises(DataError, match="has_actions is false but the archive holds 'actions'"):
        load(path)
    path = npz(tmp_path / "e.npz", {}, lengths=np.array([3, 2]), states=states, actions=np.zeros(4))
    with pytest.raises(DataError, match="4 rows: neither one per state"):
        load(path)


def test_npz_without_meta_says_what_it_could_be(tmp_path):
    path = tmp_path / "d.npz"
    np.savez(path, lengths=np.array([2]), states=np.zeros((2, 2)))
    with pytest.raises(DataError, match="lacks member '__meta__'") as info:
        load(path)
    assert "frame archive" in info.value.hint


def test_d4rl_columns_stored_as_n_by_1(tmp_path):
    h5py = pytest.importorskip("h5py")
    terminals = np.zeros((6, 1), np.float32)
    terminals[2] = 1
    path = tmp_path / "t.hdf5"
    with h5py.File(path, "w") as f:
        f["observations"] = np.arange(12, dtype=np.float32).reshape(6, 2)
        f["actions"] = np.zeros((6, 1), np.float32)
        f["rewards"] = np.arange(6, dtype=np.float32)[:, None]
        f["terminals"] = terminals
        f["timeouts"] = np.eye(6, dtype=bool)[5][:, None]
    demos = load(path)
    assert [len(t) for t in demos] == [3, 3]
    assert demos[1].rewards.tolist() == [3.0, 4.0, 5.0] and demos[0].info["terminated"] is True


def test_cli_reads_a_hand_written_npz_with_its_actions(tmp_path, capsys):
    path = npz(tmp_path / "d.npz", {"state_kind": "vector"}, lengths=np.array([3]),
               states=np.zeros((3, 2)), actions=np.array([1, 0]))
    code, out, err = run(capsys, "--json", "data", "info", path)
    assert code == 0, err
    summary = json.loads(out)["summary"]
    assert summary["action_kind"] == "discrete" and summary["n_state_actions"] == 2


def test_convert_to_d4rl_refusal_names_the_target(tmp_path, capsys):
    source = tmp_path / "d.jsonl"
    source.write_text(header(state_kind="features", action_kind="symbol") + "\n"
                      + json.dumps({"states": [{"x": 1}, {"x": 2}], "actions": ["go"]}) + "\n")
    code, _, err = run(capsys, "data", "convert", source, tmp_path / "t.hdf5")
    assert code == 2 and f"{tmp_path / 't.hdf5'}: D4RL files hold array observations" in err, err


def test_npz_bytes_text_gets_the_way_out(tmp_path):
    path = tmp_path / "d.npz"
    np.savez(path, __meta__=np.array(json.dumps({"symlearn": "demonstrations", "format_version": 1}).encode()),
             lengths=np.array([1]), states=np.zeros((1, 2)))
    with pytest.raises(DataError, match="has dtype '\\|S") as info:
        load(path)
    assert "dtype=str" in info.value.hint


def test_jsonl_null_optional_keys_and_metadata_are_absent(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(json.dumps({"symlearn": "demonstrations", "format_version": 1, "state_kind": "vector",
                                "action_kind": None, "state_dtype": None, "metadata": None}) + "\n"
                    + json.dumps({"states": [[0.1], [0.2]], "actions": None, "rewards": None, "labels": None,
                                  "info": None}) + "\n")
    demos = load(path)
    assert demos.metadata == {} and not demos.has_actions and not demos.has_rewards and demos[0].info == {}


def test_jsonl_integers_beyond_64_bits_are_named(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="discrete") + "\n" + '{"states": [123456789012345678901234567890, 1]}\n')
    with pytest.raises(DataError, match="integer beyond 64 bits"):
        load(path)


@pytest.mark.parametrize("meta", [{"states_features": ["x", "y"]}, {}])
def test_npz_feature_columns_named_by_feature(tmp_path, meta):
    # docs: `states.<k>` columns for feature dicts; members named after the feature, with or without
    # states_features, were read as empty dicts (without) or refused (with)
    path = npz(tmp_path / "d.npz", {"state_kind": "features", **meta}, lengths=np.array([2, 1]),
               **{"states.x": np.array([0.1, 0.2, 0.3]), "states.y": np.array([1, 2, 3])})
    demos = load(path)
    assert demos[0].states == ({"x": 0.1, "y": 1}, {"x": 0.2, "y": 2}) and demos[1].states == ({"x": 0.3, "y": 3},)


def test_npz_feature_columns_by_index_need_their_names(tmp_path):
    path = npz(tmp_path / "d.npz", {"state_kind": "features"}, lengths=np.array([1]), **{"states.0": np.array([1.0])})
    with pytest.raises(DataError, match="no states_features"):
        load(path)


def test_npz_declared_discrete_ids_stored_as_floats_are_refused(tmp_path):
    path = npz(tmp_path / "d.npz", {"state_kind": "discrete"}, lengths=np.array([3]), states=np.array([0.0, 1.0, 2.0]))
    with pytest.raises(DataError, match="states are vector but __meta__ says state_kind discrete") as info:
        load(path)
    assert "astype(np.int64)" in info.value.hint


def test_learn_dnf_reads_feature_dicts_by_their_keys_not_by_position(tmp_path, capsys):
    # before: --features x,y (or an --env's feature names) renamed the file's a, b by position
    path = tmp_path / "d.jsonl"
    states = [{"a": 0.1 * i, "b": 1.0} for i in range(8)]
    path.write_text(header(state_kind="features") + "\n" + json.dumps({"states": states}) + "\n")
    code, _, err = run(capsys, "learn", "dnf", "--demos", path, "--features", "x,y")
    assert code == 2 and "the states name their features (a, b); the names given are x, y" in err, err
    code, out, err = run(capsys, "--json", "learn", "dnf", "--demos", path, "--features", "b,a")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == ["b", "a"] and doc["leaves"][0]["b"] == [1, 1], doc["leaves"]


@pytest.mark.parametrize("states, args, message", [
    ([{"a": 0.1, "b": 5.0}] * 6, ("--features", "x,y", "--subsets", "s=x"), "the states have no feature 'x'"),
    ([{"a": 0.1, "c": "red"}] * 6, (), "feature 'c' is the text 'red'"),
])
def test_learn_pdfa_feature_dicts_refused_in_one_line(tmp_path, capsys, states, args, message):
    # before: internal errors (KeyError 'x'; ValueError from float('red'))
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="features") + "\n" + json.dumps({"states": states}) + "\n")
    code, _, err = run(capsys, "learn", "pdfa", "--demos", path, *args)
    assert code == 2 and message in err and "internal error" not in err, err


def test_learn_dnf_repeated_metadata_feature_name_names_the_file(tmp_path, capsys):
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="vector", metadata={"feature_names": ["x", "x"]}) + "\n"
                    + json.dumps({"states": [[0.1, 1.0], [0.2, 1.0]]}) + "\n")
    code, _, err = run(capsys, "learn", "dnf", "--demos", path)
    assert code == 2 and f"{path}: metadata \"feature_names\" names 'x' twice" in err, err


def test_jsonl_kinds_left_out_are_the_kinds_of_the_values(tmp_path):
    path = tmp_path / "d.jsonl"
    path.write_text(header() + "\n" + json.dumps({"states": [[0, 1], [1, 2]], "actions": [0]}) + "\n"
                    + json.dumps({"states": [[0.5, 1], [1, 2]], "actions": [1]}) + "\n")
    demos = load(path)
    assert demos.state_kind == "vector" and demos.action_kind == "discrete"
    assert demos[0].states.dtype == np.float64
    path.write_text(header() + "\n" + json.dumps({"states": [0, 1]}) + "\n"
                    + json.dumps({"states": [[0.5, 1], [1, 2]]}) + "\n")
    with pytest.raises(DataError, match="trajectory 1 has vector states, trajectory 0 has discrete") as info:
        load(path)
    assert f"{path}:3:" in str(info.value)
    path.write_text(header(state_kind="discrete", action_kind=None) + "\n" + json.dumps({"states": [0, 1], "actions": [1]}))
    with pytest.raises(DataError, match="action_kind is null"):  # declared null: no actions
        load(path)


def test_jsonl_strings_holding_unicode_line_separators_stay_on_their_line(tmp_path):
    # json.dumps(..., ensure_ascii=False) writes U+2028, U+0085, U+001C raw; str.splitlines cut there
    note = "a\u2028b\x85c\x1cd\u2029e"
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="discrete") + "\r\n"
                    + json.dumps({"states": [0, 1], "info": {"note": note}}, ensure_ascii=False) + "\r\n",
                    encoding="utf-8", newline="")
    (t,) = load(path)
    assert t.info == {"note": note}


def test_labels_given_as_objects_of_truth_values_are_refused_not_read_by_their_keys(tmp_path):
    # before: frozenset({"key": false, "door": true}) made both propositions true
    path = tmp_path / "d.jsonl"
    path.write_text(header(state_kind="discrete") + "\n"
                    + json.dumps({"states": [0, 1], "labels": [{"key": False, "door": True}, []]}) + "\n")
    with pytest.raises(DataError, match="labels at step 0 must be a list of the true propositions") as info:
        load(path)
    assert '["door"]' in info.value.hint and f"{path}:2:" in str(info.value)


def test_npz_labels_other_than_0_or_1_are_refused(tmp_path):
    labels = np.array([[1, 0], [0.5, 1]])
    path = npz(tmp_path / "d.npz", {"state_kind": "discrete"}, lengths=np.array([2]), states=np.array([0, 1]),
               label_names=np.array(["a", "b"]), labels=labels)
    with pytest.raises(DataError, match="holds 0.5 at row 1, column 0 \\('a'\\)"):
        load(path)


def test_minari_flags_other_than_0_or_1_are_refused(tmp_path):
    h5py = pytest.importorskip("h5py")
    (tmp_path / "ds" / "data").mkdir(parents=True)
    with h5py.File(tmp_path / "ds" / "data" / "main_data.hdf5", "w") as f:
        g = f.create_group("episode_0")
        g["observations"] = np.zeros((3, 2))
        g["actions"] = np.zeros((2, 1))
        g["rewards"] = np.zeros(2)
        g["terminations"] = np.array([0.0, 2.5])
        g["truncations"] = np.zeros(2, bool)
    with pytest.raises(DataError, match="'/episode_0/terminations' row 1 is 2.5"):
        load(tmp_path / "ds")


def test_jsonl_files_joined_name_the_second_header(tmp_path):
    one = header(state_kind="discrete") + "\n" + json.dumps({"states": [0, 1]}) + "\n"
    path = tmp_path / "d.jsonl"
    path.write_text(one + one)
    with pytest.raises(DataError, match="a second header line") as info:
        load(path)
    assert f"{path}:3:" in str(info.value)


@pytest.mark.parametrize("states, message", [
    (np.array(["a", "b", "c"]), "hold symbol states"),  # before: internal ValueError
    (np.zeros((3, 0)), "hold no value per step"),  # before: internal ZeroDivisionError in learn pdfa
])
def test_learn_pdfa_states_it_cannot_cluster_are_one_line(tmp_path, capsys, states, message):
    path = npz(tmp_path / "d.npz", {}, lengths=np.array([3]), states=states)
    code, _, err = run(capsys, "learn", "pdfa", "--demos", path)
    assert code == 2 and message in err and "internal error" not in err, err


def test_data_info_warns_where_a_d4rl_table_joins_episodes_without_a_flag(tmp_path, capsys):
    # D4RL's v0 tables have no timeouts: a time-limited episode runs into the next one and only
    # next_observations shows where; the episodes stay cut where the flags say (docs), with a warning
    first, second = np.arange(8, dtype=np.float32).reshape(4, 2), 100 + np.arange(6, dtype=np.float32).reshape(3, 2)
    path = tmp_path / "v0.npz"
    np.savez(path, observations=np.concatenate([first[:3], second[:2]]),
             next_observations=np.concatenate([first[1:], second[1:]]), actions=np.zeros((5, 1)),
             terminals=np.array([False, False, False, False, True]))
    code, out, err = run(capsys, "data", "info", path)
    assert code == 0 and "in 1 row(s) inside an episode (first: row 2) the next observation" in err, err
    assert "1 trajectories" in out
    continuous = tmp_path / "ok.npz"
    np.savez(continuous, observations=first[:3], next_observations=first[1:], actions=np.zeros((3, 1)),
             terminals=np.array([False, False, True]))
    code, _, err = run(capsys, "data", "validate", continuous)
    assert code == 0 and "warning" not in err, err
