"""``symlearn ltl eval --demos D --labeling L.json``: demonstrations labelled by a labeling file.

``learn spec --domain DIR --demos D -o SPEC.ltl`` writes ``SPEC.labeling.json`` beside the formula,
and the demonstrations it read hold state ids, not propositions. Re-checking an edited SPEC.ltl
against them needs each state's propositions, which is what this labeling gives. A table
labeling that knows none of the demonstrations' states (state names where the table has ids, a
labeling of another domain) would label every step with nothing, and every formula would be
judged on empty steps: that is refused, not evaluated.
"""

from __future__ import annotations

from typing import Any


def labelled_words(demos: Any, path: str, labeling_path: str) -> list[list[frozenset[str]]]:
    """One label word per demonstration: each state's propositions under the labeling file."""
    from symlearn.errors import DataError
    from symlearn.grounding.labeling import Labeling, load_labeling

    labeling = load_labeling(labeling_path)
    if demos.state_kind == "image":
        raise DataError("image states cannot be labelled by a labeling file", file=path,
                        hint="record the demonstrations with a labeler (symlearn.data.record(..., labeler=label))")
    if isinstance(labeling, Labeling) and demos.state_kind == "features":
        # a table is keyed by states as values (ids, names, tuples); a dict of features is none of them
        raise DataError("a table labeling labels states by id or name; these demonstrations' states are named "
                        "features", file=labeling_path,
                        hint='write a feature labeling ("kind": "features", a condition such as "x > 0.7" per '
                             "proposition; docs/FORMATS.md, Labelings)")
    if not isinstance(labeling, Labeling) and demos.state_kind in ("discrete", "symbol"):
        raise DataError(f"a feature labeling reads named features; these demonstrations' states are "
                        f"{demos.state_kind} ids", file=labeling_path,
                        hint="give a table labeling of the states (learn spec --domain writes one as "
                             "SPEC.labeling.json)")
    words = [[labeling.label(_state(state, demos.state_kind)) for state in t.states] for t in demos]
    if isinstance(labeling, Labeling) and words:
        known = {state for state, _ in labeling.items()}
        states = [_state(state, demos.state_kind) for t in demos for state in t.states]
        if not any(state in known for state in states):
            shown = ", ".join(map(repr, states[:3]))
            table = ", ".join(repr(s) for s, _ in labeling.items()[:3])
            raise DataError(f"none of the demonstrations' states ({shown}, ...) is in the labeling's table "
                            f"({table}, ...), so every step would have no proposition", file=labeling_path,
                            hint="give the labeling of the world the demonstrations come from (learn spec writes "
                                 "it as SPEC.labeling.json); a table keyed by state ids needs demonstrations "
                                 "that give states as ids")
    return words


def _state(state: Any, kind: str) -> Any:
    """A state as a labeling looks it up: numpy scalars as Python numbers, vectors as tuples."""
    if kind == "discrete":
        return int(state)
    if kind == "vector":
        return tuple(float(v) for v in state)
    return state


__all__ = ["labelled_words"]
