"""``symlearn learn rm``: reward machines from image demonstrations, files written, bad input refused."""

import json

import numpy as np
import pytest

from cli_runner import run
from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.rendered_blocks.demonstrator import demonstrations
from symlearn.learners.reward_machines.labeling import PrototypeLabeling
from symlearn.logic.automata import RewardMachine

MODULE = "symlearn.cli.learn_rm_command"


@pytest.fixture(autouse=True)
def rm_subcommand(monkeypatch):
    """Register the subcommand as main's LEARN_SUBCOMMANDS will (until that line is added there)."""
    from symlearn.cli import learn_command

    if MODULE not in learn_command.LEARN_SUBCOMMANDS:
        monkeypatch.setattr(learn_command, "LEARN_SUBCOMMANDS", (*learn_command.LEARN_SUBCOMMANDS, MODULE))


@pytest.fixture(scope="module")
def place2(tmp_path_factory):
    path = tmp_path_factory.mktemp("rm") / "frames.npz"
    demos = demonstrations("place-2", seed=1)
    demos.front.save(path)
    return path, demos


def test_demos_file_gives_the_machine_and_its_files(capsys, tmp_path, place2):
    path, demos = place2
    out_file = tmp_path / "machine.json"
    code, out, err = run(capsys, "learn", "rm", "--demos", path, "-o", out_file, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert {"states", "edges", "propositions", "kappa", "clusters", "seconds"} <= set(doc)
    assert doc["states"] == 4 and len(doc["edges"]) == 4 and doc["multiple_label_frames"] == 0
    machine = RewardMachine.load(out_file)
    assert machine.n_states == 4 and machine.gamma == 0.9 and machine.potential is not None
    names = {p.name for p in tmp_path.iterdir()}
    assert {"machine.json", "machine.labeling.json", "machine.labeling.features.safetensors", "machine.dot",
            "machine.prototypes.png", "machine.md", "machine.prototypes"} <= names
    assert sorted(p.name for p in (tmp_path / "machine.prototypes").iterdir()) == [f"u{k}.png" for k in range(4)]
    assert 'image="machine.prototypes/u0.png"' in (tmp_path / "machine.dot").read_text()
    assert "![prototypes](machine.prototypes.png)" in (tmp_path / "machine.md").read_text()
    # the saved labeling drives the saved machine through a demonstration to the goal
    labeling = PrototypeLabeling.load(tmp_path / "machine.labeling.json")
    states, rewards = machine.run(labeling.label_word(demos.front[0].states))
    assert states[-1] in machine.accepting and rewards[-1] == pytest.approx(1.0)


def test_env_and_overrides_sparse_machine(capsys, tmp_path):
    code, out, err = run(capsys, "learn", "rm", "--env", "blockworld-stack3", "--eps", 1.2, "--min-samples", 4,
                         "--no-shaping", "--seed", 2, "-o", tmp_path / "m.json", "--dot", tmp_path / "drawn.dot")
    assert code == 0, err
    assert "3 states" in out and "eps 1.2," in out and "min samples 4" in out
    machine = RewardMachine.load(tmp_path / "m.json")
    assert machine.potential is None and machine.n_states == 3
    assert (tmp_path / "drawn.dot").exists() and not (tmp_path / "m.dot").exists()


@pytest.mark.parametrize("arguments, message", [
    (("--env", "blockworld-stack4"), "unknown rendered block task 'blockworld-stack4' (hint: did you mean 'blockworld-stack3'?"),
    (("--env", "blockworld-stack2", "-o", "m.txt"), "-o must name a .json file"),
    (("--env", "blockworld-stack2", "--kappa", "-1"), "--kappa must be a positive number"),
    (("--env", "blockworld-stack2", "--gamma", "1.5"), "--gamma must be in (0, 1)"),
    (("--env", "blockworld-stack2", "--min-samples", "0"), "--min-samples must be at least 1"),
    (("--env", "blockworld-stack2", "--dot", "m.dot"), "--dot needs -o"),
    # refused before learning: the machine was written, then a companion name was too long
    (("--env", "blockworld-stack2", "-o", "m" * 240 + ".json"), "is too long a name"),
])
def test_bad_arguments_are_one_line(capsys, arguments, message):
    code, out, err = run(capsys, "learn", "rm", *arguments)
    assert code == 2 and message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_non_image_and_missing_files_are_one_line(capsys, tmp_path):
    vectors = tmp_path / "vectors.npz"
    Demonstrations([Trajectory(np.zeros((10, 3)))]).save(vectors)
    code, _, err = run(capsys, "learn", "rm", "--demos", vectors)
    assert code == 2 and "vectors.npz" in err and "not images" in err and "Traceback" not in err
    code, _, err = run(capsys, "learn", "rm", "--demos", tmp_path / "missing.npz")
    assert code == 2 and "missing.npz" in err and "Traceback" not in err


def test_never_leaving_the_start_is_one_line(capsys, tmp_path):
    path = tmp_path / "idle.npz"
    demonstrations("stack-2", seed=0, orderings=[()]).front.save(path)
    code, out, err = run(capsys, "learn", "rm", "--demos", path, "--json")
    assert code == 2 and "never" in err
    assert json.loads(out)["error"]["kind"] == "DataError"


def test_too_large_kappa_is_a_warning_with_counts(capsys, place2):
    path, _ = place2
    code, out, err = run(capsys, "learn", "rm", "--demos", path, "--kappa", 1000, "--json")
    assert code == 0
    doc = json.loads(out)
    assert doc["multiple_label_frames"] == doc["frames"]
    assert f"warning: {doc['frames']} of {doc['frames']} demonstration frames satisfy several propositions" in err


def test_a_stack_of_frames_with_run_lengths_is_read_as_image_demonstrations(capsys, tmp_path, place2):
    # a camera tour's natural file: frames stacked with the runs' lengths, no demonstrations header
    # (refused before for lacking __meta__); the same machine as from the demonstrations file
    path, demos = place2
    runs = [np.asarray(t.states) for t in demos.front]
    video = tmp_path / "video.npz"
    np.savez(video, states=np.concatenate(runs), lengths=np.array([len(r) for r in runs]))
    code, out, err = run(capsys, "learn", "rm", "--demos", video, "--json")
    assert code == 0, err
    code2, reference, _ = run(capsys, "learn", "rm", "--demos", path, "--json")
    got, want = json.loads(out), json.loads(reference)
    assert got["states"] == want["states"] == 4 and got["edges"] == want["edges"]
    flat = tmp_path / "positions.npz"
    np.savez(flat, states=np.zeros((4, 2)), lengths=np.array([2, 2]))
    code, _, err = run(capsys, "learn", "rm", "--demos", flat)
    assert code != 0 and "pictures" in err and "learn pdfa" in err
