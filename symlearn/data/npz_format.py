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

Reading checks before it decompresses: the archive's size, then every member's ``.npy``
header (plain numeric, boolean or text dtypes only; declared sizes summed against
``SYMLEARN_MAX_ARRAY_MB``, see :mod:`symlearn.input_limits`), then the row count every column
declares against ``lengths``; only then are the columns read.
"""

from __future__ import annotations

import io
import json
import os
import stat
import tokenize
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import write_bytes
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.trajectory import Trajectory
from symlearn.data.kinds import KINDS
from symlearn.data.npz_header import action_lengths_of, check_declared_kinds, complete_header
from symlearn.errors import DataError, SymlearnError
from symlearn.input_limits import MAX_JSON_DEPTH, check_size, depth, load_json

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
    """The archive (or bare ``.npy`` array) at ``path``; see :func:`open_checked`."""
    return open_checked(path)[1]


def open_checked(path: str | os.PathLike[str]) -> tuple[dict[str, tuple[np.dtype, tuple[int, ...]]], Any]:
    """``(headers, archive)``: :func:`check_arrays`' headers, then the archive (or bare ``.npy``
    array) loaded with ``allow_pickle=False``, only after those checks bounded what loading it
    takes. A file that is no NPZ gets a located error (a missing or unreadable file keeps its OS
    error, which the CLI reports as such).

    Every reader of a user's NPZ goes through here (demonstrations, frame archives, domain
    models, ``dnf eval --points``), so one set of checks covers them all."""
    headers = check_arrays(path)
    try:
        return headers, np.load(path, allow_pickle=False)
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise DataError(f"not a readable NPZ file ({exc})", file=path) from None


def _regular_file(path: Path, what: str) -> None:
    """Refuse what is not a regular file (``/dev/zero``, a pipe): numpy reads those without end."""
    info = path.stat()  # a missing file keeps its OS error
    if stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(21, "Is a directory", str(path))
    if not stat.S_ISREG(info.st_mode):
        raise DataError(f"not a regular file; {what} must be one", file=path,
                        hint="copy the data to a file first")
    check_size(info.st_size, "SYMLEARN_MAX_ARRAY_MB", what=f"{what} size", file=path)


def _read_npy_header(handle, name: str, path: Path) -> tuple[np.dtype, tuple[int, ...]]:
    """dtype and shape from a ``.npy`` header (refused: no ``.npy`` magic, other versions, and
    dtypes that are not plain numbers, booleans or text)."""
    prefix = handle.read(len(np.lib.format.MAGIC_PREFIX))
    if prefix != np.lib.format.MAGIC_PREFIX:
        # numpy would hand such a member back as raw bytes, read whole: refuse it unread
        raise DataError(f"member {name!r} is not a .npy array", file=path,
                        hint="symlearn archives hold only arrays written by numpy.savez")
    version = tuple(handle.read(2))
    if version not in ((1, 0), (2, 0)):
        raise DataError(f"member {name!r}: unsupported .npy version {version}", file=path)
    read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    try:
        shape, _, dtype = read(handle)
    except (SyntaxError, tokenize.TokenError, TypeError, KeyError, RecursionError) as exc:
        # numpy reads the header as a Python literal: text that is none fails in the tokenizer or
        # parser, not with the ValueError it raises for a literal of the wrong form
        raise DataError(f"member {name!r}: the .npy header is not a readable dictionary "
                        f"({type(exc).__name__})", file=path) from None
    if dtype.hasobject or dtype.names is not None or dtype.shape or dtype.kind not in "biufU":
        hint = ("store text as numpy str (np.array(names, dtype=str), or .astype(str) of bytes), not bytes"
                if dtype.kind == "S" else None)
        raise DataError(f"member {name!r} has dtype {dtype.str!r}; symlearn archives hold only "
                        "plain numbers, booleans and text", file=path, hint=hint)
    shape = tuple(int(x) for x in shape)
    extent = 1
    for x in shape:  # the extents as numpy multiplies them (zeros skipped, so (0, 10**20) counts too)
        extent *= max(x, 1)
    if any(x < 0 for x in shape) or extent > np.iinfo(np.intp).max:
        raise DataError(f"member {name!r} declares shape {_short_shape(shape)}, which no array can have", file=path)
    return dtype, shape


def _short_shape(shape: tuple[int, ...]) -> str:
    text = str(shape)
    return text if len(text) <= 80 else text[:77] + "..."


def _declared_bytes(dtype: np.dtype, shape: tuple[int, ...]) -> int:
    count = 1
    for extent in shape:
        count *= extent
    return count * dtype.itemsize


def check_arrays(path: str | os.PathLike[str]) -> dict[str, tuple[np.dtype, tuple[int, ...]]]:
    """:func:`member_headers` of an archive, or ``{"": (dtype, shape)}`` of a bare ``.npy`` file
    after the same checks (a regular file, its size, its header's declared size)."""
    path = Path(path)
    _regular_file(path, "array file")  # before anything opens it: opening a pipe can block
    if zipfile.is_zipfile(path):
        return member_headers(path)
    try:
        with open(path, "rb") as handle:
            if handle.read(len(np.lib.format.MAGIC_PREFIX)) != np.lib.format.MAGIC_PREFIX:
                raise DataError("not a readable NPZ file (neither a zip archive nor a .npy array)", file=path)
            handle.seek(0)
            header = _read_npy_header(handle, "(the array)", path)
    except (OSError, ValueError, EOFError) as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise DataError(f"not a readable NPZ or NPY file ({exc})", file=path) from None
    check_size(_declared_bytes(*header), "SYMLEARN_MAX_ARRAY_MB", what="declared array size", file=path)
    return {"": header}


#: members of one NPZ archive (a demonstrations archive has a dozen, one per feature column at
#: most): 100,000 members took 30 s to check header by header before anything was refused
MAX_MEMBERS = 10_000


def member_headers(path: str | os.PathLike[str]) -> dict[str, tuple[np.dtype, tuple[int, ...]]]:
    """``{member: (dtype, shape)}`` of an NPZ archive read from the ``.npy`` headers only (a few
    hundred bytes decompressed per member), after checking the archive's size and every declared
    size against ``SYMLEARN_MAX_ARRAY_MB``; object, structured and sub-array dtypes are refused.

    Every member is checked under the name numpy would load it by (``x.npy`` and a bare ``x``
    both answer to ``archive["x"]``), so no member escapes the checks; two members answering to
    one name, and members that are not ``.npy`` arrays, are refused. Sizes counted are the larger
    of what each header declares and what the zip directory says the member expands to (zipfile
    never inflates past that), so a zip bomb is refused before any of it is expanded."""
    path = Path(path)
    _regular_file(path, "archive")
    headers: dict[str, tuple[np.dtype, tuple[int, ...]]] = {}
    total = 0
    try:
        with zipfile.ZipFile(path) as archive:
            members = archive.infolist()
            if len(members) > MAX_MEMBERS:  # each header costs a decompressor and a parse (~0.2 ms)
                raise DataError(f"the archive has {len(members):,} members, more than the {MAX_MEMBERS:,} "
                                "symlearn reads", file=path,
                                hint="an archive holds a few arrays (one per feature at most)")
            for info in members:
                name = info.filename[:-4] if info.filename.endswith(".npy") else info.filename
                if name in headers:
                    raise DataError(f"two members answer to the name {name!r}", file=path,
                                    hint="an archive holds each array once")
                total += info.file_size
                check_size(total, "SYMLEARN_MAX_ARRAY_MB", what=f"decompressed size (member {name!r} and those "
                           "before it)", file=path)
                with archive.open(info) as handle:
                    dtype, shape = _read_npy_header(handle, name, path)
                total += max(0, _declared_bytes(dtype, shape) - info.file_size)
                check_size(total, "SYMLEARN_MAX_ARRAY_MB", what=f"decompressed size (member {name!r} and those "
                           "before it)", file=path)
                headers[name] = (dtype, shape)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, ValueError, EOFError, NotImplementedError,
            zlib.error, RuntimeError) as exc:  # RuntimeError: a member flagged as encrypted
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise DataError(f"not a readable NPZ file ({exc})", file=path) from None
    return headers


def read_npz(path: str | os.PathLike[str]) -> Demonstrations:
    path = Path(path)
    headers, archive = open_checked(path)
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("holds a single array, not a symlearn NPZ archive", file=path)
    with archive:
        try:
            return _unpack(path, archive, headers)
        except (ValueError, EOFError, zipfile.BadZipFile, OSError, zlib.error, RuntimeError) as exc:  # truncated ...
            if isinstance(exc, DataError):
                raise
            raise DataError(f"malformed archive: {exc}", file=path) from None


def _read_meta(path: Path, text: str) -> dict:
    try:
        header = load_json(text, source=path)
    except SymlearnError as exc:
        # the position is within the member's text, not a line of the archive: say so
        where = f" at line {exc.line}, column {exc.column}" if exc.line is not None else ""
        raise DataError(f"member '__meta__' is not a JSON header{where}: {exc.message}", file=path,
                        hint='__meta__ = json.dumps({"symlearn": "demonstrations", "format_version": 1, ...})') from None
    if not isinstance(header, dict) or header.get("symlearn") != MAGIC:
        raise DataError("not a symlearn demonstrations archive (bad __meta__)", file=path)
    version = header.get("format_version")
    if not isinstance(version, int) or isinstance(version, bool) or version > FORMAT_VERSION or version < 1:
        raise DataError(f"format_version {version!r} is not readable by this symlearn (reads {FORMAT_VERSION})",
                        file=path, hint="upgrade symlearn")
    if header.get("state_kind") is not None and header.get("state_kind") not in KINDS:
        raise DataError(f"__meta__: state_kind {header.get('state_kind')!r} is not one of {', '.join(KINDS)}",
                        file=path)
    if header.get("action_kind") is not None and header.get("action_kind") not in KINDS:
        raise DataError(f"__meta__: action_kind {header.get('action_kind')!r} is not one of {', '.join(KINDS)}",
                        file=path)
    for flag in ("has_actions", "has_rewards", "has_labels"):
        if not isinstance(header.get(flag, False), bool):
            raise DataError(f"__meta__: {flag} must be true or false", file=path)
    if not isinstance(header.get("metadata", {}) or {}, dict):
        raise DataError("__meta__: metadata must be an object", file=path)
    for prefix in ("states", "actions"):
        names = header.get(f"{prefix}_features")
        encodings = header.get(f"{prefix}_feature_encodings")
        if names is not None and (not isinstance(names, list) or not all(isinstance(n, str) for n in names)):
            raise DataError(f"__meta__: {prefix}_features must be a list of names", file=path)
        if encodings is not None and (not isinstance(encodings, list) or len(encodings) != len(names or [])
                                      or not set(encodings) <= {"array", "json"}):
            raise DataError(f"__meta__: {prefix}_feature_encodings must list 'array' or 'json' per feature",
                            file=path)
    return header


def _unpack(path: Path, archive, headers: dict) -> Demonstrations:
    def member(name: str) -> np.ndarray:
        if name not in archive.files:
            raise DataError(f"archive lacks member {name!r}", file=path)
        return archive[name]

    def rows(name: str, expected: int, what: str) -> None:
        """Check a member's declared row count before decompressing it."""
        if name not in headers:
            raise DataError(f"archive lacks member {name!r}", file=path)
        shape = headers[name][1]
        if not shape or shape[0] != expected:
            raise DataError(f"member {name!r} has {shape[0] if shape else 0} rows, expected {expected} ({what})",
                            file=path)

    if "__meta__" not in archive.files:
        raise DataError("archive lacks member '__meta__': not a symlearn demonstrations archive", file=path,
                        hint="add __meta__ = json.dumps({\"symlearn\": \"demonstrations\", \"format_version\": 1, "
                             "\"state_kind\": ...}) (docs/FORMATS.md); an archive of 'observations', 'actions', "
                             "'terminals' is read as a D4RL table, one of 'states' and 'lengths' alone is a frame "
                             "archive (learn pdfa)")
    meta = member("__meta__")
    if meta.dtype.kind != "U" or meta.ndim != 0:
        raise DataError("member '__meta__' must be one string", file=path)
    header = complete_header(path, _read_meta(path, str(meta)), headers)

    if "lengths" not in headers or len(headers["lengths"][1]) != 1 or headers["lengths"][0].kind not in "iu":
        raise DataError("member 'lengths' must be a 1-D integer array", file=path)
    lengths = member("lengths")
    if (lengths < 1).any() or (lengths > 2**31).any():
        raise DataError("member 'lengths' must be positive integers (below 2^31)", file=path)
    if len(lengths) == 0:
        raise DataError("member 'lengths' is empty: no trajectories", file=path)
    n, total = len(lengths), int(lengths.sum())
    if "info" in headers:
        rows("info", n, "one per trajectory")
    if header["state_kind"] == "features":
        for name in header["_states_members"]:
            rows(name, total, "one per state")
    else:
        rows("states", total, "one per state")
    if header.get("has_labels"):
        rows("labels", total, "one per state")
        label_shape = headers["labels"][1]
        names_shape = headers.get("label_names", (None, ()))[1]
        if "label_names" not in headers:
            raise DataError("member 'labels' without a 'label_names' member, which names its columns", file=path,
                            hint="add label_names = numpy.array([...]), one proposition per column of 'labels'")
        if len(label_shape) != 2 or len(names_shape) != 1 or label_shape[1] != names_shape[0]:
            raise DataError(f"member 'labels' has {label_shape[1] if len(label_shape) == 2 else '?'} columns but "
                            f"'label_names' has {names_shape[0] if len(names_shape) == 1 else '?'} names",
                            file=path, hint="one column per name in 'label_names'")
    states = _unpack_column(path, "states", header["state_kind"], lengths, archive, header, member)
    actions: list[Any] = [None] * n
    if header.get("has_actions"):
        action_lengths = action_lengths_of(path, headers, lengths, rows, member)
        if action_lengths.shape != lengths.shape or action_lengths.dtype.kind not in "iu":
            raise DataError("members 'action_lengths' and 'lengths' disagree in size", file=path)
        if (action_lengths < 0).any() or (action_lengths > lengths).any():
            raise DataError("member 'action_lengths': each trajectory has between 0 and its number of states "
                            "actions", file=path)
        n_actions = int(action_lengths.sum())
        if header.get("action_kind") == "features":
            for name in header["_actions_members"]:
                rows(name, n_actions, "one per action")
        elif header.get("action_kind") is not None:
            rows("actions", n_actions, "one per action")
        if header.get("action_kind") is None:
            actions = [[] for _ in range(n)]
        else:
            nonzero = action_lengths[action_lengths > 0]
            parts = iter(_unpack_column(path, "actions", header["action_kind"], nonzero, archive, header, member))
            actions = [next(parts) if k else [] for k in action_lengths]
    rewards: list[Any] = [None] * n
    if header.get("has_rewards"):
        per = action_lengths if header.get("has_actions") else lengths
        rows("rewards", int(per.sum()), "one per action, or per state without actions")
        rewards = _split(path, "rewards", member("rewards"), per)
    labels: list[Any] = [None] * n
    if header.get("has_labels"):
        names = [str(x) for x in member("label_names")]
        matrix = member("labels")
        if matrix.dtype.kind != "b":
            odd = np.argwhere((matrix != 0) & (matrix != 1))
            if len(odd):
                row, column = (int(v) for v in odd[0])
                raise DataError(f"member 'labels' holds {matrix[row, column].item()!r} at row {row}, column {column} "
                                f"({names[column]!r}); labels are booleans or 0/1", file=path)
        blocks = _split(path, "labels", matrix, lengths)
        labels = [[frozenset(names[k] for k in np.flatnonzero(r)) for r in block] for block in blocks]
    infos = [load_json(str(s), source=f"{path} (member 'info', trajectory {i})")
             for i, s in enumerate(member("info"))] if "info" in headers else [{} for _ in range(n)]
    if len(infos) != n:
        raise DataError("member 'info' has the wrong number of entries", file=path)
    if depth(header.get("metadata") or {}) > MAX_JSON_DEPTH - 1:
        raise DataError(f"__meta__: metadata is nested more than {MAX_JSON_DEPTH} levels deep", file=path)

    trajectories = []
    for i in range(n):
        try:
            trajectories.append(Trajectory(states[i], actions[i], rewards[i], labels[i], infos[i]))
        except DataError as exc:
            raise DataError(f"trajectory {i}: {exc.message}", file=path, hint=exc.hint) from None
        check_declared_kinds(path, i, trajectories[-1], header)
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
        decode = {"array": lambda v: v.item(), "json": lambda v: load_json(str(v), source=path, error=DataError)}
        columns = [_split(path, name, member(name), lengths) for name in header[f"_{prefix}_members"]]
        return [
            [{name: decode[encodings[k]](columns[k][i][t]) for k, name in enumerate(names)}
             for t in range(int(lengths[i]))]
            for i in range(len(lengths))
        ]
    blocks = _split(path, prefix, member(prefix), lengths)
    if kind == "symbol":
        return [[str(v) for v in block] for block in blocks]
    return blocks
