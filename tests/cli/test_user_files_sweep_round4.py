"""A fourth sweep of files a researcher brings (issue 25): a card-dealing domain whose players are
strings ("Alice"), hand-written rule files, one-formula LTLf files with comments, JSON lists of
traces, DOT over quoted propositions, reward-machine text with a non-terminal -5 state, models
written with zero rows, TOML tables, and labeling functions without declarations, read through
the CLI at its defaults."""

from __future__ import annotations

import json

import numpy as np
import pytest
from cli_runner import run

# --- a dealer robot: turn("Alice"|"Bob"), deck(0..3), shuffled; deal("P"), shuffle, finish, wait -------
_ACTIONS = ['deal("Alice")', 'deal("Bob")', "shuffle", "finish", "wait"]
_STATES = [(t, k, sh) for t in ("Alice", "Bob") for k in range(4) for sh in (0, 1)] + ["done"]
_HEADER = '{"symlearn": "demonstrations", "format_version": 1}\n'


def _step(s, a):
    """[(probability, next state)]: dealing passes the turn, waiting may pass it, finish ends."""
    if s == "done":
        return [(1.0, s)]
    t, k, sh = s
    other = "Bob" if t == "Alice" else "Alice"
    if a.startswith("deal("):
        return [(1.0, s if k == 0 else (other, k - 1, sh))]
    if a == "shuffle":
        return [(1.0, (t, k, 1))]
    if a == "finish":
        return [(1.0, "done")]
    return [(0.5, s), (0.5, (other, k, sh))]


def _write_cards(folder, *, model=None, toml_extra=""):
    folder.mkdir()
    index = {s: i for i, s in enumerate(_STATES)}
    P = np.zeros((len(_STATES), len(_ACTIONS), len(_STATES)))
    for i, s in enumerate(_STATES):
        for a, name in enumerate(_ACTIONS):
            for p, t in _step(s, name):
                P[i, a, index[t]] += p
    arrays = {"transitions": P, "initial": np.array([float(s != "done" and s[1] == 3 and not s[2]) for s in _STATES]) / 2,
              "terminal": np.array([s == "done" for s in _STATES]),
              "rewards": np.array([[10.0 if n == "finish" else -1.0 for n in _ACTIONS] for _ in _STATES])}
    if model:
        model(arrays)
    np.savez(folder / "model.npz", **arrays)
    facts = ["over." if s == "done" else f'turn("{s[0]}"). deck({s[1]}).' + (" shuffled." if s[2] else "")
             for s in _STATES]
    (folder / "states.jsonl").write_text("".join(json.dumps({"id": i, "facts": f}) + "\n" for i, f in enumerate(facts)))
    (folder / "actions.jsonl").write_text("".join(json.dumps({"id": a, "atom": n}) + "\n" for a, n in enumerate(_ACTIONS)))
    (folder / "bk.lp").write_text('player("Alice"). player("Bob").\nwaiting(P) :- player(P), turn(Q), P != Q.\n'
                                  "empty_deck :- deck(0).\ncards_left :- deck(N), N > 0.\n")
    (folder / "bias.las").write_text("#modeb(1, deal(var(p)), (positive)).\n#modeb(1, waiting(var(p)), (positive)).\n"
                                     "#modeb(1, empty_deck, (positive)).\n#modeb(1, cards_left, (positive)).\n"
                                     "#modeb(1, finish, (positive)).\n#maxv(1).\n")
    (folder / "domain.toml").write_text('name = "cards"\nbackground = "bk.lp"\nbias = "bias.las"\nmodel = "model.npz"\n'
                                        'states = "states.jsonl"\nactions = "actions.jsonl"\n' + toml_extra)
    return folder


@pytest.fixture
def cards(tmp_path):
    return _write_cards(tmp_path / "cards")


# --- demonstrations -----------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["logic", "mce-icrl"])
def test_demonstrations_without_a_step_are_refused_not_learned_from(capsys, cards, tmp_path, method):
    # before: one one-state episode learned ':- waiting(V1).', forbidding all 80 pairs (FPR 1), exit 0
    demos = tmp_path / "one.jsonl"
    demos.write_text(_HEADER + '{"states": [1], "actions": []}\n')
    out_file = tmp_path / "rules.lp" if method == "logic" else tmp_path / "cost.json"
    code, out, err = run(capsys, "learn", "constraints", "--domain", cards, "--demos", demos, "--method", method,
                         "-o", out_file)
    assert code == 2 and "Traceback" not in err
    assert "the demonstrations take no action (1 episode(s), 0 steps)" in err and "hint: give each" in err
    assert not out_file.exists()


@pytest.mark.parametrize("body, where, what", [
    ('{"states": [0, 1], "actions": [2]}\n{"states": [1, 3], "actions": ["deal(\\"Alice\\")"]}\n', ":3:", "action"),
    ('{"states": [14, "x"], "actions": [2]}\n', ":2:", "state"),
])
def test_ids_mixed_with_names_say_to_write_one_kind(capsys, cards, tmp_path, body, where, what):
    # before: "trajectory 1 has symbol actions of shape (), trajectory 0 has discrete ..." and no way out
    demos = tmp_path / "mixed.jsonl"
    demos.write_text(_HEADER + body)
    code, out, err = run(capsys, "domain", "check", cards, "--demos", demos)
    assert code == 2 and f"mixed.jsonl{where}" in err
    assert f"hint: write every {what} of the file the same way, all as integer ids or all as names" in err


# --- rule files ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("second, where, name", [(":- deal(P), Waiting(P).", "2:20", "Waiting"),
                                                  (":- Finish, cards_left.", "2:10", "Finish")])
def test_a_capitalised_predicate_in_a_rule_file_is_named(capsys, cards, tmp_path, second, where, name):
    # before: "clingo: syntax error, unexpected (" (or ",") with "check the ASP syntax at this position"
    rules = tmp_path / "r.lp"
    rules.write_text(f":- deal(P), waiting(P).\r\n{second}\r\n")
    code, out, err = run(capsys, "domain", "check", cards, "--rules", rules)
    assert code == 2 and f"r.lp:{where}:" in err
    assert f"{name} starts with a capital letter" in err and f"(write {name.lower()})" in err


def test_hand_written_rules_with_comments_and_strings_score_exactly(capsys, cards, tmp_path):
    rules = tmp_path / "r.lp"
    rules.write_bytes(b':- deal(P), waiting(P).\r\n:- deal(P),   empty_deck .   \r\n% odd place\r\n'
                      b':- deal(P), % here\r\n   not shuffled.\r\n:- finish, cards_left.')
    truth = tmp_path / "cards" / "truth.lp"
    truth.write_text(':- deal(P), waiting(P).\n:- deal(P), empty_deck.\n:- deal(P), not shuffled.\n'
                     ':- finish, cards_left.\n')
    (tmp_path / "cards" / "domain.toml").write_text((tmp_path / "cards" / "domain.toml").read_text()
                                                    + 'truth = "truth.lp"\n')
    code, out, err = run(capsys, "--json", "domain", "check", cards, "--rules", rules)
    doc = json.loads(out)
    assert code == 0 and doc["fpr"] == 0 and doc["fnr"] == 0 and doc["forbidden"] == doc["forbidden_by_truth"] > 0


# --- the domain's model.npz and domain.toml ------------------------------------------------------------------
def test_zero_rows_of_terminal_states_and_missing_moves_read_as_staying(capsys, tmp_path):
    # before: "transition row (s, a) = (16, 0) sums to 0, not 1" for the terminal state's rows
    def zero(arrays):
        arrays["transitions"][-1] = 0                       # the terminal state: nothing happens after it
        arrays["available"] = np.ones(arrays["transitions"].shape[:2], dtype=bool)
        arrays["available"][0, 3] = False                   # a move that does not exist
        arrays["transitions"][0, 3] = 0
    folder = _write_cards(tmp_path / "cards", model=zero)
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 0, err
    from symlearn.grounding import Domain

    P = Domain.from_folder(folder).mdp.transitions
    assert P[-1, :, -1].tolist() == [1.0] * len(_ACTIONS) and P[0, 3, 0] == 1.0


def test_a_zero_row_elsewhere_says_which_rows_may_be_zero(capsys, tmp_path):
    folder = _write_cards(tmp_path / "cards", model=lambda arrays: arrays["transitions"].__setitem__((3, 1), 0))
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "transition row (s, a) = (3, 1) sums to 0, not 1" in err
    assert "only where the move does not exist, 'available' false, or the state is 'terminal'" in err


def test_an_unknown_table_in_domain_toml_is_at_its_line(capsys, tmp_path):
    # before: "domain.toml: unknown key 'extra'" with no line
    folder = _write_cards(tmp_path / "cards", toml_extra="\n[extra]\nfoo = 1\n")
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and f"{folder / 'domain.toml'}:8: unknown key 'extra'" in err


def test_a_labeling_function_without_declarations_discovers_its_propositions(capsys, cards, tmp_path):
    # before: "the given labeling has no propositions (hint: use propositions='learn')" with --domain
    (tmp_path / "lab.py").write_text("def label(observation, info):\n    return ['over'] if observation == 16 else []\n")
    demos = tmp_path / "d.jsonl"
    demos.write_text(_HEADER + ''.join('{"states": [14, 15, 5, 11, 1, 9, 16], "actions": ["shuffle", "deal(\\"Bob\\")", '
                                       '"deal(\\"Alice\\")", "deal(\\"Bob\\")", "wait", "finish"]}\n' for _ in range(3)))
    code, out, err = run(capsys, "--json", "learn", "spec", "--domain", cards, "--demos", demos,
                         "--labeling", f"{tmp_path / 'lab.py'}:label", "--max-iterations", "1")
    assert code == 0, err
    assert "over" in json.loads(out)["propositions"]


# --- LTLf files and traces --------------------------------------------------------------------------------------
def test_a_one_formula_file_with_a_comment_writes_its_automaton(capsys, tmp_path):
    # before: "--dot, --svg and --save write one automaton; they cannot be used with --file"
    spec = tmp_path / "spec.ltl"
    spec.write_bytes(b'# edited: the door opens after every call\r\n  G(call -> F "door open")  \r\n\r\n')
    code, out, err = run(capsys, "ltl", "dfa", "--file", spec, "--save", tmp_path / "s.json", "--dot", tmp_path / "s.dot")
    assert code == 0, err
    assert "minimal DFA: 2 states" in out and (tmp_path / "s.json").exists()
    many = tmp_path / "many.ltl"
    many.write_text("F a\nG b\n")
    code, out, err = run(capsys, "ltl", "dfa", "--file", many, "--save", tmp_path / "m.json")
    assert code == 2 and "holds 2 formulas" in err and not (tmp_path / "m.json").exists()


def test_dot_over_quoted_propositions_reads_back(capsys, tmp_path):
    # before: "s.dot:10:3: expected an edge 'p -> q [label=\"...\"];' ..." on the DOT symlearn wrote
    dot = tmp_path / "s.dot"
    code, _, err = run(capsys, "ltl", "dfa", 'G(call -> F "door open")', "--dot", dot)
    assert code == 0, err
    code, out, err = run(capsys, "automaton", "explain", dot, "--trace", '[["call"], ["door open"]]')
    assert code == 0 and "ACCEPTED" in out, err


def test_a_json_list_of_traces_on_one_line_gets_a_hint(capsys, tmp_path):
    traces = tmp_path / "t.json"
    traces.write_text('[[["call"], [], ["door open"]], [["call"]]]')
    code, out, err = run(capsys, "ltl", "eval", "F call", "--traces", traces)
    assert code == 2 and "t.json:1:3:" in err and "write each trace on a line of its own" in err


# --- automata ------------------------------------------------------------------------------------------------
def test_reward_machine_text_round_trip_keeps_numbers_with_the_implicit_fail_state(capsys, tmp_path):
    # before: the text came back renumbered 0..5 with 'fail' written out (initial 1, terminal [4, 5])
    text = ("0   # start\r\n[3]\r\n(0,1,'call&!fire',ConstantRewardFunction(0))\r\n"
            "(1,2,'door',ConstantRewardFunction(0.5))\r\n(2,3,'!door',ConstantRewardFunction(1))\r\n"
            "(0,-5,'fire',ConstantRewardFunction(-1))\r\n")
    (tmp_path / "rm.txt").write_bytes(text.encode())
    assert run(capsys, "automaton", "convert", tmp_path / "rm.txt", tmp_path / "rm.json")[0] == 0
    assert run(capsys, "automaton", "convert", tmp_path / "rm.json", tmp_path / "back.txt")[0] == 0
    back = (tmp_path / "back.txt").read_text().splitlines()
    assert back[:2] == ["0", "[3]"] and "(0,-5,'fire',ConstantRewardFunction(-1))" in back and len(back) == 6
    assert run(capsys, "automaton", "convert", tmp_path / "back.txt", tmp_path / "again.json")[0] == 0
    assert json.loads((tmp_path / "again.json").read_text()) == json.loads((tmp_path / "rm.json").read_text())


def test_a_reward_machine_json_needs_no_accepting_states(capsys, tmp_path):
    # before: "rm.json:1:1: accepting: missing field" (a reward machine ends in its terminal states)
    machine = {"format": "symlearn-automaton", "version": 1, "kind": "reward_machine", "alphabet": ["a"],
               "states": 2, "initial": 0, "terminal": [1],
               "transitions": [{"source": 0, "target": 1, "guard": "a", "reward": 1}]}
    (tmp_path / "rm.json").write_text(json.dumps(machine))
    code, out, err = run(capsys, "automaton", "show", tmp_path / "rm.json")
    assert code == 0 and "terminal: 1" in out, err


def test_a_non_ascii_name_in_a_guard_is_told_to_be_quoted(capsys, tmp_path):
    machine = {"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["tea", "ü"], "states": 2,
               "initial": 0, "accepting": [1], "transitions": [{"source": 0, "target": 1, "guard": "tea & !ü"}]}
    (tmp_path / "m.json").write_text(json.dumps(machine, ensure_ascii=False))
    code, out, err = run(capsys, "automaton", "show", tmp_path / "m.json")
    assert code == 2 and "transitions[0].guard" in err and 'quote a name that is not a plain identifier: "ü"' in err


@pytest.mark.parametrize("formula, hint", [
    ("F café", 'quote other names: "café"'),
    ("F a & G !2b", 'quote other names: "2b"'),
    ('F "door', "a quoted name needs its closing quote"),
    ("F a # the goal", "a comment (#) takes a line of its own"),
])
def test_formula_mistakes_from_hand_written_files_get_a_hint(capsys, tmp_path, formula, hint):
    # before: "unexpected character 'é' ..." and no hint
    spec = tmp_path / "f.ltl"
    spec.write_text(f"# mine\n{formula}\n")
    code, out, err = run(capsys, "ltl", "dfa", "--file", spec)
    assert code == 2 and "f.ltl:2:" in err and hint in err


def test_an_undeclared_tlsf_signal_is_named_where_it_is_with_the_declared_one(capsys, tmp_path):
    # before: the column of the formula's start ("10:15") and no hint
    spec = tmp_path / "s.tlsf"
    spec.write_text('INFO {\n TITLE: "x"\n DESCRIPTION: "y"\n SEMANTICS: Finite,Mealy\n TARGET: Mealy\n}\nMAIN {\n'
                    ' INPUTS { req; }\n OUTPUTS { grant; }\n GUARANTEES { G (req -> F Grant); }\n}\n')
    code, out, err = run(capsys, "ltl", "parse", "--tlsf", spec)
    assert code == 2 and "s.tlsf:10:27: GUARANTEES names 'Grant'" in err and "did you mean 'grant'?" in err


def test_rules_learned_with_known_ones_are_scored_and_rechecked_with_them(capsys, cards, tmp_path):
    # before: FNR 0.316 and "misses the truth rule :- finish, cards_left." for the rule given as --known,
    # from learn constraints and from the re-check command its file's header names
    (cards / "truth.lp").write_text(":- deal(P), waiting(P).\n:- finish, cards_left.\n")
    (cards / "domain.toml").write_text((cards / "domain.toml").read_text() + 'truth = "truth.lp"\n')
    known = tmp_path / "known.lp"
    known.write_text("% given\r\n:- finish, cards_left.   % sure\r\n")
    demos = tmp_path / "d.jsonl"
    demos.write_text(_HEADER + ''.join('{"states": [14, 15, 5, 11, 1, 9, 16], "actions": ["shuffle", "deal(\\"Bob\\")", '
                                       '"deal(\\"Alice\\")", "deal(\\"Bob\\")", "wait", "finish"]}\n' for _ in range(3)))
    rules = tmp_path / "r.lp"
    code, out, err = run(capsys, "--json", "learn", "constraints", "--domain", cards, "--demos", demos,
                         "--known", known, "-o", rules)
    doc = json.loads(out)
    assert code == 0 and doc["fnr"] == 0 and doc["known_constraints"] > 0, err
    recheck = [line for line in rules.read_text().splitlines() if "re-check with:" in line][0]
    assert f"--known {known}" in recheck
    code, out, err = run(capsys, "--json", "domain", "check", cards, "--rules", rules, "--known", known)
    check = json.loads(out)
    assert code == 0 and check["fnr"] == 0 and check["missed_truth_rules"] == [] and check["known_rules"]
    assert check["forbidden"] == doc["constraints"]


def test_a_feature_table_by_state_name_is_read_by_the_domain(capsys, tmp_path):
    # before: "features.json: state 0 of 17 has no features: state 0 is not in the feature table"
    folder = _write_cards(tmp_path / "cards")
    lines = (folder / "states.jsonl").read_text().splitlines()
    named = [dict(json.loads(line), name=f"état {i}") for i, line in enumerate(lines)]
    (folder / "states.jsonl").write_text("".join(json.dumps(n, ensure_ascii=False) + "\n" for n in named))
    (folder / "features.json").write_text(json.dumps({"symlearn": "feature-map", "format_version": 1, "names": ["k"],
                                                      "table_by_state": [[n["name"], [i % 4]] for i, n in enumerate(named)]},
                                                     ensure_ascii=False))
    (folder / "domain.toml").write_text((folder / "domain.toml").read_text() + 'features = "features.json"\n')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 0, err
    from symlearn.grounding import Domain

    assert Domain.from_folder(folder).feature_map.features(5).tolist() == [1.0]


def test_a_capitalised_constant_in_the_bias_is_named(capsys, tmp_path):
    # before: "unexpected 'Bob).' ... (hint: declarations look like #modeb(1, p(var(t))). ...)"
    folder = _write_cards(tmp_path / "cards")
    (folder / "bias.las").write_text('#modeb(1, deal(const(player)), (positive)).\n#constant(player, "Alice").\n'
                                     "#constant(player, Bob).\n")
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "bias.las:3:19:" in err
    assert "Bob starts with a capital letter" in err and 'the string "Bob"' in err


def test_a_bias_constant_no_pair_has_is_warned_about(capsys, tmp_path):
    # before: no word; every literal deal(bob) was false and the learner found no rule for Bob
    folder = _write_cards(tmp_path / "cards")
    (folder / "bias.las").write_text('#modeb(1, deal(const(player)), (positive)).\n#constant(player, "Alice").\n'
                                     "#constant(player, bob).\n#modeb(1, empty_deck, (positive)).\n")
    code, out, err = run(capsys, "--json", "domain", "check", folder)
    warnings = json.loads(out)["bias_warnings"]
    assert code == 0 and len(warnings) == 1
    assert "#constant(player, bob): deal/1 never has bob as argument 1" in warnings[0]["message"]
    assert 'did you mean "Bob"?' in warnings[0]["message"] and warnings[0]["line"] == 1


def test_reward_machine_text_with_a_false_guard_or_a_repeated_pair(capsys, tmp_path):
    # before: "r.txt: edge 1 -> 2 has reward 1.0 but its guard is false" (no line), and a second line for
    # the same pair of states "reward machine is not deterministic" (no line)
    (tmp_path / "r.txt").write_text("0\n[2]\n(0, 1, 'c & !n', ConstantRewardFunction(1e-3))\n"
                                    "(1,\t2,'False',ConstantRewardFunction(1))\n(1,2,'True',ConstantRewardFunction(1))\n")
    code, out, err = run(capsys, "automaton", "show", tmp_path / "r.txt")
    assert code == 0 and "1 --[true / r=1]--> 2" in out, err
    (tmp_path / "twice.txt").write_text("0\n[1]\n(0,1,'a',ConstantRewardFunction(1))\n(0,1,'b',ConstantRewardFunction(1))\n")
    code, out, err = run(capsys, "automaton", "show", tmp_path / "twice.txt")
    assert code == 2 and "twice.txt:4:1: a second transition from 0 to 1 (the first is on line 3)" in err
    assert "joined by '|'" in err


@pytest.mark.parametrize("kind, extra", [("dfa", {"accepting": [1]}), ("reward_machine", {"terminal": [1]})])
def test_overlapping_guards_in_an_automaton_file_are_located(capsys, tmp_path, kind, extra):
    # before: "m.json: DFA is not deterministic: ..." with no line or field
    edge = {"reward": 0} if kind == "reward_machine" else {}
    machine = {"format": "symlearn-automaton", "version": 1, "kind": kind, "alphabet": ["a", "b"], "states": 2,
               "initial": 0, **extra, "transitions": [{"source": 0, "target": 1, "guard": "a", **edge},
                                                      {"source": 0, "target": 0, "guard": "b", **edge}]}
    (tmp_path / "m.json").write_text(json.dumps(machine, indent=1))
    code, out, err = run(capsys, "automaton", "show", tmp_path / "m.json")
    assert code == 2 and "m.json:" in err and "transitions[1].guard:" in err and "not deterministic" in err
    assert err.split("m.json:")[1].split(":")[0].isdigit()  # a line number


def test_a_table_labeling_by_state_name_is_read_by_the_domain(capsys, tmp_path):
    # before: "labeling.json:1:..: table[0]: the labeling labels state 'état 0', which is not one of the domain's ..."
    folder = _write_cards(tmp_path / "cards")
    lines = (folder / "states.jsonl").read_text().splitlines()
    named = [dict(json.loads(line), name=f"état {i}") for i, line in enumerate(lines)]
    (folder / "states.jsonl").write_text("".join(json.dumps(n, ensure_ascii=False) + "\n" for n in named))
    (folder / "labeling.json").write_text(json.dumps({"symlearn": "labeling", "format_version": 1, "kind": "table",
                                                      "propositions": [{"name": "over", "meaning": ""}],
                                                      "table": [["état 16", ["over"]]]}, ensure_ascii=False))
    (folder / "domain.toml").write_text((folder / "domain.toml").read_text() + 'labeling = "labeling.json"\n')
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 0 and "labeling: over" in out, err
    from symlearn.grounding import Domain

    assert Domain.from_folder(folder).labeling.label(16) == {"over"}


@pytest.mark.parametrize("text", ['[[["call"], []], [["call"]]]', '[["call"], []]\n[["call"]]\n'])
def test_explaining_a_file_of_several_traces_says_it_runs_one(capsys, tmp_path, text):
    # before: "trace step 0 must be a list of proposition names" / "not valid JSON: Extra data", hint [["a"], ...]
    dfa = tmp_path / "f.json"
    assert run(capsys, "ltl", "dfa", "F call", "--save", dfa)[0] == 0
    (tmp_path / "t.json").write_text(text)
    code, out, err = run(capsys, "automaton", "explain", dfa, "--trace", tmp_path / "t.json")
    assert code == 2 and "explain runs one trace" in err


def test_learn_dnf_on_one_point_warns_that_the_safe_set_is_that_point(capsys, tmp_path):
    # before: "4 rules over 2 features from 1 points" and no word
    demos = tmp_path / "one.jsonl"
    demos.write_text(_HEADER + '{"states": [[1.5, -2]]}\n')
    code, out, err = run(capsys, "learn", "dnf", "--demos", demos, "-o", tmp_path / "one.dnf")
    assert code == 0 and "only 1 distinct demonstration point(s)" in out + err
    assert "# warning: only 1 distinct" in (tmp_path / "one.dnf").read_text()


def test_a_directive_in_a_rule_file_says_to_delete_it(capsys, cards, tmp_path):
    rules = tmp_path / "r.lp"
    rules.write_bytes(b"% edited\r\n:- deal(P), waiting(P).   %* a block\r\n comment *%\r\n#show deal/1.\r\n")
    code, out, err = run(capsys, "domain", "check", cards, "--rules", rules)
    assert code == 2 and "r.lp:4:1: only rules are allowed in a hypothesis" in err and "delete this line" in err


def test_a_labeling_function_wanting_the_environment_is_named_with_a_domain(capsys, cards, tmp_path):
    # before: "d.jsonl: labeling function label needs the environment ... record(env, policy, n, labeler=...)"
    (tmp_path / "lab.py").write_text('PROPOSITIONS = ["over"]\ndef label(o, info, env):\n    return []\n')
    demos = tmp_path / "d.jsonl"
    demos.write_text(_HEADER + '{"states": [14, 15, 16], "actions": ["shuffle", "finish"]}\n')
    code, out, err = run(capsys, "learn", "spec", "--domain", cards, "--demos", demos,
                         "--labeling", f"{tmp_path / 'lab.py'}:label")
    assert code == 2 and f"{tmp_path / 'lab.py'}: labeling function label takes a third parameter" in err
    assert "def label(state, info)" in err


def test_a_reward_machine_is_refused_as_hoa_and_its_drawing_says_to_read_the_json(capsys, tmp_path):
    # before: rm.hoa written with no accepting state (its language empty, rewards gone) without a word; the
    # DOT drawing of the machine refused as "unexpected character '/' in guard 'true / 0'" with no way out
    (tmp_path / "rm.txt").write_text("0\n[1]\n(0,1,'a',ConstantRewardFunction(1))\n(0,0,'!a',ConstantRewardFunction(0))\n")
    code, out, err = run(capsys, "automaton", "convert", tmp_path / "rm.txt", tmp_path / "rm.hoa")
    assert code == 2 and "is a reward machine: HOA holds" in err and not (tmp_path / "rm.hoa").exists()
    assert run(capsys, "automaton", "convert", tmp_path / "rm.txt", tmp_path / "rm.dot")[0] == 0
    code, out, err = run(capsys, "automaton", "show", tmp_path / "rm.dot")
    assert code == 2 and "read the automaton from its .json" in err


def test_a_step_after_the_terminal_state_says_to_end_the_demonstration_there(capsys, cards, tmp_path):
    # before: the hint asked whether the demonstrations were recorded in another environment
    demos = tmp_path / "after.jsonl"
    demos.write_text(_HEADER + '{"states": [14, 15, 16, 16], "actions": ["shuffle", "finish", "wait"]}\n')
    code, out, err = run(capsys, "learn", "constraints", "--domain", cards, "--demos", demos)
    assert code == 2 and "step 2: action 'wait' is not available in state '16' (after the episode ended)" in err
    assert "end the demonstration there" in err


def test_a_list_of_background_programs_is_located_with_the_way_out(capsys, tmp_path):
    # before: "domain.toml: key 'background' must be a string, got list" (no line, no way out)
    folder = _write_cards(tmp_path / "cards")
    text = (folder / "domain.toml").read_text().replace('background = "bk.lp"', 'background = ["bk.lp", "more.lp"]')
    (folder / "domain.toml").write_text(text)
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and "domain.toml:2: key 'background' must be a string, got list" in err
    assert '#include "more.lp".' in err


def test_a_long_name_ending_in_a_foreign_character_is_reported_at_once(capsys):
    # before: the hint's search for an operator word ("eventually door") was quadratic in the name:
    # 20,000 characters took 8 s, 40,000 took 29 s
    import time

    started = time.perf_counter()
    code, out, err = run(capsys, "ltl", "parse", "F " + "a" * 200_000 + "é")
    assert code == 2 and "quote other names" in err
    assert time.perf_counter() - started < 5
