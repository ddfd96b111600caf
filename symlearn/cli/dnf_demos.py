"""``symlearn dnf eval RULES --demos D.jsonl|D.npz``: the demonstrated states as the points.

A user who edits a learned ``.dnf`` by hand re-checks it against the data it came from: how many
of the expert's states the edited rules now call unsafe, and where the first one is (demonstration
and step, which a flat point index does not say). The states are read the way ``learn dnf``
reads them (:func:`~symlearn.learners.trees.one_class_tree.feature_matrix`): feature-dict states
by their own keys, vector states as ``x0, x1, ...`` or the names ``--features`` gives, so the
names of a file ``learn dnf`` wrote match without a flag.
"""

from __future__ import annotations

import numpy as np


def demonstration_points(path: str, features: str | None) -> tuple[dict[str, np.ndarray], int, list[tuple[int, int]]]:
    """``(columns, n, where)``: ``name -> 1-D array`` of every demonstrated state, their number,
    and ``(demonstration, step)`` of each row. Unnamed vector states without ``--features`` are
    ``x0, x1, ...``; :func:`unnamed_columns_hint` says how to name them when the rules disagree."""
    from symlearn.cli.output import blame_file
    from symlearn.data import load
    from symlearn.errors import DataError
    from symlearn.learners.trees.one_class_tree import feature_matrix

    demos = load(path)
    if demos.state_kind in ("discrete", "symbol"):
        raise DataError(f"the demonstrations' states are {demos.state_kind} ids, not numeric features: a DNF "
                        "tests feature values", file=path,
                        hint="learn dnf --domain DIR turns a domain's state ids into its features; evaluate the "
                             "rules on those (save them as np.savez('points.npz', points=..., features=names))")
    names = None if features is None else [n.strip() for n in features.split(",")]
    with blame_file(path):
        X, columns = feature_matrix(demos, names)
    where = [(i, step) for i, t in enumerate(demos) for step in range(len(t.states))]
    return {name: X[:, j] for j, name in enumerate(columns)}, X.shape[0], where


def unnamed_columns_hint(path: str, features: str | None, columns) -> str | None:
    """The way out when a formula names features (``x``, ``y``: learned with ``--env`` or
    ``--features``) and the demonstrations are unnamed vectors read as ``x0, x1, ...``: a close
    name such as ``x1 for x`` would be a wrong guess there."""
    from symlearn.data import load

    if features is not None or list(columns) != [f"x{i}" for i in range(len(columns))]:
        return None
    if load(path).state_kind not in ("vector", "image"):
        return None
    return (f"the demonstrations' states are unnamed vectors, read as {', '.join(list(columns)[:4])}"
            f"{', ...' if len(columns) > 4 else ''}: name their columns in order with --features a,b,... (the "
            "names learn dnf --env or --features gave them)")


def first_unsafe_line(doc: dict) -> str | None:
    """``first: demonstration 3, step 17 (conjunction #2)`` for the first unsafe demonstrated state."""
    first = doc.get("first_unsafe")
    if not first:
        return None
    return (f"first: demonstration {first['demonstration']}, step {first['step']} "
            f"(conjunction #{first['conjunction'] + 1})")


__all__ = ["demonstration_points", "first_unsafe_line", "unnamed_columns_hint"]
