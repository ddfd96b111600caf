"""A user's domain folder: read, checked, written back; every authoring mistake is one clear error."""

from __future__ import annotations

import json

import numpy as np
import pytest
import warehouse_domain as wh

from symlearn.errors import DataError, ParseError, SymlearnError
from symlearn.grounding import Domain, FactGrounding, Labeling
from symlearn.mdp import TabularMDP


@pytest.fixture()
def folder(tmp_path):
    return wh.write_warehouse(tmp_path / "warehouse")


def test_folder_loads_and_truth_matches_an_independent_computation(folder):
    d = Domain.from_folder(folder)
    assert (d.n_states, d.n_actions) == (len(wh.states()), len(wh.ACTIONS))
    assert d.action_names == tuple(wh.ACTIONS)
    arrays = wh.build_arrays()
    # unavailable = moves off the floor, and everything in the terminal state
    expected = ~arrays["available"] | arrays["terminal"][:, None]
    np.testing.assert_array_equal(d.unavailable, expected)
    np.testing.assert_array_equal(d.truth_forbidden, wh.truth_mask(arrays))
    assert isinstance(d.labeling, Labeling) and "delivered" in d.labeling.propositions


def test_rule_mask_of_edited_rules(folder):
    d = Domain.from_folder(folder)
    only_alarm = d.rule_mask(":- alarm, move(D).")
    assert only_alarm.sum() > 0
    assert not (only_alarm & ~d.truth_forbidden).any()  # a subset of the truth
    assert d.rule_mask([]).sum() == 0
    with pytest.raises(SymlearnError, match="integrity constraints"):
        d.rule_mask("bad :- alarm.")


def test_round_trip_through_save(folder, tmp_path):
    d = Domain.from_folder(folder)
    again = Domain.from_folder(d.save(tmp_path / "copy"))
    assert again.grounding == d.grounding
    np.testing.assert_array_equal(again.mdp.transitions, d.mdp.transitions)
    np.testing.assert_array_equal(again.unavailable, d.unavailable)
    np.testing.assert_array_equal(again.truth_forbidden, d.truth_forbidden)
    assert again.labeling == d.labeling


def test_domain_built_in_python_is_the_same_class():
    P = np.zeros((3, 2, 3))
    P[0, 0, 1] = P[0, 1, 2] = P[1, :, 1] = P[2, :, 2] = 1
    mdp = TabularMDP(P, np.zeros((3, 2)), [1, 0, 0], [False, True, True])
    d = Domain("fork", background="", bias="#modeb(1, danger). #modeb(1, go(const(side))). #constant(side, left).",
               grounding=FactGrounding(["danger.", "", ""], ["go(left)", "go(right)"]), mdp=mdp,
               truth=":- danger, go(left).")
    assert d.truth_forbidden.astype(int).tolist() == [[1, 0], [0, 0], [0, 0]]


# --- authoring mistakes ---------------------------------------------------------------------------
def _edit(folder, name, text):
    (folder / name).write_text(text)


def test_missing_key(folder):
    toml = (folder / "domain.toml").read_text().replace('bias = "bias.las"\n', "")
    _edit(folder, "domain.toml", toml)
    with pytest.raises(DataError, match="missing key 'bias'") as info:
        Domain.from_folder(folder)
    assert info.value.file.endswith("domain.toml")


def test_missing_file_names_the_key(folder):
    (folder / "truth.lp").unlink()
    with pytest.raises(DataError, match="key 'truth': file 'truth.lp' not found"):
        Domain.from_folder(folder)


def test_unknown_key_and_bad_toml(folder):
    _edit(folder, "domain.toml", (folder / "domain.toml").read_text() + 'colour = "red"\n')
    with pytest.raises(DataError, match="unknown key 'colour'"):
        Domain.from_folder(folder)
    _edit(folder, "domain.toml", 'name = "x\n')
    with pytest.raises(ParseError, match="invalid TOML") as info:
        Domain.from_folder(folder)
    assert info.value.line == 1


def test_rows_that_do_not_sum_to_one(folder):
    arrays = wh.build_arrays()
    arrays["transitions"][5, 2, :] *= 0.5
    np.savez(folder / "model.npz", **arrays)
    with pytest.raises(DataError, match=r"\(s, a\) = \(5, 2\) sums to 0.5"):
        Domain.from_folder(folder)


def test_flags_written_as_0_1_integers_read_as_booleans(folder):
    """``terminal``/``available`` as 0/1 integers (``np.zeros(S, dtype=int)``, as numpy users
    write flags) read as the booleans they mean; a 2 in them is still a mistake."""
    reference = Domain.from_folder(folder)
    arrays = wh.build_arrays()
    arrays["terminal"] = arrays["terminal"].astype(np.int64)
    arrays["available"] = arrays["available"].astype(np.uint8)
    np.savez(folder / "model.npz", **arrays)
    d = Domain.from_folder(folder)
    np.testing.assert_array_equal(d.unavailable, reference.unavailable)
    np.testing.assert_array_equal(d.truth_forbidden, reference.truth_forbidden)
    arrays["terminal"][0] = 2
    np.savez(folder / "model.npz", **arrays)
    with pytest.raises(DataError, match="'terminal' must be boolean .or 0/1 integers., got int64 with values other"):
        Domain.from_folder(folder)


def test_shapes_that_disagree(folder):
    lines = (folder / "states.jsonl").read_text().splitlines()
    _edit(folder, "states.jsonl", "\n".join(lines[:-1]) + "\n")
    with pytest.raises(DataError, match=f"lists {len(lines) - 1} states, model.npz has {len(lines)}"):
        Domain.from_folder(folder)
    wh.write_warehouse(folder)
    arrays = wh.build_arrays()
    arrays["available"] = arrays["available"][:, :3]
    np.savez(folder / "model.npz", **arrays)
    with pytest.raises(DataError, match="'available' must have shape"):
        Domain.from_folder(folder)


def test_state_facts_without_exactly_one_answer_set(folder):
    lines = (folder / "states.jsonl").read_text().splitlines()
    lines[3] = json.dumps({"id": 3, "facts": "at(0,0). at(9,9). :- at(9,9)."})
    _edit(folder, "states.jsonl", "\n".join(lines) + "\n")
    with pytest.raises(ParseError, match="not a ground fact") as info:
        Domain.from_folder(folder)
    assert info.value.line == 4
    lines[3] = json.dumps({"id": 3, "facts": "at(0,0). blocked(north). -blocked(north)."})
    _edit(folder, "states.jsonl", "\n".join(lines) + "\n")
    with pytest.raises(DataError, match="state 3 .*unsatisfiable") as info:
        Domain.from_folder(folder)
    assert info.value.line == 4 and info.value.file.endswith("states.jsonl")
    _edit(folder, "bk.lp", wh.BACKGROUND + "{ extra }.\n")
    wh_lines = [json.dumps({"id": i, "facts": wh.state_facts(s)}) for i, s in enumerate(wh.states())]
    _edit(folder, "states.jsonl", "\n".join(wh_lines) + "\n")
    with pytest.raises(DataError, match="more than one answer set"):
        Domain.from_folder(folder)


def test_bias_with_examples(folder):
    _edit(folder, "bias.las", wh.BIAS + "#pos(p1, {}, {}, { alarm. }).\n")
    with pytest.raises(DataError, match="bias file holds examples") as info:
        Domain.from_folder(folder)
    assert info.value.file.endswith("bias.las")


def test_jsonl_mistakes_are_located(folder):
    _edit(folder, "actions.jsonl", '{"id": 0, "atom": "move(north)"}\n{"id": 1, "atom": 7}\n')
    with pytest.raises(DataError, match='"atom" must be a string') as info:
        Domain.from_folder(folder)
    assert info.value.line == 2
    _edit(folder, "actions.jsonl", '{"id": 0, "atom": "move(north)"\n')
    with pytest.raises(ParseError, match="invalid JSON") as info:
        Domain.from_folder(folder)
    assert info.value.line == 1


def test_demonstration_outside_the_domain(folder):
    d = Domain.from_folder(folder)
    from symlearn.data import Demonstrations, Trajectory

    bad_state = Demonstrations([Trajectory(states=[0, 1, 99], actions=[0, 1])])
    with pytest.raises(DataError, match=r"demonstration 0: states: step 2: state 99 is outside"):
        d.episodes(bad_state)
    bad_action = Demonstrations([Trajectory(states=[0, 1], actions=["move(up)"])])
    with pytest.raises(DataError, match=r"demonstration 0: actions: unknown action 'move\(up\)'"):
        d.episodes(bad_action)


def test_feature_map_in_the_folder(folder, tmp_path):
    from symlearn.grounding import FeatureMap

    cells = [s[0] if s != "done" else (-1, -1) for s in wh.states()]
    FeatureMap(["x", "y"], table=np.array(cells, dtype=float)).save(folder / "features.json")
    (folder / "domain.toml").write_text((folder / "domain.toml").read_text() + 'features = "features.json"\n')
    d = Domain.from_folder(folder)
    assert d.feature_map.features(0).tolist() == [0.0, 0.0]
    again = Domain.from_folder(d.save(tmp_path / "copy"))
    assert again.feature_map == d.feature_map


def test_an_unsafe_truth_rule_is_located_in_the_truth_file(folder):
    # before: '<hypothesis>:N:1', a name no file has
    _edit(folder, "truth.lp", (folder / "truth.lp").read_text() + ":- go(D), at(X, Y), X > Z.\n")
    line = (folder / "truth.lp").read_text().splitlines().index(":- go(D), at(X, Y), X > Z.") + 1
    with pytest.raises(ParseError, match="unsafe variable Z") as info:
        Domain.from_folder(folder).truth_forbidden
    assert info.value.file == str(folder / "truth.lp") and info.value.line == line


def test_a_misspelt_key_is_named_before_the_key_it_leaves_missing(folder):
    # before: "missing key 'background'", the misspelt 'backgrund' not mentioned
    toml = (folder / "domain.toml").read_text()
    _edit(folder, "domain.toml", toml.replace("background =", "backgrund ="))
    line = next(i for i, t in enumerate(toml.splitlines(), start=1) if t.startswith("background ="))
    with pytest.raises(DataError, match=r"unknown key 'backgrund' \(did you mean 'background'\?\)") as info:
        Domain.from_folder(folder)
    assert info.value.file.endswith("domain.toml") and info.value.line == line
