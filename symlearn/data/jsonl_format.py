"""JSONL persistence for symbolic and discrete demonstrations.

Line 1 is a header object; every further non-blank line is one trajectory::

    {"symlearn": "demonstrations", "format_version": 1, "state_kind": "discrete",
     "state_dtype": "int64", "action_kind": "symbol", "action_dtype": null, "metadata": {}}
    {"states": [0, 1, 2], "actions": ["go(north)", "go(east)"], "labels": [[], ["key"], []]}

Keys of a trajectory line: ``states`` (required), ``actions``, ``rewards``, ``labels``, ``info``.
Kinds and dtypes live in the header so that, e.g., a 1-D integer vector is not read back as ids.
Floats are written with Python's shortest round-trip ``repr``, so values come back bit-exact.
Images do not belong here (use NPZ).
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import atomic_open
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.kinds import KINDS
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError
from symlearn.input_limits import MAX_JSON_DEPTH, depth, load_json, read_input_text

FORMAT_VERSION = 1
MAGIC = "demonstrations"
_LINE_KEYS = ("states", "actions", "rewards", "labels", "info")


def _column_to_json(kind: str | None, values: Any) -> Any:
    if kind in ("discrete", "vector"):
        return values.tolist()
    if kind == "features":
        return [dict(row) for row in values]
    return list(values)


def _dtype_name(kind: str | None, values: Any) -> str | None:
    return str(values.dtype) if kind in ("discrete", "vector") else None


def write_jsonl(demos: Demonstrations, path: str | os.PathLike[str]) -> None:
    if demos.state_kind == "image":
        shape = tuple(np.shape(demos[0].states)[1:])
        raise DataError(f"{path}: states of shape {shape} per step (images, matrices) cannot be written as JSONL",
                        hint="save to a .npz file")
    ref_actions = next((t for t in demos if t.n_actions), demos[0])
    header = {
        "symlearn": MAGIC,
        "format_version": FORMAT_VERSION,
        "state_kind": demos.state_kind,
        "state_dtype": _dtype_name(demos.state_kind, demos[0].states),
        "action_kind": demos.action_kind,
        "action_dtype": _dtype_name(demos.action_kind, ref_actions.actions) if ref_actions.n_actions else None,
        "metadata": demos.metadata,
    }
    with atomic_open(path, "w") as out:
        out.write(json.dumps(header, allow_nan=False) + "\n")
        for traj in demos:
            line: dict[str, Any] = {"states": _column_to_json(traj.state_kind, traj.states)}
            if traj.actions is not None:
                line["actions"] = _column_to_json(traj.action_kind, traj.actions)
            if traj.rewards is not None:
                line["rewards"] = traj.rewards.tolist()
            if traj.labels is not None:
                line["labels"] = [sorted(step) for step in traj.labels]
            if traj.info:
                line["info"] = traj.info
            out.write(json.dumps(line, allow_nan=False) + "\n")


def read_jsonl(path: str | os.PathLike[str]) -> Demonstrations:
    path = Path(path)
    text = read_input_text(path, what="demonstrations file")  # size cap; bad bytes at line:col
    # lines end at \n only (\r\n too): str.splitlines would also cut at U+2028, U+0085 and other
    # characters JSON strings may hold raw (json.dumps(..., ensure_ascii=False) writes them so)
    lines = [line[:-1] if line.endswith("\r") else line for line in text.split("\n")]
    header, start = None, 0
    for number, raw in enumerate(lines, start=1):
        if raw.strip():
            header, start = _read_header(path, number, raw), number
            break
    if header is None:
        raise DataError("file is empty: expected a header line and at least one trajectory", file=path)

    trajectories, numbers = [], []
    for number, raw in enumerate(lines[start:], start=start + 1):
        if not raw.strip():
            continue
        trajectories.append(_read_trajectory(path, number, raw, header))
        numbers.append(number)
    if not trajectories:
        raise DataError("no trajectories after the header line", file=path, line=start)
    trajectories = _common_dtypes(trajectories, header)
    try:
        return Demonstrations(trajectories, metadata=header.get("metadata") or {})
    except DataError as exc:
        # "trajectory 3 has no actions but trajectory 0 ...": point at the line of trajectory 3
        found = re.search(r"trajectory (\d+)", exc.message)
        line = numbers[int(found.group(1))] if found and int(found.group(1)) < len(numbers) else None
        raise DataError(exc.message, file=path, line=line, hint=exc.hint) from None


def _common_dtypes(trajectories: list[Trajectory], header: dict[str, Any]) -> list[Trajectory]:
    """Without a declared dtype, JSON numbers of a vector column read as int64 on a line that
    happens to hold only whole numbers (``[[0, 1], [1, 2]]``) and as float64 on the next: give
    every trajectory the column's common dtype, as one array of all of them would have."""
    common: dict[str, np.dtype] = {}
    for key, kind_key, dtype_key in (("states", "state_kind", "state_dtype"), ("actions", "action_kind", "action_dtype")):
        kind = header.get(kind_key) or next((getattr(t, kind_key) for t in trajectories if getattr(t, kind_key)), None)
        if header.get(dtype_key) is not None or kind not in ("vector", "image"):
            continue
        arrays = [getattr(t, key) for t in trajectories if getattr(t, key) is not None and len(getattr(t, key))]
        dtypes = {a.dtype for a in arrays if isinstance(a, np.ndarray)}
        if len(dtypes) > 1:
            common[key] = np.result_type(*dtypes)
    if not common:
        return trajectories

    def cast(t: Trajectory, key: str) -> Any:
        values = getattr(t, key)
        if key not in common or values is None or not len(values):
            return values
        return values.astype(common[key])

    return [Trajectory(cast(t, "states"), cast(t, "actions"), t.rewards, t.labels, t.info) for t in trajectories]


def _parse_line(path: Path, number: int, raw: str) -> Any:
    try:  # typed fields are checked below, free-form ones (metadata, info) with depth()
        return load_json(raw, source=path, line=number, max_depth=None, parse_constant=_reject_constant)
    except ValueError as exc:  # from _reject_constant
        raise DataError(str(exc), file=path, line=number, column=_column_of(raw, "NaN", "Infinity")) from None


def _reject_constant(name: str) -> Any:
    raise ValueError(f"non-finite number {name} is not allowed")


def _column_of(raw: str, *needles: str) -> int | None:
    found = [raw.find(n) for n in needles if raw.find(n) >= 0]
    return min(found) + 1 if found else None


def _read_header(path: Path, number: int, raw: str) -> dict[str, Any]:
    header = _parse_line(path, number, raw)
    if not isinstance(header, dict) or header.get("symlearn") != MAGIC:
        raise DataError(
            "missing header: the first line must be a symlearn demonstrations header",
            file=path, line=number, column=1,
            hint='start the file with {"symlearn": "demonstrations", "format_version": 1, ...}',
        )
    version = header.get("format_version")
    if not isinstance(version, int) or version < 1:
        raise DataError(f"bad format_version {version!r}", file=path, line=number, column=_column_of(raw, '"format_version"'))
    if version > FORMAT_VERSION:
        raise DataError(
            f"format_version {version} is newer than this symlearn reads ({FORMAT_VERSION})",
            file=path, line=number, hint="upgrade symlearn",
        )
    for key in ("state_kind", "action_kind"):
        kind = header.get(key)
        if kind is not None and kind not in KINDS:
            raise DataError(f"unknown {key} {kind!r} (known: {', '.join(KINDS)})",
                            file=path, line=number, column=_column_of(raw, f'"{key}"'))
    # a kind left out is the kind the values are (as Trajectory reads them); every line must agree
    header["_inferred"] = tuple(key for key in ("state_kind", "action_kind")
                                if key not in header or key == "state_kind" and header[key] is None)
    if header.get("metadata") is None:
        header["metadata"] = {}
    if not isinstance(header["metadata"], dict):
        raise DataError("header metadata must be an object", file=path, line=number, column=_column_of(raw, '"metadata"'))
    if depth(header.get("metadata") or {}) > MAX_JSON_DEPTH - 1:
        raise DataError(f"header metadata is nested more than {MAX_JSON_DEPTH} levels deep", file=path,
                        line=number, column=_column_of(raw, '"metadata"'))
    for key in ("state_dtype", "action_dtype"):
        if header.get(key) is not None:
            header[key] = _plain_dtype(header[key], key, path, number, raw)
    return header


#: the dtypes a discrete or vector column may declare: plain numbers, nothing that could make one
#: header line allocate gigabytes ("(1000,1000,100)f8" sub-arrays, "V2000000000", "<U1000000000").
PLAIN_DTYPES = ("bool", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
                "float16", "float32", "float64")


def _plain_dtype(value: Any, key: str, path: Path, number: int, raw: str) -> str:
    dtype = None
    if isinstance(value, str) and len(value) <= 16:
        try:
            dtype = np.dtype(value)
        except Exception:  # numpy's dtype parser raises TypeError, ValueError, even SyntaxError (",int64")
            dtype = None
    if dtype is None or dtype.name not in PLAIN_DTYPES or dtype.shape or dtype.names is not None:
        shown = json.dumps(value)
        raise DataError(f"{key} {shown[:60]} is not a plain numeric dtype", file=path, line=number,
                        column=_column_of(raw, f'"{key}"'), hint=f"use one of {', '.join(PLAIN_DTYPES)}")
    return dtype.name


def _read_trajectory(path: Path, number: int, raw: str, header: dict[str, Any]) -> Trajectory:
    obj = _parse_line(path, number, raw)

    def fail(message: str, key: str | None = None, hint: str | None = None) -> DataError:
        column = _column_of(raw, f'"{key}"') if key else 1
        return DataError(message, file=path, line=number, column=column, hint=hint)

    if not isinstance(obj, dict):
        raise fail(f"a trajectory line must be a JSON object, got {type(obj).__name__}")
    if obj.get("symlearn") == MAGIC:
        raise fail("a second header line: only line 1 is a header (were two files joined?)", "symlearn",
                   hint="keep the first header and remove this line; the trajectories must agree with it")
    unknown = sorted(set(obj) - set(_LINE_KEYS))
    if unknown:
        raise fail(f"unknown key {unknown[0]!r}", unknown[0], hint=f"known keys: {', '.join(_LINE_KEYS)}")
    if "states" not in obj:
        raise fail("trajectory has no 'states'")
    # an optional key given as null (pandas, other tools' exporters) is an absent key
    obj = {key: value for key, value in obj.items() if value is not None or key == "states"}
    if header.get("action_kind") is None and obj.get("actions") and "action_kind" not in header["_inferred"]:
        raise fail("trajectory has actions but the header says action_kind is null", "actions")

    fields: dict[str, Any] = {}
    for key, kind_key, dtype_key in (("states", "state_kind", "state_dtype"), ("actions", "action_kind", "action_dtype")):
        if key in obj:
            fields[key] = _column_from_json(obj[key], header.get(kind_key), header.get(dtype_key), key, fail)
    for key in ("rewards", "labels", "info"):
        if key in obj:
            fields[key] = obj[key]
    if isinstance(obj.get("info"), (dict, list)) and depth(obj["info"]) > MAX_JSON_DEPTH - 1:
        raise fail(f"'info' is nested more than {MAX_JSON_DEPTH} levels deep", "info")
    try:
        traj = Trajectory(**fields)
    except DataError as exc:
        # Point at the field the message talks about first ("3 actions for 2 states" -> actions).
        mentioned = [k for k in _LINE_KEYS if k in exc.message]
        field = min(mentioned, key=exc.message.find) if mentioned else None
        raise fail(exc.message, field, exc.hint) from None
    if "state_kind" not in header["_inferred"] and traj.state_kind != header["state_kind"]:
        hint = None
        if traj.state_kind == "discrete" and header["state_kind"] == "vector":
            hint = ("a flat list of integers is read as discrete ids: declare state_kind discrete, or write each "
                    "step as a list ([[1], [2]]) or declare a float state_dtype for one-number vector states")
        raise fail(f"states are {traj.state_kind} but the header says {header['state_kind']}", "states", hint)
    if traj.n_actions and "action_kind" not in header["_inferred"] and traj.action_kind != header.get("action_kind"):
        raise fail(f"actions are {traj.action_kind} but the header says {header.get('action_kind')}", "actions")
    return traj


def _column_from_json(values: Any, kind: str | None, dtype: str | None, key: str, fail) -> Any:
    if not isinstance(values, list):
        raise fail(f"'{key}' must be a list, got {type(values).__name__}", key)
    if kind in ("discrete", "vector") and values:
        try:
            array = np.asarray(values)
        except ValueError:
            raise fail(f"'{key}' are ragged", key, hint="every step must have the same shape") from None
        if array.dtype == object and any(isinstance(v, int) and not -2**63 <= v < 2**64
                                         for v in np.ravel(array) if not isinstance(v, bool)):
            raise fail(f"'{key}' hold an integer beyond 64 bits", key,
                       hint="symlearn keeps integers as int64; write such numbers as floats or strings")
        if array.dtype == object or array.dtype.kind not in "biuf":
            raise fail(f"'{key}' must be numbers for {kind} {key}", key)
        if kind == "discrete" and (array.ndim != 1 or array.dtype.kind not in "iu"):
            raise fail(f"'{key}' must be a flat list of integer ids for discrete {key}", key)
        if dtype is not None:
            with np.errstate(over="ignore", invalid="ignore"):
                cast = array.astype(dtype)
            if np.dtype(dtype).kind == "f":
                # a float column is read to its nearest value of the declared width (a float32 written
                # as "0.1" is the float32 nearest 0.1); only a number beyond its range does not fit
                fits = bool(np.isfinite(cast).all())
            else:
                fits = bool(np.array_equal(cast, array))
            if not fits:
                raise fail(f"'{key}' do not fit the header dtype {dtype}", key,
                           hint="integers beyond the type's range, fractions for an integer type, or numbers "
                                "beyond a float type's range; declare a wider dtype")
            array = cast
        return array
    return values
