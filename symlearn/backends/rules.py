"""One way to ask "is this action allowed here?", whatever form the constraints take.

A constraint set is a boolean forbidden mask over (state, action) for environments with
integer observations; a rule set is anything with ``allowed(state, action) -> bool`` (an ASP
hypothesis, through an environment-specific translation of states to facts) or a plain callable.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from symlearn.errors import ModelError, SymlearnError

AllowedFn = Callable[[Any, int], bool]


def allowed_function(constraints: Any, n_actions: int, n_states: int | None = None) -> AllowedFn:
    """Normalise ``constraints`` (forbidden mask, object with ``allowed``, or callable)."""
    if hasattr(constraints, "allowed") and callable(constraints.allowed):
        return constraints.allowed
    if callable(constraints):
        return constraints
    mask = np.asarray(constraints)
    if mask.ndim != 2 or mask.shape[1] != n_actions or (n_states is not None and mask.shape[0] != n_states):
        raise ModelError(f"a constraint mask must have shape (S, A) with A = {n_actions}"
                         + (f", S = {n_states}" if n_states is not None else "") + f", got {mask.shape}")
    forbidden = mask.astype(bool)

    def allowed(state: Any, action: int) -> bool:
        if not isinstance(state, (int, np.integer)) or not 0 <= int(state) < forbidden.shape[0]:
            raise SymlearnError(f"state {state!r} is outside the constraint mask (0..{forbidden.shape[0] - 1})",
                                hint="a mask over (S, A) needs integer observations")
        return not forbidden[int(state), int(action)]

    return allowed


def action_mask(allowed: AllowedFn, state: Any, n_actions: int) -> np.ndarray:
    """0/1 vector (int8, the common convention) of the actions allowed in ``state``."""
    return np.fromiter((bool(allowed(state, a)) for a in range(n_actions)), dtype=np.int8, count=n_actions)
