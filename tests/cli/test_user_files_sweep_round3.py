"""A third sweep of files a researcher writes by hand from the documentation (a drone domain with
CRLF, BOM and tabs, hand-written automata, reward-machine text, TLSF, DNF files, frame archives),
read through the CLI at its defaults: every mistake is one line at its file, line and column, and
what is read back is what was written."""

from __future__ import annotations

import json

import numpy as np
import pytest
from cli_runner import run

# --- a small domain folder, written as a user would ------------------------------------------------
_CELLS = 3  # a corridor 0..2, the drone starts in 0 and lands in 2; cell 1 is a no-fly zone it may not enter


def _write_drone(folder, *, background=None, bias=None):
    """A corridor drone: states are cells, actions fly(east), fly(west), hover."""
    folder.mkdir()
    actions = ["fly(east)", "fly(west)", "hover"]
    moves = {"fly(east)": 1, "fly(west)": -1, "hover": 0}
    P = np.zeros((_CELLS, 3, _CELLS))
    for s in range(_CELLS):
        for a, name in enumerate(actions):
            P[s, a, min(max(s + moves[name], 0), _CELLS - 1)] = 1.0
    terminal = np.array([s == _CELLS - 1 for s in range(_CELLS)])
    np.savez(folder / "model.npz", transitions=P, initial=np.eye(_CELLS)[0], terminal=terminal)
    (folder / "drone.lp").write_bytes((background or "% the corridor\r\n\tnofly(1).\r\n").encode())
    (folder / "bias.las").write_text(bias if bias is not None else "#modeb(1, hover).\n")
    (folder / "states.jsonl").write_text("".join(json.dumps({"id": s, "facts": f"at({s})."}) + "\n"
                                                 for s in range(_CELLS)))
    (folder / "actions.jsonl").write_text("".join(json.dumps({"id": a, "atom": name}) + "\n"
                                                  for a, name in enumerate(actions)))
    (folder / "domain.toml").write_text('name = "drone"\nbackground = "drone.lp"\nbias = "bias.las"\n'
                                        'model = "model.npz"\nstates = "states.jsonl"\nactions = "actions.jsonl"\n')
    return folder


def _demos(path):
    path.write_text('{"symlearn": "demonstrations", "format_version": 1}\n'
                    '{"states": [0, 1, 2], "actions": ["fly(east)", "fly(east)"]}\n')
    return path


def test_an_unsafe_rule_in_the_background_is_located_in_the_background_file(capsys, tmp_path):
    # before: "<drone pair contexts>:2:9", a line of the program symlearn generates
    folder = _write_drone(tmp_path / "drone", background="\ufeff% comment\r\n\r\nnofly(1).\r\n  bad(X) :- not nofly(1).\r\n")
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "Traceback" not in err
    assert err.startswith(f"symlearn: error: {folder / 'drone.lp'}:4:3: unsafe variable X"), err


def test_a_modeh_in_a_domains_bias_is_refused_at_its_line(capsys, tmp_path):
    # before: an internal error (WorkerCrash: clingo rejected generated constraint ...)
    folder = _write_drone(tmp_path / "drone", bias="% rules with heads\n#modeb(1, hover).\n  #modeh(stuck).\n")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", _demos(tmp_path / "d.jsonl"),
                         "-o", tmp_path / "rules.lp")
    assert code == 2 and "internal error" not in err
    assert f"{folder / 'bias.las'}:3:3: the bias declares #modeh(stuck)" in err
    assert not (tmp_path / "rules.lp").exists()


def test_a_bias_without_modes_is_named_where_rules_are_learned(capsys, tmp_path):
    folder = _write_drone(tmp_path / "drone", bias="% nothing declared yet\n")
    code, out, err = run(capsys, "domain", "check", folder)  # checking the folder needs no bias
    assert code == 0, err
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", _demos(tmp_path / "d.jsonl"))
    assert code == 2 and f"{folder / 'bias.las'}: the bias declares no #modeb or #modec" in err, err
    assert "induction task" not in err


@pytest.mark.parametrize("rules, hint", [
    ("// the drone may not hover\n:- hover.\n", "comments in ASP start with '%'"),
    (":- hover. // why\n", "comments in ASP start with '%'"),
    (":- fly(D), at(0.5).\n", "ASP has no decimal numbers"),
])
def test_rule_file_syntax_errors_get_a_hint_in_the_users_terms(capsys, tmp_path, rules, hint):
    folder = _write_drone(tmp_path / "drone")
    path = tmp_path / "edited.lp"
    path.write_text(rules)
    code, out, err = run(capsys, "domain", "check", folder, "--rules", path)
    assert code == 2 and f"{path}:1:" in err and hint in err, err


def test_a_misspelt_directive_in_the_bias_is_suggested(capsys, tmp_path):
    folder = _write_drone(tmp_path / "drone", bias="#modeb(1, hover).\n#constnt(dir, east).\n")
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'bias.las'}:2:1:" in err and "did you mean #constant?" in err, err


# --- DNF files ------------------------------------------------------------------------------------
@pytest.mark.parametrize("text, column, says", [
    ("speed > 1\n1.5 < x\n", 1, "the feature first"),
    ("temp > \u22123\n", 8, "write the ASCII '-'"),
])
def test_dnf_mistakes_from_mathematical_writing_get_a_hint(capsys, tmp_path, text, column, says):
    path = tmp_path / "rules.dnf"
    path.write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "dnf", "show", path)
    assert code == 2 and f"{path}:{text.count(chr(10), 0, text.index(text.splitlines()[-1])) + 1}:{column}:" in err
    assert says in err, err


def test_dnf_errors_name_true_and_false_not_the_grammars_tokens(capsys, tmp_path):
    path = tmp_path / "rules.dnf"
    path.write_text("2 < x\n")
    code, out, err = run(capsys, "dnf", "show", path)
    assert code == 2 and "bottom" not in err and "top" not in err and "true" in err, err


# --- automata ---------------------------------------------------------------------------------------
_DFA = """{"format": "symlearn-automaton", "version": 1, "kind": "dfa",
 "alphabet": ["door", "key"],
 "states": 3, "initial": 0, "accepting": [2],
 "state_names": ["start", "has key", "done"],
 "transitions": [
   {"source": 0, "target": 1, "guard": "key"},
   {"source": 1, "target": 2, "guard": "door"},
   {"source": 0, "target": 0, "guard": "!key"}
 ]}
"""


@pytest.mark.parametrize("old, new, where, says", [
    ('"guard": "door"', '"guard": "dor"', "7:40", "transitions[1].guard: guard 'dor' uses dor, outside the alphabet"),
    ('"target": 2', '"target": 3', "7:28", "transitions[1].target: target 3 is not a state"),
    ('"guard": "door"', '"guard": "door &"', "7:40", "transitions[1].guard: unexpected end"),
    ('"accepting": [2]', '"accepting": ["done"]', "3:43", "accepting[0]: expected an integer"),
    ('"initial": 0', '"initial": 5', "3:26", "initial: initial state 5 is not a state"),
    ('"start", "has key", "done"', '"start", "done"', "4:17", "state_names: 2 state names for 3 states"),
    ('"kind": "dfa"', '"kind": "DFA"', "1:56", "kind: unknown automaton kind 'DFA'"),
    ('"target": 1, "guard": "key"', '"target": 1', "6:4", "transitions[0].guard: missing field"),
])
def test_a_hand_written_automatons_mistakes_are_at_their_line_and_column(capsys, tmp_path, old, new, where, says):
    # before: "bad.json: transitions[1].guard: ..." without a line, or the constructor's words
    # ("DFA guard 'dor' on state 1 ...") without the field
    path = tmp_path / "bad.json"
    assert old in _DFA
    path.write_text(_DFA.replace(old, new, 1))
    code, out, err = run(capsys, "automaton", "show", path)
    assert code == 2 and "Traceback" not in err
    assert err.startswith(f"symlearn: error: {path}:{where}: {says}"), err


_RM = """# coffee, then the office; a plant is a failure
0      # initial
[2, -1]
(0, 0, '!c & !n', ConstantRewardFunction(0))
(0,1,'c&!n',ConstantRewardFunction(0))
(1,1,'!o&!n',ConstantRewardFunction(0))
(1,2,'o&!n',ConstantRewardFunction(1))
(0,-1,'n',ConstantRewardFunction(-1))
(1,-1,'n',ConstantRewardFunction(-1.5e0))
"""


def test_reward_machine_text_to_json_and_back_keeps_the_files_state_numbers(capsys, tmp_path):
    # before: the text written back renumbered the states 0..3 (the initial state became 1, the failure 0)
    (tmp_path / "task.txt").write_text(_RM)
    for source, target in [("task.txt", "task.json"), ("task.json", "back.txt"), ("back.txt", "again.json")]:
        code, out, err = run(capsys, "automaton", "convert", tmp_path / source, tmp_path / target)
        assert code == 0, err
    back = (tmp_path / "back.txt").read_text().splitlines()
    assert back[:2] == ["0", "[-1, 2]"]
    assert "(1,2,'!n&o',ConstantRewardFunction(1))" in back and "(0,-1,'n',ConstantRewardFunction(-1))" in back
    assert json.loads((tmp_path / "task.json").read_text()) == json.loads((tmp_path / "again.json").read_text())


def test_explaining_a_reward_machine_names_the_file_once_and_says_why(capsys, tmp_path):
    path = tmp_path / "task.txt"
    path.write_text(_RM)
    code, out, err = run(capsys, "automaton", "explain", path, "--trace", '[["c"], ["o"]]')
    assert code == 2 and err.count(str(path)) == 1 and "terminal states are not accepting states" in err, err


# --- TLSF -------------------------------------------------------------------------------------------
_TLSF = """INFO {
  TITLE:       "arbiter"
  DESCRIPTION: "two clients"
  SEMANTICS:   %s
  TARGET:      Mealy
}
MAIN {
  INPUTS { r_1; r_2; }
  OUTPUTS { g_1; g_2; }
  GUARANTEES { G !(g_1 && g_2); G (r_1 -> X[!] F g_1); }
}
"""


def test_a_tlsf_file_with_infinite_trace_semantics_is_refused(capsys, tmp_path):
    # before: read as LTLf without a word, though Mealy alone means LTL on infinite traces
    path = tmp_path / "arbiter.tlsf"
    path.write_text(_TLSF % "Mealy")
    code, out, err = run(capsys, "ltl", "parse", "--tlsf", path)
    assert code == 2 and f"{path}:4:16: SEMANTICS: Mealy is infinite-trace (LTL) semantics" in err, err
    path.write_text(_TLSF % "Finite,Mealy")
    code, out, err = run(capsys, "ltl", "parse", "--tlsf", path)
    assert code == 0, err


# --- sub-goals from frames ---------------------------------------------------------------------------
def test_a_goal_some_demonstrations_start_near_stays_a_sub_goal(capsys, tmp_path):
    # A cup and a lid start at random places; every demonstration puts the cup at (0.5, 0.5) and then
    # the lid at (-0.5, 0.5). One demonstration's lid starts next to its goal, so its approach chains
    # its first frame into the goal's cluster. Before: the lid's cluster was dropped as a start place
    # for all 12 demonstrations ("1 sub-goals ... plan: cup_0").
    rng = np.random.default_rng(0)
    cup_goal, lid_goal = np.array([0.5, 0.5, 0.0]), np.array([-0.5, 0.5, 0.0])
    runs = []
    for k in range(12):
        cup = np.r_[rng.uniform(-1, 0, 2), 0.0]
        lid = lid_goal + [0.06, 0.0, 0.0] if k == 0 else np.r_[rng.uniform(0, 1, 2), 0.0]
        frames = []
        for obj, goal in ((cup, cup_goal), (lid, lid_goal)):
            start = obj.copy()
            for t in range(1, 11):
                obj[:] = start + (goal - start) * t / 10
                frames.append(np.r_[cup, lid])
            frames += [np.r_[cup, lid]] * 5
        runs.append(np.array(frames))
    np.savez(tmp_path / "frames.npz", states=np.concatenate(runs), lengths=[len(r) for r in runs],
             feature_names=["cup_x", "cup_y", "cup_z", "lid_x", "lid_y", "lid_z"])
    code, out, err = run(capsys, "learn", "pdfa", "--demos", tmp_path / "frames.npz",
                         "--subsets", "cup=cup_x,cup_y,cup_z;lid=3,4,5", "--json", "-q")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["plan"] == ["cup_0", "lid_0"], doc["plan"]


# --- rule arguments no answer set matches ------------------------------------------------------------
@pytest.mark.parametrize("rules, where, says", [
    # a capitalised constant is a variable: the rule forbids every flight
    (":- fly(East).\n", "1:8", "variable East occurs nowhere else in its rule, so it matches every value of fly/1's "
                               "argument 1; did you mean the constant east?"),
    (":- hover, nofly(\"1\").\n", "1:17", "nofly/1 never has \"1\" as argument 1 (it has: 1), so the atom is always "
                                          "false; did you mean 1?"),
])
def test_domain_check_warns_about_arguments_no_pair_has(capsys, tmp_path, rules, where, says):
    # before: no warning (clingo accepts both); the first forbade every flight, the second nothing
    folder = _write_drone(tmp_path / "drone")
    path = tmp_path / "edited.lp"
    path.write_text(rules)
    code, out, err = run(capsys, "domain", "check", folder, "--rules", path)
    assert code == 0, err
    assert f"warning: {path}:{where}: {says}" in out, out
    code, out, err = run(capsys, "domain", "check", folder, "--rules", path, "--json")
    assert json.loads(out)["warnings"][0]["line"] == 1


def test_learned_rules_and_well_written_ones_get_no_argument_warning(capsys, tmp_path):
    folder = _write_drone(tmp_path / "drone")
    path = tmp_path / "edited.lp"
    path.write_text(":- fly(east), at(A), nofly(B), B = A + 1.\n:- fly(V1), hover.\n")
    code, out, err = run(capsys, "domain", "check", folder, "--rules", path)
    # no argument warning; the second rule pairs two actions, which no pair has together, so since
    # the fifth sweep it is named as a rule that forbids nothing (and only that)
    warned = [line for line in out.splitlines() if line.startswith("warning:")]
    assert code == 0 and len(warned) == 1 and "edited.lp:2:1: rule :- fly(V1), hover. forbids no" in warned[0], out


_LAB = """% never add a reagent that reacts explosively with one in the flask
reaction("Na", "H2O", explosive).
reaction(B, A, K) :- reaction(A, B, K).
#pos(ok, {}, {}, { in_flask("Oil"). add("Na"). }).
#neg(bad, {}, {}, { in_flask("Na"). add("H2O"). }).
#modeb(1, add(var(r)), (positive)).
#modeb(1, in_flask(var(r)), (positive)).
#modeb(1, reaction(var(r), var(r), const(k)), (positive)).
#constant(k, explosive).
#maxv(2).
"""


def test_ilp_check_names_a_string_written_for_a_constant(capsys, tmp_path):
    # before: only "bad (negative) ... no rule excludes it", with nothing pointing at the quotes
    (tmp_path / "lab.las").write_text(_LAB)
    rules = tmp_path / "edited.lp"
    rules.write_text(':- add(R), in_flask(S), reaction(R, S, "explosive").\n')
    code, out, err = run(capsys, "ilp", "check", tmp_path / "lab.las", rules)
    assert code == 2 and "bad" in err
    assert (f'warning: {rules}:1:40: reaction/3 never has "explosive" as argument 3 (it has: explosive), so the '
            "atom is always false; did you mean explosive?") in out, out
    rules.write_text(":- add(R), in_flask(S), reaction(R, S, explosive).\n")
    code, out, err = run(capsys, "ilp", "check", tmp_path / "lab.las", rules)
    assert code == 0 and "warning" not in out, out


# --- LTLf formulas ------------------------------------------------------------------------------------
@pytest.mark.parametrize("formula, says", [
    ("F key & eventually door", "'eventually' is read as a proposition here; write 'F'"),
    ("always !lava", "'always' is read as a proposition here; write 'G'"),
])
def test_an_operator_written_as_a_word_is_named_where_the_next_name_fails(capsys, formula, says):
    # before: the error at 'door' had no hint (the word before it parsed as a proposition)
    code, out, err = run(capsys, "ltl", "parse", formula)
    assert code == 2 and says in err, err


# --- labelings --------------------------------------------------------------------------------------
def _labeling(propositions, table):
    return ('{"symlearn": "labeling", "format_version": 1, "kind": "table",\n'
            f' "propositions": {propositions},\n "table": {table}}}\n')


@pytest.mark.parametrize("propositions, table, where, says", [
    # names alone, a plausible shortcut: before, "malformed labeling (TypeError: string indices must be integers ...)"
    ('["hovering"]', '[[0, ["hovering"]]]', "2:19", 'propositions[0]: expected an object with a "name"'),
    ('[{"name": "hovering"}]', '[[0, ["hovering"]], [2, ["hoverng"]]]', "3:31",
     'table[1]: proposition "hoverng" is not declared'),
    ('[{"name": "hovering"}]', '[[0, ["hovering"]], [7, ["hovering"]]]', "3:31",
     "table[1]: the labeling labels state 7, which is not one of the domain's 3 states"),
])
def test_a_labeling_files_mistakes_are_at_their_line_and_column(capsys, tmp_path, propositions, table, where, says):
    # before: "labels.json: table[1]: ..." without a line and column
    folder = _write_drone(tmp_path / "drone")
    path = tmp_path / "labels.json"
    path.write_text(_labeling(propositions, table))
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", _demos(tmp_path / "d.jsonl"),
                         "--labeling", path)
    assert code == 2 and "Traceback" not in err
    assert err.startswith(f"symlearn: error: {path}:{where}: {says}"), err


# --- NPZ demonstrations written with numpy ----------------------------------------------------------
def test_labels_without_their_names_say_what_is_missing(capsys, tmp_path):
    # before: "member 'labels' has 1 columns but 'label_names' has ? names"
    meta = json.dumps({"symlearn": "demonstrations", "format_version": 1})
    np.savez(tmp_path / "d.npz", __meta__=meta, lengths=[2], states=[0, 1], labels=[[True], [False]])
    code, out, err = run(capsys, "data", "info", tmp_path / "d.npz")
    assert code == 2 and "member 'labels' without a 'label_names' member" in err and "?" not in err, err


def test_a_broken_meta_header_is_placed_inside_the_member(capsys, tmp_path):
    # before: "d.npz:2:22: invalid JSON ...", a line and column of the binary archive
    np.savez(tmp_path / "d.npz", __meta__='{"symlearn": "demonstrations",\n "format_version": 1,,}', lengths=[2],
             states=[0, 1])
    code, out, err = run(capsys, "data", "info", tmp_path / "d.npz")
    assert code == 2 and err.startswith(f"symlearn: error: {tmp_path / 'd.npz'}: member '__meta__' is not a JSON "
                                        "header at line 2, column 22"), err


# --- a domain's model.npz -----------------------------------------------------------------------------
def test_a_model_where_every_state_is_terminal_says_so(capsys, tmp_path):
    # before: "warning: ... predicate at/1 is defined nowhere", a consequence of having no pair at all
    folder = _write_drone(tmp_path / "drone")
    arrays = dict(np.load(folder / "model.npz"))
    arrays["terminal"][:] = True
    np.savez(folder / "model.npz", **arrays)
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'model.npz'}: the model has no state-action pair" in err, err


def test_an_initial_distribution_that_does_not_sum_to_one_says_what_it_sums_to(capsys, tmp_path):
    # before: "initial must be a probability vector of length 3" of a vector of length 3
    folder = _write_drone(tmp_path / "drone")
    arrays = dict(np.load(folder / "model.npz"))
    arrays["initial"] = np.array([1.0, 1.0, 0.0])
    np.savez(folder / "model.npz", **arrays)
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "it sums to 2, not 1" in err, err


def test_learn_dnf_on_whole_number_features_counts_the_states_not_the_volume(capsys, tmp_path):
    # Two counters, every combination demonstrated: the formula forbids no possible state. Before:
    # "warning: the formula marks 100% of the demonstrations' bounding box unsafe" (the safe boxes
    # around single points have no volume).
    lines = ['{"symlearn": "demonstrations", "format_version": 1}']
    for first in [0, 1, 2] * 8:  # the players take turns: each demonstration starts with another one
        lines.append(json.dumps({"states": [{"turn": (first + c) % 3 + 1, "played": c} for c in range(4)]}))
    (tmp_path / "d.jsonl").write_text("\n".join(lines) + "\n")
    code, out, err = run(capsys, "learn", "dnf", "--demos", tmp_path / "d.jsonl", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["unsafe_share"] == 0.0 and doc["warnings"] == [], doc["warnings"]


def test_a_ragged_feature_map_row_is_named_at_its_line(capsys, tmp_path):
    # before: "malformed feature map (ValueError: setting an array element with a sequence. ... inhomogeneous ...)"
    folder = _write_drone(tmp_path / "drone")
    (folder / "features.json").write_text('{"symlearn": "feature-map", "format_version": 1, "names": ["x"],\n'
                                          ' "table": [[0], [1], [2, 5]]}\n')
    with open(folder / "domain.toml", "a") as toml:
        toml.write('features = "features.json"\n')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "inhomogeneous" not in err
    assert err.startswith(f"symlearn: error: {folder / 'features.json'}:2:22: table[2]: 2 values for 1 feature names"), err


def test_a_dnf_json_files_mistake_is_at_its_line_and_column(capsys, tmp_path):
    # before: "rules.json: conjunctions[1][0]: unknown comparison '=<'" without a line and column
    path = tmp_path / "rules.json"
    path.write_text('{"symlearn": "dnf", "format_version": 1,\n'
                    ' "conjunctions": [[["speed", ">", 1.5]], [["x_0", "=<", 0]]]}\n')
    code, out, err = run(capsys, "dnf", "show", path)
    assert code == 2 and err.startswith(f"symlearn: error: {path}:2:43: conjunctions[1][0]: unknown comparison"), err


def test_a_labeling_state_that_is_an_object_is_named_at_its_line(capsys, tmp_path):
    folder = _write_drone(tmp_path / "drone")
    path = tmp_path / "labels.json"
    path.write_text(_labeling('[{"name": "hovering"}]', '[[{"cell": 0}, ["hovering"]]]'))
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", _demos(tmp_path / "d.jsonl"),
                         "--labeling", path)
    assert code == 2 and err.startswith(f"symlearn: error: {path}:3:12: table[0]: state"), err
