"""Rule support (learners/constraints/rule_support.py): how much likelier the demonstrations are
with each learned rule, the planner's rationality refitted with and without it."""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from symlearn.data import load
from symlearn.grounding import Domain
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
from symlearn.learners.constraints.rule_support import WEAK_SUPPORT, rule_support

GUIDE = Path(__file__).resolve().parents[3] / "docs" / "guide"


@pytest.fixture(scope="module")
def floor(tmp_path_factory):
    """The guide's floor: a rug the careful driver goes round, every step (waiting too) costing 1."""
    folder = tmp_path_factory.mktemp("floor")
    subprocess.run([sys.executable, str(GUIDE / "make_domain.py"), "--episodes", "20"], cwd=folder, check=True,
                   capture_output=True, timeout=120)
    return Domain.from_folder(folder / "floor_domain"), load(folder / "floor_demos.jsonl")


def test_the_rug_is_needed_and_waiting_is_not(floor):
    domain, demos = floor
    support = {s.rule: s for s in rule_support(domain, domain.episodes(demos), [":- wait.", ":- move(D), rug_ahead(D)."],
                                               "given", 30)}
    rug, wait = support[":- move(D), rug_ahead(D)."], support[":- wait."]
    assert rug.gain > 50 and not rug.weak  # without it even a deliberate planner crosses the rug
    assert wait.gain < WEAK_SUPPORT and wait.weak  # a deliberate planner never waits either
    assert rug.rationality_without < rug.rationality_with  # the detour looks random without the rug rule


def test_the_learner_warns_about_the_rule_it_did_not_need(floor):
    domain, demos = floor
    from symlearn.learners.constraints.rule_support import WeakRuleWarning

    with pytest.warns(WeakRuleWarning, match=r"rule :- wait\. is weakly supported"):
        # a random planner (the temperature fitted once without the rug rule) and no evidence test:
        # the defaults do not learn `:- wait.` at all (test_logic_evidence.py)
        learner = LogicConstraintInference(iterations=20, reward="given", min_evidence=None,
                                           refit_rationality=False).fit(demos, domain)
    assert ":- wait." in learner.rules_ and [r.rule for r in learner.rule_support_ if r.weak] == [":- wait."]
    assert learner.result_.metrics["weak_rules"] == 1
    text = learner.artefact_text()
    assert "% Weakly supported" in text and "%   :- wait.  (0.00 nats)" in text
    with warnings.catch_warnings():  # with the sparse reward nothing is fitted: measured, not reported
        warnings.simplefilter("error")
        sparse = LogicConstraintInference(iterations=20, reward="sparse").fit(demos, domain)
    assert sparse.rule_support_ and sparse.result_.metrics["weak_rules"] == 0
    assert "Weakly supported" not in sparse.artefact_text()


def test_no_rules_no_support(floor):
    domain, demos = floor
    assert rule_support(domain, domain.episodes(demos), [], "given", 30) == []


def test_the_cli_prints_it_as_a_note_not_a_warning(capsys, floor, tmp_path):
    import json
    import subprocess as sp

    from cli_runner import run

    folder = tmp_path / "f"
    sp.run([sys.executable, str(GUIDE / "make_domain.py"), "--episodes", "20"], cwd=tmp_path, check=True,
           capture_output=True, timeout=120)
    legacy = ("--rationality", "1.6332", "--min-evidence", "0")  # the temperature fitted without the rug rule
    code, out, err = run(capsys, "learn", "constraints", "--domain", tmp_path / "floor_domain", "--demos",
                         tmp_path / "floor_demos.jsonl", "--json", "-q", *legacy)
    assert code == 0, err
    doc = json.loads(out)
    assert doc["warnings"] == [] and len(doc["notes"]) == 1 and "rule :- wait. is weakly supported" in doc["notes"][0]
    assert [r["rule"] for r in doc["rule_support"] if r["weak"]] == [":- wait."]
    code, out, err = run(capsys, "learn", "constraints", "--domain", tmp_path / "floor_domain", "--demos",
                         tmp_path / "floor_demos.jsonl", *legacy)
    assert "note: rule :- wait. is weakly supported" in out and "warning:" not in out


def test_two_spellings_of_one_needed_rule_are_not_both_weak(floor):
    """Each of two rules forbidding the same pairs costs nothing to drop while the other stays;
    checked together, one is needed and the other, reported weak, names it."""
    domain, demos = floor
    rules = [":- move(D), rug_ahead(D).", ":- rug_ahead(D), move(D).", ":- wait."]
    support = rule_support(domain, domain.episodes(demos), rules, "given", 30)
    first, second, wait = support
    assert first.gain < WEAK_SUPPORT and second.gain < WEAK_SUPPORT   # alone, each looks unneeded
    assert first.weak and first.overlaps == (rules[1],) and "keep that one" in first.text()
    assert not second.weak and second.joint_gain > 50 and second.overlaps == ()
    assert wait.weak and wait.overlaps == ()   # waiting shares no pair with the rug rules
    assert [r.rule for r in support if r.weak] == [rules[0], rules[2]]


def test_a_weak_rule_wider_than_the_needed_one_says_some_of_its_pairs(floor):
    """A weak rule that shares only some pairs with the needed one it names: the note says 'some of
    its pairs' (before: 'also forbids its pairs', as if deleting it lost nothing the other keeps)."""
    domain, demos = floor
    # never driving west: the rug's west pairs, and west from (1,2) where the rug is south
    rules = [":- move(west), rug_ahead(D).", ":- move(D), rug_ahead(D).", ":- rug_ahead(D), move(D)."]
    support = rule_support(domain, domain.episodes(demos), rules, "given", 30)
    wide, narrow, spelling = support
    assert wide.weak and len(wide.overlaps) == 1 and wide.overlaps[0] in rules[1:]
    assert not wide.overlaps_cover and "also forbids some of its pairs" in wide.text()
    assert wide.as_dict()["overlaps_cover"] is False
    weak_spelling = narrow if narrow.weak else spelling
    assert weak_spelling.overlaps_cover and "also forbids its pairs and is needed" in weak_spelling.text()
    # the rule file's header says the same
    learner = LogicConstraintInference(iterations=20, reward="given").fit(demos, domain)
    learner.rule_support_ = support
    text = learner._lp_text()
    assert f"%   {rules[0]}  (0.00 nats; {wide.overlaps[0]} forbids some of its pairs too: keep that)" in text, text
