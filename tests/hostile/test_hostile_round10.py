"""Tenth round of issue 26: what a fresh held-out corpus of ~620 generated cases still found
(docs/BENCHMARKS.md, "Tenth round"). Every input is generated here and run through the real
command in a child process (tests/support/hostile.py): exit 0, or exit 2 and one line, no
traceback, bounded time and memory, inputs untouched.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from hostile import assert_refused, assert_survived, run_command


# -- an error quoting a huge token, or the excerpt of a huge line, stays short --------------------
def test_an_error_message_quoting_a_huge_token_is_bounded(tmp_path):
    (tmp_path / "f.ltl").write_text("F a\nG (a -> X b) " + "x" * 5_000_000 + "\n")
    result = run_command(["ltl", "dfa", "--file", "f.ltl"], cwd=tmp_path, timeout=60)
    line = assert_refused(result, names="f.ltl:2:14", max_seconds=30)
    assert len(result.stderr) < 5000, len(result.stderr)
    assert "characters]" in line
    excerpt, caret = result.stderr_lines[1:]
    assert excerpt.startswith("  G (a -> X b) xxx") and excerpt.endswith("...")
    assert caret.index("^") == excerpt.index("xxx")


def test_an_excerpt_far_into_a_long_line_keeps_its_caret_under_the_character():
    from symlearn.errors import ParseError, with_excerpt

    line = "a & " * 10_000 + "? & b"
    column = line.index("?") + 1
    text = str(ParseError(with_excerpt("unexpected character '?'", line, column), file="f.ltl", line=1,
                          column=column))
    message, excerpt, caret = text.split("\n")
    assert len(excerpt) < 200 and excerpt.startswith("  ...")
    assert excerpt[caret.index("^")] == "?"
    short = str(ParseError(with_excerpt("unexpected character '?'", "a ? b", 3)))
    assert short.split("\n")[1:] == ["  a ? b", "    ^"]


# -- sweep files: TOML dates, and a folder's modules never shadow the libraries -------------------
SWEEP = '[sweep]\nname = "t"\ncommand = ["symlearn", "ltl", "parse", "{f}", "--json"]\nseeds = 1\n[grid]\n'


@pytest.mark.parametrize("values", ["f = [1979-05-27T07:32:00Z]", "f = [{a = [07:32:00]}]"])
def test_a_toml_date_in_a_sweep_is_refused_at_its_key(tmp_path, values):
    (tmp_path / "s.toml").write_text(SWEEP + values + "\n")
    result = run_command(["sweep", "run", "s.toml", "--local"], cwd=tmp_path, timeout=60)
    assert_refused(result, names="s.toml:6:1", contains="TOML date or time", max_seconds=30)
    assert not (tmp_path / "s-results").exists()


def test_a_sweep_command_does_not_import_modules_lying_in_the_sweep_folder(tmp_path):
    folder = tmp_path / "sweep"
    folder.mkdir()
    (folder / "s.toml").write_text(SWEEP + 'f = ["F a"]\n')
    for module in ("json", "typing"):  # what `python -m symlearn` imports first, were the folder on sys.path
        (folder / f"{module}.py").write_text(f"open({str(tmp_path / 'IMPORTED')!r}, 'w')\nraise SystemExit(3)\n")
    result = run_command(["sweep", "run", "sweep/s.toml", "--local", "--workers", "1"], cwd=tmp_path, timeout=90)
    assert_survived(result, max_seconds=60)
    assert result.returncode == 0, result.describe()
    assert not (tmp_path / "IMPORTED").exists()


# -- outputs onto a named pipe or a device: streamed into, never replaced by a file --------------
def test_an_output_onto_a_named_pipe_without_a_reader_is_one_line(tmp_path):
    os.mkfifo(tmp_path / "out.json")
    result = run_command(["ltl", "dfa", "F a", "--save", "out.json"], cwd=tmp_path, timeout=30)
    assert_refused(result, names="out.json", contains="nothing reads", max_seconds=20)
    assert (tmp_path / "out.json").is_fifo()
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]  # no temporary sibling either


def test_an_output_onto_a_named_pipe_with_a_reader_is_streamed(tmp_path):
    pipe = tmp_path / "out.json"
    os.mkfifo(pipe)
    received = []

    def read():
        with open(pipe) as handle:
            received.append(handle.read())

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    result = run_command(["ltl", "dfa", "F a", "--save", "out.json"], cwd=tmp_path, timeout=30)
    reader.join(10)
    assert result.returncode == 0, result.describe()
    assert pipe.is_fifo(), "the pipe was replaced by a regular file"
    assert '"symlearn-automaton"' in received[0]


def test_atomic_open_writes_into_a_character_device_without_replacing_it(tmp_path):
    from symlearn.atomic import write_text

    link = tmp_path / "null.txt"  # a link to /dev/null: the device is written into, the link stays
    link.symlink_to("/dev/null")
    write_text(link, "x" * 1000)
    assert link.is_symlink() and Path("/dev/null").is_char_device()
    assert [p.name for p in tmp_path.iterdir()] == ["null.txt"]


# -- a .npy header that is no Python literal ----------------------------------------------------
@pytest.mark.parametrize("header", [b"{'descr': lambda}\n", b"{'descr': '<f8', 'shape': (1,\n", b"{'a': [[[[\n"])
@pytest.mark.parametrize("command", [["data", "info", "{file}"], ["learn", "dnf", "--demos", "{file}"],
                                     ["learn", "pdfa", "--demos", "{file}"]], ids=lambda c: " ".join(c[:2]))
def test_an_npy_header_that_is_no_literal_is_one_line(tmp_path, header, command):
    import io
    import struct
    import zipfile

    import numpy as np

    member = b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header + b"\0" * 32
    lengths = io.BytesIO()
    np.save(lengths, np.array([1]))
    with zipfile.ZipFile(tmp_path / "x.npz", "w") as archive:
        archive.writestr("states.npy", member)
        archive.writestr("lengths.npy", lengths.getvalue())
    result = run_command([a.replace("{file}", "x.npz") for a in command], cwd=tmp_path, timeout=60)
    assert_refused(result, names="x.npz", contains="header", max_seconds=30)


# -- an archive of very many members is refused from its directory --------------------------------
@pytest.mark.parametrize("command", [["data", "info", "x.npz"], ["learn", "pdfa", "--demos", "x.npz"],
                                     ["dnf", "eval", "r.dnf", "--points", "x.npz"]], ids=lambda c: " ".join(c[:2]))
def test_an_archive_of_many_members_is_refused_before_its_headers_are_read(tmp_path, command):
    import io
    import zipfile

    import numpy as np

    one = io.BytesIO()
    np.save(one, np.zeros(1))
    with zipfile.ZipFile(tmp_path / "x.npz", "w", zipfile.ZIP_STORED) as archive:
        for i in range(12_000):  # 100,000 took > 60 s header by header
            archive.writestr(f"m{i}.npy", one.getvalue())
    (tmp_path / "r.dnf").write_text("x > 1\n")
    result = run_command(command, cwd=tmp_path, timeout=60)
    assert_refused(result, names="x.npz", contains="12,000 members", max_seconds=20)


# -- domain.toml itself a link out of its folder ---------------------------------------------------
def test_a_domain_toml_linked_from_outside_the_folder_is_refused(tmp_path):
    from warehouse_domain import write_warehouse

    write_warehouse(tmp_path / "wh")
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    text = (tmp_path / "wh" / "domain.toml").read_text()
    (outside / "domain.toml").write_text(text.replace('name = "warehouse"', 'name = "SECRET"'))
    (tmp_path / "wh" / "domain.toml").unlink()
    (tmp_path / "wh" / "domain.toml").symlink_to(outside / "domain.toml")
    result = run_command(["domain", "check", "wh"], cwd=tmp_path, timeout=60)
    assert_refused(result, names="domain.toml", contains="outside the domain folder", max_seconds=30)
    assert "SECRET" not in result.stdout + result.stderr
    trusted = run_command(["domain", "check", "wh", "--allow-outside"], cwd=tmp_path, timeout=60)
    assert trusted.returncode == 0, trusted.describe()
    (tmp_path / "wh" / "domain.toml").unlink()  # a link to a file inside the folder is the folder's own
    (tmp_path / "wh" / "real.toml").write_text(text)
    (tmp_path / "wh" / "domain.toml").symlink_to("real.toml")
    inside = run_command(["domain", "check", "wh"], cwd=tmp_path, timeout=60)
    assert inside.returncode == 0, inside.describe()


# -- an output (or a companion written beside it) that is one of the command's inputs ------------
def _automaton(folder: Path) -> None:
    from symlearn.logic.ltlf import parse, to_dfa

    (folder / "aut.json").write_text(to_dfa(parse("F a")).to_json())


@pytest.mark.parametrize("args, named, spared", [
    (["automaton", "convert", "aut.json", "aut.json"], "aut.json", ["aut.json"]),
    (["automaton", "convert", "aut.json", "link.json"], "link.json", ["aut.json"]),  # a link to the input
    (["automaton", "show", "aut.json", "--dot", "hard.json"], "hard.json", ["aut.json"]),  # a hard link
    (["ltl", "dfa", "--file", "f.ltl", "--save", "f.ltl"], "f.ltl", ["f.ltl"]),
    (["ilp", "learn", "t.las", "--bk", "b.lp", "-o", "b.lp"], "b.lp", ["b.lp"]),
    # a companion: the policy's .json beside its weights is the machine train reads
    (["train", "--env", "blockworld-stack2", "--algo", "dqrm", "--machine", "aut.json", "-o", "aut.safetensors"],
     "aut.safetensors", ["aut.json"]),
])
def test_no_command_writes_over_its_own_input(tmp_path, args, named, spared):
    _automaton(tmp_path)
    (tmp_path / "link.json").symlink_to("aut.json")
    os.link(tmp_path / "aut.json", tmp_path / "hard.json")
    (tmp_path / "f.ltl").write_text("F a\n")
    (tmp_path / "t.las").write_text("#modeh(p).\n#pos(e1, {p}, {}).\n")
    (tmp_path / "b.lp").write_text("q.\n")
    (tmp_path / "x.labeling.json").write_text('{"f": "x > 1"}')
    before = {name: (tmp_path / name).read_bytes() for name in spared}
    result = run_command(args, cwd=tmp_path, timeout=60)
    assert_refused(result, names=named, contains="would overwrite", max_seconds=30)
    assert {name: (tmp_path / name).read_bytes() for name in spared} == before
    assert (tmp_path / "link.json").is_symlink()


def test_an_output_over_a_file_that_is_no_input_is_replaced(tmp_path):
    _automaton(tmp_path)
    (tmp_path / "old.json").write_text("old")
    result = run_command(["automaton", "convert", "aut.json", "old.json"], cwd=tmp_path, timeout=60)
    assert result.returncode == 0, result.describe()
    assert (tmp_path / "old.json").read_text() == (tmp_path / "aut.json").read_text()


# -- --env-kwargs of the wrong JSON type for a bundled environment --------------------------------
@pytest.mark.parametrize("args, kwargs, key", [
    (["learn", "dnf", "--env", "toy-navigation", "--n-demos", "2"], '{"max_steps": "10"}', "max_steps"),
    (["learn", "dnf", "--env", "toy-navigation", "--n-demos", "2"], '{"speed": true}', "speed"),
    (["learn", "icrl", "--env", "blocked-point", "--n-demos", "2", "--iterations", "1", "--steps", "1024"],
     '{"wall": [1]}', "wall"),
])
def test_env_kwargs_of_the_wrong_type_are_one_line(tmp_path, args, kwargs, key):
    result = run_command([*args, "--env-kwargs", kwargs], cwd=tmp_path, timeout=60)
    assert_refused(result, contains=[key, "must be a number"], max_seconds=30)
    fine = run_command(["learn", "dnf", "--env", "toy-navigation", "--n-demos", "2", "--env-kwargs",
                        '{"max_steps": 50.0, "speed": 1}'], cwd=tmp_path, timeout=60)
    assert fine.returncode == 0, fine.describe()


def test_an_output_folder_that_takes_no_files_is_named_not_the_temporary_sibling(tmp_path):
    from symlearn.atomic import write_text

    with pytest.raises(OSError) as caught:
        write_text("/proc/x.json", "{}")  # /proc exists, but no file can be created in it
    assert caught.value.filename == "/proc/x.json"
    result = run_command(["ltl", "dfa", "F a", "--save", "/proc/x.json"], cwd=tmp_path, timeout=30)
    line = assert_refused(result, names="/proc/x.json", max_seconds=20)
    assert ".tmp" not in line


# -- a Python labeling that returns without end, or a million names a step ------------------------
@pytest.mark.parametrize("body", [
    "import itertools\ndef f(o, i):\n    return (f'p{k}' for k in itertools.count())\n",  # a generator without end
    "def f(o, i):\n    return [f'p{k}' for k in range(200000)]\n",  # discovered one by one: was quadratic
])
def test_a_python_labeling_returning_too_many_names_is_one_line(tmp_path, body):
    from symlearn.grounding.labeling_function import MAX_NAMES, FunctionLabeling, load_labeling_function

    (tmp_path / "lab.py").write_text(body)
    labeling = load_labeling_function(f"{tmp_path / 'lab.py'}:f")
    assert isinstance(labeling, FunctionLabeling)
    import time

    from symlearn.errors import DataError

    start = time.perf_counter()
    with pytest.raises(DataError, match=f"more than {MAX_NAMES:,} names"):
        labeling.label([0.5], {}, where="demonstration 0, step 0")
    assert time.perf_counter() - start < 5


def test_a_python_labeling_discovering_names_step_by_step_is_bounded(tmp_path):
    from symlearn.errors import DataError
    from symlearn.grounding.labeling_function import MAX_NAMES, load_labeling_function

    (tmp_path / "lab.py").write_text("def f(o, i):\n    return [f'p{o}-{k}' for k in range(1000)]\n")
    labeling = load_labeling_function(f"{tmp_path / 'lab.py'}:f")
    with pytest.raises(DataError, match="different names"):
        for step in range(MAX_NAMES // 1000 + 1):
            labeling.label(step, {})
    assert len(labeling.propositions) == MAX_NAMES


def test_an_output_pipe_closed_by_its_reader_is_one_line(tmp_path):
    import json

    chain = {"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a"], "states": 20000,
             "initial": 0, "accepting": [19999],
             "transitions": [{"source": i, "target": i + 1, "guard": "a"} for i in range(19999)]}
    (tmp_path / "chain.json").write_text(json.dumps(chain))
    pipe = tmp_path / "out.dot"
    os.mkfifo(pipe)

    def read_a_little():  # `| head -c 10`: far less than the drawing (> 64 KB, a pipe's buffer)
        with open(pipe, "rb") as handle:
            handle.read(10)

    reader = threading.Thread(target=read_a_little, daemon=True)
    reader.start()
    result = run_command(["automaton", "show", "chain.json", "--dot", "out.dot"], cwd=tmp_path, timeout=60)
    reader.join(10)
    assert_refused(result, names="out.dot", contains="closed it", max_seconds=40)
