"""Every ``learn`` command writes its learned artefact through the learner's own ``save``, so the
file a user gets from ``symlearn learn ... -o FILE`` is the file ``learner.save(FILE)`` writes in
Python for the same fit.

Each case runs the command in-process with every learner's ``save`` recorded, then saves the
learner the command fitted once more from Python and compares the two files byte for byte. A
command that writes the artefact itself records no ``save`` call and fails.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import pytest

from cli_runner import run
from learner_classes import learner_classes

#: learn subcommand -> (output file name, arguments of a small run)
CASES = {
    "spec": ("spec.ltl", ["learn", "spec", "--env", "office-1", "--n-demos", 10, "--max-iterations", 3]),
    "constraints-logic": ("rules.lp", ["learn", "constraints", "--env", "hanoi", "--n-demos", 10, "--method", "logic",
                                       "--iterations", 3]),
    "constraints-ml": ("ml.json", ["learn", "constraints", "--env", "gridworld", "--method", "ml"]),
    "constraints-mce-icrl": ("mce.json", ["learn", "constraints", "--env", "gridworld", "--method", "mce-icrl",
                                          "--iterations", 50]),
    "dnf": ("unsafe.dnf", ["learn", "dnf", "--env", "toy-navigation", "--n-demos", 20]),
    "dnf-json": ("unsafe.json", ["learn", "dnf", "--env", "toy-navigation", "--n-demos", 20]),
    "pdfa": ("plan.json", ["learn", "pdfa", "--env", "blocks-place-2", "--n-demos", 20]),
    "rm": ("machine.json", ["learn", "rm", "--env", "blockworld-stack2"]),
    "icrl": ("cost.safetensors", ["learn", "icrl", "--env", "blocked-point", "--n-demos", 3, "--steps", 2048,
                                  "--iterations", 1, "--cost-inputs", "x,y"]),
}


@pytest.fixture
def saves(monkeypatch):
    """``(learner, path)`` of every outermost ``save`` a learner makes (an override calling
    ``super().save`` counts once)."""
    calls: list[tuple[object, Path]] = []
    depth = [0]

    def recorded(original):
        @functools.wraps(original)
        def save(self, path, *args, **kwargs):
            depth[0] += 1
            try:
                written = original(self, path, *args, **kwargs)
            finally:
                depth[0] -= 1
            if depth[0] == 0:
                calls.append((self, Path(path)))
            return written
        return save

    from symlearn.learners.base import Learner

    for cls in [Learner, *learner_classes().values()]:
        if "save" in vars(cls):
            monkeypatch.setattr(cls, "save", recorded(vars(cls)["save"]))
    return calls


def test_every_learn_command_has_a_case():
    from symlearn.cli.learn_command import LEARN_SUBCOMMANDS

    commands = {"spec"} | {m.rsplit(".", 1)[1].removeprefix("learn_").removesuffix("_command")
                           for m in LEARN_SUBCOMMANDS}
    assert commands <= {name.split("-")[0] for name in CASES}


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_command_writes_what_learner_save_writes(case, saves, capsys, tmp_path):
    name, args = CASES[case]
    output = tmp_path / "cli" / name
    output.parent.mkdir()
    code, _, err = run(capsys, *args, "-o", output, "--json")
    assert code == 0, err
    written = [(learner, path) for learner, path in saves if path == output]
    assert len(written) == 1, f"{case}: the command wrote {output.name} without the learner's save ({saves})"
    learner = written[0][0]
    again = tmp_path / "python" / name
    again.parent.mkdir()
    learner.save(again)
    if output.suffix == ".safetensors":
        # the same tensors and metadata: safetensors orders the metadata keys of its header as a
        # hash map does, so two saves of one module in one process can differ in those bytes
        assert _safetensors(output) == _safetensors(again)
        assert output.with_suffix(".json").read_bytes() == again.with_suffix(".json").read_bytes()
    else:
        assert output.read_bytes() == again.read_bytes()
    if case in PROVENANCE:  # what the file says of its origin came to the learner with its inputs
        assert PROVENANCE[case](output)


#: case -> what its file must say of where it comes from (the CLI knows; the learner is told
#: through the demonstrations' metadata["source"] and the world's name)
PROVENANCE = {
    "dnf": lambda path: path.read_text().splitlines()[0].startswith(
        "# unsafe set learned by a one-class tree (max depth 5) from 20 expert episodes of toy-navigation ("),
    "constraints-ml": lambda path: json.loads(path.read_text())["domain"] == "gridworld",
    "constraints-mce-icrl": lambda path: json.loads(path.read_text())["domain"] == "gridworld",
}


def _safetensors(path: Path) -> tuple[dict, dict]:
    from safetensors import safe_open

    with safe_open(str(path), framework="numpy") as f:
        return f.metadata(), {key: f.get_tensor(key).tobytes() for key in f.keys()}
