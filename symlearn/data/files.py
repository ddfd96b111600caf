"""Choose the file format from the path (suffix, folder, content) and turn OS errors into readable ones.

Read: ``.jsonl`` (symlearn), ``.npz`` (symlearn's archive when it has a ``__meta__`` member, a
D4RL table when it has ``observations``), ``.hdf5``/``.h5`` (a Minari ``main_data.hdf5`` when
it holds ``episode_<i>`` groups, a D4RL table otherwise) and a folder (a Minari dataset).
Written: ``.jsonl`` and ``.npz`` in symlearn's formats, ``.hdf5``/``.h5`` as a D4RL table, and
``.npz`` as a D4RL table with ``format="d4rl"``.
"""

from __future__ import annotations

import os
import zipfile
from pathlib import Path

from symlearn.data.demonstrations import Demonstrations
from symlearn.errors import DataError

SUFFIXES = (".jsonl", ".npz", ".hdf5", ".h5")
HDF5_SUFFIXES = (".hdf5", ".h5")
#: what ``save(..., format=)`` accepts; ``None`` picks by suffix
SAVE_FORMATS = ("symlearn", "d4rl")


def _format_of(path: Path, *, writing: bool = False) -> str:
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        hint = ("use .jsonl for symbolic/discrete traces, .npz for numeric/image arrays, .hdf5 for a D4RL "
                "table" + (" (Minari datasets are read, not written: minari's DataCollector writes them)"
                           if writing else ", or a Minari dataset folder"))
        if not writing:
            hint = _content_hint(path) or hint
        raise DataError(f"unknown demonstrations format {suffix or '(no suffix)'!r}", file=path, hint=hint)
    return suffix


def _content_hint(path: Path) -> str | None:
    """What to do with a file whose suffix says nothing, judged by its first bytes: JSONL saved as
    ``.json`` (the commonest slip) only needs renaming; a JSON list of trajectories or a CSV table
    needs rewriting, and the hint says into what."""
    import stat

    try:
        if not stat.S_ISREG(path.stat().st_mode):
            return None
        with open(path, "rb") as f:
            head = f.read(512).decode("utf-8", errors="replace").lstrip("\ufeff \t\r\n")
    except OSError:
        return None
    if head.startswith("{") and '"symlearn"' in head.split("\n", 1)[0] and '"demonstrations"' in head.split("\n", 1)[0]:
        return f"the file holds JSONL demonstrations (a header line, one trajectory per line): rename it {path.stem}.jsonl"
    if head.startswith("[") or head.startswith("{"):
        return ("demonstrations in JSON are JSONL: a header line {\"symlearn\": \"demonstrations\", \"format_version\": 1}, "
                "then one trajectory per line, {\"states\": [...], \"actions\": [...]} (docs/FORMATS.md), saved as .jsonl")
    if path.suffix.lower() in (".csv", ".tsv", ".txt"):
        return ("tables are not read as demonstrations: write one line per episode, {\"states\": [{\"x\": 0.1, "
                "\"y\": 0.2}, ...]}, after a header line {\"symlearn\": \"demonstrations\", \"format_version\": 1} "
                "in a .jsonl file, or np.savez an .npz (docs/FORMATS.md)")
    return None


def save(demos: Demonstrations, path: str | os.PathLike[str], *, format: str | None = None) -> None:
    """Write ``demos`` to ``path``; the old file survives any failure. ``format="d4rl"`` writes a
    D4RL table (the only choice for ``.hdf5``/``.h5``; for ``.npz`` instead of symlearn's archive)."""
    path = Path(path)
    suffix = _format_of(path, writing=True)
    if format is not None and format not in SAVE_FORMATS:
        raise DataError(f"unknown format {format!r}", hint=f"use one of {', '.join(SAVE_FORMATS)}")
    if suffix in HDF5_SUFFIXES and format == "symlearn":
        raise DataError("symlearn writes HDF5 only as a D4RL table", file=path, hint="use .npz or .jsonl")
    if suffix == ".jsonl" and format == "d4rl":
        raise DataError("a D4RL table is an .npz or .hdf5 file", file=path)
    _refuse_unreadable_text(demos, path)
    if suffix in HDF5_SUFFIXES or format == "d4rl":
        from symlearn.data.d4rl_format import write_d4rl

        write_d4rl(demos, path)
    elif suffix == ".jsonl":
        from symlearn.data.jsonl_format import write_jsonl

        write_jsonl(demos, path)
    else:
        from symlearn.data.npz_format import write_npz

        write_npz(demos, path)


def _refuse_unreadable_text(demos: Demonstrations, path: Path) -> None:
    """Refuse, before anything is written, text no reader takes back: a string with a lone
    surrogate (half of a UTF-16 pair, not a character -- Python's reading of bytes that are not
    UTF-8) in the metadata, a trajectory's actions, labels or info."""
    from symlearn.input_limits import lone_surrogate_at

    found = lone_surrogate_at(demos.metadata, "metadata")
    for i, traj in enumerate(demos):
        if found:
            break
        for field in ("actions", "labels", "info"):
            value = getattr(traj, field)
            if field == "labels" and value is not None:
                value = [sorted(step) for step in value]
            found = lone_surrogate_at(value, f"trajectory {i}, {field}") if value is not None else None
            if found:
                break
    if found:
        raise DataError(f"{found} holds a lone surrogate (half of a UTF-16 pair, not a character): "
                        "the file could not be read back", file=path,
                        hint="decode the text that came from bytes (a file name, say) with errors='replace', "
                             "or write the character itself")


def detect(path: str | os.PathLike[str]) -> str:
    """Which reader ``path`` goes to: ``jsonl``, ``npz``, ``d4rl-npz``, ``d4rl-hdf5`` or ``minari``."""
    path = Path(path)
    if path.is_dir():
        if path.suffix.lower() in SUFFIXES:
            raise DataError("is a directory, expected a demonstrations file", file=path)
        return "minari"
    fmt = _format_of(path)
    if not path.exists():
        raise DataError("no such file", file=path)
    if fmt == ".jsonl":
        return "jsonl"
    if fmt == ".npz":
        names = _npz_members(path)
        return "d4rl-npz" if "__meta__" not in names and "observations" in names else "npz"
    from symlearn.data.hdf5_reading import top_level_names
    from symlearn.data.minari_format import is_episode_group

    return "minari" if any(is_episode_group(name) for name in top_level_names(path)) else "d4rl-hdf5"


def _npz_members(path: Path) -> set[str]:
    """Member names of an archive (a damaged one, or no regular file: none, and symlearn's reader
    says what is wrong -- zipfile would read ``/dev/zero`` without end looking for a directory)."""
    import stat

    try:
        if not stat.S_ISREG(path.stat().st_mode):
            return set()
    except OSError:
        return set()
    try:
        with zipfile.ZipFile(path) as archive:
            return {name[:-4] for name in archive.namelist() if name.endswith(".npy")}
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError, NotImplementedError, RuntimeError):
        return set()


def load(path: str | os.PathLike[str]) -> Demonstrations:
    """Read demonstrations written by :func:`save`, a D4RL table or a Minari dataset."""
    path = Path(path)
    fmt = detect(path)
    if fmt == "minari":
        from symlearn.data.minari_format import read_minari

        return read_minari(path)
    if fmt == "jsonl":
        from symlearn.data.jsonl_format import read_jsonl

        return read_jsonl(path)
    if fmt == "d4rl-npz":
        from symlearn.data.d4rl_format import read_d4rl_npz

        return read_d4rl_npz(path)
    if fmt == "d4rl-hdf5":
        from symlearn.data.d4rl_format import read_d4rl_hdf5

        return read_d4rl_hdf5(path)
    from symlearn.data.npz_format import read_npz

    return read_npz(path)
