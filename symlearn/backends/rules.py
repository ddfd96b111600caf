"""One way to ask "is this action allowed here?", whatever form the constraints take.

A constraint set is a boolean forbidden mask over (state, action) for environments with
integer observations; a rule set is anything with ``allowed(state, action) -> bool`` (an ASP
hypothesis, through an environment-specific translation of states to facts) or a plain callable.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
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


def rules_allowed(hypothesis: Any, action_atoms: Sequence[str]) -> AllowedFn:
    """``allowed(state_facts, action_index)`` of an ASP hypothesis (anything with
    ``allowed(state_facts, action_atom)``, e.g. :class:`~symlearn.logic.asp.Hypothesis`).

    ``action_atoms[i]`` is the ASP atom of action ``i`` (``go(north)``). Each distinct
    (state facts, action) is decided by clingo once and remembered, so a shield built on the
    rules themselves costs one solver call per new pair, not per step. Use it with
    ``Shield(env, rules_allowed(h, atoms), state_of=observation -> facts)``.
    """
    atoms = tuple(action_atoms)
    cache: dict[tuple[str, int], bool] = {}

    def allowed(state_facts: Any, action: int) -> bool:
        facts = state_facts if isinstance(state_facts, str) else " ".join(state_facts)
        key = (facts, int(action))
        if key not in cache:
            if not 0 <= int(action) < len(atoms):
                raise SymlearnError(f"action {action} has no ASP atom (known: {len(atoms)} actions)")
            cache[key] = bool(hypothesis.allowed(facts, atoms[int(action)]))
        return cache[key]

    return allowed


def action_mask(allowed: AllowedFn, state: Any, n_actions: int) -> np.ndarray:
    """0/1 vector (int8, the common convention) of the actions allowed in ``state``."""
    return np.fromiter((bool(allowed(state, a)) for a in range(n_actions)), dtype=np.int8, count=n_actions)
