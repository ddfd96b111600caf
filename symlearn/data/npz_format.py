"""NPZ persistence for numeric and image demonstrations (``allow_pickle=False`` both ways).

Per-step columns of all trajectories are concatenated along axis 0; ``lengths`` and
``action_lengths`` cut them apart again. Members:

``__meta__``        0-d string: JSON header (format version, kinds, metadata, feature names)
``lengths``         int64 ``(N,)`` states per trajectory
``states``          concatenated states (array and symbol kinds), or
``states.<k>``      column ``k`` of feature-dict states, names in the header
``action_lengths``, ``actions`` / ``actions.<k>``  likewise, when there are actions
``rewards``         float64, concatenated
``label_names``, ``labels``  string vocabulary ``(K,)`` and boolean matrix ``(total states, K)``
``info``            string ``(N,)``: each trajectory's info as JSON
"""

from __future__ import annotations

import io
import json
import os
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import write_bytes
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError

FORMAT_VERSION = 1
MAGIC = "demonstrations"


def _pack_column(prefix: str, kind: str, columns: list[Any], arrays: dict[str, np.ndarray], header: dict) -> None:
    if kind == "features":
        names = sorted(columns[0][0]) if columns and columns[0] else []
        encodings = []
        for k, name in enumerate(names):
            values = [row[name] for col in columns for row in col]
            if len({type(v) for v in values}) == 1:
                arrays[f"{prefix}.{k}"] = np.asarray(values)
                encodings.append("array")
            else:  # mixed Python types: JSON text per value keeps each one exactly
                arrays[f"{prefix}.{k}"] = np.asarray([json.dumps(v) for v in values], dtype=str)
                encodings.append("json")
        header[f"{prefix}_features"] = names
        header[f"{prefix}_feature_encodings"] = encodings
    elif kind == "symbol":
        arrays[prefix] = np.asarray([v for col in columns for v in col], dtype=str)
    else:
        arrays[prefix] = np.concatenate(columns)


def write_npz(demos: Demonstrations, path: str | os.PathLike[str]) -> None:
    header: dict[str, Any] = {
        "symlearn": MAGIC,
        "format_version": FORMAT_VERSION,
        "state_kind": demos.state_kind,
        "action_kind": demos.action_kind,
        "has_actions": demos.has_actions,
        "has_rewards": demos.has_rewards,
        "has_labels": demos.has_labels,
        "metadata": demos.metadata,
    }
    arrays: dict[str, np.ndarray] = {"lengths": np.array([len(t) for t in demos], dtype=np.int64)}
    _pack_column("states", demos.state_kind, [t.states for t in demos], arrays, header)
    if demos.has_actions:
        arrays["action_lengths"] = np.array([t.n_actions for t in demos], dtype=np.int64)
        with_actions = [t.actions for t in demos if t.n_actions]
        if demos.action_kind is not None:
            _pack_column("actions", demos.action_kind, with_actions, arrays, header)
    if demos.has_rewards:
        arrays["rewards"] = np.concatenate([t.rewards for t in demos])
    if demos.has_labels:
        vocabulary = sorted({p for t in demos for step in t.labels for p in step})
        index = {p: k for k, p in enumerate(vocabulary)}
        matrix = np.zeros((demos.n_steps, len(vocabulary)), dtype=bool)
        row = 0
        for t in demos:
            for step in t.labels:
                matrix[row, [index[p] for p in step]] = True
                row += 1
        arrays["label_names"] = np.asarray(vocabulary, dtype=str)
        arrays["labels"] = matrix
    arrays["info"] = np.asarray([json.dumps(t.info, allow_nan=False) for t in demos], dtype=str)
    arrays["__meta__"] = np.asarray(json.dumps(header, allow_nan=False))
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    write_bytes(path, buffer.getvalue())


def open_npz(path: str | os.PathLike[str]) -> Any:
    """``np.load(path, allow_pickle=False)`` with a located error for a file that is no NPZ (a
    missing or unreadable file keeps its OS error, which the CLI reports as such)."""
    try:
        return np.load(path, allow_pickle=False)
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise DataError(f"not a readable NPZ file ({exc})", file=path) from None


def read_npz(path: str | os.PathLike[str]) -> Demonstrations:
    path = Path(path)
    archive = open_npz(path)
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("holds a single array, not a symlearn NPZ archive", file=path)
    with archive:
        try:
            return _unpack(path, archive)
        except ValueError as exc:  # object arrays refuse to load without pickle, bad JSON ...
            raise DataError(f"malformed archive: {exc}", file=path) from None


def _unpack(path: Path, archive) -> Demonstrations:
    def member(name: str) -> np.ndarray:
        if name not in archive.files:
            raise DataError(f"archive lacks member {name!r}", file=path)
        return archive[name]

    header = json.loads(str(member("__meta__")))
    if not isinstance(header, dict) or header.get("symlearn") != MAGIC:
        raise DataError("not a symlearn demonstrations archive (bad __meta__)", file=path)
    version = header.get("format_version")
    if not isinstance(version, int) or version > FORMAT_VERSION:
        raise DataError(f"format_version {version!r} is not readable by this symlearn (reads {FORMAT_VERSION})",
                        file=path, hint="upgrade symlearn")

    lengths = member("lengths")
    if lengths.dtype.kind not in "iu" or lengths.ndim != 1 or (lengths < 1).any():
        raise DataError("member 'lengths' must be positive integers", file=path)
    states = _unpack_column(path, "states", header["state_kind"], lengths, archive, header, member)
    n = len(lengths)
    actions: list[Any] = [None] * n
    if header.get("has_actions"):
        action_lengths = member("action_lengths")
        if action_lengths.shape != lengths.shape:
            raise DataError("members 'action_lengths' and 'lengths' disagree in size", file=path)
        if header.get("action_kind") is None:
            actions = [[] for _ in range(n)]
        else:
            nonzero = action_lengths[action_lengths > 0]
            parts = iter(_unpack_column(path, "actions", header["action_kind"], nonzero, archive, header, member))
            actions = [next(parts) if k else [] for k in action_lengths]
    rewards: list[Any] = [None] * n
    if header.get("has_rewards"):
        per = action_lengths if header.get("has_actions") else lengths
        rewards = _split(path, "rewards", member("rewards"), per)
    labels: list[Any] = [None] * n
    if header.get("has_labels"):
        names = [str(x) for x in member("label_names")]
        rows = _split(path, "labels", member("labels"), lengths)
        labels = [[frozenset(names[k] for k in np.flatnonzero(r)) for r in block] for block in rows]
    infos = [json.loads(str(s)) for s in member("info")]
    if len(infos) != n:
        raise DataError("member 'info' has the wrong number of entries", file=path)

    trajectories = []
    for i in range(n):
        try:
            trajectories.append(Trajectory(states[i], actions[i], rewards[i], labels[i], infos[i]))
        except DataError as exc:
            raise DataError(f"trajectory {i}: {exc.message}", file=path, hint=exc.hint) from None
    try:
        return Demonstrations(trajectories, metadata=header.get("metadata") or {})
    except DataError as exc:
        raise DataError(exc.message, file=path, hint=exc.hint) from None


def _split(path: Path, name: str, values: np.ndarray, lengths: np.ndarray) -> list[np.ndarray]:
    if values.ndim == 0 or len(values) != int(lengths.sum()):
        raise DataError(f"member {name!r} has {0 if values.ndim == 0 else len(values)} rows, expected {int(lengths.sum())}",
                        file=path)
    return np.split(values, np.cumsum(lengths)[:-1])


def _unpack_column(path, prefix, kind, lengths, archive, header, member) -> list[Any]:
    if kind == "features":
        names = header.get(f"{prefix}_features") or []
        encodings = header.get(f"{prefix}_feature_encodings") or ["array"] * len(names)
        decode = {"array": lambda v: v.item(), "json": lambda v: json.loads(str(v))}
        columns = [_split(path, f"{prefix}.{k}", member(f"{prefix}.{k}"), lengths) for k in range(len(names))]
        return [
            [{name: decode[encodings[k]](columns[k][i][t]) for k, name in enumerate(names)}
             for t in range(int(lengths[i]))]
            for i in range(len(lengths))
        ]
    blocks = _split(path, prefix, member(prefix), lengths)
    if kind == "symbol":
        return [[str(v) for v in block] for block in blocks]
    return blocks
