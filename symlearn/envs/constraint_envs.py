"""The environments constraint learners run on, behind one interface (CLI, demo, benchmarks).

A :class:`ConstraintSetting` gives what every tabular constraint learner needs: the nominal
MDP, the pairs that exist at all (``space``), the ground-truth forbidden mask to score against,
what is known in advance (unavailable moves), the reward to plan with, and a bundled expert.

* ``hanoi``, ``junction-lights``, ``junction-priority``, ``junction-combined``: the logic
  domains (:mod:`symlearn.envs.logic_mdp`), with ASP facts for every pair, so the ``logic``
  method can induce rules; reward inferred as sparse (reaching where demonstrations ended).
* ``gridworld``: the stochastic gridworld (:mod:`symlearn.envs.gridworld`) with its own reward;
  no ASP facts, so only the ``ml`` and ``mce-icrl`` methods.

>>> setting = constraint_setting("junction-priority")
>>> setting.mdp.n_states, int(setting.truth.sum()), setting.logic is not None
(54, 223, True)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.envs.registry import Kind, entries, get
from symlearn.mdp import TabularMDP

#: name -> (logic domain name or None, one-line description): a view of the registry's
#: constraint-learning entries (:mod:`symlearn.envs.registry`), kept for existing callers.
CONSTRAINT_ENVS: dict[str, tuple[str | None, str]] = {
    e.name: (e.name if Kind.RULES in e.kinds else None, e.description) for e in entries(Kind.CONSTRAINTS)
}


@dataclass(frozen=True, eq=False)
class ConstraintSetting:
    name: str
    mdp: TabularMDP
    space: np.ndarray  # (S, A) pairs that exist (False: unavailable moves, exit states)
    truth: np.ndarray  # (S, A) forbidden by the ground truth
    reward: str  # "sparse" or "given"
    expert: Callable[[int, int], Any]  # (n, seed) -> Demonstrations
    logic: Any = None  # the LogicMDP where ASP rules can be learned
    rationality: float = 1.0
    grid: Any = None  # a grid environment whose cells a learned cost map is drawn on (the gridworld)

    @property
    def known(self) -> np.ndarray:
        """Pairs forbidden in advance: those that are no move at all (never in terminal states)."""
        return ~self.space & ~self.mdp.terminal[:, None]


def constraint_setting(name: str, stochasticity: float = 0.0) -> ConstraintSetting:
    """The setting called ``name`` (a registry entry of kind ``constraints``; see ``symlearn envs``).

    An unknown name raises :class:`~symlearn.errors.UnknownNameError` listing the known ones."""
    entry = get(name, Kind.CONSTRAINTS, what="environment")
    if Kind.RULES not in entry.kinds:  # no ASP facts: the gridworld
        return _gridworld(stochasticity)
    from symlearn.envs.logic_mdp import logic_mdp

    lm = logic_mdp(entry.name)
    return ConstraintSetting(entry.name, lm.mdp, ~lm.unavailable, lm.truth_forbidden, "sparse",
                             lm.expert_demonstrations, lm)


def _gridworld(stochasticity: float) -> ConstraintSetting:
    from symlearn.data import record
    from symlearn.envs.gridworld import StochasticGridworld

    env = StochasticGridworld(stochasticity)
    mdp = env.to_tabular()
    space = np.ones((mdp.n_states, mdp.n_actions), dtype=bool)
    space[mdp.terminal] = False

    def expert(n: int, seed: int):
        policy = env.expert_policy()
        return record(env, lambda s: int(policy[s]), n, seed=seed, desc="gridworld expert")

    return ConstraintSetting("gridworld", mdp, space, env.constraint_mask() & space, "given", expert,
                             rationality=3.0, grid=env)


__all__ = ["CONSTRAINT_ENVS", "ConstraintSetting", "constraint_setting"]
