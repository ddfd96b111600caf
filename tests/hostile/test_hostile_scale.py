"""Reliability at scale and on the newer readers (issue 26): every case is generated here at its
size (no stored files), run through the real command in a child process under ``RLIMIT_AS``
(tests/support/hostile.py), and must end in one clear line and exit 2, within bounded time and
memory, or (for the large-input cases) finish within a time that only linear work allows.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest

from hostile import check, run_command
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
    ["learn", "pdfa", "--demos", "{file}", "--out", "out.json"],
    ["dnf", "eval", "rules.dnf", "--points", "{file}"],
    ["learn", "rm", "--demos", "{file}", "--out", "out.json"],
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


@pytest.mark.parametrize("hidden, words", [([100_000, 100_000, 100_000], "do not fit the configured model"),
                                           ([-3], "positive layer widths"),
                                           ([1e300], "not a feature-network configuration")])
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
