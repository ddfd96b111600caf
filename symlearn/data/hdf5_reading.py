"""Reading other tools' HDF5 files (D4RL, Minari) without trusting what they declare.

h5py reads a dataset into one array of the size its header declares, so every dataset a reader
will read is checked first, from its header only: a plain number or boolean dtype (object,
variable-length, string, reference, compound and sub-array dtypes are refused: symlearn never
needs them, and object data is where pickles hide), stored inside the file (external links,
external raw storage and virtual datasets would read other files), and the declared sizes of
all of them summed against ``SYMLEARN_MAX_ARRAY_MB``, as for NPZ archives
(:mod:`symlearn.input_limits`). The file's own size is bounded by the same limit.

h5py is optional (the ``formats`` extra); without it these readers raise
:class:`~symlearn.errors.MissingDependencyError`.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

import numpy as np

from symlearn.errors import DataError, OptionalDependency
from symlearn.input_limits import check_size

# worded as symlearn.optional words the extras' hints
H5PY = OptionalDependency("h5py", "installed by `make test`; else .venv/bin/pip install -e '.[formats]' "
                                  "(from a wheel: pip install 'symlearn[formats]')")


def h5py_module() -> Any:
    try:
        import h5py
    except ImportError:
        raise H5PY.error("reading and writing HDF5 files") from None
    return h5py


@contextmanager
def open_hdf5(path: str | os.PathLike[str]) -> Iterator[Any]:
    """The file opened read-only, after its size is checked; a file that is no HDF5 is a
    located :class:`DataError` (a missing or unreadable file keeps its OS error)."""
    h5py = h5py_module()
    path = Path(path)
    check_size(path.stat().st_size, "SYMLEARN_MAX_ARRAY_MB", what="file size", file=path)
    try:
        handle = h5py.File(path, "r")
    except OSError as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise DataError(f"not a readable HDF5 file ({_reason(exc)})", file=path) from None
    try:
        with handle:
            yield handle
    except (OSError, RuntimeError, KeyError, ValueError, TypeError, IndexError) as exc:
        # A damaged file fails wherever h5py next reads its structure (a group's keys, a shape, an
        # attribute); what h5py raised is the file's fault, anything else is ours and propagates.
        if isinstance(exc, (FileNotFoundError, PermissionError)) or not _raised_in_h5py(exc):
            raise
        raise DataError(f"damaged HDF5 file ({_reason(exc)})", file=path) from None


def _raised_in_h5py(exc: BaseException) -> bool:
    """Whether the innermost frame of ``exc`` is h5py's (its compiled modules included)."""
    frame = exc.__traceback__
    while frame is not None and frame.tb_next is not None:
        frame = frame.tb_next
    return frame is not None and str(frame.tb_frame.f_globals.get("__name__", "")).startswith("h5py")


def _reason(exc: BaseException) -> str:
    # h5py's message, on one line (the CLI prints errors as one line)
    return " ".join(str(exc).split())


def member(path: Path, group: Any, name: str, *, required: bool = True) -> Any:
    """``group[name]`` if it is a dataset or group stored in this file; ``None`` when absent
    and not ``required``. External links are refused before h5py follows them."""
    h5py = h5py_module()
    where = f"{group.name.rstrip('/')}/{name}"
    try:
        link = group.get(name, getlink=True)
    except (OSError, KeyError, ValueError) as exc:
        raise DataError(f"{where!r} cannot be read ({_reason(exc)})", file=path) from None
    if link is None:
        if required:
            raise DataError(f"has no {where!r}", file=path)
        return None
    if isinstance(link, h5py.ExternalLink):
        raise DataError(f"{where!r} is a link to another file ({link.filename}); symlearn reads only what "
                        "is inside the file", file=path)
    try:
        return group[name]
    except (OSError, KeyError, ValueError) as exc:
        raise DataError(f"{where!r} cannot be read ({_reason(exc)})", file=path) from None


def check_dataset(path: Path, dataset: Any) -> tuple[np.dtype, tuple[int, ...]]:
    """``(dtype, shape)`` of a dataset that is plain numbers or booleans stored in this file."""
    h5py = h5py_module()
    name = dataset.name
    if not isinstance(dataset, h5py.Dataset):
        raise DataError(f"{name!r} is a {type(dataset).__name__.lower()}, expected an array", file=path)
    if dataset.shape is None:
        raise DataError(f"{name!r} is an empty (null) dataset", file=path)
    dtype = dataset.dtype
    special = (h5py.check_vlen_dtype(dtype) is not None or h5py.check_string_dtype(dtype) is not None
               or h5py.check_ref_dtype(dtype) is not None)
    if special or dtype.hasobject or dtype.names is not None or dtype.subdtype is not None \
            or dtype.kind not in "biuf":
        raise DataError(f"{name!r} has dtype {dtype.str!r}; symlearn reads only plain numbers and booleans "
                        "from HDF5 (no strings, variable-length or object data)", file=path)
    if dataset.is_virtual or dataset.external:
        raise DataError(f"{name!r} is stored outside the file (a virtual or external dataset); symlearn reads "
                        "only what is inside the file", file=path)
    return dtype, tuple(int(n) for n in dataset.shape)


def declared_bytes(datasets: Iterable[Any], path: Path) -> int:
    """Check every dataset and the sum of their declared sizes against ``SYMLEARN_MAX_ARRAY_MB``
    before any of them is read."""
    total = 0
    for dataset in datasets:
        dtype, shape = check_dataset(path, dataset)
        count = 1
        for extent in shape:
            count *= extent
        total += count * dtype.itemsize
        check_size(total, "SYMLEARN_MAX_ARRAY_MB",
                   what=f"declared size (dataset {dataset.name!r} and those before it)", file=path)
    return total


def read(path: Path, dataset: Any) -> np.ndarray:
    """The whole dataset as an array (checked already by :func:`declared_bytes`); a broken
    chunk or an unavailable compression filter is a located :class:`DataError`."""
    try:
        return np.asarray(dataset[()])
    except (OSError, ValueError, TypeError, RuntimeError) as exc:
        raise DataError(f"{dataset.name!r} cannot be read ({_reason(exc)})", file=path) from None


def names(path: Path, group: Any) -> list[str]:
    """The member names of ``group``; a name that does not decode as text is a damaged file."""
    found = list(group.keys())
    for name in found:
        if not isinstance(name, str):
            raise DataError(f"{group.name!r} has a member whose name is not text ({name!r})", file=path)
    return found


def top_level_names(path: str | os.PathLike[str]) -> list[str]:
    """The names at the root of an HDF5 file (to tell a Minari file from a D4RL table)."""
    with open_hdf5(path) as handle:
        return names(Path(path), handle)
