"""A learned constraint set as a file: the forbidden state-action pairs by name, as JSON.

``{"format": "symlearn-constraints", "version": 1, "method": ..., "domain": ...,
"forbidden": [[state, action], ...], "multipliers": {state: value}}`` (``multipliers`` only for
MCE-ICRL with one multiplier per state), ``domain`` only when the learner's world names itself: a
:class:`~symlearn.grounding.Domain`, or a :class:`~symlearn.mdp.TabularMDP` with a ``name``
(:func:`world_name`). Names are the model's state and action
names, so the file reads without the ids. The learners' ``save`` and ``learn constraints -o``
write this text, so both give the same file.

>>> import numpy as np
>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((2, 2, 2)); P[:, :, 1] = 1
>>> mdp = TabularMDP(P, np.zeros((2, 2)), [1, 0], [False, True], ("a", "b"), ("left", "right"))
>>> print(constraint_set_text(np.array([[True, False], [False, False]]), mdp, method="ml"), end="")
{
 "format": "symlearn-constraints",
 "version": 1,
 "method": "ml",
 "forbidden": [
  [
   "a",
   "left"
  ]
 ]
}
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np


def constraint_set_document(forbidden: np.ndarray, mdp: Any, *, method: str, domain: str | None = None,
                            multipliers: dict[str, float] | None = None) -> dict[str, Any]:
    names_s = mdp.state_names or tuple(str(s) for s in range(mdp.n_states))
    names_a = mdp.action_names or tuple(str(a) for a in range(mdp.n_actions))
    doc: dict[str, Any] = {"format": "symlearn-constraints", "version": 1, "method": method}
    if domain is not None:
        doc["domain"] = domain
    doc["forbidden"] = [[names_s[s], names_a[a]] for s, a in zip(*np.asarray(forbidden).nonzero())]
    if multipliers is not None:
        doc["multipliers"] = multipliers
    return doc


def constraint_set_text(forbidden: np.ndarray, mdp: Any, **kwargs: Any) -> str:
    """The document as the file holds it (one-space indents: a person reads and edits it)."""
    return json.dumps(constraint_set_document(forbidden, mdp, **kwargs), indent=1) + "\n"


def world_name(world: Any) -> str | None:
    """The name a constraint set gives its world: a Domain's (or a bundled wrapper's ``.domain``),
    a TabularMDP's ``name`` (the bundled gridworld's model is ``"gridworld"``), else None (an
    unnamed model or an environment does not name itself)."""
    from symlearn.grounding import Domain
    from symlearn.mdp import TabularMDP

    for candidate in (world, getattr(world, "domain", None)):
        if isinstance(candidate, Domain):
            return candidate.name
    return world.name if isinstance(world, TabularMDP) else None


__all__ = ["constraint_set_document", "constraint_set_text", "world_name"]
