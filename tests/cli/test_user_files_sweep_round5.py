"""A fifth sweep of files a researcher brings (issue 25): a kitchen domain whose true rules join an
object and a place through two variables (``:- put, at(P), hot(P), holding(O), fragile(O).``),
hand-edited DNF files re-checked against the demonstrations they came from, reward-machine text
with numbers past float range, read through the CLI at its defaults."""

from __future__ import annotations

import json
import random

import numpy as np
import pytest
from cli_runner import run

# --- a kitchen: places fridge, counter, stove, sink in a row; holding nothing, an egg, a pan or a glass ------
_PLACES = ["fridge", "counter", "stove", "sink"]
_OBJECTS = ["egg", "pan", "glass"]
_ACTIONS = ["move(-1)", "move(1)", "take(egg)", "take(pan)", "take(glass)", "put", "wait"]
_STATES = [(p, h) for p in range(4) for h in ["none"] + _OBJECTS] + ["end"]
_TRUTH = (":- put, at(P), hot(P), holding(O), fragile(O).\n:- take(O), busy.\n"
          ":- put, at(P), wet(P), holding(O), metal(O).\n")


def _step(s, a):
    """The next state (None: the move does not exist). A pan put on the stove ends the episode."""
    p, h = s
    if a.startswith("move("):
        t = p + int(a[5:-1])
        return (t, h) if 0 <= t <= 3 else None
    if a.startswith("take("):
        return (p, a[5:-1]) if p == 0 else s
    if a == "put" and h != "none":
        return "end" if (p, h) == (2, "pan") else (p, "none")
    return s


def _forbidden(s, a):
    p, h = s
    return ((a == "put" and h in ("egg", "glass") and p == 2) or (a.startswith("take(") and h != "none")
            or (a == "put" and h == "pan" and p == 3))


def _write_kitchen(folder):
    folder.mkdir()
    index = {s: i for i, s in enumerate(_STATES)}
    n_s, n_a = len(_STATES), len(_ACTIONS)
    P = np.zeros((n_s, n_a, n_s))
    available = np.ones((n_s, n_a), dtype=bool)
    for i, s in enumerate(_STATES):
        for a, name in enumerate(_ACTIONS):
            t = s if s == "end" else _step(s, name)
            available[i, a] = t is not None
            P[i, a, index[s if t is None else t]] = 1.0
    rewards = np.array([[10.0 if s != "end" and _step(s, n) == "end" else -1.0 for n in _ACTIONS] for s in _STATES])
    np.savez(folder / "model.npz", transitions=P, available=available, rewards=rewards,
             initial=np.array([float(s != "end" and s[1] == "none") for s in _STATES]) / 4,
             terminal=np.array([s == "end" for s in _STATES]))
    facts = ["served." if s == "end" else f"at({_PLACES[s[0]]})." + (f" holding({s[1]})." if s[1] != "none" else "")
             for s in _STATES]
    (folder / "states.jsonl").write_text("".join(json.dumps({"id": i, "facts": f}) + "\n" for i, f in enumerate(facts)))
    (folder / "actions.jsonl").write_text("".join(json.dumps({"id": a, "atom": n}) + "\n" for a, n in enumerate(_ACTIONS)))
    (folder / "bk.lp").write_text("hot(stove). wet(sink).\nfragile(egg). fragile(glass). metal(pan).\n"
                                  "busy :- holding(_).\n")
    (folder / "bias.las").write_text("".join(f"#modeb(1, {m}, (positive)).\n" for m in [
        "put", "take(var(obj))", "at(var(place))", "holding(var(obj))", "fragile(var(obj))", "metal(var(obj))",
        "hot(var(place))", "wet(var(place))", "busy"]) + "#maxv(2).\n")
    (folder / "truth.lp").write_text(_TRUTH)
    (folder / "domain.toml").write_text('name = "kitchen"\nbackground = "bk.lp"\nbias = "bias.las"\n'
                                        'model = "model.npz"\nstates = "states.jsonl"\nactions = "actions.jsonl"\n'
                                        'truth = "truth.lp"\n')
    # a cook who picks among the allowed moves at random, but heads for the stove with a pan twice as often
    rng = random.Random(0)
    lines = ['{"symlearn": "demonstrations", "format_version": 1}']
    for _ in range(80):
        s = (rng.randrange(4), "none")
        states, actions = [index[s]], []
        while s != "end" and len(actions) < 25:
            allowed = [a for a in _ACTIONS if _step(s, a) is not None and not _forbidden(s, a)]
            a = rng.choice(allowed + [a for a in allowed if a == "put" or a.startswith("take")])
            s = _step(s, a)
            states.append(index[s])
            actions.append(a)
        lines.append(json.dumps({"states": states, "actions": actions}))
    (folder.parent / "cook.jsonl").write_text("\n".join(lines) + "\n")
    return folder


@pytest.fixture(scope="module")
def kitchen(tmp_path_factory):
    return _write_kitchen(tmp_path_factory.mktemp("k") / "kitchen")


def test_a_rule_joining_two_variables_is_learned_with_max_body(capsys, kitchen, tmp_path):
    # before: no way to search rules of more than 3 body literals from a domain folder (--max-body was
    # an unknown option), so the fragile-on-the-stove rule was missed (FNR > 0) with no word why
    rules = tmp_path / "r.lp"
    code, out, err = run(capsys, "--json", "learn", "constraints", "--domain", kitchen, "--demos",
                         kitchen.parent / "cook.jsonl", "--max-body", "5", "-o", rules)
    assert code == 0, err
    doc = json.loads(out)
    joined = [r for r in doc["rules"] if "fragile(" in r and "hot(" in r]
    assert joined and doc["max_body"] == 5, doc["rules"]
    # the metal-on-the-wet-board rule is the evidence test's to judge: the random cook never stood
    # there with metal, so learning it gains the demonstrations under 1 nat; without the test
    # every truth rule comes back
    assert doc["fnr"] < 0.05 and doc["stop_reason"] == "min_evidence"
    code, out, err = run(capsys, "--json", "learn", "constraints", "--domain", kitchen, "--demos",
                         kitchen.parent / "cook.jsonl", "--max-body", "5", "--min-evidence", "0")
    assert code == 0, err
    assert json.loads(out)["fnr"] == 0


def test_the_stop_line_and_the_unexplained_note_name_the_body_length(capsys, kitchen, tmp_path):
    # before: "stopped: no undemonstrated pair the bias can forbid is left" while a truth rule was
    # missed (FNR 0.077): nothing said the bias's rules were cut at 3 literals
    code, out, err = run(capsys, "learn", "constraints", "--domain", kitchen, "--demos",
                         kitchen.parent / "cook.jsonl")
    assert code == 0, err
    assert "can forbid (with rules of at most 3 body literals, --max-body) is left" in out

    from symlearn.learners.constraints.logic_constraint_inference import Unexplained, unexplained_lines

    lines = unexplained_lines([Unexplained(1, 9, 5, "stove/egg / put", 0.01)], max_body=4)
    assert "or rules longer than 4 body literals (--max-body)" in lines[0]


@pytest.mark.parametrize("args, message", [
    (["--max-body", "0"], "--max-body must be at least 1, got 0"),
    (["--max-body", "4", "--method", "ml"], "--max-body bounds the rules of --method logic"),
])
def test_a_wrong_max_body_is_one_line(capsys, kitchen, args, message):
    code, out, err = run(capsys, "learn", "constraints", "--domain", kitchen, "--demos",
                         kitchen.parent / "cook.jsonl", *args)
    assert code == 2 and message in err and "Traceback" not in err


def test_the_domain_keeps_one_space_per_body_length(kitchen):
    from symlearn.grounding import Domain

    d = Domain.from_folder(kitchen)
    longest = max(len(c.body) for c in d.space(5).candidates)
    assert longest == 5 and max(len(c.body) for c in d.hypothesis_space.candidates) == 3
    assert d.space(5) is d.space(5)


# --- a hand-edited DNF re-checked against the demonstrations it was learned from ----------------------------
def _corner_demos(path, crlf=False):
    rng = random.Random(1)
    lines = ['\ufeff{"symlearn": "demonstrations", "format_version": 1, "state_kind": "features"}']
    for _ in range(6):
        states = [{"x": round(rng.random() * 0.6, 3), "y": round(rng.random(), 3)} for _ in range(10)]
        lines.append(json.dumps({"states": states}).replace(", ", ",\t"))
    path.write_bytes(("\r\n" if crlf else "\n").join(lines).encode() + b"\r\n")
    return path


def test_dnf_eval_reads_the_demonstrations_states(capsys, tmp_path):
    # before: "corner.jsonl: not a readable NPZ file" (--points only); an NPZ of demonstrations was refused
    demos = _corner_demos(tmp_path / "corner.jsonl", crlf=True)
    rules = tmp_path / "edited.dnf"
    rules.write_text("# tightened by hand\nx > 0.5 & y > 0.5\nx > 0.9\n")
    code, out, err = run(capsys, "--json", "dnf", "eval", rules, "--demos", demos)
    assert code == 0, err
    doc = json.loads(out)
    xs = [(s["x"], s["y"]) for line in demos.read_text(encoding="utf-8-sig").splitlines()[1:]
          for s in json.loads(line)["states"]]
    expected = [x > 0.5 and y > 0.5 or x > 0.9 for x, y in xs]
    assert doc["n_points"] == 60 and doc["unsafe"] == expected and doc["unsafe_count"] == sum(expected) > 0
    first = expected.index(True)
    assert doc["first_unsafe"] == {"demonstration": first // 10, "step": first % 10, "conjunction": 0}
    code, out, err = run(capsys, "dnf", "eval", rules, "--demos", demos)
    assert "of 60 demonstrated states unsafe" in out and f"first: demonstration {first // 10}, step {first % 10}" in out


def test_dnf_eval_on_vector_demonstrations_uses_learn_dnf_names(capsys, tmp_path):
    from symlearn.data import Demonstrations, Trajectory

    demos = tmp_path / "v.npz"
    Demonstrations([Trajectory(states=np.array([[0.1, 0.2], [0.8, 0.9]]))]).save(demos)
    rules = tmp_path / "r.dnf"
    rules.write_text("x1 > 0.5\n")
    code, out, err = run(capsys, "--json", "dnf", "eval", rules, "--demos", demos)
    assert code == 0, err
    assert json.loads(out)["unsafe"] == [False, True]
    code, out, err = run(capsys, "--json", "dnf", "eval", rules, "--demos", demos, "--features", "x0,x1")
    assert code == 0 and json.loads(out)["unsafe"] == [False, True]
    # rules over the names learn dnf --env gave: the hint says to name the columns, not "x1 for x"
    rules.write_text("y > 0.5\n")
    code, out, err = run(capsys, "dnf", "eval", rules, "--demos", demos)
    assert code == 2 and "the demonstrations' states are unnamed vectors, read as x0, x1: name their columns" in err
    code, out, err = run(capsys, "--json", "dnf", "eval", rules, "--demos", demos, "--features", "x,y")
    assert code == 0 and json.loads(out)["unsafe"] == [False, True]


def test_a_feature_renamed_in_the_rules_is_named_with_the_close_one(capsys, tmp_path):
    demos = _corner_demos(tmp_path / "corner.jsonl")
    rules = tmp_path / "renamed.dnf"
    rules.write_text("X > 0.5 & yy > 0.5\n")
    code, out, err = run(capsys, "dnf", "eval", rules, "--demos", demos)
    assert code == 2 and "the rules use features X, yy, which the demonstrations do not have" in err
    assert "did you mean x for X, y for yy?" in err


def test_dnf_eval_of_id_demonstrations_says_why(capsys, kitchen, tmp_path):
    rules = tmp_path / "r.dnf"
    rules.write_text("x > 1\n")
    code, out, err = run(capsys, "dnf", "eval", rules, "--demos", kitchen.parent / "cook.jsonl")
    assert code == 2 and "states are discrete ids, not numeric features" in err


# --- reward-machine text -------------------------------------------------------------------------------------
def test_a_reward_past_float_range_is_located(capsys, tmp_path):
    # before: "rm.txt: reward of edge 0 -> 1 must be a finite number, got inf" (no line, no column)
    machine = tmp_path / "rm.txt"
    machine.write_text("0\n[2]\n(0,1,'a',ConstantRewardFunction(1e400))\n(1,2,'b',ConstantRewardFunction(1))\n")
    code, out, err = run(capsys, "automaton", "show", machine)
    assert code == 2 and "rm.txt:3:33: reward 1e400 is too large: it reads as infinity" in err


# --- an edited SPEC.ltl re-checked on the unlabelled demonstrations learn spec read -------------------------
def _kitchen_labeling(path):
    table = [[i, [p for p, held in (("pan", "pan"), ("egg", "egg")) if s != "end" and s[1] == held]
              + (["stove"] if s != "end" and s[0] == 2 else []) + (["served"] if s == "end" else [])]
             for i, s in enumerate(_STATES)]
    path.write_text(json.dumps({"symlearn": "labeling", "format_version": 1, "kind": "table",
                                "propositions": [{"name": n, "meaning": ""} for n in ("pan", "egg", "stove", "served")],
                                "table": table}))
    return path


def test_ltl_eval_labels_unlabelled_demonstrations_with_the_labeling_file(capsys, kitchen, tmp_path):
    # before: "these demonstrations have no labels, so a formula has nothing to read" and no way to
    # use the SPEC.labeling.json that learn spec writes beside SPEC.ltl
    labeling = _kitchen_labeling(tmp_path / "spec.labeling.json")
    spec = tmp_path / "spec.ltl"
    spec.write_text("# edited by hand: the pan is on the stove just before serving\nF (pan & stove & X served)\n\n")
    demos = kitchen.parent / "cook.jsonl"
    code, out, err = run(capsys, "--json", "ltl", "eval", "--file", spec, "--demos", demos, "--labeling", labeling)
    assert code == 0, err
    index = {i: s for i, s in enumerate(_STATES)}
    ended = [index[json.loads(line)["states"][-1]] == "end" for line in demos.read_text().splitlines()[1:]]
    assert json.loads(out)["results"] == ended and 0 < sum(ended) < len(ended)
    code, out, err = run(capsys, "--json", "ltl", "eval", "G !egg", "--demos", demos, "--labeling", labeling)
    took_egg = [any(index[i] != "end" and index[i][1] == "egg" for i in json.loads(line)["states"])
                for line in demos.read_text().splitlines()[1:]]
    assert code == 0 and json.loads(out)["results"] == [not t for t in took_egg] and any(took_egg)


def test_a_labeling_that_knows_none_of_the_states_is_refused(capsys, kitchen, tmp_path):
    labeling = _kitchen_labeling(tmp_path / "l.json")
    demos = tmp_path / "named.jsonl"
    demos.write_text('{"symlearn": "demonstrations", "format_version": 1}\n{"states": ["a", "b"]}\n')
    code, out, err = run(capsys, "ltl", "eval", "F pan", "--demos", demos, "--labeling", labeling)
    assert code == 2 and "none of the demonstrations' states ('a', 'b', ...) is in the labeling's table" in err
    corner = _corner_demos(tmp_path / "corner.jsonl")
    code, out, err = run(capsys, "ltl", "eval", "F pan", "--demos", corner, "--labeling", labeling)
    assert code == 2 and "Traceback" not in err and "states are named features" in err
    code, out, err = run(capsys, "ltl", "eval", "F pan", "--traces", demos, "--labeling", labeling)
    assert code == 2 and "--labeling labels the states of --demos" in err


def test_a_feature_labeling_labels_feature_demonstrations(capsys, tmp_path):
    corner = _corner_demos(tmp_path / "corner.jsonl")
    labeling = tmp_path / "f.json"
    labeling.write_text(json.dumps({"symlearn": "labeling", "format_version": 1, "kind": "features",
                                    "features": {"symlearn": "feature-map", "format_version": 1, "names": ["x", "y"]},
                                    "propositions": [{"name": "right", "meaning": "", "when": "x > 0.5"}]}))
    code, out, err = run(capsys, "--json", "ltl", "eval", "G !right", "--demos", corner, "--labeling", labeling)
    assert code == 0, err
    expected = [all(s["x"] <= 0.5 for s in json.loads(line)["states"])
                for line in corner.read_text(encoding="utf-8-sig").splitlines()[1:]]
    assert json.loads(out)["results"] == expected


# --- sub-goal tours with a broken one-frame recording --------------------------------------------------------
def test_a_demonstration_that_visits_no_subgoal_is_warned_about(capsys, tmp_path):
    # before: "plan: (stop at once) (p = 0.5)" from one tour and one one-frame recording, no word why
    rng = random.Random(3)
    stations = [(0.1, 0.1), (0.9, 0.1), (0.5, 0.9)]
    states, x, y = [], 0.5, 0.5
    for tx, ty in stations:
        while abs(tx - x) + abs(ty - y) > 0.05:
            d = ((tx - x) ** 2 + (ty - y) ** 2) ** 0.5
            x, y = x + 0.05 * (tx - x) / d, y + 0.05 * (ty - y) / d
            states.append({"x": x, "y": y})
        states += [{"x": tx + rng.gauss(0, 0.005), "y": ty + rng.gauss(0, 0.005)} for _ in range(8)]
        x, y = tx, ty
    demos = tmp_path / "tours.jsonl"
    demos.write_text('{"symlearn": "demonstrations", "format_version": 1, "state_kind": "features"}\n'
                     + json.dumps({"states": states}) + "\n" + json.dumps({"states": [{"x": 0.5, "y": 0.5}]}) + "\n")
    code, out, err = run(capsys, "--json", "learn", "pdfa", "--demos", demos, "--features", "x,y")
    assert code == 0, err
    warnings = json.loads(out)["warnings"]
    assert any("1 of 2 demonstrations visit no sub-goal (demonstration 1 (1 frame))" in w for w in warnings)


# --- demonstrations under a suffix symlearn does not read -----------------------------------------------------
@pytest.mark.parametrize("name, body, hint", [
    ("demos.json", '{"symlearn": "demonstrations", "format_version": 1}\n{"states": [{"x": 1}]}\n',
     "the file holds JSONL demonstrations (a header line, one trajectory per line): rename it demos.jsonl"),
    ("list.json", '[{"states": [{"x": 1}]}]', "demonstrations in JSON are JSONL: a header line"),
    ("table.csv", "x,y\n0.1,0.2\n", "tables are not read as demonstrations: write one line per episode"),
])
def test_a_demonstrations_file_under_another_suffix_says_what_to_do(capsys, tmp_path, name, body, hint):
    # before: only "unknown demonstrations format '.json'" with the list of suffixes
    path = tmp_path / name
    path.write_bytes(b"\xef\xbb\xbf" + body.encode())
    code, out, err = run(capsys, "learn", "dnf", "--demos", path)
    assert code == 2 and f"{name}: unknown demonstrations format" in err and hint in err


# --- a hand-edited rule whose conditions never hold together ----------------------------------------------------
def test_a_rule_that_forbids_nothing_is_warned_about_at_its_line(capsys, kitchen, tmp_path):
    # before: "rules (2) forbid 72 pairs" and nothing about the second rule, which can never fire
    rules = tmp_path / "edited.lp"
    rules.write_text(":- take(O), busy.\n% my change\n:- put, holding(O), at(P), hot(P), fragile(O), metal(O).\n"
                     ":- put, at(P), holding(O), fragile(o).\n")
    code, out, err = run(capsys, "--json", "domain", "check", kitchen, "--rules", rules)
    assert code == 0, err
    warnings = json.loads(out)["warnings"]
    idle = [w for w in warnings if "forbids no state-action pair" in w["message"]]
    assert [(w["line"], w["column"]) for w in idle] == [(3, 1)]      # line 4 is warned about for its 'o' already
    assert any(w["line"] == 4 and "never has o as argument 1" in w["message"] for w in warnings)
    code, out, err = run(capsys, "domain", "check", kitchen, "--rules", rules)
    assert "warning: " in out + err and "edited.lp:3:1: rule :- put, holding(O), at(P), hot(P), fragile(O), metal(O). " \
        "forbids no state-action pair" in out + err


def test_a_formula_with_no_split_says_it_only_bounds_the_range(capsys, tmp_path):
    # before: "x < 0 / x > 1 / y < 0 / y > 1" for an expert who avoids the corner x > 0.7 & y > 0.7,
    # and nothing said the inside of the range was left alone (FNR 1 on the corner)
    rng = random.Random(2)
    lines = ['{"symlearn": "demonstrations", "format_version": 1, "state_kind": "features"}']
    for _ in range(20):
        states = []
        while len(states) < 30:
            x, y = rng.random(), rng.random()
            if not (x > 0.7 and y > 0.7):
                states.append({"x": x, "y": y})
        lines.append(json.dumps({"states": states}))
    demos = tmp_path / "corner.jsonl"
    demos.write_text("\n".join(lines) + "\n")
    out_file = tmp_path / "c.dnf"
    code, out, err = run(capsys, "--json", "learn", "dnf", "--demos", demos, "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert len(doc["leaves"]) == 1 and any(n.startswith("no split: the rules only bound") for n in doc["notes"])
    assert "# no split: the rules only bound each feature's range" in out_file.read_text()
