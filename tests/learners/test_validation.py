"""Validation on held-out demonstrations (issue #25 section 2): the split, the reports, the CLI."""

from __future__ import annotations

import json

import numpy as np
import pytest
import warehouse_domain as wh
from cli_runner import run

from symlearn.data import Demonstrations, Trajectory
from symlearn.errors import DataError, SymlearnError
from symlearn.learners.validation import Validation, forbidden_pairs_report, holdout, unsafe_states_report


def numbered(n: int) -> Demonstrations:
    return Demonstrations([Trajectory(states=[i, i + 1], actions=[0]) for i in range(n)])


def test_holdout_splits_whole_demonstrations_reproducibly():
    demos = numbered(10)
    train, held = holdout(demos, 0.3, seed=4)
    assert (len(train), len(held)) == (7, 3)
    starts = sorted(int(t.states[0]) for t in list(train) + list(held))
    assert starts == list(range(10))  # a partition
    again_train, again_held = holdout(demos, 0.3, seed=4)
    assert [t.states[0] for t in again_held] == [t.states[0] for t in held]
    assert [t.states[0] for t in holdout(demos, 0.3, seed=5)[1]] != [t.states[0] for t in held]
    # at least one on each side
    assert [len(x) for x in holdout(numbered(2), 0.01)] == [1, 1]
    assert [len(x) for x in holdout(numbered(2), 0.99)] == [1, 1]


@pytest.mark.parametrize("fraction", [0, 1, 1.5, -0.1, True])
def test_fraction_must_lie_strictly_between_0_and_1(fraction):
    with pytest.raises(SymlearnError, match="strictly between 0 and 1"):
        holdout(numbered(5), fraction)


def test_one_demonstration_cannot_be_validated():
    with pytest.raises(DataError, match="at least 2 demonstrations"):
        holdout(numbered(1), 0.5)


def test_reports_count_what_the_constraint_forbids():
    forbidden = np.zeros((4, 2), dtype=bool)
    forbidden[2, 1] = True
    episodes = [(np.array([0, 1, 2]), np.array([0, 0])), (np.array([2, 3, 3]), np.array([1, 0]))]
    report = forbidden_pairs_report(forbidden, episodes, 0.5, 2, lambda s, a: f"s{s}/a{a}")
    assert (report.steps, report.forbidden, report.share) == (4, 1, 0.25)
    assert report.first == "held-out demonstration 1, step 0: s2/a1" and "1 of 4 held-out expert steps" in report.warning()
    assert forbidden_pairs_report(np.zeros((4, 2), dtype=bool), episodes, 0.5, 2).warning() is None
    states = [np.array([[0.0, 0.0], [2.0, 0.0]])]
    report = unsafe_states_report(lambda X: X[:, 0] > 1, states, ["x", "y"], 0.2, 4)
    assert (report.steps, report.forbidden, report.unit) == (2, 1, "states")
    assert report.first == "held-out demonstration 0, state 1: x=2, y=0"
    assert Validation(0.2, 4, 1, 2, 1).as_dict()["share"] == 0.5


def test_cli_constraints_validation_catches_an_over_strict_rule(capsys, tmp_path):
    folder = wh.write_warehouse(tmp_path / "warehouse")
    few, many = tmp_path / "few.jsonl", tmp_path / "many.jsonl"
    wh.expert_demonstrations(5, seed=0).save(few)
    wh.expert_demonstrations(60, seed=0).save(many)
    # a random planner and no evidence test (the learner before 2026-12-08), so that 3 deliveries
    # give a rule to catch: the defaults learn none from them
    legacy = ("--rationality", "2.8", "--min-evidence", "0")
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", few, "--validation", 0.4,
                         "--json", *legacy)
    assert code == 0, err
    doc = json.loads(out)
    v = doc["validation"]
    assert (v["n_train"], v["n_held_out"]) == (3, 2) and v["steps"] > 0
    # 3 deliveries are too few: a spurious rule forbids a held-out expert step, and the truth agrees
    assert v["forbidden"] > 0 and doc["fpr"] > 0
    assert len(doc["warnings"]) == 1 and "held-out expert steps" in doc["warnings"][0]
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", many, "--validation", 0.2,
                         "--json")
    doc = json.loads(out)
    assert doc["validation"]["forbidden"] == 0 and doc["warnings"] == [] and doc["fpr"] == 0.0
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", few, "--validation", 0.4,
                         *legacy)
    assert "validation: " in out and "warning: the learned constraint forbids" in out
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", few, "--validation", 2)
    assert code == 2 and "strictly between 0 and 1" in err


def test_cli_dnf_validation(capsys, tmp_path):
    rng = np.random.default_rng(0)
    path = tmp_path / "demos.npz"
    Demonstrations([Trajectory(states=rng.uniform(0, 1, (40, 2))) for _ in range(10)]).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--validation", 0.3, "--json")
    assert code == 0, err
    v = json.loads(out)["validation"]
    assert (v["n_train"], v["n_held_out"], v["unit"]) == (7, 3, "states") and v["steps"] == 120
    assert 0 <= v["forbidden"] <= v["steps"]


def test_cli_dnf_validation_is_written_into_the_rule_files_header(capsys, tmp_path):
    from symlearn.logic import dnf

    rng = np.random.default_rng(1)
    path, rules = tmp_path / "demos.npz", tmp_path / "rules.dnf"
    Demonstrations([Trajectory(states=rng.uniform(0, 1, (40, 2))) for _ in range(10)]).save(path)
    code, out, err = run(capsys, "learn", "dnf", "--demos", path, "--validation", 0.3, "-o", rules, "--json")
    assert code == 0, err
    doc = json.loads(out)
    text = rules.read_text()
    header = [line for line in text.splitlines() if line.startswith("#")]
    v = doc["validation"]
    assert any(line.startswith(f"# validation: {v['forbidden']} of {v['steps']} held-out expert states unsafe")
               for line in header)
    assert str(dnf.load(rules)) == doc["formula"]  # the extra header lines are comments
    assert all(line.startswith("#") for line in text.splitlines()[:len(header)])
