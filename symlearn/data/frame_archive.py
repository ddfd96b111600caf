"""Frame archives: numeric demonstrations where NaN means "not observed" (NPZ, no pickle).

Sub-goal learning reads object positions from a camera that sometimes misses an object; those
frames carry NaN, which :class:`~symlearn.data.Demonstrations` (rightly) refuses. A frame
archive is the plain numeric form of such demonstrations, read and written with
``allow_pickle=False``. Members:

``states``         float ``(total frames, k)``: every demonstration's frames, concatenated (NaN allowed)
``lengths``        int ``(N,)``: frames per demonstration (each >= 1, summing to ``total frames``)
``feature_names``  optional text ``(k,)``

Reading checks the members' ``.npy`` headers first (dtypes, declared sizes against
``SYMLEARN_MAX_ARRAY_MB``, through :func:`symlearn.data.npz_format.member_headers`), then shapes
and lengths; infinite values are refused (unknown is NaN).

>>> import numpy as np, tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "frames.npz")
>>> _ = save_frames(path, [np.array([[0.0, np.nan], [1.0, 2.0]]), np.zeros((3, 2))], ["x", "y"])
>>> runs, names = load_frames(path)
>>> [r.shape for r in runs], names, bool(np.isnan(runs[0][0, 1]))
([(2, 2), (3, 2)], ('x', 'y'), True)
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from symlearn.atomic import write_bytes
from symlearn.errors import DataError


def is_frame_archive(path: str | os.PathLike[str]) -> bool:
    """An NPZ archive with ``states`` and ``lengths`` but no symlearn demonstrations header."""
    from symlearn.data.npz_format import member_headers

    members = member_headers(path)
    return "__meta__" not in members and {"states", "lengths"} <= set(members)


def save_frames(path: str | os.PathLike[str], runs: Sequence[np.ndarray],
                feature_names: Sequence[str] | None = None) -> Path:
    """Write demonstrations (one ``(T_i, k)`` float array each) atomically."""
    arrays = [np.asarray(r, dtype=np.float64) for r in runs]
    if not arrays or any(a.ndim != 2 or len(a) == 0 for a in arrays) or len({a.shape[1] for a in arrays}) != 1:
        raise DataError("frames must be non-empty (T, k) arrays with one k")
    members = {"states": np.concatenate(arrays), "lengths": np.asarray([len(a) for a in arrays], dtype=np.int64)}
    if feature_names is not None:
        if len(feature_names) != arrays[0].shape[1]:
            raise DataError(f"{len(feature_names)} feature names for {arrays[0].shape[1]} features")
        members["feature_names"] = np.asarray(list(feature_names), dtype=str)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **members)
    return write_bytes(path, buffer.getvalue())


def load_frames(path: str | os.PathLike[str]) -> tuple[list[np.ndarray], tuple[str, ...] | None]:
    """``(runs, feature names or None)``; every problem a :class:`DataError` naming the file."""
    from symlearn.data.npz_format import open_checked

    source = str(path)
    headers, archive = open_checked(path)
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("holds a single array, not a frame archive", file=source)
    with archive:
        for name in ("states", "lengths"):
            if name not in headers:
                raise DataError(f"a frame archive needs a member {name!r}", file=source,
                                hint="members: states (frames x features, NaN = unobserved), lengths (frames per "
                                     "demonstration), optional feature_names")
        s_dtype, s_shape = headers["states"]
        if s_dtype.kind not in "iuf" or len(s_shape) != 2 or s_shape[1] < 1:
            raise DataError(f"member 'states' must be a numeric (frames, features) array, got {s_dtype.str} "
                            f"{s_shape}", file=source)
        lengths = _lengths(archive, headers["lengths"], s_shape[0], "rows", source)
        states = _member(archive, "states", source).astype(np.float64)
        names = None
        if "feature_names" in headers:
            raw = _member(archive, "feature_names", source)
            if raw.dtype.kind != "U" or raw.shape != (s_shape[1],):
                raise DataError(f"'feature_names' must be {s_shape[1]} strings", file=source)
            names = tuple(str(n) for n in raw)
            repeated = sorted({n for n in names if names.count(n) > 1})
            if repeated or any(not n.strip() for n in names):
                what = f"names {repeated[0]!r} twice" if repeated else "has an empty name"
                raise DataError(f"'feature_names' {what}", file=source,
                                hint="--subsets picks columns by name: give each column one name")
    if np.isinf(states).any():
        row = int(np.flatnonzero(np.isinf(states).any(axis=1))[0])
        demo = int(np.searchsorted(np.cumsum(lengths), row, side="right"))
        raise DataError(f"demonstration {demo} has an infinite feature value (row {row} of 'states')",
                        file=source, hint="NaN marks an unobserved feature; infinity is not allowed")
    return np.split(states, np.cumsum(lengths)[:-1]), names


def _lengths(archive, header: tuple[np.dtype, tuple[int, ...]], total: int, unit: str, source: str) -> np.ndarray:
    """The ``lengths`` member, checked: a non-empty integer vector of positive runs summing to the
    ``total`` rows (or frames) of ``states``."""
    dtype, shape = header
    if dtype.kind not in "iu" or len(shape) != 1 or shape[0] < 1:
        raise DataError(f"member 'lengths' must be a non-empty integer vector, got {dtype.str} {shape}", file=source)
    lengths = _member(archive, "lengths", source).astype(np.int64)
    if (lengths < 1).any() or int(lengths.sum()) != total:
        raise DataError(f"'lengths' must be positive and sum to the {total} {unit} of 'states', "
                        f"they sum to {int(lengths.sum())}", file=source)
    return lengths


def _member(archive, name: str, source: str) -> np.ndarray:
    """One member, its data read: a member shorter than its header declares (truncated, or a
    corrupt zip entry) is a :class:`DataError`, not numpy's ``ValueError``/``EOFError``."""
    import zipfile
    import zlib

    try:
        return archive[name]
    except (ValueError, EOFError, OSError, zipfile.BadZipFile, zlib.error, RuntimeError) as exc:
        if isinstance(exc, DataError):
            raise
        raise DataError(f"member {name!r} is malformed: {exc}", file=source) from None


def load_video(path: str | os.PathLike[str]):
    """A frame archive whose ``states`` are pictures -- ``(total frames, H, W[, C])`` with
    ``lengths`` -- as :class:`~symlearn.data.Demonstrations` of the image kind, one per run.

    Why: camera tours are most naturally saved as a stack of frames and the run lengths, the same
    two members as a position archive; ``learn rm`` refused such a file for lacking the
    demonstrations header. Position archives (2-D ``states``) stay :func:`load_frames`'s."""
    from symlearn.data.demonstrations import Demonstrations
    from symlearn.data.npz_format import open_checked
    from symlearn.data.trajectory import Trajectory

    source = str(path)
    headers, archive = open_checked(path)
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise DataError("holds a single array, not a frame archive", file=source)
    with archive:
        s_dtype, s_shape = headers["states"]
        if s_dtype.kind not in "iuf" or len(s_shape) not in (3, 4) or 0 in s_shape:
            raise DataError(f"member 'states' must hold numeric pictures (frames, H, W[, C]), got {s_dtype.str} "
                            f"{s_shape}", file=source,
                            hint="a (frames, features) archive of positions is learn pdfa's input")
        lengths = _lengths(archive, headers["lengths"], s_shape[0], "frames", source)
        frames = _member(archive, "states", source)
    if frames.dtype.kind == "f" and not np.isfinite(frames).all():
        raise DataError("member 'states' holds NaN or infinite pixels", file=source)
    ends = np.cumsum(lengths)
    return Demonstrations([Trajectory(states=frames[end - n:end]) for n, end in zip(lengths, ends)])
