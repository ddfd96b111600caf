"""No command writes over one of its own inputs (issue 26, tenth round).

``train --machine m.json -o m.safetensors`` wrote the policy's ``m.json`` beside its weights,
over the machine it had just read; ``learn spec --labeling x.labeling.json -o x.ltl`` would
write its labeling companion over the labeling given. Checked once for every command, before it
does any work, from the parsed arguments: every file a command writes (its output options and
the companions written beside them) against every file it reads (the arguments naming existing
files and the companions read beside them). The same file under another name (a symlink, a hard
link) counts as the same file.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterable, Iterator
from pathlib import Path

from symlearn.errors import DataError, printable

#: options (argparse dests) that name a file a command writes
OUTPUT_DESTS = ("output", "save", "dot", "svg", "log", "target")
#: options that name folders a command writes into or reads its own cache from: neither side
SKIPPED_DESTS = ("out", "tensorboard", "expert_cache", "handler", "group_parser", "command")


def _stem_companions(path: Path, suffixes: Iterable[str]) -> list[Path]:
    stem = path.with_suffix("")
    return [stem.with_name(stem.name + suffix) for suffix in suffixes]


def written_beside(path: Path, dest: str, module: str) -> list[Path]:
    """The files a command writes for an output option ``dest`` naming ``path``: the path and its
    companions (docs/FORMATS.md)."""
    files = [path]
    if dest in ("output", "save") and path.suffix == ".safetensors":  # every model is weights + .json
        files.append(path.with_suffix(".json"))
    if dest == "output" and module.endswith("learn_command") and path.suffix == ".ltl":  # learn spec
        files += _stem_companions(path, (".labeling.json", ".dot", ".svg"))
    if dest == "output" and module.endswith("learn_rm_command"):
        files += _stem_companions(path, (".labeling.json", ".labeling.features.safetensors",
                                         ".labeling.features.json", ".md", ".prototypes.png", ".dot"))
    if dest == "output" and module.endswith("learn_constraints_command") and path.suffix == ".json":
        files += _stem_companions(path, (".costmap.txt", ".costmap.dot", ".costmap.svg"))
    return files


def read_beside(path: Path) -> list[Path]:
    """A file a command reads and the companions read with it: a model's ``.json`` beside its
    ``.safetensors``, a reward machine's labeling (and its features) beside ``machine.json``."""
    files = [path]
    if path.suffix == ".safetensors":
        files.append(path.with_suffix(".json"))
    if path.suffix == ".json":
        files += _stem_companions(path, (".labeling.json", ".labeling.features.safetensors",
                                         ".labeling.features.json"))
    return files


def _words(value: object) -> Iterator[str]:
    if isinstance(value, (str, os.PathLike)):
        yield os.fspath(value)
    elif isinstance(value, (list, tuple)):
        for item in value:
            yield from _words(item)


def _regular(path: Path) -> os.stat_result | None:
    try:
        info = path.stat()
    except (OSError, ValueError):
        return None
    import stat

    return info if stat.S_ISREG(info.st_mode) else None


def _domain_files(folder: Path) -> list[Path]:
    """domain.toml and the files it names, of a folder given as ``--domain``."""
    import tomllib

    toml = folder / "domain.toml"
    try:
        if _regular(toml) is None or toml.stat().st_size > 1 << 20:
            return []
        if not toml.resolve().is_relative_to(folder.resolve()):
            return []  # a link out of the folder: its reader refuses it, unread
        config = tomllib.loads(toml.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return []  # the reader reports what is wrong with it
    return [toml] + [folder / value for value in config.values() if isinstance(value, str) and value]


def _inputs(args: argparse.Namespace) -> list[Path]:
    found: list[Path] = []
    module = getattr(getattr(args, "handler", None), "__module__", "") or ""
    for dest, value in vars(args).items():
        if dest in OUTPUT_DESTS or dest in SKIPPED_DESTS:
            continue
        if dest == "labeling" and module.endswith("learn_command"):
            continue  # learn spec writes back the labeling it was given (FORMATS.md: SPEC.labeling.json)
        for word in _words(value):
            if not word or len(word) > 4096 or "\0" in word:
                continue
            if dest == "domain":
                found += _domain_files(Path(word))
                continue
            if ":" in word and word.split(":")[0].endswith(".py"):  # FILE.py:function
                word = word.split(":")[0]
            found += read_beside(Path(word))
    return found


def _outputs(args: argparse.Namespace) -> list[tuple[str, str, Path]]:
    module = getattr(getattr(args, "handler", None), "__module__", "") or ""
    found = []
    for dest in OUTPUT_DESTS:
        for word in _words(getattr(args, dest, None)):
            if not word or len(word) > 4096 or "\0" in word:
                continue
            found += [(dest, word, path) for path in written_beside(Path(word), dest, module)]
    return found


def check_outputs_spare_inputs(args: argparse.Namespace) -> None:
    """Refuse (before any work) an output, or a companion written beside it, that is one of the
    files the command reads."""
    outputs = [(dest, word, path, info) for dest, word, path in _outputs(args)
               if (info := _regular(path)) is not None]  # a file not there yet is nobody's input
    if not outputs:
        return
    inputs = [(path, info) for path in _inputs(args) if (info := _regular(path)) is not None]
    for dest, word, path, info in outputs:
        for source, seen in inputs:
            if (info.st_dev, info.st_ino) == (seen.st_dev, seen.st_ino):
                option = "the output" if dest == "target" else f"--{dest.replace('_', '-')}"
                beside = "" if str(path) == word else f", written beside {printable(word)},"
                same = "" if str(source) == str(path) else f" (as {printable(source)})"
                raise DataError(f"{option} would overwrite {printable(path)}{beside} which this command "
                                f"reads{same}", file=word, hint="write the output under another name")
