from pathlib import Path

import pytest

from symlearn.envs.ilp_tasks import (DEFAULT_TASKS, Example, default_task_text, demonstration_examples,
                                     exhaustive_examples, sampled_examples, task_text, with_label_noise,
                                     write_task)
from symlearn.envs.logic_domains import DOMAIN_NAMES, logic_domain
from symlearn.errors import DataError
from symlearn.logic.ilp import load_task, parse_task
from symlearn.resources import background_kb_path


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_exhaustive_examples_are_labelled_by_the_truth(name):
    domain = logic_domain(name)
    examples = exhaustive_examples(domain)
    pairs = list(domain.state_actions())
    assert len(examples) == len(pairs)
    for example, (state, action) in zip(examples, pairs):
        assert example.positive == domain.is_allowed(state, action)
        assert example.facts == domain.facts(state, action)
    assert len({e.id for e in examples}) == len(examples)


@pytest.mark.parametrize("name", DOMAIN_NAMES)
def test_demonstration_examples_are_deterministic_and_truthful(name):
    domain = logic_domain(name)
    first = demonstration_examples(domain, n_episodes=8, seed=5)
    assert first == demonstration_examples(domain, n_episodes=8, seed=5)
    labels = {facts: ok for facts, ok in domain.pairs()}
    assert all(labels[e.facts] == e.positive for e in first)
    assert any(e.positive for e in first) and any(not e.positive for e in first)
    assert len({e.facts for e in first}) == len(first)  # no duplicated pair
    capped = demonstration_examples(domain, n_episodes=8, seed=5, max_negatives=3)
    assert sum(not e.positive for e in capped) == 3
    assert [e for e in capped if e.positive] == [e for e in first if e.positive]


def test_different_seeds_give_different_traffic_demonstrations():
    domain = logic_domain("junction-lights")
    assert demonstration_examples(domain, 5, seed=1) != demonstration_examples(domain, 5, seed=2)


def test_sampled_examples():
    domain = logic_domain("hanoi")
    sample = sampled_examples(domain, 10, 4, seed=3)
    assert sample == sampled_examples(domain, 10, 4, seed=3)
    assert sample != sampled_examples(domain, 10, 4, seed=4)
    labels = dict(domain.pairs())
    assert [e.positive for e in sample] == [True] * 10 + [False] * 4
    assert all(labels[e.facts] == e.positive for e in sample)
    assert len({e.facts for e in sample}) == 14
    assert len(sampled_examples(domain, 114, 102)) == 216
    with pytest.raises(DataError, match="asked for 115 allowed pairs, hanoi has 114"):
        sampled_examples(domain, 115, 0)


def test_label_noise():
    clean = exhaustive_examples(logic_domain("junction-lights"))
    noisy = with_label_noise(clean, 0.1, penalty=3, seed=1)
    assert noisy == with_label_noise(clean, 0.1, penalty=3, seed=1)
    assert sum(a.positive != b.positive for a, b in zip(clean, noisy)) == 25
    assert all(b.penalty == 3 and a.facts == b.facts and a.id == b.id for a, b in zip(clean, noisy))
    assert with_label_noise(clean, 0.0, penalty=1) == [Example.from_facts(e.id, e.positive, e.facts, 1) for e in clean]
    with pytest.raises(DataError, match=r"noise fraction must be in \[0, 1\]"):
        with_label_noise(clean, 1.5, penalty=1)
    with pytest.raises(DataError, match="penalty must be a positive integer"):
        with_label_noise(clean, 0.1, penalty=0)


def test_example_lines():
    assert Example.from_facts("n3", False, ("a.", "go(x).")).to_text() == "#neg(n3, {}, {}, { a. go(x). })."
    assert Example.from_facts("p1", True, ("a.",), penalty=10).to_text() == "#pos(p1@10, {}, {}, { a. })."
    assert Example.from_facts("p2", True, ("at(1, 2).",)).facts == ("at(1,2).",)


def test_bad_requests():
    domain = logic_domain("hanoi")
    with pytest.raises(DataError, match="at least one example"):
        task_text(domain, [])
    with pytest.raises(DataError, match="n_episodes"):
        demonstration_examples(domain, n_episodes=0)


@pytest.mark.parametrize("relative", sorted(DEFAULT_TASKS))
def test_bundled_tasks_are_up_to_date_and_parse(relative):
    path = background_kb_path(*Path(relative).parts)
    text = path.read_text(encoding="utf-8")
    assert text == default_task_text(relative), "run: python benchmarks/make_ilp_tasks.py"
    task = load_task(path)
    n_pos, n_neg = text.count("\n#pos("), text.count("\n#neg(")
    assert (len(task.positives), len(task.negatives)) == (n_pos, n_neg)
    assert task.constraints_only and task.modeb


def test_written_task_round_trips_through_the_parser(tmp_path):
    domain = logic_domain("junction-priority")
    examples = demonstration_examples(domain, n_episodes=3, seed=0, penalty=4)
    path = write_task(tmp_path / "t.las", domain, examples)
    task = parse_task(path.read_text(), source=str(path))
    assert len(task.examples) == len(examples)
    assert all(e.penalty == 4 for e in task.examples)
    assert [e.positive for e in task.examples] == [e.positive for e in examples]
