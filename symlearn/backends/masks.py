"""Constraint sets as action masks an environment's shield can use.

A learner reports its constraint set as a boolean forbidden mask over the state-action ids of a
nominal :class:`~symlearn.mdp.TabularMDP` (a domain's model). Two steps turn it into the mask a
:class:`~symlearn.backends.shield.Shield` takes:

* :func:`closed_mask` -- drop the ids that are no real state-action pair (``unavailable``) and,
  with ``close=True``, close the set with :func:`~symlearn.rl.tabular.restrict`: a state where
  every action is forbidden is *empty*, so the pairs that can enter it are forbidden too (the
  restriction step of the logic-constrained Q-learning algorithm).
* :func:`env_mask` -- that, cut down to the ids an environment observes. A domain model may hold
  states no observation shows (for instance the absorbing exit states of a junction); they come
  after the observed ones, so the environment's ids are the first ``n``. Given the observation
  names instead of their number, the order is checked against ``mdp.state_names``.

>>> import numpy as np
>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((3, 2, 3)); P[:, 0, 0] = 1; P[:, 1, 2] = 1; P[0, 1] = [0, 1, 0]
>>> mdp = TabularMDP(P, np.zeros((3, 2)), [1, 0, 0], [False] * 3, ("a", "b", "exit"))
>>> forbidden = np.zeros((3, 2), bool); forbidden[1] = True   # state b has no allowed action
>>> env_mask(mdp, forbidden, 2, close=False)[0].tolist(), env_mask(mdp, forbidden, ["a", "b"])[0].tolist()
([False, False], [False, True])
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from symlearn.errors import ModelError
from symlearn.mdp import TabularMDP
from symlearn.rl.tabular import check_mask, restrict

__all__ = ["closed_mask", "env_mask", "observed_ids"]


def closed_mask(mdp: TabularMDP, forbidden: np.ndarray, unavailable: np.ndarray | None = None, *,
                close: bool = True) -> np.ndarray:
    """The forbidden ``(S, A)`` mask over ``mdp``'s ids, without ``unavailable`` ids, closed
    under the model when ``close`` (pairs entering a state with no allowed action are forbidden).

    Unavailable ids are never reported as forbidden: they are no behaviour a rule can forbid.
    While closing they count as forbidden, because no agent may use them either: a state whose
    available actions are all forbidden is empty, whatever ids it has besides.
    """
    mask = check_mask(mdp, forbidden, "forbidden mask")
    absent = np.zeros_like(mask) if unavailable is None else check_mask(mdp, unavailable, "unavailable mask")
    if close:
        mask = restrict(mdp, mask | absent).forbidden
    return mask & ~absent


def observed_ids(mdp: TabularMDP, observations: int | Sequence[str]) -> int:
    """How many leading state ids of ``mdp`` an environment observes.

    ``observations`` is that number, or the names of the environment's observations in id order;
    names must equal the first ``mdp.state_names`` (otherwise the ids would mean other states).
    """
    if isinstance(observations, (int, np.integer)) and not isinstance(observations, bool):
        n = int(observations)
    else:
        names = tuple(str(name) for name in observations)
        n = len(names)
        if names != tuple(mdp.state_names[:n]):
            first = next((i for i, (a, b) in enumerate(zip(names, mdp.state_names)) if a != b), min(n, mdp.n_states))
            raise ModelError(
                f"the environment's observation ids do not start the model's state ids "
                f"(first difference at id {first})",
                hint="an environment mask needs the model to number the observed states first, in the same order")
    if not 0 < n <= mdp.n_states:
        raise ModelError(f"an environment with {n} observation ids cannot use a mask over {mdp.n_states} states")
    return n


def env_mask(mdp: TabularMDP, forbidden: np.ndarray, observations: int | Sequence[str], *,
             unavailable: np.ndarray | None = None, close: bool = True) -> np.ndarray:
    """:func:`closed_mask` cut to the environment's observation ids (see :func:`observed_ids`).

    The closure runs on the whole model first, so a pair that leads into an unobserved empty
    state is still forbidden.
    """
    n = observed_ids(mdp, observations)
    return closed_mask(mdp, forbidden, unavailable, close=close)[:n].copy()
