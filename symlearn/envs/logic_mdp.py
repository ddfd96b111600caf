"""A logic domain as a tabular MDP: the model the constraint-inference loop plans in.

:class:`~symlearn.envs.logic_domains.LogicDomain` knows states, actions, the ground truth and
the ASP facts of every pair; the exact algorithms need transition tensors. :func:`logic_mdp`
builds the *nominal* MDP (no rule removes any action) and keeps the index in both directions,
so that a forbidden ``(S, A)`` mask, a list of domain pairs and a set of ASP examples can be
turned into one another.

* **Hanoi**: the 60 configurations, the 6 moves "top disk of peg i to peg j"; a move from an
  empty peg is no pair of the domain (the ASP side cannot even describe it), so it is
  *unavailable*: it stays put in the MDP and is handed to the learners as a known constraint.
  Episodes start with the pile on the first peg and end when it is on the last one.
* **Traffic junctions**: every cell with every observation (light phase, car on the right),
  plus one absorbing *exit* state per side of the grid: driving past the edge leaves the scene
  there. The observation is redrawn after every step with the model's probabilities, so the
  dynamics are stochastic; drives start at an entry of the roads. Exit states are no pairs.

>>> lm = logic_mdp("traffic-lights")
>>> lm.mdp.n_states, lm.mdp.n_actions, int(lm.unavailable.sum())
(54, 5, 20)
>>> int(lm.truth_forbidden.sum()), len(lm.domain.pairs()) - sum(ok for _, ok in lm.domain.pairs())
(196, 196)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.logic_domains import LogicDomain, logic_domain
from symlearn.errors import DataError, ModelError
from symlearn.mdp import TabularMDP

Pair = tuple[Any, Any]


@dataclass(frozen=True, eq=False)
class LogicMDP:
    """A :class:`TabularMDP` whose state-action ids map to the pairs of a :class:`LogicDomain`.

    ``states[i]`` / ``actions[j]`` are the model's objects (an ``exit <side>`` marker for the
    exit states of a junction).
    ``unavailable[s, a]`` marks ids that are no pair of the domain (exit states, Hanoi moves
    from an empty peg); ``truth_forbidden[s, a]`` the pairs the ground truth forbids.
    """

    domain: LogicDomain
    mdp: TabularMDP
    states: tuple[Any, ...]
    actions: tuple[Any, ...]
    unavailable: np.ndarray
    _state_ids: dict[Any, int] = field(repr=False)

    @property
    def name(self) -> str:
        return self.domain.name

    def pair(self, s: int, a: int) -> Pair | None:
        """The domain pair of ids ``(s, a)``, or ``None`` where it is no pair."""
        return None if self.unavailable[s, a] else (self.states[s], self.actions[a])

    def ids(self, state: Any, action: Any) -> tuple[int, int]:
        try:
            return self._state_ids[state], self.actions.index(action)
        except (KeyError, ValueError):
            raise ModelError(f"({state}, {action}) is no state-action pair of {self.name}") from None

    def mask(self, pairs: Iterable[Pair]) -> np.ndarray:
        """Boolean ``(S, A)`` marking ``pairs``."""
        mask = np.zeros(self.unavailable.shape, dtype=bool)
        for state, action in pairs:
            mask[self.ids(state, action)] = True
        return mask

    def pairs_of(self, mask: np.ndarray) -> list[Pair]:
        """The domain pairs marked in ``mask`` (unavailable ids are skipped), in id order."""
        return [self.pair(int(s), int(a)) for s, a in np.argwhere(mask & ~self.unavailable)]

    @cached_property
    def truth_forbidden(self) -> np.ndarray:
        """Pairs the domain's ground truth forbids (never an unavailable id)."""
        truth = np.zeros(self.unavailable.shape, dtype=bool)
        for (s, a) in np.argwhere(~self.unavailable):
            truth[s, a] = not self.domain.is_allowed(self.states[s], self.actions[a])
        return truth

    def facts(self, s: int, a: int) -> tuple[str, ...]:
        pair = self.pair(s, a)
        if pair is None:
            raise ModelError(f"ids ({s}, {a}) are no state-action pair of {self.name}")
        return self.domain.facts(*pair)

    def rule_mask(self, rules: Iterable[str] | str) -> np.ndarray:
        """Every pair a rule set forbids (answer sets of B that are no answer sets of B u H)."""
        return self.mask(self.domain.forbidden_pairs(rules))

    # --- demonstrations ----------------------------------------------------------------------
    def expert_demonstrations(self, n: int, seed: int = 0, source: str = "native") -> Demonstrations:
        """``n`` complete drives (or games) of a rule-abiding expert, as integer ids.

        ``source="native"`` uses the domain model's own expert; ``"sumo"`` (traffic junctions
        ``lights`` and ``priority``, needs the ``sumo`` extra) lets SUMO drive the cars, see
        :mod:`symlearn.envs.sumo_junction`. Each trajectory ends with the state the last action
        leads to (an exit state for a drive), which is where the sparse inferred reward of
        constraint inference puts its goal; a drive cut off before it left the grid is skipped.
        """
        if n < 1:
            raise DataError(f"the number of demonstrations must be at least 1, got {n}")
        if source not in ("native", "sumo"):
            raise DataError(f"unknown demonstration source {source!r}", hint="use 'native' or 'sumo'")
        model = self.domain.model
        if source == "sumo":
            if not hasattr(model, "next_cell") or model.variant not in ("lights", "priority"):
                raise DataError(f"SUMO drives only the lights and priority junctions, not {self.name}")
            from symlearn.envs.sumo_junction import sumo_expert_episodes

            episodes = iter(sumo_expert_episodes(model, n, seed))
            draw = lambda: next(episodes, None)  # noqa: E731 -- SUMO replaces dropped cars itself
        else:
            rng = np.random.default_rng(seed)
            draw = lambda: model.expert_episode(rng, max_steps=500)  # noqa: E731
        trajectories = []
        while len(trajectories) < n:
            steps = draw()
            if steps is None:
                break
            final = self._final_state(*steps[-1]) if steps else None
            if final is None:
                continue  # a cut-off drive has no goal; draw another
            states = [self._state_ids[s] for s, _ in steps] + [final]
            actions = [self.actions.index(a) for _, a in steps]
            trajectories.append(Trajectory(states=states, actions=actions))
        if not trajectories:
            raise DataError(f"the {source} expert produced no complete episode in {self.name}")
        return Demonstrations(trajectories)

    def _final_state(self, state: Any, action: Any) -> int | None:
        model = self.domain.model
        if hasattr(model, "next_cell"):
            if model.next_cell(state.cell, action) is not None:
                return None
            return self._state_ids[_Exit(action)]
        nxt = model.apply(state, action)
        return self._state_ids[nxt] if nxt == model.goal_state() else None


@dataclass(frozen=True)
class _Exit:
    side: str

    def __str__(self) -> str:
        return f"exit {self.side}"


def logic_mdp(domain: LogicDomain | str) -> LogicMDP:
    """The nominal tabular MDP of a bundled logic domain (``hanoi``, ``traffic-*``)."""
    domain = logic_domain(domain) if isinstance(domain, str) else domain
    model = domain.model
    if hasattr(model, "next_cell"):
        return _junction_mdp(domain)
    return _hanoi_mdp(domain)


def _hanoi_mdp(domain: LogicDomain) -> LogicMDP:
    model = domain.model
    states, actions = tuple(model.states()), tuple(model.actions)
    P = model.transition_matrix()
    unavailable = np.array([[not model.is_available(s, m) for m in actions] for s in states])
    initial = np.zeros(len(states))
    initial[model.state_index(model.initial_state())] = 1.0
    goal = model.state_index(model.goal_state())
    mdp = TabularMDP(P, np.zeros(unavailable.shape), initial, np.zeros(len(states), dtype=bool),
                     tuple(map(str, states)), tuple(map(str, actions))).make_absorbing([goal])
    unavailable[goal] = True  # the game is over: nothing is demonstrated or inferred there
    return LogicMDP(domain, mdp, states, actions, unavailable, {s: i for i, s in enumerate(states)})


def _junction_mdp(domain: LogicDomain) -> LogicMDP:
    model = domain.model
    cells_states = tuple(model.states())
    exits = tuple(_Exit(side) for side in ("north", "east", "south", "west"))
    states: Sequence[Any] = cells_states + exits
    ids = {s: i for i, s in enumerate(states)}
    actions = tuple(model.actions)
    n_s, n_a = len(states), len(actions)
    observations = model.observation_distribution()
    by_cell: dict[tuple[int, int], list[tuple[int, float]]] = {}
    for state in cells_states:
        for light, car, p in observations:
            if state.light == light and state.car_on_right == car:
                by_cell.setdefault(state.cell, []).append((ids[state], p))
    P = np.zeros((n_s, n_a, n_s))
    for state in cells_states:
        i = ids[state]
        for a, action in enumerate(actions):
            nxt = model.next_cell(state.cell, action)
            if nxt is None:
                P[i, a, ids[_Exit(action)]] = 1.0
            else:
                for j, p in by_cell[nxt]:
                    P[i, a, j] += p
    terminal = np.zeros(n_s, dtype=bool)
    terminal[[ids[e] for e in exits]] = True
    for e in exits:
        P[ids[e], :, ids[e]] = 1.0
    initial = np.zeros(n_s)
    entries = model.entries()
    for cell in entries:
        for j, p in by_cell[cell]:
            initial[j] += p / len(entries)
    unavailable = np.zeros((n_s, n_a), dtype=bool)
    unavailable[terminal] = True
    mdp = TabularMDP(P, np.zeros((n_s, n_a)), initial, terminal,
                     tuple(map(str, states)), actions)
    return LogicMDP(domain, mdp, tuple(states), actions, unavailable, ids)


__all__ = ["LogicMDP", "logic_mdp"]
