"""D4RL-style transition tables in HDF5 (``.hdf5``/``.h5``) or NPZ, read and written.

One row per transition, all episodes one after another:

``observations``       ``(N, ...)`` the state each action was taken in
``actions``            ``(N, ...)``
``rewards``            ``(N,)`` (optional here)
``terminals``          ``(N,)`` booleans (or 0/1 numbers): the episode terminated after this row
``timeouts``           ``(N,)`` booleans: the episode was cut off after this row (optional;
                       older D4RL files have none)
``next_observations``  ``(N, ...)`` optional: the state each action led to
``infos/...``, ``metadata/...``  per-step extras and dataset notes: not read

Episodes end at rows where ``terminals | timeouts``. With ``next_observations`` an episode of
``k`` rows is ``k + 1`` states (its last row's next observation closes it) and ``k`` actions;
without, it is ``k`` states with an action in each. Rows after the last episode end (a file cut
in the middle of an episode) form one more trajectory flagged ``info["partial"] = true``. Each
trajectory's info says ``terminated`` and ``truncated`` (not terminated; the last row was a
timeout or the file ended).

Writing adds one member D4RL tools ignore, ``symlearn_header`` (UTF-8 JSON as ``uint8``): the
metadata, every trajectory's info and labels, so that a symlearn -> D4RL -> symlearn round trip
gives back exactly what was written; a file without it (any D4RL file) is read from its arrays
alone. Demonstrations written this way need array states (discrete, vector or image), actions
in every trajectory, and either ``T - 1`` actions everywhere (``next_observations`` written)
or ``T`` everywhere (none written).

Reading checks every array's dtype and declared size before it reads any (NPZ:
:func:`~symlearn.data.npz_format.member_headers`; HDF5: :mod:`symlearn.data.hdf5_reading`) and
the row counts of all of them against ``observations``.
"""

from __future__ import annotations

import io
import json
import os
import zipfile
import zlib
from pathlib import Path
from typing import Any, Callable

import numpy as np

from symlearn.atomic import write_bytes
from symlearn.data import kinds
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError
from symlearn.input_limits import check_size, depth, load_json, MAX_JSON_DEPTH

HEADER = "symlearn_header"
MAGIC = "d4rl-demonstrations"
FORMAT_VERSION = 1
COLUMNS = ("observations", "actions", "rewards", "terminals", "timeouts", "next_observations")
REQUIRED = ("observations", "actions", "terminals")
# gzip (every HDF5 build reads it) at level 1 with byte shuffling: on 1M rows of 17 random float32
# features (the worst case) level 4, h5py's default, wrote in 15.4 s, this in 11.2 s, 6 % smaller
_COMPRESSED = {"compression": "gzip", "compression_opts": 1, "shuffle": True}


# --- writing ------------------------------------------------------------------------------------


def to_table(demos: Demonstrations) -> dict[str, np.ndarray]:
    """The D4RL columns (and the ``symlearn_header``) of ``demos``."""
    if demos.state_kind not in kinds.ARRAY_KINDS:
        raise DataError(f"D4RL files hold array observations; these demonstrations have {demos.state_kind} states",
                        hint="save them as .jsonl or .npz instead")
    if not demos.has_actions or demos.action_kind not in kinds.ARRAY_KINDS:
        raise DataError(f"D4RL files hold array actions in every row; these demonstrations have "
                        f"{'no' if not demos.has_actions else demos.action_kind} actions",
                        hint="save them as .jsonl or .npz instead")
    closing = {len(t) - t.n_actions for t in demos}
    if 0 in {t.n_actions for t in demos}:
        index = next(i for i, t in enumerate(demos) if t.n_actions == 0)
        raise DataError(f"trajectory {index} has no action: a D4RL row is a transition")
    if len(closing) != 1:
        raise DataError("some trajectories end with a final state and some do not; a D4RL file has next "
                        "observations for all rows or for none")
    with_next = closing == {1}
    table: dict[str, list[np.ndarray]] = {name: [] for name in COLUMNS}
    last = len(demos) - 1
    for i, t in enumerate(demos):
        k = t.n_actions
        table["observations"].append(t.states[:k])
        table["actions"].append(t.actions)
        if demos.has_rewards:
            table["rewards"].append(t.rewards)
        terminated = t.info.get("terminated") is True
        # a partial trajectory can stay open only at the end; elsewhere it would run into the next
        open_end = bool(t.info.get("partial")) and i == last and not terminated
        ends = np.zeros(k, dtype=bool)
        table["terminals"].append(ends.copy())
        table["timeouts"].append(ends.copy())
        if terminated:
            table["terminals"][-1][-1] = True
        elif not open_end:
            table["timeouts"][-1][-1] = True
        if with_next:
            table["next_observations"].append(t.states[1:])
    arrays = {name: np.concatenate(parts) for name, parts in table.items() if parts}
    header = {"symlearn": MAGIC, "format_version": FORMAT_VERSION, "metadata": demos.metadata,
              "info": [t.info for t in demos],
              "labels": [[sorted(step) for step in t.labels] for t in demos] if demos.has_labels else None}
    arrays[HEADER] = np.frombuffer(json.dumps(header, allow_nan=False).encode("utf-8"), dtype=np.uint8)
    return arrays


def write_d4rl(demos: Demonstrations, path: str | os.PathLike[str]) -> None:
    """Write ``demos`` as a D4RL table: HDF5 for ``.hdf5``/``.h5``, NPZ otherwise."""
    path = Path(path)
    try:
        arrays = to_table(demos)
    except DataError as exc:  # name the file being written
        raise DataError(exc.message, file=exc.file or path, hint=exc.hint) from None
    buffer = io.BytesIO()
    if path.suffix.lower() in (".hdf5", ".h5"):
        from symlearn.data.hdf5_reading import h5py_module

        h5py = h5py_module()
        with h5py.File(buffer, "w") as handle:
            for name, values in arrays.items():
                handle.create_dataset(name, data=values, **(_COMPRESSED if values.nbytes > 4096 else {}))
    else:
        np.savez_compressed(buffer, **arrays)
    write_bytes(path, buffer.getvalue())


# --- reading ------------------------------------------------------------------------------------


def read_d4rl_npz(path: str | os.PathLike[str], report: dict[str, Any] | None = None) -> Demonstrations:
    from symlearn.data.npz_format import member_headers, open_npz

    path = Path(path)
    headers = member_headers(path)  # dtypes and the sizes they declare, before decompressing
    shapes = {name: shape for name, (_, shape) in headers.items() if name in COLUMNS or name == HEADER}
    archive = open_npz(path)
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("holds a single array, not a D4RL table", file=path)
    with archive:
        try:
            return _from_table(path, shapes, lambda name: archive[name], report)
        except (ValueError, EOFError, zipfile.BadZipFile, OSError, zlib.error, RuntimeError) as exc:  # truncated ...
            raise DataError(f"malformed archive: {exc}", file=path) from None


def read_d4rl_hdf5(path: str | os.PathLike[str], report: dict[str, Any] | None = None) -> Demonstrations:
    from symlearn.data import hdf5_reading as h5

    path = Path(path)
    with h5.open_hdf5(path) as handle:
        datasets = {}
        for name in (*COLUMNS, HEADER):
            dataset = h5.member(path, handle, name, required=False)
            if dataset is not None:
                datasets[name] = dataset
        h5.declared_bytes(datasets.values(), path)
        shapes = {name: tuple(int(n) for n in ds.shape) for name, ds in datasets.items()}
        return _from_table(path, shapes, lambda name: h5.read(path, datasets[name]), report)


def _from_table(path: Path, shapes: dict[str, tuple[int, ...]], read: Callable[[str], np.ndarray],
                report: dict[str, Any] | None = None) -> Demonstrations:
    for name in REQUIRED:
        if name not in shapes:
            raise DataError(f"has no {name!r}: not a D4RL table", file=path,
                            hint="a D4RL table has observations, actions, terminals (and rewards, timeouts)")
    n = shapes["observations"][0] if shapes["observations"] else 0
    if n == 0:
        raise DataError("'observations' has no rows", file=path)
    for name in COLUMNS:
        if name in shapes and (not shapes[name] or shapes[name][0] != n):
            rows = shapes[name][0] if shapes[name] else 0
            raise DataError(f"{name!r} has {rows} rows, 'observations' has {n}", file=path,
                            hint="every column has one row per transition")
        if name in ("rewards", "terminals", "timeouts") and name in shapes and shapes[name] not in ((n,), (n, 1)):
            raise DataError(f"{name!r} has shape {shapes[name]}, expected ({n},)", file=path)
    if "next_observations" in shapes and shapes["next_observations"] != shapes["observations"]:
        raise DataError(f"'next_observations' has shape {shapes['next_observations']}, 'observations' has "
                        f"{shapes['observations']}", file=path)
    header = _read_header(path, shapes, read) if HEADER in shapes else None
    read = _flat_per_row(read, ("rewards", "terminals", "timeouts"))
    ends = _flags(path, "terminals", read("terminals"))
    timeouts = _flags(path, "timeouts", read("timeouts")) if "timeouts" in shapes else np.zeros(n, dtype=bool)
    observations = read("observations")
    actions = read("actions")
    rewards = read("rewards") if "rewards" in shapes else None
    following = read("next_observations") if "next_observations" in shapes else None
    stops = np.flatnonzero(ends | timeouts)
    if report is not None and following is not None:
        joined = np.flatnonzero(_discontinuities(observations, following) & ~(ends | timeouts))
        report["joined_rows"] = [int(r) for r in joined[:1]] + [len(joined)] if len(joined) else []
    bounds = [(int(start), int(stop) + 1) for start, stop in zip(np.r_[0, stops[:-1] + 1], stops)]
    if not len(stops) or stops[-1] != n - 1:
        bounds.append((int(stops[-1]) + 1 if len(stops) else 0, n))
    if header is not None and len(header["info"]) != len(bounds):
        raise DataError(f"{HEADER}: {len(header['info'])} trajectories described, the rows hold {len(bounds)}",
                        file=path, hint="the arrays were edited after symlearn wrote them; remove symlearn_header")
    trajectories = []
    for i, (start, stop) in enumerate(bounds):
        terminated = bool(ends[stop - 1])
        states = observations[start:stop]
        if following is not None:
            states = np.concatenate([states, following[stop - 1:stop]])
        info: dict[str, Any] = {"terminated": terminated, "truncated": not terminated}
        if not (ends[stop - 1] or timeouts[stop - 1]):
            info["partial"] = True
        labels = None
        if header is not None:
            info = header["info"][i]
            labels = None if header.get("labels") is None else header["labels"][i]
        try:
            trajectories.append(Trajectory(states, actions[start:stop],
                                           None if rewards is None else rewards[start:stop], labels, info))
        except DataError as exc:
            raise DataError(f"episode {i} (rows {start}..{stop - 1}): {exc.message}", file=path,
                            hint=exc.hint) from None
    metadata = header["metadata"] if header is not None else {"source_format": "d4rl"}
    try:
        return Demonstrations(trajectories, metadata=metadata)
    except DataError as exc:
        raise DataError(exc.message, file=path, hint=exc.hint) from None


def _discontinuities(observations: np.ndarray, following: np.ndarray) -> np.ndarray:
    """Rows whose next observation is not the following row's observation (relative tolerance
    1e-5; the last row is never one). Inside an episode such a row means two episodes were joined
    without a flag (D4RL's v0 tables have no ``timeouts``): ``data info`` says so; the episodes
    are still cut where the flags say (docs/FORMATS.md)."""
    n = len(observations)
    found = np.zeros(n, dtype=bool)
    if n > 1:
        a = np.asarray(following[:-1]).reshape(n - 1, -1)  # views: no float64 copy of a large table
        b = np.asarray(observations[1:]).reshape(n - 1, -1)
        with np.errstate(invalid="ignore", over="ignore"):
            found[:-1] = ~np.isclose(a, b, rtol=1e-5, atol=1e-8, equal_nan=True).all(axis=1)
    return found


def _flat_per_row(read: Callable[[str], np.ndarray], names: tuple[str, ...]) -> Callable[[str], np.ndarray]:
    """``read``, with the one-number-per-row columns given as ``(N,)`` also where a tool stored
    them as ``(N, 1)`` (checked above: no other shape gets here)."""
    def flat(name: str) -> np.ndarray:
        values = read(name)
        return values.reshape(-1) if name in names and values.ndim == 2 else values
    return flat


def _flags(path: Path, name: str, values: np.ndarray) -> np.ndarray:
    if values.dtype.kind == "b":
        return values.astype(bool, copy=False)
    odd = np.flatnonzero((values != 0) & (values != 1))
    if len(odd):
        raise DataError(f"{name!r} row {int(odd[0])} is {values[odd[0]].item()!r}; expected a boolean or 0/1", file=path)
    return values.astype(bool)


def _read_header(path: Path, shapes: dict, read: Callable[[str], np.ndarray]) -> dict[str, Any]:
    shape = shapes[HEADER]
    if len(shape) != 1:
        raise DataError(f"{HEADER} must be a 1-D uint8 array of UTF-8 JSON", file=path)
    check_size(shape[0], "SYMLEARN_MAX_INPUT_MB", what=f"{HEADER} size", file=path)
    raw = read(HEADER)
    if raw.dtype != np.uint8:
        raise DataError(f"{HEADER} must be a 1-D uint8 array of UTF-8 JSON, got dtype {raw.dtype}", file=path)
    from symlearn.input_limits import decode_utf8

    header = load_json(decode_utf8(raw.tobytes(), source=f"{path} ({HEADER})"), source=f"{path} ({HEADER})")
    if not isinstance(header, dict) or header.get("symlearn") != MAGIC:
        raise DataError(f"{HEADER} is not a symlearn D4RL header", file=path)
    version = header.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool) or not 1 <= version <= FORMAT_VERSION:
        raise DataError(f"{HEADER}: format_version {version!r} is not readable by this symlearn "
                        f"(reads {FORMAT_VERSION})", file=path, hint="upgrade symlearn")
    if not isinstance(header.get("metadata"), dict) or depth(header["metadata"]) > MAX_JSON_DEPTH - 1:
        raise DataError(f"{HEADER}: metadata must be a JSON object", file=path)
    infos = header.get("info")
    if not isinstance(infos, list) or not all(isinstance(info, dict) for info in infos):
        raise DataError(f"{HEADER}: info must be a list of objects, one per trajectory", file=path)
    labels = header.get("labels")
    if labels is not None and (not isinstance(labels, list) or len(labels) != len(infos)
                               or not all(isinstance(steps, list) and all(isinstance(s, list) for s in steps)
                                          for steps in labels)):
        raise DataError(f"{HEADER}: labels must be null or one list of label lists per trajectory", file=path)
    return header
