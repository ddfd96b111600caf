"""Where the demonstrations of a ``learn`` command come from, and that they say so."""

from symlearn.data import Demonstrations, Trajectory
from symlearn.recipes.environments import resolve_env
from symlearn.recipes.experts import demonstrations


def test_the_source_is_the_expert_or_the_file(tmp_path):
    target = resolve_env("toy-navigation", None)
    recorded = demonstrations(target, None, 2, seed=0)
    assert recorded.metadata["source"] == "2 expert episodes of toy-navigation"
    assert recorded.metadata["env"] == "symlearn/toy-navigation-v0"  # the expert's own metadata kept
    recorded.save(tmp_path / "recorded.jsonl")
    again = demonstrations(target, tmp_path / "recorded.jsonl", 5)
    assert again.metadata["source"] == f"{tmp_path / 'recorded.jsonl'} (2 expert episodes of toy-navigation)"
    Demonstrations([Trajectory([[0.0, 1.0], [1.0, 1.0]])]).save(tmp_path / "plain.jsonl")
    assert demonstrations(None, tmp_path / "plain.jsonl", 5).metadata["source"] == str(tmp_path / "plain.jsonl")
