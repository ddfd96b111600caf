"""Which state-action pairs a domain's mode bias can forbid at all, given the demonstrations.

Maximum-likelihood inference proposes the most visited undemonstrated pair, but the induction step
can only turn it into a rule when some candidate rule of the bias fires on it *and on no
demonstrated pair* (a demonstrated pair is a hard positive example unless the data is declared
noisy). A pair outside that reach is a constraint the bias cannot express: inferring it wastes an
iteration (the ILP leaves it uncovered), and the next iteration infers its sibling (``wait`` in the
next cell) again. :func:`bias_reach` computes the reach once per fit -- one grounding of every
candidate body over the answer sets of every pair -- so the loop can skip such pairs and report
them instead.
"""

from __future__ import annotations

import numpy as np

from symlearn.grounding import Domain


def bias_reach(domain: Domain, demonstrated: np.ndarray, *, noise: bool = False,
               max_body: int | None = None) -> np.ndarray | None:
    """``(S, A)`` mask of the pairs some candidate integrity constraint of the bias forbids while
    forbidding no demonstrated pair (with ``noise=True`` demonstrated pairs may be forbidden too,
    so any candidate counts). None when the space holds rules with heads (their effect is not a
    per-pair firing, so no pair can be ruled out this way). ``max_body``: the candidates' longest
    body (None: the ILP default), the same the induction searches."""
    from symlearn.logic.ilp.encoding import firing_rows

    space = domain.space(max_body)
    if any(not c.is_constraint for c in space.candidates):
        return None
    pairs = domain.pair_ids
    reach = np.zeros(domain.unavailable.shape, dtype=bool)
    if not pairs:
        return reach
    rows = firing_rows(space.candidates, domain._worlds, range(len(pairs)))
    shown = np.array([bool(demonstrated[s, a]) for s, a in pairs])
    for fired in rows.values():
        index = np.fromiter(fired, dtype=np.int64)
        if not noise and shown[index].any():
            continue
        for i in index:
            s, a = pairs[i]
            reach[s, a] = True
    return reach


__all__ = ["bias_reach"]
