"""Hostile and malformed input never takes the process down (issue 15, classes 2, 3, 5, 6, 10 and
the newcomer path): one clear line, exit 2, nothing left behind, bounded time and memory.

Every case runs the real command in a child process under ``RLIMIT_AS`` (tests/support/hostile.py).
The regression corpus (``corpus/MANIFEST.json``) replays every input that once crashed; the
seeded mutation fuzzer (tests/support/fuzz_inputs.py) runs a short round here and a long one
under ``slow`` and from ``benchmarks/fuzz_inputs.py``.
"""

from __future__ import annotations

import io
import json
import os
import re
import signal
import struct
import subprocess
import sys
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest

from hostile import assert_refused, assert_survived, check, run_command, run_python
from zip_bombs import deflate as _deflate, zip_of as _zip

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
CORPUS = HERE / "corpus"
HEADER = ('{"symlearn": "demonstrations", "format_version": 1, "state_kind": "%s", "state_dtype": %s, '
          '"action_kind": null, "action_dtype": null, "metadata": {}}\n')


@pytest.fixture(scope="module")
def dfa_file(tmp_path_factory) -> Path:
    from symlearn.logic.ltlf import parse, to_dfa

    path = tmp_path_factory.mktemp("dfa") / "spec.json"
    path.write_text(to_dfa(parse("(coffee T office) & G !plant")).to_json())
    return path


def _demos(tmp_path: Path, name: str = "demos.jsonl") -> Path:
    from symlearn.data import Demonstrations, Trajectory

    path = tmp_path / name
    Demonstrations([Trajectory(states=[0, 1, 2], actions=["go(east)", "go(east)"],
                               labels=[[], ["key"], ["door"]])]).save(path)
    return path


# -- the regression corpus -----------------------------------------------------------------------
CASES = json.loads((CORPUS / "MANIFEST.json").read_text())["cases"]


@pytest.mark.parametrize("case", CASES, ids=[c["file"] for c in CASES])
def test_regression_corpus(case, tmp_path, dfa_file):
    source = tmp_path / case["file"]
    source.write_bytes((CORPUS / case["file"]).read_bytes())
    args = [a.replace("{file}", source.name).replace("{dfa}", str(dfa_file)) for a in case["command"]]
    check(args, cwd=tmp_path, timeout=30, names=source.name, location=case["location"],
          contains=case["contains"], outputs=case.get("outputs", ()))


# -- class 2: sizes trusted before checking ------------------------------------------------------
def test_jsonl_header_dtypes_must_be_plain_numbers():
    """The issue's three dtypes run through the CLI in the corpus; more of them in-process here."""
    from symlearn.data.jsonl_format import _plain_dtype
    from symlearn.errors import DataError

    for dtype in ("(1000,1000,100)f8", "V2000000000", "<U1000000000", "O", "complex128", "M8", 7, None, "f8" * 20):
        with pytest.raises(DataError, match="not a plain numeric dtype"):
            _plain_dtype(dtype, "state_dtype", Path("d.jsonl"), 1, "")
    assert _plain_dtype("<f8", "state_dtype", Path("d.jsonl"), 1, "") == "float64"


def _npz_bomb(path: Path, member: str, zero_blocks: int, declared_rows: int) -> None:
    """A valid symlearn NPZ whose ``member`` is replaced by int64 zeros: ``zero_blocks`` x 8 MB
    really inside (a few KB compressed), declaring ``declared_rows`` rows."""
    from symlearn.data import Demonstrations, Trajectory

    buffer = io.BytesIO()
    Demonstrations([Trajectory(states=[0, 1, 2], actions=[0, 1])]).save(tmp := path.with_suffix(".seed.npz"))
    with zipfile.ZipFile(tmp) as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    tmp.unlink()
    np.lib.format.write_array_header_1_0(buffer, {"descr": "<i8", "fortran_order": False, "shape": (declared_rows,)})
    packed = {name: _deflate(data, 0) for name, data in members.items() if name != f"{member}.npy"}
    packed[f"{member}.npy"] = _deflate(buffer.getvalue(), zero_blocks)
    path.write_bytes(_zip(packed))


def test_npz_zip_bomb_is_refused_from_its_header(tmp_path):
    """1 GB of zeros in a ~1 MB file: refused from the member header, nothing decompressed."""
    path = tmp_path / "bomb.npz"
    _npz_bomb(path, "states", 128, 128 * (8 << 20) // 8)
    assert path.stat().st_size < 1_200_000
    result = check(["data", "info", path.name], cwd=tmp_path, timeout=30, memory_mb=1024, names="bomb.npz",
                   contains=["SYMLEARN_MAX_ARRAY_MB", "exceeds the limit"])
    assert result.max_rss_mb < 300


def test_npz_row_count_is_checked_before_decompressing(tmp_path):
    """Under a raised limit the bomb fits, but its row count disagrees with 'lengths': refused
    before the gigabyte is decompressed (the run stays far below it)."""
    path = tmp_path / "bomb.npz"
    _npz_bomb(path, "states", 64, 64 * (8 << 20) // 8)
    result = check(["data", "validate", path.name], cwd=tmp_path, timeout=30, memory_mb=1024,
                   env={"SYMLEARN_MAX_ARRAY_MB": "4096"}, names="bomb.npz", contains="rows, expected 3")
    assert result.max_rss_mb < 300


def test_reading_dev_zero_stops_at_the_input_limit(tmp_path):
    for args in (["ltl", "dfa", "--file", "/dev/zero"], ["ltl", "eval", "F a", "--traces", "/dev/zero"]):
        check(args, cwd=tmp_path, timeout=30, memory_mb=512, env={"SYMLEARN_MAX_INPUT_MB": "4"}, names="/dev/zero",
              contains=["larger than the limit of 4 MB", "SYMLEARN_MAX_INPUT_MB"])


def test_input_limit_is_overridable(tmp_path):
    path = tmp_path / "traces.jsonl"
    path.write_text(('[' + '["a"], ' * 60 + '["b"]]\n') * 3000)  # 1.3 MB, 3000 traces
    check(["ltl", "eval", "F b", "--traces", path.name, "--json"], cwd=tmp_path, timeout=30,
          env={"SYMLEARN_MAX_INPUT_MB": "1"}, names="traces.jsonl", contains="exceeds the limit of 1 MB")
    result = run_command(["ltl", "eval", "F b", "--traces", path.name, "--json"], cwd=tmp_path, timeout=60,
                         env={"SYMLEARN_MAX_INPUT_MB": "0"})
    assert result.returncode == 0 and sum(json.loads(result.stdout)["results"]) == 3000


def test_automaton_state_count_limit_is_overridable(tmp_path):
    doc = {"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a"], "states": 3000,
           "initial": 0, "accepting": [0], "transitions": []}
    (tmp_path / "a.json").write_text(json.dumps(doc))
    check(["automaton", "show", "a.json"], cwd=tmp_path, timeout=30, env={"SYMLEARN_MAX_STATES": "1000"},
          names="a.json", contains="3,000")
    assert run_command(["automaton", "show", "a.json"], cwd=tmp_path, timeout=60).returncode == 0


# -- class 3: exponential guard printing -----------------------------------------------------------
def test_dfa_of_many_eventualities_prints_fast(tmp_path):
    formula = " & ".join(f"F p{i}" for i in range(9))  # 512 states, 19,683 edges
    result = run_command(["ltl", "dfa", formula, "--json"], cwd=tmp_path, timeout=40)
    assert_survived(result, max_seconds=25)
    doc = json.loads(result.stdout)
    assert result.returncode == 0 and doc["states"] == 512 and doc["edges"] == 3 ** 9


def test_dnf_guard_prints_factored_not_as_4096_cubes(tmp_path):
    formula = " | ".join(f"(p{i} & q{i})" for i in range(12))
    result = run_command(["ltl", "dfa", formula, "--json", "--save", "dfa.json"], cwd=tmp_path, timeout=40)
    assert_survived(result, max_seconds=20, max_rss_mb=600)
    guards = [e["guard"] for row in json.loads(result.stdout)["transitions"] for e in row]
    assert "(!p0 | !q0) & (!p1 | !q1)" in " ".join(guards) and max(map(len, guards)) < 300
    from symlearn.logic.automata import load_automaton

    assert load_automaton(tmp_path / "dfa.json").n_states == 3  # the factored guards read back


def test_guard_text_round_trips_and_stays_small():
    """In-process: factored printing is exact (parse(str(g)) == g) and linear on these families."""
    from symlearn.logic.guards import Guard

    for n in (9, 12):
        g = Guard.parse(" | ".join(f"(p{i} & q{i})" for i in range(n)))
        for x in (g, ~g):
            text = str(x)
            assert Guard.parse(text) == x and len(text) < 30 * n
    h = Guard.parse(" | ".join(f"(a{i} & (b{i} | !c{i}))" for i in range(8)))
    assert Guard.parse(str(~h)) == ~h


def test_exploding_dot_label_stops_at_the_node_limit(tmp_path):
    label = " | ".join(f"(a{i} & b{i})" for i in range(300))  # exponential BDD in name order
    (tmp_path / "big.dot").write_text(
        'digraph MONA_DFA {\n node [shape = doublecircle]; 2;\n node [shape = circle]; 1;\n init -> 1;\n'
        f' 1 -> 2 [label="{label}"];\n 1 -> 1 [label="~({label})"];\n 2 -> 2 [label="true"];\n}}\n')
    check(["automaton", "show", "big.dot"], cwd=tmp_path, timeout=30, memory_mb=1024,
          env={"SYMLEARN_MAX_BDD_NODES": "200000"}, names="big.dot", location=True,
          contains=["200,000 nodes", "SYMLEARN_MAX_BDD_NODES"])


# -- class 5: recursion and encoding ------------------------------------------------------------------
def test_deep_json_in_every_json_reader(tmp_path, dfa_file):
    deep = "[" * 100_000 + "]" * 100_000
    (tmp_path / "a.jsonl").write_text(HEADER % ("discrete", '"int64"') + '{"states": [0], "info": {"x": ' + deep + "}}\n")
    (tmp_path / "h.jsonl").write_text(deep + "\n")
    (tmp_path / "a.json").write_text(deep)
    (tmp_path / "t.jsonl").write_text(deep + "\n")
    for args, name in ((["data", "validate", "a.jsonl"], "a.jsonl"), (["data", "info", "h.jsonl"], "h.jsonl"),
                       (["automaton", "show", "a.json"], "a.json"), (["ltl", "eval", "F a", "--traces", "t.jsonl"], "t.jsonl"),
                       (["automaton", "explain", str(dfa_file), "--trace", "t.jsonl"], "t.jsonl")):
        check(args, cwd=tmp_path, timeout=30, names=name, location=True, contains="nested more than")


def test_deep_json_in_library_readers(tmp_path):
    """Readers without a command of their own (labelings, LTL samples, feature maps), in a child."""
    (tmp_path / "l.json").write_text("[" * 100_000 + "]" * 100_000)
    code = """
from symlearn.errors import SymlearnError
from symlearn.grounding.labeling import load_labeling
from symlearn.data.ltl_samples import load_sample
from symlearn.grounding.features import FeatureMap
for read in (load_labeling, load_sample, FeatureMap.load):
    try:
        read("l.json")
    except SymlearnError as exc:
        assert "nested more than" in str(exc) and "l.json:1:" in str(exc), str(exc)
    else:
        raise AssertionError(read)
print("ok")
"""
    result = run_python(code, cwd=tmp_path, timeout=60)
    assert result.returncode == 0 and result.stdout.strip() == "ok", result.describe()


def test_deeply_nested_formula_is_linear(tmp_path):
    (tmp_path / "f.ltl").write_text("!" * 30_000 + "p\n" + "(" * 10_000 + "p" + ")" * 10_000 + "\n")
    result = run_command(["ltl", "dfa", "--file", "f.ltl"], cwd=tmp_path, timeout=30, memory_mb=1024)
    assert_survived(result, max_seconds=20, max_rss_mb=400)
    result = run_command(["ltl", "parse", "!" * 30_000 + "p"], cwd=tmp_path, timeout=30)
    assert result.returncode == 0 and result.max_rss_mb < 300, result.describe()  # was quadratic: 5 GB at 100,000


def test_non_utf8_inputs_name_the_byte(tmp_path):
    (tmp_path / "d.jsonl").write_bytes(HEADER.encode() % (b"discrete", b'"int64"') + b'{"states": [0], "info": {"n": "\xe9"}}\n')
    (tmp_path / "a.json").write_bytes(b'{"format": "symlearn-automaton", "kind": "\xff"}')
    (tmp_path / "a.dot").write_bytes(b"digraph MONA_DFA {\n init -> 1;\n 1 -> 1 [label=\"\xfe\"];\n}\n")
    for args, name, where in ((["data", "validate", "d.jsonl"], "d.jsonl", ":2:"),
                              (["automaton", "show", "a.json"], "a.json", ":1:"),
                              (["automaton", "show", "a.dot"], "a.dot", ":3:")):
        line = check(args, cwd=tmp_path, timeout=30, names=name, location=True, contains="not UTF-8").stderr
        assert where in line


def test_npz_labels_with_more_columns_than_names(tmp_path):
    from symlearn.data import Demonstrations, Trajectory

    Demonstrations([Trajectory(states=[0, 1, 2], labels=[[], ["a"], ["b"]])]).save(tmp_path / "d.npz")
    with np.load(tmp_path / "d.npz") as archive:
        members = {k: archive[k] for k in archive.files}
    members["labels"] = np.ones((3, 5), dtype=bool)
    np.savez_compressed(tmp_path / "d.npz", **members)
    check(["data", "info", "d.npz"], cwd=tmp_path, timeout=30, names="d.npz", contains="5 columns but 'label_names' has 2")


# -- class 6: files ------------------------------------------------------------------------------------
def test_outputs_honour_the_umask_and_keep_an_existing_mode(tmp_path):
    source = _demos(tmp_path)
    old = os.umask(0o022)
    try:
        assert run_command(["data", "convert", source.name, "d.npz"], cwd=tmp_path, timeout=30).returncode == 0
        assert (tmp_path / "d.npz").stat().st_mode & 0o777 == 0o644
        existing = tmp_path / "old.jsonl"
        existing.write_text("")
        os.chmod(existing, 0o640)
        assert run_command(["data", "convert", source.name, existing.name], cwd=tmp_path, timeout=30).returncode == 0
        assert existing.stat().st_mode & 0o777 == 0o640  # an existing file replaced: its mode kept
        # (converting a file onto itself is refused since the tenth round: no command writes over its input)
        os.umask(0o077)
        assert run_command(["data", "convert", source.name, "e.npz"], cwd=tmp_path, timeout=30).returncode == 0
        assert (tmp_path / "e.npz").stat().st_mode & 0o777 == 0o600
    finally:
        os.umask(old)


def test_sigterm_during_a_write_leaves_no_temporary_file(tmp_path):
    """The write is held open (a slow disk), SIGTERM arrives: exit 143, no target, no .tmp."""
    source = _demos(tmp_path)
    code = f"""
import sys, time
import symlearn.atomic as atomic
real = atomic.atomic_open
from contextlib import contextmanager
@contextmanager
def slow(path, mode="w", encoding="utf-8"):
    with real(path, mode, encoding) as handle:
        handle.write("x" * 1000 if "b" not in mode else b"x" * 1000)
        print("writing", flush=True)
        time.sleep(30)
        yield handle
atomic.atomic_open = slow
from symlearn.cli.main import main
sys.exit(main(["data", "convert", {source.name!r}, "out.jsonl"]))
"""
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "writing"
    assert list(tmp_path.glob(".out.jsonl.*.tmp"))  # the write is under way
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 143 and "terminated" in err and "Traceback" not in err
    assert not (tmp_path / "out.jsonl").exists() and not list(tmp_path.glob("*.tmp")) and \
        not list(tmp_path.glob(".*.tmp"))


def test_learn_spec_refuses_an_output_name_that_would_clash(tmp_path):
    (tmp_path / "notes.svg").write_text("<svg>mine</svg>")
    check(["learn", "spec", "--env", "office-1", "-o", "notes.txt"], cwd=tmp_path, timeout=30,
          contains=["notes.txt", "must end in .ltl", "notes.ltl"])
    assert (tmp_path / "notes.svg").read_text() == "<svg>mine</svg>" and not (tmp_path / "notes.txt").exists()


@pytest.mark.parametrize("method, name, hint", [("ml", "X.lp", "X.json"), ("logic", "rules.json", "rules.lp"),
                                                ("mce-icrl", "cost.lp", "cost.json")])
def test_learn_constraints_refuses_a_mismatched_suffix(tmp_path, method, name, hint):
    env = "gridworld" if method != "logic" else "hanoi"
    check(["learn", "constraints", "--env", env, "--method", method, "-o", name], cwd=tmp_path, timeout=30,
          contains=[name, hint], outputs=[name], max_seconds=15)


# -- class 10: looser edges ------------------------------------------------------------------------------
def test_labeling_files_are_checked(tmp_path):
    code = """
import json
from symlearn.errors import SymlearnError
from symlearn.grounding.labeling import load_labeling
base = {"symlearn": "labeling", "format_version": 1, "kind": "table",
        "propositions": [{"name": "a", "meaning": ""}, {"name": "b", "meaning": ""}]}
cases = {
    "dup_state": ({**base, "table": [[0, ["a"]], [0, ["b"]]]}, "listed twice"),
    "undeclared": ({**base, "table": [[0, ["c"]]]}, "not declared"),
    "dup_prop": ({**base, "propositions": base["propositions"] * 2, "table": []}, "declared twice"),
}
for name, (doc, expected) in cases.items():
    open(name + ".json", "w").write(json.dumps(doc))
    try:
        load_labeling(name + ".json")
    except SymlearnError as exc:
        assert expected in str(exc) and name + ".json" in str(exc), str(exc)
    else:
        raise AssertionError(name)
text = json.dumps({**base, "table": [[0, ["a"]]]}).replace('"kind": "table"', '"kind": "table", "kind": "table"')
open("k.json", "w").write(text)
try:
    load_labeling("k.json")
except SymlearnError as exc:
    assert "appears twice" in str(exc) and "k.json:1:" in str(exc), str(exc)
else:
    raise AssertionError("duplicate key")
print("ok")
"""
    result = run_python(code, cwd=tmp_path, timeout=60)
    assert result.returncode == 0 and result.stdout.strip() == "ok", result.describe()


def test_ltl_eval_warns_about_propositions_that_never_hold(tmp_path):
    (tmp_path / "t.jsonl").write_text('[["cofee"], ["office"]]\n')
    result = run_command(["ltl", "eval", "F coffee", "--traces", "t.jsonl"], cwd=tmp_path, timeout=30)
    assert result.returncode == 0 and "coffee" in result.stderr and "cofee" in result.stderr, result.describe()


@pytest.mark.parametrize("dialect, formula, forbidden", [("spot", "(coffee T office) & a W b", " T "),
                                                         ("ltlf2dfa", "(coffee T office) & a W b", " W ")])
def test_ltl_parse_expands_what_the_target_cannot_read(tmp_path, dialect, formula, forbidden):
    from symlearn.logic.ltlf import parse
    from symlearn.logic.ltlf.to_dfa import equivalent

    result = run_command(["ltl", "parse", formula, "--to", dialect, "--json"], cwd=tmp_path, timeout=30)
    printed = json.loads(result.stdout)["formula"]
    assert result.returncode == 0 and forbidden not in f" {printed} " and " T " not in f" {printed} "
    assert equivalent(parse(printed, dialect), parse(formula))
    assert "cannot read" in result.stderr


def test_hoa_export_says_how_a_dfa_is_encoded(tmp_path, dfa_file):
    result = run_command(["automaton", "convert", str(dfa_file), "spec.hoa"], cwd=tmp_path, timeout=30)
    text = (tmp_path / "spec.hoa").read_text()
    assert result.returncode == 0 and "from_ltlf" in result.stderr
    assert "finite words" in text.splitlines()[1] and '"alive"' in text and "/*" in text


def test_json_errors_print_an_error_document(tmp_path):
    (tmp_path / "bad.ltl").write_text("F (\n")
    result = run_command(["ltl", "dfa", "--file", "bad.ltl", "--json"], cwd=tmp_path, timeout=30)
    assert_refused(result, names="bad.ltl", location=True)
    error = json.loads(result.stdout)["error"]
    assert error["file"] == "bad.ltl" and error["line"] == 1 and error["kind"] == "ParseError" and error["message"]
    result = run_command(["data", "info", "missing.jsonl", "--json"], cwd=tmp_path, timeout=30)
    assert result.returncode == 2 and json.loads(result.stdout)["error"]["file"] == "missing.jsonl"


def test_learn_spec_refuses_demonstrations_of_another_environment(tmp_path):
    from symlearn.cli.learn_command import _check_demos_world
    from symlearn.data import Demonstrations
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task
    from symlearn.errors import DataError

    demos = expert_demonstrations(get_task("craft-1"), 3, seed=0)
    office = get_task("office-1")
    with pytest.raises(DataError, match="recorded in task 'craft-1'"):
        _check_demos_world(demos, "craft.jsonl", office, office.make_env())
    Demonstrations(list(demos)).save(tmp_path / "anonymous.jsonl")  # no metadata: the labels give it away
    check(["learn", "spec", "--env", "office-1", "--demos", "anonymous.jsonl"], cwd=tmp_path, timeout=60,
          names="anonymous.jsonl", contains="another environment")


# -- the newcomer path -------------------------------------------------------------------------------------
def test_readme_creates_demos_jsonl_before_converting_it():
    text = (REPO / "README.md").read_text()
    lines = text.splitlines()
    assert lines[3:5] == ["make demo    # fresh machine: creates .venv, installs everything, runs `symlearn demo` "
                          "into ./symlearn-demo/",
                          "make test    # fresh machine: installs everything incl. test tools and oracles, runs "
                          "the full test suite"]
    created = text.index('demos.save("demos.jsonl")')
    uses = [m.start() for m in re.finditer(r"data (convert|info) demos\.jsonl", text)]
    assert uses and all(at > created for at in uses)


def test_doctor_hints_match_the_readme():
    from symlearn.optional import ENGINES

    readme = (REPO / "README.md").read_text()
    for engine in ENGINES.values():
        for command in re.findall(r"\.venv/bin/pip install -e '\.\[\w+\]'", engine.install_hint):
            assert command in readme, (engine.name, command)
        if engine.name == "spot":
            assert "install it from your distribution or conda-forge" in readme
    extras = set(re.findall(r"pip install -e '\.\[(\w+)\]'", readme))
    hinted = {x for e in ENGINES.values() for x in re.findall(r"'\.\[(\w+)\]'", e.install_hint)}
    assert extras == hinted


def test_mce_icrl_writes_the_cost_map(tmp_path):
    result = run_command(["learn", "constraints", "--env", "gridworld", "--method", "mce-icrl", "--n-demos", 5,
                          "--iterations", 10, "-o", "cost.json"], cwd=tmp_path, timeout=60)
    assert result.returncode == 0, result.describe()
    assert "learned cost per cell" in result.stdout and result.stdout.count("\n") > 8
    assert json.loads((tmp_path / "cost.json").read_text())["format"] == "symlearn-constraints"
    grid = (tmp_path / "cost.costmap.txt").read_text()
    assert "threshold" in grid and len(grid.splitlines()) == 2 + 7
    assert "digraph" in (tmp_path / "cost.costmap.dot").read_text()
    from symlearn.rendering import dot_available

    if dot_available():
        assert "<svg" in (tmp_path / "cost.costmap.svg").read_text()


def test_demo_pictures_show_counts_and_whole_titles():
    from symlearn.demo.demonstrations_pipeline import _state_graph_dot
    from symlearn.demo.gridworld_pipeline import constraint_map_dot
    from symlearn.envs.gridworld import StochasticGridworld

    env = StochasticGridworld(0.3)
    counts = np.zeros(env.n_states)
    counts[env.forbidden_states] = 4
    dot = constraint_map_dot(env, counts, "ML inference: forbidden actions per cell (p = 0.3; thick border = "
                                          "truly forbidden)")
    assert ">4<" in dot and "4.0" not in dot and "<br/>" in dot and "label=\"ML" not in dot
    from symlearn.data import Demonstrations, Trajectory

    desc = np.array([list("SFFF"), list("FHFH"), list("FFFH"), list("HFFG")])
    demos = Demonstrations([Trajectory(states=[0, 1, 2, 6, 10, 14, 15], actions=[2, 2, 1, 1, 1, 2])])
    grid = _state_graph_dot(demos, desc)
    assert grid.count("<tr>") == 4 + 1 and "rankdir" not in grid and "->" not in grid


# -- the fuzzer ---------------------------------------------------------------------------------------------
def test_mutation_fuzzer_short_run(tmp_path):
    """500 seeded mutants over every reader but domain folders (each read in a worker process, too
    slow for this round: benchmarks/fuzz_inputs.py covers them), in a child with 1 GB: no crash."""
    code = f"""
import json
from fuzz_inputs import READERS, fuzz_readers
report = fuzz_readers(500, 20240, {str(tmp_path)!r}, formats=[f for f in READERS if f != "domain"])
print(json.dumps(report))
"""
    result = run_python(code, cwd=tmp_path, timeout=90, memory_mb=1024)
    assert result.returncode == 0, result.describe()
    report = json.loads(result.stdout)
    assert report["inputs"] == 500 and len(report["per_format"]) == 19
    assert not report["crashes"], json.dumps(report["crashes"], indent=1)


@pytest.mark.slow
def test_mutation_fuzzer_through_the_cli(tmp_path):
    """The long run: mutants through the real commands (benchmarks/fuzz_inputs.py does more)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("fuzz_benchmark", REPO / "benchmarks" / "fuzz_inputs.py")
    benchmark = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(benchmark)
    report = benchmark.run_cli_fuzz(20, seed=7, folder=tmp_path)
    assert not report["crashes"], json.dumps(report["crashes"], indent=1)


@pytest.mark.slow
def test_issue_examples_at_full_size(tmp_path):
    formula = " & ".join(f"F p{i}" for i in range(10))
    result = run_command(["ltl", "dfa", formula, "--json"], cwd=tmp_path, timeout=60)
    assert_survived(result, max_seconds=30)
    assert json.loads(result.stdout)["states"] == 1024
