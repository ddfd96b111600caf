"""The labeling of eq. 7.5: proposition ``p_i`` holds in a frame whose features lie within ``kappa`` of prototype ``i``.

``kappa`` defaults to half the smallest distance between two prototypes. By the triangle
inequality no frame can then be within ``kappa`` of two prototypes, so at most one proposition
holds in *any* frame (not only in the demonstrations), which is what the thesis asks kappa to be
tuned for (the machine cannot be in two states at once). A ``kappa`` given by the user that lets
several propositions hold in a demonstration frame gives a :class:`MultipleLabelsWarning` with
the count (see :func:`check_exclusive`).

The labeling is a grounding like any other (``propositions``, ``meanings``, ``label``,
``label_word``; ``label_matrix`` for a batch) over the features it was built with, and it saves
as ``NAME.json`` (the ``labeling`` envelope, ``kind: prototypes``: kappa, propositions,
meanings, prototype feature vectors, the feature extractor's configuration) plus, for PCA
features, ``NAME.features.safetensors`` (mean and components as plain arrays, read without
running code). A labeling built on a user's callable encoder saves without features; pass the
same callable to :meth:`PrototypeLabeling.load`.

>>> import numpy as np
>>> from symlearn.learners.reward_machines.features import CallableFeatures
>>> mean_colour = CallableFeatures(lambda f: f.mean(axis=(1, 2)))
>>> lab = PrototypeLabeling(mean_colour, np.array([[0.0, 0, 0], [1.0, 1, 1]]))
>>> lab.kappa, lab.propositions
(0.8660254037844386, ('p0', 'p1'))
>>> lab.label(np.ones((4, 4, 3))), lab.label(np.full((4, 4, 3), 0.5))
(frozenset({'p1'}), frozenset())
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import write_bytes, write_text
from symlearn.errors import DataError, ModelError
from symlearn.grounding.labeling import LabelingBase
from symlearn.input_limits import load_json, read_input_bytes, read_input_text
from symlearn.learners.reward_machines.features import CallableFeatures, PCAFeatures, as_frames

MAGIC = "labeling"
FORMAT_VERSION = 1


class MultipleLabelsWarning(UserWarning):
    """Several propositions hold in some frames (kappa too large)."""


def default_kappa(prototypes: np.ndarray) -> float:
    """Half the smallest distance between two prototypes (see the module docstring)."""
    if len(prototypes) < 2:
        raise DataError("one prototype only: the demonstrations never leave their first sub-goal",
                        hint="check that the demonstrations show the task being done, or lower eps")
    gaps = np.linalg.norm(prototypes[:, None] - prototypes[None], axis=-1)
    gaps[np.diag_indices(len(prototypes))] = np.inf
    smallest = float(gaps.min())
    if smallest <= 0:
        raise DataError("two prototypes have identical features; their propositions could not be told apart")
    return smallest / 2


class PrototypeLabeling(LabelingBase):
    """Propositions ``p_i``: feature distance to prototype ``i`` below ``kappa`` (eq. 7.5)."""

    def __init__(self, features, prototypes: np.ndarray, kappa: float | None = None,
                 propositions: Sequence[str] | None = None, meanings: dict[str, str] | None = None) -> None:
        self.features = features
        self.prototypes = np.asarray(prototypes, dtype=np.float64)
        if self.prototypes.ndim != 2 or len(self.prototypes) == 0:
            raise ModelError(f"prototypes must be a (k, d) array with k >= 1, got shape {self.prototypes.shape}")
        if not np.isfinite(self.prototypes).all():  # a NaN prototype would match no frame, silently
            raise ModelError("prototypes must be finite numbers (a NaN or infinite entry is no centre)")
        self.kappa = default_kappa(self.prototypes) if kappa is None else float(kappa)
        if not (np.isfinite(self.kappa) and self.kappa > 0):
            raise DataError(f"kappa must be a positive number, got {kappa!r}")
        names = tuple(propositions) if propositions is not None else tuple(f"p{i}" for i in range(len(self.prototypes)))
        if len(names) != len(self.prototypes) or len(set(names)) != len(names):
            raise ModelError(f"{len(names)} proposition names (distinct) needed for {len(self.prototypes)} prototypes")
        self._propositions = names
        self._meanings = dict(meanings or {p: f"the scene looks like prototype {i}" for i, p in enumerate(names)})

    @property
    def propositions(self) -> tuple[str, ...]:
        return self._propositions

    # -- labelling ---------------------------------------------------------------------------------
    def distances(self, frames: Any, *, features: np.ndarray | None = None) -> np.ndarray:
        """``(N, k)`` feature distances of frames (or of given ``features``) to every prototype."""
        values = self.features.transform(as_frames(frames)) if features is None else np.asarray(features)
        if values.ndim != 2 or values.shape[1] != self.prototypes.shape[1]:
            raise DataError(f"features of shape {values.shape} do not match prototypes of dimension "
                            f"{self.prototypes.shape[1]}")
        return np.linalg.norm(values[:, None, :] - self.prototypes[None], axis=-1)

    def label_matrix(self, frames: Any = None, *, features: np.ndarray | None = None) -> np.ndarray:
        """``(N, k)`` booleans: which propositions hold in each frame."""
        return self.distances(frames, features=features) < self.kappa

    def label(self, state: Any) -> frozenset[str]:
        """The propositions holding in one frame ``(H, W[, C])``."""
        row = self.label_matrix(np.asarray(state)[None])[0]
        return frozenset(p for p, holds in zip(self._propositions, row) if holds)

    def label_word(self, states: Any) -> tuple[frozenset[str], ...]:
        matrix = self.label_matrix(np.asarray(states))
        return tuple(frozenset(p for p, holds in zip(self._propositions, row) if holds) for row in matrix)

    # -- files -------------------------------------------------------------------------------------
    def to_dict(self, features_file: str | None = None) -> dict[str, Any]:
        return {"symlearn": MAGIC, "format_version": FORMAT_VERSION, "kind": "prototypes", "kappa": self.kappa,
                "propositions": list(self._propositions), "meanings": self.meanings,
                "prototypes": self.prototypes.tolist(), "features": {**self.features.config(), "file": features_file}}

    def save(self, path: str | os.PathLike[str]) -> list[Path]:
        """Write ``path`` (JSON) and, for PCA features, ``<stem>.features.safetensors`` beside it."""
        path = Path(path)
        written = []
        features_file = None
        if isinstance(self.features, PCAFeatures):
            from safetensors.numpy import save as save_arrays

            features_file = path.with_suffix("").name + ".features.safetensors"
            written.append(write_bytes(path.with_name(features_file), save_arrays(self.features.arrays())))
        elif not isinstance(self.features, CallableFeatures) and hasattr(self.features, "save"):
            features_file = path.with_suffix("").name + ".features.safetensors"
            written += self.features.save(path.with_name(features_file))
        written.insert(0, write_text(path, json.dumps(self.to_dict(features_file), indent=1) + "\n"))
        return written

    @classmethod
    def load(cls, path: str | os.PathLike[str], feature_extractor=None) -> PrototypeLabeling:
        """Read a saved labeling; ``feature_extractor`` is needed when it was built on a callable."""
        path = Path(path)
        document = load_json(read_input_text(path), source=str(path))
        if not isinstance(document, dict) or document.get("symlearn") != MAGIC or document.get("kind") != "prototypes":
            raise DataError("not a prototype labeling (expected symlearn: labeling, kind: prototypes)", file=path)
        if document.get("format_version") != FORMAT_VERSION:
            raise DataError(f"unsupported labeling format_version {document.get('format_version')!r}", file=path)
        try:
            prototypes = np.asarray(document["prototypes"], dtype=np.float64)
            kappa, names = float(document["kappa"]), document["propositions"]
            features_doc = document["features"]
        except (KeyError, TypeError, ValueError, OverflowError) as exc:  # OverflowError: 1e400 as an integer
            raise DataError(f"malformed prototype labeling: {exc}", file=path) from None
        kind = features_doc.get("kind") if isinstance(features_doc, dict) else None
        if feature_extractor is not None:
            features = CallableFeatures(feature_extractor) if not hasattr(feature_extractor, "transform") \
                else feature_extractor
        elif kind == "pca":
            from safetensors import SafetensorError
            from safetensors.numpy import load as load_arrays

            file = _features_file(path, features_doc)
            try:
                arrays = load_arrays(read_input_bytes(file, variable="SYMLEARN_MAX_ARRAY_MB", what="features file"))
            except (SafetensorError, OSError) as exc:
                raise DataError(f"cannot read the features file {file.name}: {exc}", file=path) from None
            try:
                features = PCAFeatures.from_arrays(features_doc, arrays)
            except ModelError as exc:
                raise ModelError(exc.message, file=path, hint=exc.hint) from None
        elif kind == "autoencoder":
            from symlearn.learners.reward_machines.autoencoder import AutoencoderFeatures

            file = _features_file(path, features_doc)
            features = AutoencoderFeatures.load(file)
        else:
            raise DataError(f"the labeling's features ({kind}) cannot be loaded from files",
                            file=path, hint="pass feature_extractor= (the encoder it was built with)")
        meanings = document.get("meanings") if isinstance(document.get("meanings"), dict) else None
        try:
            return cls(features, prototypes, kappa, names, meanings)
        except (DataError, ModelError) as exc:
            raise type(exc)(exc.message, file=exc.file or path, hint=exc.hint) from None


def check_exclusive(matrix: np.ndarray, what: str = "demonstration frames") -> int:
    """Warn (with the count) when several propositions hold in some frames; returns that count."""
    several = int(np.sum(matrix.sum(axis=1) > 1))
    if several:
        warnings.warn(f"{several} of {len(matrix)} {what} satisfy several propositions at once (kappa too "
                      "large); the machine would be in two states at once there", MultipleLabelsWarning, stacklevel=3)
    return several


def check_machine_labeling(machine, labeling, *, source: str | None = None) -> None:
    """Refuse a machine whose guards read propositions the labeling never produces (counted and named)."""
    missing = sorted(set(machine.alphabet) - set(labeling.propositions))
    if missing:
        shown = ", ".join(missing[:8]) + (", ..." if len(missing) > 8 else "")
        raise DataError(f"the machine reads {len(missing)} proposition(s) the labeling lacks: {shown}",
                        file=source, hint="use the labeling written beside the machine (MACHINE.labeling.json)")


__all__ = ["MultipleLabelsWarning", "PrototypeLabeling", "check_exclusive", "check_machine_labeling", "default_kappa"]


def _features_file(labeling: Path, features_doc: dict) -> Path:
    """The features file a saved labeling names: a plain file name in the labeling's own folder
    (never a path elsewhere, nor the folder itself)."""
    file = features_doc.get("file")
    if not isinstance(file, str) or Path(file).name != file or file in ("", ".", ".."):
        raise DataError("the labeling names no features file beside it", file=labeling,
                        hint="'features.file' is a file name in the labeling's folder")
    return labeling.with_name(file)
