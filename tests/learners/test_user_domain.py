"""Bring your own domain: a warehouse authored from scratch in a temporary folder is learned end to
end, through the API and the CLI, with every constraint method and with specification learning."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
import warehouse_domain as wh
from cli_runner import run

from symlearn.data import Demonstrations, Trajectory, load
from symlearn.grounding import Domain
from symlearn.learners.base import LearnerResult, NotFittedError
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
from symlearn.learners.constraints.mce_icrl import MCEICRL
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.learners.temporal.spec_from_demos import SpecLearner
from symlearn.logic.asp import Hypothesis


@pytest.fixture(scope="module")
def warehouse(tmp_path_factory):
    root = tmp_path_factory.mktemp("byod")
    folder = wh.write_warehouse(root / "warehouse")
    demos = wh.expert_demonstrations(60, seed=0)
    demos.save(root / "demos.jsonl")
    wh.expert_demonstrations(8, seed=3, atoms=True).save(root / "demos_atoms.jsonl")
    return root, folder


def test_logic_api_learns_both_rules(warehouse):
    root, folder = warehouse
    domain = Domain.from_folder(folder)
    learner = LogicConstraintInference(iterations=20, reward="given", rationality=3.0)
    assert "rules_" not in learner.__dict__
    with pytest.raises(NotFittedError):
        learner.save(root / "nothing.lp")
    learner.fit(load(root / "demos.jsonl"), domain)
    assert sorted(learner.rules_) == [":- alarm, move(V1).", ":- move(V1), blocked(V1)."]
    assert learner.score() == {"fpr": 0.0, "fnr": 0.0, "accuracy": 1.0, "forbidden": 64}
    assert isinstance(learner.result_, LearnerResult)
    assert learner.result_.metrics["fnr"] == 0.0 and learner.result_.timings["total"] > 0
    assert all(hasattr(h, "as_dict") for h in learner.result_.history)
    path = learner.save(root / "rules.lp")
    # read, edit, re-check: dropping the alarm rule brings back exactly the alarm moves
    edited = Hypothesis.from_lp(path)
    kept = [r for r in edited.rules if "alarm" not in r]
    missed = domain.truth_forbidden & ~domain.rule_mask(kept)
    assert missed.sum() > 0
    alarm_states = [i for i, s in enumerate(wh.states()) if s != "done" and s[1]]
    assert set(np.argwhere(missed)[:, 0]) <= set(alarm_states)


def test_learners_share_the_contract(warehouse):
    root, folder = warehouse
    domain = Domain.from_folder(folder)
    demos = load(root / "demos.jsonl")
    for learner in (MLConstraintInference(reward="given", rationality=3.0, horizon=30),
                    MCEICRL(features="state_action", n_iterations=100)):
        params = learner.get_params()
        assert learner.fit(demos, domain) is learner
        assert learner.get_params() == params  # fit never changes hyper-parameters
        assert learner.result_.learner == type(learner).__name__
        forbidden = learner.result_.artefact
        assert forbidden.shape == (domain.n_states, domain.n_actions)
        assert not (forbidden & domain.unavailable).any()
        saved = json.loads(learner.save(root / f"{type(learner).__name__}.json").read_text())
        assert saved["format"] == "symlearn-constraints" and len(saved["forbidden"]) == int(forbidden.sum())
        if isinstance(learner, MLConstraintInference):
            # inference never forbids a demonstrated pair (MCE-ICRL's costs may: they are soft)
            for t in demos:
                assert not forbidden[np.asarray(t.states[:-1]), np.asarray(t.actions)].any()
    clone = MLConstraintInference(horizon=7).set_params(horizon=9)
    assert clone.horizon == 9 and "horizon=9" in repr(clone)


@pytest.mark.parametrize("method", ["logic", "ml", "mce-icrl"])
def test_cli_learns_the_warehouse(warehouse, capsys, method):
    root, folder = warehouse
    out_file = root / f"out_{method}.{'lp' if method == 'logic' else 'json'}"
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", root / "demos.jsonl",
                         "--method", method, "--rationality", 3, "--json", "-o", out_file)
    assert code == 0, err
    doc = json.loads(out)
    assert {"rules", "constraints", "fpr", "fnr", "accuracy", "iterations", "seconds"} <= set(doc)
    assert doc["env"] == "warehouse" and doc["method"] == method
    assert 0 <= doc["fpr"] <= 1 and 0 <= doc["fnr"] <= 1 and doc["constraints"] > 0
    if method == "logic":
        assert doc["fpr"] == 0.0 and doc["fnr"] == 0.0
        assert Hypothesis.from_lp(out_file).rules == doc["rules"]
    else:
        assert doc["rules"] is None
        assert len(json.loads(out_file.read_text())["forbidden"]) == doc["constraints"]


def test_cli_without_truth_scores_null_and_reads_action_atoms(warehouse, capsys, tmp_path):
    root, _ = warehouse
    folder = wh.write_warehouse(tmp_path / "no_truth", truth=False)
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", root / "demos_atoms.jsonl",
                         "--method", "ml", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["fpr"] is None and doc["fnr"] is None and doc["accuracy"] is None


def test_cli_bad_domain_input_is_one_line(warehouse, capsys, tmp_path):
    root, _ = warehouse
    code, out, err = run(capsys, "learn", "constraints", "--domain", tmp_path, "--demos", root / "demos.jsonl")
    assert code == 2 and "no domain.toml" in err and "Traceback" not in err
    folder = wh.write_warehouse(tmp_path / "w")
    bad = tmp_path / "bad.jsonl"
    from symlearn.data import Demonstrations, Trajectory

    Demonstrations([Trajectory(states=[0, 1, 500], actions=[0, 1])]).save(bad)
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder, "--demos", bad)
    assert code == 2 and "state 500 is outside" in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "learn", "constraints", "--domain", folder)
    assert code == 2 and "--demos" in err


def test_spec_learning_on_a_user_domain(tmp_path, capsys):
    folder = wh.write_warehouse(tmp_path / "det", alarm_prob=0.0)  # deterministic: the exact successor table
    demos = wh.expert_demonstrations(30, seed=0, alarm_prob=0.0)
    demos.save(tmp_path / "demos.jsonl")
    domain = Domain.from_folder(folder)
    learner = SpecLearner(random_state=0).fit(demos, domain)
    assert "delivered" in str(learner.formula_)
    assert learner.success_rate("F delivered") == 1.0
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", tmp_path / "demos.jsonl", "--json",
                         "-o", tmp_path / "spec.ltl")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["formula"] == str(learner.formula_) and doc["success_rate"] is None
    assert (tmp_path / "spec.ltl").read_text().strip() == doc["formula"]
    learned = SpecLearner(propositions="learn", random_state=0).fit(demos, domain)
    assert learned.labeling_.propositions  # grown propositions "agent in state ..."


def test_spec_learning_on_a_stochastic_domain_that_starts_in_several_states(tmp_path, capsys):
    """The warehouse's alarm comes and goes at random (the constraint learners' setting): the
    nominal policies' episodes sample the moves and the start states instead of refusing them."""
    import numpy as np

    folder = wh.write_warehouse(tmp_path / "stochastic", alarm_prob=0.2)
    model = dict(np.load(folder / "model.npz"))
    starts = np.flatnonzero(model["initial"])
    neighbour = int(np.flatnonzero(model["transitions"][starts[0]].max(axis=0))[-1])
    model["initial"][:] = 0
    model["initial"][[starts[0], neighbour]] = 0.5   # two start states
    np.savez(folder / "model.npz", **model)
    demos = wh.expert_demonstrations(30, seed=0, alarm_prob=0.2)
    demos.save(tmp_path / "demos.jsonl")
    domain = Domain.from_folder(folder)
    learner = SpecLearner(random_state=0).fit(demos, domain)
    assert learner.model_.dynamics is not None
    assert "delivered" in str(learner.formula_) and learner.success_rate("F delivered") >= 0.9
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", tmp_path / "demos.jsonl", "--json")
    assert code == 0, err
    assert json.loads(out)["formula"] == str(learner.formula_)


def test_spec_learning_reads_demonstrations_that_name_their_states(tmp_path, capsys):
    """states.jsonl's names are usable in demonstrations instead of ids (docs/FORMATS.md), for
    `learn spec --domain` as for `learn constraints --domain`."""
    folder = wh.write_warehouse(tmp_path / "det", alarm_prob=0.0)
    demos = wh.expert_demonstrations(10, seed=0, alarm_prob=0.0)
    domain = Domain.from_folder(folder)
    named = Demonstrations([Trajectory(states=[domain.state_names[s] for s in t.states], actions=t.actions)
                            for t in demos])
    named.save(tmp_path / "named.jsonl")
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", tmp_path / "named.jsonl", "--json")
    assert code == 0, err
    assert "delivered" in json.loads(out)["formula"]


def test_dnf_learning_through_a_domain_feature_map(tmp_path, capsys):
    # the folder is read in the bounded worker and comes back whole, feature map included
    from symlearn.grounding import FeatureMap

    folder = wh.write_warehouse(tmp_path / "warehouse", alarm_prob=0.0)
    cells = [s[0] if s != "done" else (-1, -1) for s in wh.states()]
    FeatureMap(["x", "y"], table=np.array(cells, dtype=float)).save(folder / "features.json")
    (folder / "domain.toml").write_text((folder / "domain.toml").read_text() + 'features = "features.json"\n')
    wh.expert_demonstrations(20, seed=0, alarm_prob=0.0).save(tmp_path / "demos.jsonl")
    code, out, err = run(capsys, "learn", "dnf", "--domain", folder, "--demos", tmp_path / "demos.jsonl", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["features"] == ["x", "y"] and doc["samples"] > 0
    code, out, err = run(capsys, "learn", "dnf", "--domain", folder, "--demos", tmp_path / "demos.jsonl",
                         "--timeout", "-1")
    assert code == 2 and "--timeout" in err and len(err.strip().splitlines()) == 1


def test_a_labeling_naming_a_state_the_domain_lacks_is_the_labelings_error(tmp_path, capsys):
    """A table labeling of a state id the folder does not have: refused when the folder is read
    (domain check said nothing before) and, given as --labeling, named by its own file (before:
    the demonstrations file was blamed)."""
    folder = wh.write_warehouse(tmp_path / "det", alarm_prob=0.0)
    wh.expert_demonstrations(5, seed=0, alarm_prob=0.0).save(tmp_path / "demos.jsonl")
    doc = json.loads((folder / "labeling.json").read_text())
    doc["table"].append([999, [doc["propositions"][0]["name"]]])
    (tmp_path / "bad.json").write_text(json.dumps(doc))
    code, out, err = run(capsys, "learn", "spec", "--domain", folder, "--demos", tmp_path / "demos.jsonl",
                         "--labeling", tmp_path / "bad.json")
    # located at the entry's line:col since the third sweep of users' files
    assert code == 2 and re.match(rf"symlearn: error: {re.escape(str(tmp_path / 'bad.json'))}:1:\d+: table\[", err), err
    assert "state 999" in err
    (folder / "labeling.json").write_text(json.dumps(doc))
    code, out, err = run(capsys, "domain", "check", folder)
    assert code == 2 and re.search(rf"{re.escape(str(folder / 'labeling.json'))}:1:\d+: table\[", err), err
    assert "state 999" in err
