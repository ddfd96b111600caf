"""What specification learning needs to know about a world, and how it is read from one.

:class:`TaskModel` is the declared interface: a successor table (or dynamics to sample), a
labeling of states, a start state, an episode horizon and a way to say what a state is. It is read from

* a :class:`~symlearn.grounding.Domain`: a successor table where its transitions are
  deterministic (each ``P[s, a]`` puts all mass on one successor) and its start is one state,
  else its transition probabilities and start distribution as ``dynamics``, which episodes
  sample; its ``labeling`` gives the propositions (only needed with given propositions);
* a *labelled tabular environment*: anything with ``observation_space.n``, ``action_space.n``,
  ``next_state(s, a) -> s'``, ``labeling`` and ``reset(seed=) -> (s, info)`` (the office and craft
  worlds; ``max_steps`` and ``cell_of`` are used when present).

>>> import numpy as np
>>> from symlearn.grounding import Domain, FactGrounding, Labeling
>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((2, 1, 2)); P[0, 0, 1] = P[1, 0, 1] = 1
>>> mdp = TabularMDP(P, np.zeros((2, 1)), [1, 0], [False, False])
>>> d = Domain("line", background="", bias="", grounding=FactGrounding(["", ""], ["go"]), mdp=mdp,
...            labeling=Labeling({1: {"end"}}))
>>> m = task_model(d, horizon=5)
>>> m.successors.tolist(), m.start, sorted(m.labeling.label(1))
([[1], [1]], 0, ['end'])
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from symlearn.errors import ModelError


@dataclass(frozen=True)
class TaskModel:
    successors: np.ndarray  # (S, A) int: the next state of each move (with dynamics: the most likely)
    labeling: Any  # the world's own labeling (None if it has none)
    start: int  # (with dynamics: the most likely start state)
    horizon: int
    describe: Callable[[int], str]  # "agent in cell (3, 4)" -- meaning of a learned proposition
    state_names: tuple[str, ...] = ()  # a domain's state names, which demonstrations may use for ids
    # a domain whose moves are stochastic or that starts in several states: sampled from these
    # (symlearn.rl.crm_q_learning.Dynamics); None: the successor table and the one start are exact
    dynamics: Any = None

    @property
    def n_states(self) -> int:
        return int(self.successors.shape[0])

    def step(self, s: np.ndarray, a: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return self.successors[s, a] if self.dynamics is None else self.dynamics.step(s, a, rng)

    def starts(self, n: int, rng: np.random.Generator) -> np.ndarray:
        return np.full(n, self.start) if self.dynamics is None else self.dynamics.starts(n, rng)


def task_model(world: Any, *, horizon: int | None = None) -> TaskModel:
    """A :class:`TaskModel` of a Domain or a labelled tabular environment (see module)."""
    from symlearn.grounding import Domain

    inner = getattr(world, "domain", None)
    if isinstance(world, Domain) or isinstance(inner, Domain):
        return _from_domain(world if isinstance(world, Domain) else inner, horizon)
    missing = [a for a in ("next_state", "labeling", "observation_space", "action_space", "reset")
               if not hasattr(world, a)]
    if missing:
        raise ModelError(f"{type(world).__name__} is neither a Domain nor a labelled tabular environment "
                         f"(it has no {missing[0]})",
                         hint="pass a symlearn.grounding.Domain with a labeling, or an office/craft world")
    n_s, n_a = int(world.observation_space.n), int(world.action_space.n)
    succ = np.array([[world.next_state(s, a) for a in range(n_a)] for s in range(n_s)], dtype=np.int64)
    start = int(world.reset(seed=0)[0])
    cell = getattr(world, "cell_of", None)
    describe = (lambda s: f"agent in cell {cell(s)}") if cell else (lambda s: f"agent in state {s}")
    return TaskModel(succ, world.labeling, start, int(horizon or getattr(world, "max_steps", 200)), describe)


def _from_domain(domain: Any, horizon: int | None) -> TaskModel:
    P = np.asarray(domain.mdp.transitions)
    initial = np.asarray(domain.mdp.initial)
    dynamics = None
    if not np.all(np.isclose(P.max(axis=2), 1.0)) or np.count_nonzero(initial) != 1:
        # stochastic moves or several start states: episodes sample them (the thesis' worlds are
        # deterministic grids; a domain folder's model.npz need not be)
        from symlearn.rl.crm_q_learning import Dynamics

        dynamics = Dynamics.of(P, initial)
    names = domain.state_names
    return TaskModel(P.argmax(axis=2).astype(np.int64), domain.labeling, int(initial.argmax()),
                     int(horizon or 200), lambda s: f"agent in state {names[s]}", tuple(names or ()), dynamics)


__all__ = ["TaskModel", "task_model"]
