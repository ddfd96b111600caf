"""Reliability at scale and on the newer readers (issue 26): every case is generated here at its
size (no stored files), run through the real command in a child process under ``RLIMIT_AS``
(tests/support/hostile.py), and must end in one clear line and exit 2, within bounded time and
memory, or (for the large-input cases) finish within a time that only linear work allows.
"""

from __future__ import annotations

import io
import json
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest

from hostile import assert_refused, assert_survived, check, run_command
from zip_bombs import deflate as _deflate, zip_of as _zip


# -- NPZ: every member numpy would load is size-checked, under the name numpy loads it by --------
def _bomb_member(rows: int, zero_blocks: int) -> tuple[bytes, int, int]:
    """An int64 ``.npy`` member declaring ``rows`` rows, with ``zero_blocks`` x 8 MB of zeros
    really inside (a few KB compressed)."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<i8", "fortran_order": False, "shape": (rows,)})
    return _deflate(header.getvalue(), zero_blocks)


def _suffixless_bomb(path: Path, member: str, zero_blocks: int = 128) -> Path:
    """A frame archive whose ``member`` is stored without the ``.npy`` suffix (numpy loads it by
    that name all the same), holding a ~1 GB bomb."""
    small = io.BytesIO()
    np.save(small, np.ones(3, dtype=np.int64))
    members = {"lengths.npy": _deflate(small.getvalue(), 0),
               member: _bomb_member(zero_blocks * (8 << 20) // 8, zero_blocks)}
    path.write_bytes(_zip(members))
    return path


SUFFIXLESS_READERS = [
    ["data", "info", "{file}"],
    ["learn", "pdfa", "--demos", "{file}", "-o", "out.json"],
    ["dnf", "eval", "rules.dnf", "--points", "{file}"],
    ["learn", "rm", "--demos", "{file}", "-o", "out.json"],
]


@pytest.mark.parametrize("command", SUFFIXLESS_READERS, ids=lambda c: " ".join(c[:2]))
def test_npz_member_without_npy_suffix_is_size_checked(tmp_path, command):
    path = _suffixless_bomb(tmp_path / "bomb.npz", "states")
    assert path.stat().st_size < 1_200_000
    (tmp_path / "rules.dnf").write_text("x > 0.5\n")
    result = check([a.replace("{file}", path.name) for a in command], cwd=tmp_path, timeout=30, memory_mb=1024,
                   names="bomb.npz", contains=["SYMLEARN_MAX_ARRAY_MB", "exceeds the limit"])
    assert result.max_rss_mb < 400


def test_npz_zip_directory_size_bounds_expansion(tmp_path):
    """A member whose .npy header declares 3 rows but whose zip entry expands to 1 GB: refused
    from the zip directory, before inflating."""
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<i8", "fortran_order": False, "shape": (3,)})
    path = tmp_path / "bomb.npz"
    path.write_bytes(_zip({"points.npy": _deflate(header.getvalue(), 128)}))
    (tmp_path / "rules.dnf").write_text("x > 0.5\n")
    result = check(["dnf", "eval", "rules.dnf", "--points", path.name], cwd=tmp_path, timeout=30, memory_mb=1024,
                   names="bomb.npz", contains="SYMLEARN_MAX_ARRAY_MB")
    assert result.max_rss_mb < 400


def test_npz_member_answering_to_one_name_twice_is_refused(tmp_path):
    small = io.BytesIO()
    np.save(small, np.ones(3))
    path = tmp_path / "twice.npz"
    path.write_bytes(_zip({"points.npy": _deflate(small.getvalue(), 0), "points": _deflate(small.getvalue(), 0)}))
    (tmp_path / "rules.dnf").write_text("x > 0.5\n")
    check(["dnf", "eval", "rules.dnf", "--points", path.name, "--features", "x"], cwd=tmp_path, timeout=30,
          names="twice.npz", contains="two members answer to the name 'points'")


def test_npz_member_that_is_no_array_is_refused(tmp_path):
    path = tmp_path / "raw.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("notes.txt", "hello")
    check(["data", "info", path.name], cwd=tmp_path, timeout=30, names="raw.npz",
          contains="member 'notes.txt' is not a .npy array")


def test_bare_npy_declaring_more_than_it_holds_is_refused(tmp_path):
    path = tmp_path / "points.npy"
    with open(path, "wb") as handle:
        np.lib.format.write_array_header_1_0(handle, {"descr": "<f8", "fortran_order": False,
                                                      "shape": (10**9, 4)})
    (tmp_path / "rules.dnf").write_text("x > 0.5\n")
    result = check(["dnf", "eval", "rules.dnf", "--points", path.name, "--features", "x,y,z,w"], cwd=tmp_path,
                   timeout=30, memory_mb=1024, names="points.npy", contains="declared array size")
    assert result.max_rss_mb < 400


@pytest.mark.parametrize("command", [["dnf", "eval", "rules.dnf", "--points", "/dev/zero"],
                                     ["data", "info", "/dev/zero.npz"]])
def test_npz_readers_refuse_a_device(tmp_path, command):
    (tmp_path / "rules.dnf").write_text("x > 0.5\n")
    if command[-1] == "/dev/zero.npz":  # data picks the format from the suffix: a symlink to the device
        (tmp_path / "zero.npz").symlink_to("/dev/zero")
        command = ["data", "info", "zero.npz"]
    result = check(command, cwd=tmp_path, timeout=30, memory_mb=1024, contains="not a regular file")
    assert result.seconds < 20


# -- model files: weights capped, layer sizes from the configuration never allocated unchecked -----
def _saved_cost(folder: Path) -> Path:
    import gymnasium as gym
    import torch

    import symlearn.envs  # noqa: F401  (registers the gymnasium ids)
    from symlearn.envs.registry import get
    from symlearn.learners.neural import NeuralCost
    from symlearn.learners.neural.feature_network import FeatureNetwork

    cost = NeuralCost.for_env(gym.make(get("blocked-point").gym_id),
                              FeatureNetwork([0], 0, 1, (8,), torch.Generator().manual_seed(0)))
    cost.set_lambdas([1.0])
    cost.save(folder / "cost.safetensors")
    return folder / "cost.safetensors"


@pytest.mark.parametrize("hidden, words", [
    ([100_000, 100_000, 100_000], "do not fit the configured model"),
    pytest.param([-3], "positive layer widths", marks=pytest.mark.slow),
    pytest.param([1e300], "not a feature-network configuration", marks=pytest.mark.slow),
    ([64.5, 8], "must be whole numbers")])  # int() read 64.5 as 64, silently (held-out pass)
def test_cost_configuration_layer_sizes_are_not_allocated(tmp_path, hidden, words):
    """3 x 10^10 weights declared beside an 8-unit file: refused from shapes built on the meta
    device, nothing allocated (an internal MemoryError before)."""
    import json

    path = _saved_cost(tmp_path)
    document = json.loads(path.with_suffix(".json").read_text())
    document["config"]["phi"]["hidden_sizes"] = hidden
    path.with_suffix(".json").write_text(json.dumps(document))
    result = check(["train", "--env", "blocked-point", "--cost", path.name, "--steps", 256], cwd=tmp_path,
                   timeout=60, memory_mb=3072, contains=words)
    assert result.max_rss_mb < 1000


def test_weights_file_read_is_capped(tmp_path):
    path = _saved_cost(tmp_path)
    path.unlink()
    path.symlink_to("/dev/zero")
    result = check(["train", "--env", "blocked-point", "--cost", path.name, "--steps", 256], cwd=tmp_path,
                   timeout=60, memory_mb=3072, env={"SYMLEARN_MAX_ARRAY_MB": "8"}, names="cost.safetensors",
                   contains=["larger than the limit of 8 MB", "SYMLEARN_MAX_ARRAY_MB"])
    assert result.max_rss_mb < 1000


def test_saved_labeling_is_checked(tmp_path):
    """NaN prototypes are refused; a features file outside the labeling's folder is never opened."""
    import json

    from symlearn.errors import SymlearnError
    from symlearn.learners.reward_machines.labeling import PrototypeLabeling

    base = {"symlearn": "labeling", "kind": "prototypes", "format_version": 1, "kappa": 1.0,
            "propositions": ["a"], "prototypes": [[0.0, 1.0]]}
    cases = [({"prototypes": [[float("nan"), 1.0]], "features": {"kind": "pca", "file": "f.safetensors"}},
              None),
             ({"features": {"kind": "autoencoder", "file": "../../etc/passwd"}}, "features file beside it"),
             ({"features": {"kind": "autoencoder", "file": None}}, "features file beside it"),
             ({"features": {"kind": "pca", "file": "/etc/passwd"}}, "features file beside it"),
             ({"prototypes": [[10**400]], "features": {"kind": "pca", "file": "f"}}, "malformed")]
    for extra, words in cases:
        path = tmp_path / "m.labeling.json"
        path.write_text(json.dumps({**base, **extra}))
        with pytest.raises(SymlearnError) as caught:
            PrototypeLabeling.load(path, feature_extractor=(lambda x: x) if words is None else None)
        assert "m.labeling.json" in str(caught.value) and "\n" not in str(caught.value)
        assert (words or "finite") in str(caught.value), str(caught.value)


# -- sweep files: only the experiment named runs; sizes bounded before cells are listed ------------
CELL = "def cell(seed, n=1):\n    return {'value': seed * n}\n"


def _sweep(folder: Path, head: str, rest: str = "") -> Path:
    (folder / "cells.py").write_text(CELL)
    path = folder / "s.toml"
    path.write_text(f"[sweep]\n{head}\n{rest}")
    return path


@pytest.mark.parametrize("target, words", [
    ('function = "logging:basicConfig"', "standard library"),
    ('function = "os:system"', "standard library"),
    ('function = "numpy:savez"', "library symlearn builds on"),
    ('function = "symlearn.atomic:write_text"', "library symlearn builds on"),
    (f'function = "{Path(io.__file__).resolve()}:open"', "inside the Python installation"),
    # an installed library not on any list: sympy:simplify evaluates its `expr` string (found by a
    # held-out pass; the policy is now an allow-list of the user's own code)
    ('function = "sympy:simplify"\n[fixed]\nexpr = "__import__(\'os\').system(\'touch pwned\')"',
     "a package installed in"),
    ('command = ["sh", "-c", "touch pwned"]', "must start with 'symlearn'"),
    ('command = ["/bin/rm", "x"]', "must start with 'symlearn'"),
])
def test_sweep_runs_only_the_experiment_it_names(tmp_path, target, words):
    path = _sweep(tmp_path, target + "\nseeds = 1")
    check(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=30, names="s.toml",
          location=True, contains=["refused", words])
    assert not (tmp_path / "out").exists() and not (tmp_path / "pwned").exists()


def test_sweep_of_its_own_file_still_runs(tmp_path):
    path = _sweep(tmp_path, 'function = "cells.py:cell"\nseeds = 2')
    result = run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=60)
    assert result.returncode == 0, result.describe()


def test_sweep_of_its_own_module_or_an_allowed_package_runs(tmp_path):
    # a module of the user's own in the current folder (not installed) runs as before
    path = _sweep(tmp_path, 'function = "cells:cell"\nseeds = 2')
    result = run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=60)
    assert result.returncode == 0, result.describe()
    # an installed package passes the policy when the user names it on the command line (sympy is
    # torch's dependency, so always installed; its simplify then fails the signature check)
    path = _sweep(tmp_path, 'function = "sympy:simplify"\nseeds = 1')
    result = run_command(["sweep", "run", path.name, "--out", "out2", "--local", "--allow-package", "sympy"],
                         cwd=tmp_path, timeout=60)
    assert result.returncode == 2 and "a package installed in" not in result.stderr, result.describe()
    assert "simplify() needs parameter expr" in result.stderr and not (tmp_path / "out2").exists()


MARKING_CELL = ("from pathlib import Path\n\ndef cell(seed, n=1):\n"
                "    (Path(__file__).parent / 'ran').write_text('x')\n    return {'value': seed}\n")


def _outside_case(tmp_path: Path) -> tuple[Path, Path]:
    """A sweep folder ``exp`` (the current folder too) and a Python file elsewhere on the machine."""
    exp, elsewhere = tmp_path / "exp", tmp_path / "elsewhere"
    exp.mkdir()
    elsewhere.mkdir()
    (elsewhere / "x.py").write_text(MARKING_CELL)
    return exp, elsewhere


@pytest.mark.parametrize("how", ["absolute", "climbing", "symlink"])
def test_sweep_function_files_stay_in_the_sweep_folder(tmp_path, how):
    # found by the eighth held-out pass: an absolute /elsewhere/x.py:f ran (the policy said "or absolute")
    exp, elsewhere = _outside_case(tmp_path)
    named = {"absolute": f"{elsewhere / 'x.py'}", "climbing": "../elsewhere/x.py", "symlink": "link.py"}[how]
    if how == "symlink":
        (exp / "link.py").symlink_to(elsewhere / "x.py")
    path = exp / "s.toml"
    path.write_text(f'[sweep]\nfunction = "{named}:cell"\nseeds = 1\n')
    check(["sweep", "run", path.name, "--out", "out", "--local"], cwd=exp, timeout=30, names="s.toml",
          location=True, contains=["refused", "lies outside the sweep file's folder", "--allow-outside"])
    assert not (exp / "out").exists() and not (elsewhere / "ran").exists()
    # the user's own permission, on the command line, runs it
    result = run_command(["sweep", "run", path.name, "--out", "out", "--local", "--allow-outside"], cwd=exp,
                         timeout=60)
    assert result.returncode == 0, result.describe()
    assert (elsewhere / "ran").exists()


@pytest.mark.parametrize("words, grid", [
    (["ltl", "dfa", "F a", "--save", "{where}"], '["/elsewhere/f.json"]'),
    (["ltl", "dfa", "F a", "--save={where}"], '["../f.json"]'),
    (["ltl", "dfa", "F a", "--save", "~/{where}"], '["f.json"]'),
    (["ltl", "dfa", "F a", "--save", "{where}/f.json"], '["ok", "sub/../../out"]'),
])
def test_sweep_commands_stay_in_the_sweep_folder(tmp_path, words, grid):
    # found by the eighth held-out pass: `symlearn ... --save /elsewhere/f` wrote outside the folder;
    # every cell's words are checked (parameters put in) before any cell runs
    exp, _ = _outside_case(tmp_path)
    path = exp / "s.toml"
    path.write_text(f"[sweep]\ncommand = {json.dumps(['symlearn', *words])}\nseeds = 1\n[grid]\nwhere = {grid}\n")
    check(["sweep", "run", path.name, "--out", "out", "--local"], cwd=exp, timeout=30, names="s.toml",
          location=True, contains=["refused", "lies outside", "--allow-outside"])
    assert not (exp / "out").exists()


def test_sweep_commands_may_name_paths_inside_the_folder(tmp_path):
    exp, _ = _outside_case(tmp_path)
    (exp / "sub").mkdir()
    path = exp / "s.toml"
    words = ["symlearn", "ltl", "dfa", "F a", "--save", "{where}", "--json"]
    path.write_text(f"[sweep]\ncommand = {json.dumps(words)}\nseeds = 1\n"
                    f"[grid]\nwhere = [\"a.json\", \"sub/../b.json\", \"{exp / 'c.json'}\"]\n")
    result = run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=exp, timeout=120)
    assert result.returncode == 0, result.describe()
    assert all((exp / name).exists() for name in ("a.json", "b.json", "c.json"))


@pytest.mark.parametrize("rest, words", [
    ("seeds = 1000000000\n", "makes more than 1,000,000 cells"),
    ("seeds = 1000\n[grid]\nn = [" + ", ".join(map(str, range(2000))) + "]\n", "more than 1,000,000 cells"),
    ("seeds = [-1]\n", "seed -1 is out of range"),
    ("seeds = [10000000000000000000]\n", "out of range"),
    ("seeds = 1\n[fixed]\nn = " + "[" * 5000 + "]" * 5000 + "\n", "nested more than"),
    ("seeds = 1\n[fixed]\nn = " + "{a = " * 5000 + "1" + "}" * 5000 + "\n", "nested more than"),
])
def test_sweep_sizes_are_bounded_before_cells_are_listed(tmp_path, rest, words):
    path = _sweep(tmp_path, 'function = "cells.py:cell"', rest)
    result = check(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=30,
                   memory_mb=1024, names="s.toml", contains=words)
    assert result.seconds < 20 and result.max_rss_mb < 400


def test_recorded_sweep_with_wrongly_typed_fields(tmp_path):
    import json

    path = _sweep(tmp_path, 'function = "cells.py:cell"\nseeds = 2')
    assert run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=60).returncode == 0
    meta_path = tmp_path / "out" / "sweep.json"
    original = json.loads(meta_path.read_text())
    for key, value in (("seeds", 3), ("grid", [1]), ("path", 7), ("cases", {"a": 1}), ("retries", "x"),
                       ("seeds", ["a"]), ("function", None)):
        meta = json.loads(json.dumps(original))
        meta["spec"][key] = value
        meta_path.write_text(json.dumps(meta))
        check(["sweep", "report", "out"], cwd=tmp_path, timeout=30, names="sweep.json",
              contains="recorded sweep is malformed")
    for value in ("2", 3, -1, 2.0, [2], 10**30):  # "cells" as the runner wrote it: 2
        meta_path.write_text(json.dumps(dict(original, cells=value)))
        check(["sweep", "report", "out"], cwd=tmp_path, timeout=30, names="sweep.json",
              contains=["\"cells\"", "its grid has 2"])
    meta = dict(original, spec=[1, 2])
    meta_path.write_text(json.dumps(meta))
    check(["sweep", "report", "out"], cwd=tmp_path, timeout=30, names="sweep.json")
    path.write_text(path.read_text().replace("seeds = 2", "seeds = 3"))  # another sweep meets the odd record
    check(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=30, contains="holds the results")


def test_results_store_lines_are_capped(tmp_path):
    path = _sweep(tmp_path, 'function = "cells.py:cell"\nseeds = 1')
    assert run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=60).returncode == 0
    store = tmp_path / "out" / "results.jsonl"
    store.unlink()
    store.symlink_to("/dev/zero")
    result = check(["sweep", "report", "out"], cwd=tmp_path, timeout=30, memory_mb=1024, names="results.jsonl",
                   contains="not a regular file")
    assert result.max_rss_mb < 400
    store.unlink()
    store.write_bytes(b"[" * (3 << 20))  # one 3 MB line without an end
    check(["sweep", "report", "out"], cwd=tmp_path, timeout=30, memory_mb=1024, env={"SYMLEARN_MAX_INPUT_MB": "1"},
          names="results.jsonl", contains="longer than the limit of 1 MB")


def test_a_metric_beyond_a_float_is_reported_as_infinite(tmp_path):
    # a 1001-digit integer in results.jsonl stopped `sweep report` with an OverflowError (held-out pass)
    import json

    path = _sweep(tmp_path, 'function = "cells.py:cell"\nseeds = 2')
    assert run_command(["sweep", "run", path.name, "--out", "out", "--local"], cwd=tmp_path, timeout=60).returncode == 0
    store = tmp_path / "out" / "results.jsonl"
    records = [json.loads(line) for line in store.read_text().splitlines()]
    records[0]["metrics"]["value"] = 10 ** 1000
    store.write_text("".join(json.dumps(r) + "\n" for r in records))
    result = run_command(["sweep", "report", "out", "--no-plots"], cwd=tmp_path, timeout=60)
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.describe()
    assert "inf" in (tmp_path / "out" / "report" / "report.md").read_text()


# -- the command line: seeds and paths ----------------------------------------------------------
@pytest.mark.parametrize("seed", ["-1", str(10**40), str(2**32)])
@pytest.mark.parametrize("place", ["before", "after"])
def test_seed_out_of_range_is_one_line(tmp_path, seed, place):
    command = ["learn", "pdfa", "--env", "blocks-place-2", "--n-demos", "2", "-o", "p.json"]
    args = [f"--seed={seed}", *command] if place == "before" else [*command, f"--seed={seed}"]
    check(args, cwd=tmp_path, timeout=30, contains=["--seed", "out of range", "4,294,967,295"],
          outputs=["p.json"])


@pytest.mark.parametrize("make_out", ["file_as_folder", "long_name"])
def test_output_path_errors_are_one_line(tmp_path, make_out):
    (tmp_path / "afile").write_text("x")
    out = "afile/spec.json" if make_out == "file_as_folder" else "a" * 300 + ".json"
    check(["ltl", "dfa", "F a", "--save", out], cwd=tmp_path, timeout=30,
          contains="afile" if make_out == "file_as_folder" else "file name too long")
    sweep = _sweep(tmp_path, 'function = "cells.py:cell"\nseeds = 1')
    check(["sweep", "run", sweep.name, "--out", "afile", "--local"], cwd=tmp_path, timeout=30, names="afile")


def test_an_output_name_just_under_the_limit_is_written(tmp_path):
    """250 bytes is a legal name; its temporary sibling (".NAME.XXXXXXXX.tmp") must be too."""
    name = "a" * 245 + ".json"
    result = run_command(["ltl", "dfa", "F a", "--save", name], cwd=tmp_path, timeout=30)
    assert result.returncode == 0, result.describe()
    assert (tmp_path / name).is_file() and len(list(tmp_path.iterdir())) == 1


# -- JSON on the command line is read as strictly as a file --------------------------------------
@pytest.mark.parametrize("text, words", [
    ('{"wall": 1, "wall": 2}', 'key "wall" appears twice'),
    ('{"wall": 1e400}', "too large for a float"),
    ('{"wall": 1' + "0" * 400 + '}', "is too large"),
    ('{"wall": ' + "[" * 30_000 + "]" * 30_000 + "}", "nested more than 32 levels"),
    ('{"wall": NaN}', "NaN is not a JSON number"),
])
def test_env_kwargs_json_is_strict(tmp_path, text, words):
    result = check(["learn", "icrl", "--env", "blocked-point", "--env-kwargs", text, "-o", "c.safetensors"],
                   cwd=tmp_path, timeout=60, names="--env-kwargs", contains=words, outputs=["c.safetensors"])
    assert result.seconds < 30


def test_option_json_helper():
    from symlearn.errors import DataError
    from symlearn.json_document import load_option_json

    assert load_option_json('{"a": [1, 2.5, {"b": null}]}', "--x") == {"a": [1, 2.5, {"b": None}]}
    assert load_option_json("[1]", "--x", kind=None) == [1]
    with pytest.raises(DataError, match="--x must be a JSON object"):
        load_option_json("[1]", "--x")


# -- the DNF text parser is linear -----------------------------------------------------------------
def _rules(n: int) -> str:
    return "".join(f"x{i % 7} > {i * 0.001:.3f} & y < {i % 97}.5 & z >= -{i % 13}\n" for i in range(n))


def test_dnf_parser_is_linear_and_small(tmp_path):
    """10^5 conjunctions (3 MB): ~50 s and ~400 MB through lark before, a few seconds now."""
    path = tmp_path / "big.dnf"
    path.write_text(_rules(100_000))
    result = run_command(["dnf", "show", path.name, "--json"], cwd=tmp_path, timeout=60, memory_mb=2048)
    assert result.returncode == 0, result.describe()
    assert result.seconds < 20 and result.max_rss_mb < 600, result.describe()


def test_dnf_scanner_agrees_with_the_grammar(monkeypatch):
    """Random well- and ill-formed texts: the scanner's reading (and every error) is the one the
    lark grammar gives when it reads every line itself."""
    import random

    from symlearn.logic import dnf

    def outcome(text):
        try:
            return [str(c) for c in dnf.parse(text, source="f")]
        except Exception as exc:  # noqa: BLE001 - the error itself is compared
            return f"{type(exc).__name__}: {exc}"

    rng = random.Random(26)
    pieces = ["x", "y1", '"a b"', '"q\\"#"', "true", "false", "\u22a4", "\u22a5", "inf", "<", "<=", ">=", "\u2264",
              "=", "1", "-2.5", "+.5", "1e3", "1e999", "nan", "&", "&&", "\u2227", "|", "||", "\u2228", " ", " ",
              "\t", "#c", "\n", "\r\n", "and", "1.2.3", "_z"]
    texts = []
    for _ in range(3000):
        if rng.random() < 0.5:
            atoms = [rng.choice(["x", '"a b"', "inf", "true"]) + rng.choice([" ", ""]) + rng.choice(["<", ">=", "\u2264", "="])
                     + rng.choice([" ", ""]) + rng.choice(["1", "-2.5", "1e999", "nan", "", "1x"]) for _ in range(3)]
            texts.append(rng.choice([" & ", "&&", " | "]).join(atoms) + rng.choice(["", " #c", " |", "\r\n"]) * 2)
        else:
            texts.append("".join(rng.choice(pieces) for _ in range(rng.randint(1, 12))))
    fast = [outcome(t) for t in texts]
    monkeypatch.setattr(dnf, "_scan_line", lambda line, seen: None)
    slow = [outcome(t) for t in texts]
    assert fast == slow
    assert sum(isinstance(f, list) for f in fast) > 50 and sum(isinstance(f, str) for f in fast) > 1000


# -- domain folders read only what lies inside them ------------------------------------------------
SECRET = "secret_fact(73912846)."  # a number no temporary path contains (pytest-42/ did)


def _warehouse(tmp_path: Path) -> tuple[Path, Path]:
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "support"))
    import warehouse_domain as wh

    folder = wh.write_warehouse(tmp_path / "warehouse")
    secret = tmp_path / "secret.lp"
    secret.write_text(SECRET + "\n")
    return folder, secret


def _set_key(folder: Path, key: str, value: str) -> None:
    import re

    toml = folder / "domain.toml"
    toml.write_text(re.sub(rf'^{key} = ".*"$', f"{key} = {value!r}".replace("'", '"'), toml.read_text(), flags=re.M))


def _escape(folder: Path, secret: Path, how: str) -> None:
    if how == "absolute":
        _set_key(folder, "background", str(secret))
    elif how == "dotdot":
        _set_key(folder, "background", "../secret.lp")
    elif how == "symlink":
        (folder / "bk.lp").unlink()
        (folder / "bk.lp").symlink_to(secret)
    elif how == "include_background":
        (folder / "bk.lp").write_text((folder / "bk.lp").read_text() + '\n#include "../secret.lp".\n')
    elif how == "include_linked":  # an include of a file inside the folder that is a link out of it
        (folder / "inner.lp").symlink_to(secret)
        (folder / "bk.lp").write_text((folder / "bk.lp").read_text() + '\n#include "inner.lp".\n')
    elif how == "include_bias":
        (folder / "bias.las").write_text((folder / "bias.las").read_text() + f'\n#include "{secret}".\n')
    elif how == "include_facts":
        lines = (folder / "states.jsonl").read_text().splitlines()
        import json

        first = json.loads(lines[0])
        first["facts"] += f' #include "{secret}".'
        (folder / "states.jsonl").write_text("\n".join([json.dumps(first), *lines[1:]]) + "\n")
    elif how == "include_atom":
        import json

        lines = (folder / "actions.jsonl").read_text().splitlines()
        first = json.loads(lines[0])
        first["atom"] = f'#include "{secret}".'
        (folder / "actions.jsonl").write_text("\n".join([json.dumps(first), *lines[1:]]) + "\n")
    elif how in ("include_facts_no_dot", "include_atom_no_dot"):
        # without its final '.': the reader appends one to a state's facts, so clingo read the
        # file anyway and echoed its first rule in the error (found by a held-out pass)
        import json

        name, key = ("states.jsonl", "facts") if how == "include_facts_no_dot" else ("actions.jsonl", "atom")
        lines = (folder / name).read_text().splitlines()
        first = json.loads(lines[0])
        first[key] = f'#include "{secret}"'
        (folder / name).write_text("\n".join([json.dumps(first), *lines[1:]]) + "\n")


ESCAPES = ["absolute", "dotdot", "symlink", "include_background", "include_linked", "include_bias",
           "include_facts", "include_atom", "include_facts_no_dot", "include_atom_no_dot"]


@pytest.mark.parametrize("how", ESCAPES)
def test_domain_folder_is_confined(tmp_path, how):
    folder, secret = _warehouse(tmp_path)
    _escape(folder, secret, how)
    line = check(["domain", "check", folder], cwd=tmp_path, timeout=60, contains="#include" if "include" in how
                 else "outside" if how != "dotdot" else "leaves the domain folder").stderr
    assert "secret_fact" not in line and "73912846" not in line


def test_domain_path_the_file_system_refuses_is_one_short_line(tmp_path):
    """A 100 kB name in domain.toml (found by the fuzzer): OSError 'File name too long' escaped
    the reader; now a located error that quotes the name cut short."""
    folder, _ = _warehouse(tmp_path)
    _set_key(folder, "bias", "a" * 100_000)
    line = check(["domain", "check", folder], cwd=tmp_path, timeout=60, names="domain.toml",
                 contains=["key 'bias'", "100,000 characters", "is not a usable file name"]).stderr
    assert len(line) < 600


@pytest.mark.parametrize("how", ["absolute", "symlink", "include_background"])
def test_allow_outside_reads_a_trusted_folder(tmp_path, how):
    folder, secret = _warehouse(tmp_path)
    import shutil

    shutil.copy(folder / "bk.lp", secret)  # the outside file is the real background now
    if how == "include_background":
        (folder / "bk.lp").write_text('#include "../secret.lp".\n')
    else:
        _escape(folder, secret, how)
    refused = run_command(["domain", "check", folder], cwd=tmp_path, timeout=60)
    assert refused.returncode == 2, refused.describe()
    result = run_command(["domain", "check", folder, "--allow-outside"], cwd=tmp_path, timeout=120)
    assert result.returncode == 0, result.describe()


@pytest.mark.parametrize("megabytes", [64, 128, 192, 256])
def test_small_worker_memory_limits_are_one_line(tmp_path, megabytes):
    """Below the minimum: refused up front (an ImportError of numpy or a failed thread start was
    an internal error); at it and above, a small domain is checked: the limit is counted on top of
    the worker's libraries (with a bare 128 MB of address space, a 3-state domain ran out)."""
    from symlearn.worker import MIN_MEMORY_MB

    folder, _ = _warehouse(tmp_path)
    result = run_command(["domain", "check", folder, "--max-memory", megabytes], cwd=tmp_path, timeout=60)
    if megabytes < MIN_MEMORY_MB:
        assert_refused(result, contains=["too small", f"at least {MIN_MEMORY_MB} MB"])
    else:
        assert result.returncode == 0, result.describe()


@pytest.mark.parametrize("tensor, value, words", [
    ("phi.obs_index", 5, "contradicts the configuration"),
    pytest.param("phi.input_scale", float("nan"), "NaN or infinite", marks=pytest.mark.slow),
    pytest.param("phi.input_scale", 0.0, "non-positive", marks=pytest.mark.slow)])
def test_cost_tensors_that_contradict_the_configuration(tmp_path, tensor, value, words):
    import torch
    from safetensors.torch import load_file, save_file

    path = _saved_cost(tmp_path)
    tensors = load_file(path)
    tensors[tensor] = torch.full_like(tensors[tensor], value)
    save_file(tensors, path, metadata={"format": "symlearn-torch-module", "kind": "neural-icrl-cost"})
    check(["train", "--env", "blocked-point", "--cost", path.name, "--steps", 256], cwd=tmp_path, timeout=60,
          memory_mb=3072, names="cost.safetensors", contains=words)


# -- automata: minimisation is not quadratic on chains ------------------------------------------
def _chain(n: int) -> dict:
    edges = [e for i in range(n - 1) for e in ({"source": i, "target": i + 1, "guard": "a"},
                                             {"source": i, "target": i, "guard": "!a"})]
    edges.append({"source": n - 1, "target": n - 1, "guard": "true"})
    return {"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a"], "states": n,
            "initial": 0, "accepting": [n - 1], "state_names": None, "transitions": edges}


def test_automaton_show_and_convert_of_a_long_chain(tmp_path):
    """20,000 states: > 60 s before (Moore's rounds, one per state), a few seconds now."""
    import json

    (tmp_path / "chain.json").write_text(json.dumps(_chain(20_000)))
    for args in (["automaton", "show", "chain.json"], ["automaton", "convert", "chain.json", "out.hoa"]):
        result = run_command(args, cwd=tmp_path, timeout=60, memory_mb=2048)
        assert result.returncode == 0 and result.seconds < 30, result.describe()


def test_hopcroft_partition_agrees_with_moore():
    import json
    import random

    from symlearn.logic.automata.json_format import dfa_from_dict
    from symlearn.logic.automata import transition_diagram as td
    from symlearn.logic.automata.transition_diagram import (
        coarsest_blocks, coarsest_blocks_hopcroft, coarsest_blocks_moore,
    )

    minterms = ["a & b", "a & !b", "!a & b", "!a & !b"]
    rng = random.Random(26)
    for _ in range(200):
        n = rng.randint(1, 12)
        edges = [{"source": q, "target": rng.randrange(n), "guard": g} for q in range(n) for g in minterms]
        doc = {"format": "symlearn-automaton", "version": 1, "kind": "dfa", "alphabet": ["a", "b"], "states": n,
               "initial": 0, "accepting": [q for q in range(n) if rng.random() < 0.4], "state_names": None,
               "transitions": edges}
        dfa = dfa_from_dict(json.loads(json.dumps(doc)))
        diagram, roots = dfa.transition_diagram()
        accepting = [q in dfa.accepting for q in range(len(roots))]
        slow = coarsest_blocks_moore(diagram, roots, accepting)
        pairs = [(p, q) for p in range(len(roots)) for q in range(len(roots))]
        switched_early = td.MOORE_ROUNDS
        td.MOORE_ROUNDS = 1  # one Moore round, then Hopcroft from the partition it reached
        try:
            mixed = coarsest_blocks(diagram, roots, accepting)
        finally:
            td.MOORE_ROUNDS = switched_early
        for fast in (coarsest_blocks(diagram, roots, accepting), coarsest_blocks_hopcroft(diagram, roots, accepting),
                     mixed):
            assert [fast[p] == fast[q] for p, q in pairs] == [slow[p] == slow[q] for p, q in pairs]


def test_integers_too_large_for_a_float(tmp_path):
    """JSON keeps 10^400 as an exact integer; turning it into a bound overflowed (internal error)."""
    big = "1" + "0" * 400
    (tmp_path / "rules.json").write_text('{"symlearn": "dnf", "format_version": 1, "conjunctions": '
                                         f'[[["x", "<", {big}]]]}}')
    check(["dnf", "show", "rules.json"], cwd=tmp_path, timeout=30, names="rules.json", contains="too large for a float")
    from symlearn.logic.automata.json_format import _finite_float

    assert not _finite_float(10**400) and _finite_float(10**300) and not _finite_float(float("nan"))


def test_hypothesis_space_of_a_huge_bias_is_refused_without_listing_it():
    """20,000 #modeb allow ~10^12 rule shapes; they were listed before any limit applied
    (minutes, gigabytes). Now enumerated lazily and refused at the rule or shape limit."""
    import resource
    import time

    from symlearn.errors import LimitExceededError
    from symlearn.logic.ilp.parser import parse_task
    from symlearn.logic.ilp.space import generate_space

    task = parse_task("#modeh(goal).\n" + "".join(f"#modeb(1, q{i}).\n" for i in range(20_000)), source="big.las")
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    with pytest.raises(LimitExceededError, match="more than 2000 rules"):
        generate_space(task, limit=2_000)
    assert time.perf_counter() - start < 20
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 300_000  # KB


@pytest.mark.parametrize("limit, words", [
    (["--timeout", "2"], "time limit of 2 s reached while learning constraints in the domain"),
    pytest.param(["--max-memory", "300"], "memory limit of 300 MB reached while learning constraints",
                 marks=pytest.mark.slow)])
def test_learn_constraints_on_a_domain_runs_in_the_bounded_worker(tmp_path, limit, words):
    """A bias with 20,000 #modeb: learning in the folder ran in-process, past 90 s and 2 GB, before;
    now in domain check's bounded worker, stopped at --timeout / --max-memory (18 s and the rule
    limit without them)."""
    import warehouse_domain as wh

    folder, _ = _warehouse(tmp_path)
    bias = folder / "bias.las"
    bias.write_text(bias.read_text() + "".join(f"#modeb(1, q{i}).\n" for i in range(20_000)))
    wh.expert_demonstrations(20).save(tmp_path / "demos.jsonl")
    result = check(["learn", "constraints", "--domain", folder, "--demos", "demos.jsonl", "-o", "rules.lp", *limit],
                   cwd=tmp_path, timeout=30, memory_mb=2048, contains=words, outputs=["rules.lp"])
    assert result.seconds < 15 and result.max_rss_mb < 600


# -- ltl dfa: conjunctions of thousands of conjuncts --------------------------------------------
@pytest.mark.parametrize("conjunct, n", [("p{i}", 10_000), ("G(!a{i}p | a{i}q)", 4_000)])
def test_ltl_dfa_of_thousands_of_small_conjuncts(tmp_path, conjunct, n):
    """Joined one by one, each conjunct copied the BDD built so far: > 60 s and > 2 GB (the node
    limit) for 10,000 literals before; a balanced join makes it a few seconds."""
    (tmp_path / "f.ltl").write_text(" & ".join(conjunct.format(i=i) for i in range(n)) + "\n")
    result = run_command(["ltl", "dfa", "--file", "f.ltl"], cwd=tmp_path, timeout=60, memory_mb=4096)
    assert result.returncode == 0, result.describe()
    assert result.seconds < 20 and result.max_rss_mb < 600, result.describe()


@pytest.mark.parametrize("conjunct, n, words", [
    ("F p{i}", 2000, "2000 independent conjuncts reach at least"),
    ("G(!p{i} | q{i})", 4_000, "interleave in name order"),
])
def test_ltl_dfa_refuses_products_from_a_bound_before_the_work(tmp_path, conjunct, n, words):
    """F p1 & ... & F p2000 climbed past 2 GB before the state limit stopped it; the product of
    independent conjuncts is now bounded first (symlearn/logic/ltlf/conjunct_bound.py)."""
    (tmp_path / "f.ltl").write_text(" & ".join(conjunct.format(i=i) for i in range(n)) + "\n")
    result = check(["ltl", "dfa", "--file", "f.ltl"], cwd=tmp_path, timeout=60, memory_mb=4096, names="f.ltl",
                   contains=words)
    assert result.seconds < 15 and result.max_rss_mb < 400, result.describe()


@pytest.mark.parametrize("flag, value, words", [
    ("--n-steps", "1e9", "--n-steps must be between 1 and 262,144"),
    ("--steps", "1e12", "--steps must be between 1 and 1,000,000,000"),
    ("--n-envs", "1e6", "--n-envs must be between 1 and 256"),
    ("--n-steps", "1e400", "--n-steps must be a whole number"),
])
def test_train_sizes_from_flags_are_bounded_before_allocation(tmp_path, flag, value, words):
    """A rollout buffer is n_envs x n_steps: sized from the flags, it is refused before anything
    is built (torch is not even imported)."""
    result = check(["train", "--env", "CartPole-v1", flag, value], cwd=tmp_path, timeout=30, memory_mb=1024,
                   contains=words)
    assert result.seconds < 10 and result.max_rss_mb < 200


# -- one line, not a library's warning before it (a held-out pass, 2026-12-04) ----------------------
def test_an_all_nan_frame_archive_is_one_line(tmp_path):
    frames = np.full((6, 4), np.nan)
    np.savez(tmp_path / "allnan.npz", states=frames, lengths=np.array([3, 3]))
    result = check(["learn", "pdfa", "--demos", "allnan.npz"], cwd=tmp_path, timeout=60, names="allnan.npz",
                   contains="unobserved")
    assert "warning" not in result.stderr.lower()


@pytest.mark.parametrize("env", ["blocked-point", "point-circle"])
def test_an_arena_beyond_float32_is_refused(tmp_path, env):
    result = check(["train", "--env", env, "--steps", "256", "--n-steps", "128", "--env-kwargs", '{"arena": 1e308}'],
                   cwd=tmp_path, timeout=60, contains="arena must be in")
    assert "warning" not in result.stderr.lower()


@pytest.mark.parametrize("env", ["blocked-point", "point-circle", "gridworld"])
def test_an_episode_length_past_the_cap_is_refused(tmp_path, env):
    # 9e18 was accepted, and a recording ran an endless episode to its own step cap (33 s)
    result = check(["train", "--env", env, "--steps", "256", "--n-steps", "128", "--env-kwargs", '{"max_steps": 9e18}'],
                   cwd=tmp_path, timeout=60, contains=["max_steps must be a whole number in [1, 1,000,000]"])
    assert result.seconds < 30


def test_a_huge_state_id_is_a_gap_not_a_memory_limit(tmp_path):
    # the first missing id came from set(range(largest + 1)): an id of 10^18 ran the worker out of
    # memory, reported as "memory limit reached while grounding" (held-out pass)
    import json

    folder, _ = _warehouse(tmp_path)
    lines = (folder / "states.jsonl").read_text().splitlines()
    last = json.loads(lines[-1])
    last["id"] = 10 ** 18
    (folder / "states.jsonl").write_text("\n".join([*lines[:-1], json.dumps(last)]) + "\n")
    result = check(["domain", "check", folder], cwd=tmp_path, timeout=60, names="states.jsonl",
                   contains=["ids must be 0..1000000000000000000 without gaps", "is missing"])
    assert result.seconds < 20 and result.max_rss_mb < 400


# -- dnf eval: the points x conjunctions table is never held whole (held-out pass, 2026-12-06) -----
def test_dnf_eval_of_many_points_and_conjunctions_is_blockwise(tmp_path):
    """10^5 conjunctions x 10^4 points: numpy was asked for the whole 10^9-cell table at once (an
    internal MemoryError under the cap; 3.7 GiB at 2e5 x 2e4); now a block of points at a time."""
    rng = np.random.default_rng(26)
    (tmp_path / "r.dnf").write_text("".join(f"x > {i * 1e-5:.5f} & y < {i % 97}.5\n" for i in range(100_000)))
    np.savez(tmp_path / "p.npz", points=rng.random((10_000, 2)))
    result = run_command(["dnf", "eval", "r.dnf", "--points", "p.npz", "--features", "x,y", "--json"],
                         cwd=tmp_path, timeout=120, memory_mb=1024)
    assert result.returncode == 0 and "Traceback" not in result.stderr, result.describe()
    assert result.max_rss_mb < 700, result.describe()
    import json

    doc = json.loads(result.stdout)
    assert doc["unsafe_count"] == 10_000 and len(doc["conjunction_hits"]) == 100_000
    check(["dnf", "eval", "r.dnf", "--points", "p.npz", "--features", "x,y", "--per-conjunction"], cwd=tmp_path,
          timeout=120, memory_mb=1024, names="r.dnf", contains=["--per-conjunction would list more than 10,000,000"])


def test_dnf_eval_blocks_agree_with_the_whole_table(tmp_path, monkeypatch, capsys):
    import json

    import symlearn.cli.dnf_command as dnf_command
    from symlearn.cli.main import main
    from symlearn.logic.dnf import load

    rng = np.random.default_rng(7)
    (tmp_path / "r.dnf").write_text("".join(f"x > {rng.random():.3f} & y <= {rng.random():.3f}\nx == {i}\n"
                                            for i in range(40)))
    points = rng.random((1_001, 2))
    points[::50, 0] = 3.0
    np.savez(tmp_path / "p.npz", points=points)
    monkeypatch.setattr(dnf_command, "EVAL_BLOCK_CELLS", 7 * 80)  # 7 points a block
    assert main(["--json", "dnf", "eval", str(tmp_path / "r.dnf"), "--points", str(tmp_path / "p.npz"),
                 "--features", "x,y", "--per-conjunction"]) == 0
    doc = json.loads(capsys.readouterr().out)
    whole = load(tmp_path / "r.dnf").evaluate(points, "x,y", per_conjunction=True)
    assert doc["unsafe"] == whole.any(axis=1).tolist()
    assert doc["conjunction_hits"] == whole.sum(axis=0).tolist()
    assert doc["holding"] == [np.flatnonzero(row).tolist() for row in whole]


def test_learn_spec_refuses_an_output_whose_companions_are_too_long(tmp_path):
    """-o of 254 bytes is a legal name, but SPEC.labeling.json beside it is not: the formula was
    learned and written, then 'File name too long' left it without its labeling (held-out pass)."""
    out = "a" * 250 + ".ltl"
    check(["learn", "spec", "--env", "office-1", "--n-demos", "3", "-o", out], cwd=tmp_path, timeout=60,
          contains=["too long a name", "NAME.labeling.json", "255 bytes"], outputs=[out])
    assert list(tmp_path.iterdir()) == []
    out = "a" * 235 + ".ltl"  # its companions fit: written as before
    result = run_command(["learn", "spec", "--env", "office-1", "--n-demos", "3", "-o", out], cwd=tmp_path, timeout=60)
    assert result.returncode == 0, result.describe()
    assert (tmp_path / out).is_file() and (tmp_path / ("a" * 235 + ".labeling.json")).is_file()


@pytest.mark.parametrize("directive", ['#include %* note *% "{secret}".', '#include % note\n "{secret}" .',
                                       '#include "{secret}" %* note *% .', '#include\t%*a*%%*b*%"{secret}"\n.'])
def test_a_comment_inside_an_include_does_not_hide_it(tmp_path, directive):
    """clingo allows comments between #include and its file name; the directive pattern did not,
    so the folder check never saw it and clingo read the outside file (held-out pass, 2026-12-06)."""
    folder, secret = _warehouse(tmp_path)
    secret.write_text("broken(\n")  # were it read, clingo's syntax error would show it
    (folder / "bk.lp").write_text((folder / "bk.lp").read_text() + "\n" + directive.format(secret=secret) + "\n")
    line = check(["domain", "check", folder], cwd=tmp_path, timeout=60, names="bk.lp", location=True,
                 contains="outside the folder").stderr
    assert "syntax error" not in line


def test_an_include_the_pattern_cannot_read_is_refused(tmp_path):
    from symlearn.errors import ParseError
    from symlearn.logic.asp.program import Program, expand_includes

    (tmp_path / "a.lp").write_text("x.\n")
    (tmp_path / "m.lp").write_text('p.\n#include "a.lp" % no final dot\n')
    with pytest.raises(ParseError, match=r"m.lp:2:1: an #include symlearn cannot read"):
        expand_includes(Program.from_file(tmp_path / "m.lp", expand=False), within=tmp_path)
    (tmp_path / "m.lp").write_text('p. #include %* c *% "a.lp". q.\n')
    parts = expand_includes(Program.from_file(tmp_path / "m.lp", expand=False), within=tmp_path).parts
    assert [p.text for p in parts] == ["p. ", "x.\n", " q.\n"]


@pytest.mark.parametrize("text", [
    "#include " + "%" * 100_000 + "x",          # a run of '%' inside a directive: split two ways per '%'
    "%*\n" * 200_000,                           # unclosed block comments: each rescanned the rest
    '#include %* c *% % note\n "f.lp" .\n' * 50_000,
])
def test_the_include_scan_is_linear(text):
    """The #include patterns match every comment one way only: a run of '%' after '#include'
    took 1 s at 24 characters (doubling with each one), 20,000 unclosed '%*' lines 4.6 s."""
    from symlearn.logic.asp.program import _INCLUDE, find_include

    started = time.perf_counter()
    list(_INCLUDE.finditer(text))
    find_include(text)
    assert time.perf_counter() - started < 2.0


@pytest.mark.parametrize("text", ["%*\n" * 200_000, "a(1). %* x\n" * 100_000 + "\u00e9."])
def test_the_bracket_and_character_scans_are_linear(text):
    """The scans that skip comments before the bracket-depth and character checks: an unclosed '%*'
    rescanned the rest of the text from every later one (quadratic; 20,000 lines took seconds).
    It now runs to the end, as clingo reads it (and refuses it)."""
    from symlearn.logic.asp.clingo_adapter import _CODE_CHARACTER
    from symlearn.logic.asp.program import _SKIP

    started = time.perf_counter()
    _SKIP.sub("", text)
    list(_CODE_CHARACTER.finditer(text))
    assert time.perf_counter() - started < 2.0


def test_an_unclosed_block_comment_is_clingos_error_at_its_place(tmp_path):
    (tmp_path / "h.lp").write_text(":- move(X), wall(X).\n%* a note\nthat never ends\n:- b.\n")
    check(["ilp", "check", str(Path(__file__).resolve().parents[2] / "background_kb/hanoi/tasks/hanoi.las"),
           "h.lp"], cwd=tmp_path, timeout=60, names="h.lp", location=True)
