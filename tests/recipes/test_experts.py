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


def test_a_file_recorded_in_another_environment_is_read_with_a_warning(tmp_path):
    import warnings

    import pytest

    from symlearn.recipes.experts import recorded_env

    target = resolve_env("toy-navigation", None)
    path = tmp_path / "elsewhere.jsonl"
    Demonstrations([Trajectory([[0.0, 1.0], [1.0, 1.0]])], metadata={"env": "ALE/Pong-v5"}).save(path)
    notes = []
    loaded = demonstrations(target, path, 5, note=notes.append)
    assert len(loaded) == 1 and len(notes) == 1
    assert notes[0].startswith("warning: ") and "ALE/Pong-v5" in notes[0] and "\n" not in notes[0]
    with pytest.warns(UserWarning, match="recorded in ALE/Pong-v5"):  # no note function: a Python warning
        demonstrations(target, path, 5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        demonstrations(None, path, 5)  # no --env: nothing to compare with
    # what names no gymnasium id says nothing either way
    for env in ("ToyNavigationEnv", "gridworld (coordinates)", 3, None):
        assert recorded_env(Demonstrations([Trajectory([[0.0]])], metadata={"env": env})) is None


def test_the_bundled_experts_name_their_own_environment(tmp_path):
    """A bundled expert's file read back with its own --env (by name or gymnasium id): no warning."""
    from symlearn.recipes.experts import check_recorded_env

    for name in ("toy-navigation", "blocked-point", "safenav-point-goal"):
        target = resolve_env(name, None)
        demos = demonstrations(target, None, 1, seed=0)
        for alias in (name, target.gym_id):
            notes = []
            assert check_recorded_env(resolve_env(alias, None), demos, "file", notes.append), (name, alias, notes)
