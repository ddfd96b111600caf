"""What a hand-written NPZ demonstrations archive may leave out of ``__meta__``, filled in from
its members (docs/FORMATS.md, "Demonstrations, NPZ"): the ``has_*`` flags, the kinds, the
feature columns' member names, ``action_lengths``; and the check that a kind ``__meta__``
declares is the kind the values are. :mod:`symlearn.data.npz_format` reads the rest."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from symlearn.data.kinds import KINDS
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError


def _column_members(prefix: str, headers: dict) -> list[str]:
    return [name for name in headers if name == prefix or name.startswith(prefix + ".")]


def check_declared_kinds(path: Path, i: int, trajectory: Trajectory, header: dict) -> None:
    """A kind ``__meta__`` declares must be the kind the values are (ids stored as floats would
    otherwise become vector states without a word); kinds filled in from the members are not checked."""
    for what, kind, key in (("states", trajectory.state_kind, "state_kind"),
                            ("actions", trajectory.action_kind, "action_kind")):
        declared = header.get(key)
        if declared is None or key in header.get("_inferred", ()) or kind is None or kind == declared:
            continue
        hint = None
        if declared == "discrete":
            hint = f"store discrete {what} as integers ({what}.astype(np.int64))"
        elif kind == "discrete" and declared == "vector":
            hint = f"1-D integers are discrete ids: for one-number vectors store {what} as floats or with shape (N, 1)"
        raise DataError(f"trajectory {i}: {what} are {kind} but __meta__ says {key} {declared}", file=path, hint=hint)


def complete_header(path: Path, header: dict, headers: dict) -> dict:
    """Fill in what a hand-written ``__meta__`` may leave out, from the members present: the
    ``has_actions``/``has_rewards``/``has_labels`` flags (an ``actions`` member is not dropped
    because no flag names it) and a kind that an array member shows (``symbol`` for text, else
    whatever its values are). A flag that is ``false`` while its member is there is refused."""
    header = dict(header)
    present = {"has_actions": bool(_column_members("actions", headers)) or "action_lengths" in headers,
               "has_rewards": "rewards" in headers, "has_labels": "labels" in headers}
    members = {"has_actions": "actions", "has_rewards": "rewards", "has_labels": "labels"}
    for flag, here in present.items():
        if flag not in header:
            header[flag] = here
        elif header[flag] is False and here:
            raise DataError(f"__meta__ says {flag} is false but the archive holds {members[flag]!r}", file=path,
                            hint=f"set {flag} to true, or remove the member")
    for prefix, key in (("states", "state_kind"), ("actions", "action_kind")):
        if header.get(key) is None and prefix in headers:
            header[key] = "symbol" if headers[prefix][0].kind == "U" else "vector"  # the values decide later
            header["_inferred"] = (*header.get("_inferred", ()), key)
    if header.get("state_kind") is None:
        raise DataError("__meta__ has no state_kind and the archive no 'states' member", file=path,
                        hint=f"state_kind is one of {', '.join(KINDS)}")
    for prefix, key in (("states", "state_kind"), ("actions", "action_kind")):
        if header.get(key) == "features":
            header[f"_{prefix}_members"] = _feature_members(path, prefix, header, headers)
    return header


def _feature_members(path: Path, prefix: str, header: dict, headers: dict) -> list[str]:
    """The members holding the feature columns, in the order of ``<prefix>_features``: ``<prefix>.<k>``
    by index (as symlearn writes them) or ``<prefix>.<name>`` by name; without ``<prefix>_features``
    the names are those of ``<prefix>.<name>`` members (sorted)."""
    names = header.get(f"{prefix}_features")
    suffixes = [name[len(prefix) + 1:] for name in headers if name.startswith(prefix + ".")]
    if names is None:
        if not suffixes or all(suffix.isdigit() for suffix in suffixes):
            raise DataError(f"__meta__ has no {prefix}_features: the names of the {prefix}.<k> feature columns",
                            file=path, hint=f'add "{prefix}_features": [name, ...] (column k is {prefix}.k), or '
                                            f"name the members {prefix}.<feature name>")
        names = sorted(suffixes)
        header[f"{prefix}_features"] = names
    members = []
    for k, name in enumerate(names):
        for candidate in (f"{prefix}.{k}", f"{prefix}.{name}"):
            if candidate in headers:
                members.append(candidate)
                break
        else:
            raise DataError(f"archive lacks member '{prefix}.{k}' (or '{prefix}.{name}') for feature {name!r}",
                            file=path)
    return members


def action_lengths_of(path: Path, headers: dict, lengths: np.ndarray, rows, member) -> np.ndarray:
    """``action_lengths``, or, where the archive has none, what the actions' row count allows:
    one action per state, or one fewer per trajectory (the last state is final)."""
    n = len(lengths)
    if "action_lengths" in headers:
        rows("action_lengths", n, "one per trajectory")
        return member("action_lengths")
    columns = _column_members("actions", headers)
    shape = headers[columns[0]][1] if columns else ()
    count = shape[0] if shape else 0
    total = int(lengths.sum())
    if count == total:
        return lengths.copy()
    if count == total - n:
        return lengths - 1
    raise DataError(f"member {columns[0] if columns else 'actions'!r} has {count} rows: neither one per state "
                    f"({total}) nor one fewer per trajectory ({total - n})", file=path,
                    hint="add an 'action_lengths' member: the number of actions of each trajectory")
