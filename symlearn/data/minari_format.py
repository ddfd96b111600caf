"""Minari datasets read from a local folder, with h5py only (the minari package is not needed).

A dataset folder, as Minari's ``DataCollector.create_dataset`` writes it
(``$MINARI_DATASETS_PATH/<namespace>/<name>-v<N>/``), holds ``data/metadata.json`` and
``data/main_data.hdf5``; the HDF5 file has one group ``episode_<i>`` per episode with

``observations``   ``T + 1`` rows (the reset observation, then one per step), or a group of
                   such datasets for a ``Dict``/``Tuple`` observation space
``actions``        ``T`` rows
``rewards``        ``T`` floats
``terminations``, ``truncations``  ``T`` booleans
``infos``          a group of per-step arrays (not read: symlearn keeps one JSON info per
                   trajectory, not per step; their names are listed in ``metadata["minari_infos"]``)

and the attributes ``id`` and ``seed`` (when the episode was reset with one). Episode ``i``
becomes one trajectory with ``T + 1`` states and ``T`` actions; its info holds ``seed``,
``terminated`` (the last step's termination) and ``truncated`` (the last step's truncation, or
the episode did not terminate: :func:`~symlearn.data.recording.record`'s convention), so a
dataset collected while :func:`record` drove the environment reads back equal to what
``record`` returned. Dict and Tuple observations are flattened into one vector per step
(:mod:`symlearn.data.flat_observations`; column names in ``metadata["feature_names"]``); Dict
and Tuple actions, Text spaces and JPEG-encoded image observations are refused. The folder may
be given as the dataset folder, its ``data`` folder, or the ``main_data.hdf5`` file itself.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.data import hdf5_reading as h5
from symlearn.data.demonstrations import Demonstrations
from symlearn.data.flat_observations import flatten_leaves, leaf_name, ordered_keys
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError
from symlearn.input_limits import load_json, read_input_text

DATA_FILE = "main_data.hdf5"
METADATA_FILE = "metadata.json"
_EPISODE = re.compile(r"episode_(\d+)\Z")


def minari_files(path: str | os.PathLike[str]) -> tuple[Path, Path | None]:
    """``(main_data.hdf5, metadata.json or None)`` of a dataset folder, its data folder or the
    HDF5 file itself; ``DataError`` when ``path`` is none of those."""
    path = Path(path)
    if path.is_file():
        metadata = path.parent / METADATA_FILE
        return path, metadata if metadata.is_file() else None
    for folder in (path / "data", path):
        if (folder / DATA_FILE).is_file():
            metadata = folder / METADATA_FILE
            return folder / DATA_FILE, metadata if metadata.is_file() else None
    if (path / "data" / METADATA_FILE).is_file() or (path / METADATA_FILE).is_file():
        raise DataError(f"this Minari dataset has no {DATA_FILE}", file=path,
                        hint="only the hdf5 data format is read; a dataset written with data_format='arrow' "
                             "can be rewritten by minari with data_format='hdf5'")
    raise DataError("is a directory but not a Minari dataset (no data/main_data.hdf5)", file=path,
                    hint="give a Minari dataset folder, or a .jsonl/.npz/.hdf5 demonstrations file")


def is_episode_group(name: str) -> bool:
    return _EPISODE.match(name) is not None


def _read_metadata(path: Path | None) -> dict[str, Any]:
    if path is None:
        return {}
    doc = load_json(read_input_text(path), source=path)
    if not isinstance(doc, dict):
        raise DataError("must hold a JSON object", file=path)
    if doc.get("data_format", "hdf5") != "hdf5":
        raise DataError(f"data_format {doc.get('data_format')!r} is not read by symlearn (only 'hdf5')", file=path)
    return doc


def _embedded_json(doc: dict, key: str, path: Path | None) -> Any:
    """Minari stores spaces and the environment spec as JSON text inside the JSON."""
    value = doc.get(key)
    if isinstance(value, str):
        return load_json(value, source=f"{path} ({key})")
    return value


def _is_jpeg_image_space(space: Any) -> bool:
    return (isinstance(space, dict) and space.get("type") == "Box" and space.get("dtype") == "uint8"
            and len(space.get("shape") or ()) in (2, 3))


def _observation_leaves(path: Path, node: Any, prefix: tuple[str, ...]) -> list[tuple[str, Any]]:
    """``(column name, dataset)`` of every leaf under ``node``, in flattening order."""
    h5py = h5.h5py_module()
    if isinstance(node, h5py.Dataset):
        return [(leaf_name(prefix), node)]
    if not isinstance(node, h5py.Group):
        raise DataError(f"{node.name!r} is a {type(node).__name__.lower()}, expected an array or a group",
                        file=path)
    leaves = []
    for key in ordered_keys(h5.names(path, node)):
        leaves += _observation_leaves(path, h5.member(path, node, key), prefix + (key,))
    return leaves


def read_minari(path: str | os.PathLike[str]) -> Demonstrations:
    data_file, metadata_file = minari_files(path)
    doc = _read_metadata(metadata_file)
    observation_space = _embedded_json(doc, "observation_space", metadata_file)
    env_spec = _embedded_json(doc, "env_spec", metadata_file)
    h5py = h5.h5py_module()
    with h5.open_hdf5(data_file) as handle:
        names = [name for name in h5.names(data_file, handle) if _EPISODE.match(name)]
        if not names:
            raise DataError("holds no episode_<i> groups: not a Minari dataset", file=data_file)
        names.sort(key=lambda name: int(_EPISODE.match(name).group(1)))
        plans = [_plan_episode(data_file, handle, name, h5py) for name in names]
        if doc.get("jpeg_encoding") and _is_jpeg_image_space(observation_space) and plans[0]["tree"] is None:
            # Minari stores such frames as JPEG bytes (ragged ones as variable-length arrays)
            expected = tuple(observation_space["shape"])
            shape = tuple(plans[0]["observations"][0][1].shape or ())[1:]
            if shape != expected:
                raise DataError(f"image observations are stored JPEG-encoded (per-step shape {shape}, the space "
                                f"says {expected}); symlearn does not decode images", file=data_file,
                                hint="collect the dataset again with jpeg_encoding off, or convert it with minari")
        h5.declared_bytes([ds for plan in plans for ds in plan["datasets"]], data_file)
        trajectories, infos, feature_names = [], set(), None
        for i, plan in enumerate(plans):
            trajectory, columns = _read_episode(data_file, plan)
            if i and columns != feature_names:
                raise DataError(f"{plan['name']!r}: observation entries {columns} differ from those of "
                                f"{plans[0]['name']!r} ({feature_names})", file=data_file)
            feature_names = columns
            trajectories.append(trajectory)
            infos.update(plan["infos"])
    metadata: dict[str, Any] = {"source_format": "minari"}
    for key in ("dataset_id", "minari_version", "algorithm_name"):
        if isinstance(doc.get(key), str):
            metadata[key] = doc[key]
    if isinstance(env_spec, dict) and isinstance(env_spec.get("id"), str):
        metadata["env"] = env_spec["id"]
    if feature_names:
        metadata["feature_names"] = feature_names
    if infos:
        metadata["minari_infos"] = sorted(infos)
    try:
        return Demonstrations(trajectories, metadata=metadata)
    except DataError as exc:
        raise DataError(exc.message, file=data_file, hint=exc.hint) from None


def _plan_episode(path: Path, handle: Any, name: str, h5py: Any) -> dict[str, Any]:
    """The datasets one episode will read, found from headers only."""
    group = h5.member(path, handle, name)
    if not isinstance(group, h5py.Group):
        raise DataError(f"{name!r} is an array, expected an episode group", file=path)
    node = h5.member(path, group, "observations")
    tree = None if isinstance(node, h5py.Dataset) else node
    observations = _observation_leaves(path, node, ())
    if isinstance(h5.member(path, group, "actions"), h5py.Group):
        raise DataError(f"'/{name}/actions' is a group (a Dict or Tuple action space); symlearn reads array "
                        "actions only", file=path)
    columns = {key: h5.member(path, group, key) for key in ("actions", "rewards", "terminations", "truncations")}
    info_group = h5.member(path, group, "infos", required=False)
    infos = h5.names(path, info_group) if isinstance(info_group, h5py.Group) else []
    seed = group.attrs.get("seed")
    return {"name": name, "tree": tree, "observations": observations, "columns": columns, "infos": infos,
            "seed": int(seed) if isinstance(seed, (int, np.integer)) else None,
            "datasets": [ds for _, ds in observations] + list(columns.values())}


def _read_episode(path: Path, plan: dict[str, Any]) -> tuple[Trajectory, list[str] | None]:
    name = plan["name"]
    columns = plan["columns"]
    steps = h5.check_dataset(path, columns["actions"])[1]
    n = steps[0] if steps else 0
    for key in ("rewards", "terminations", "truncations"):
        shape = h5.check_dataset(path, columns[key])[1]
        if shape != (n,):
            raise DataError(f"'/{name}/{key}' has shape {shape}, expected ({n},): one per action", file=path)
    for leaf, dataset in plan["observations"]:
        shape = h5.check_dataset(path, dataset)[1]
        if not shape or shape[0] != n + 1:
            where = "observations" if plan["tree"] is None else f"observations/{leaf}"
            raise DataError(f"'/{name}/{where}' has {shape[0] if shape else 0} rows, expected {n + 1} "
                            f"(one more than the {n} actions)", file=path)
    leaves = [(leaf, h5.read(path, dataset)) for leaf, dataset in plan["observations"]]
    feature_names = None
    if plan["tree"] is None:
        states = leaves[0][1]
    else:
        states, feature_names = flatten_leaves(leaves, f"'/{name}/observations'")
    actions = h5.read(path, columns["actions"])
    rewards = h5.read(path, columns["rewards"])
    from symlearn.data.d4rl_format import _flags  # booleans or 0/1, anything else refused

    terminations = _flags(path, f"/{name}/terminations", h5.read(path, columns["terminations"]))
    truncations = _flags(path, f"/{name}/truncations", h5.read(path, columns["truncations"]))
    terminated = bool(n and terminations[-1])
    info: dict[str, Any] = {}
    if plan["seed"] is not None:
        info["seed"] = plan["seed"]
    info.update({"terminated": terminated, "truncated": bool(n and truncations[-1]) or not terminated})
    try:
        trajectory = Trajectory(states, actions, rewards, None, info)
    except DataError as exc:
        raise DataError(f"{name!r}: {exc.message}", file=path, hint=exc.hint) from None
    return trajectory, feature_names
