"""A bundled logic domain as a :class:`~symlearn.grounding.Domain`: the model the learners plan in.

:class:`~symlearn.envs.logic_domains.LogicDomain` knows states, actions, the ground truth and
the ASP facts of every pair as Python objects; the learners need a
:class:`~symlearn.grounding.Domain` (nominal tabular MDP, fact grounding by integer ids,
background, bias, truth) -- the same class a user's domain folder loads into. :func:`logic_mdp`
builds that domain (``.domain``) and keeps the index between ids and the model's objects in
both directions, plus the bundled experts, which a user's domain does not have.

* **Hanoi**: the 60 configurations, the 6 moves "top disk of peg i to peg j"; a move from an
  empty peg is no pair of the domain (the ASP side cannot even describe it), so it is
  *unavailable*: it stays put in the MDP and is handed to the learners as a known constraint.
  Episodes start with the pile on the first peg and end when it is on the last one.
* **Traffic junctions**: every cell with every observation (light phase, car on the right),
  plus one absorbing *exit* state per side of the grid: driving past the edge leaves the scene
  there. The observation is redrawn after every step with the model's probabilities, so the
  dynamics are stochastic; drives start at an entry of the roads. Exit states are no pairs.

>>> lm = logic_mdp("junction-lights")
>>> lm.mdp.n_states, lm.mdp.n_actions, int(lm.unavailable.sum())
(54, 5, 20)
>>> int(lm.truth_forbidden.sum()), len(lm.logic.pairs()) - sum(ok for _, ok in lm.logic.pairs())
(196, 196)
>>> lm.domain
Domain('junction-lights': 54 states x 5 actions, 250 pairs, truth)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.data import Demonstrations, Trajectory
from symlearn.envs.logic_domains import LogicDomain, logic_domain
from symlearn.errors import DataError, ModelError
from symlearn.grounding import Domain, FactGrounding
from symlearn.logic.asp.program import Program
from symlearn.mdp import TabularMDP

Pair = tuple[Any, Any]


@dataclass(frozen=True, eq=False)
class LogicMDP:
    """A bundled :class:`~symlearn.grounding.Domain` with the model objects behind its ids.

    ``domain`` is what learners take; ``logic`` the :class:`LogicDomain` (model, files);
    ``states[i]`` / ``actions[j]`` are the model's objects (an ``exit <side>`` marker for the
    exit states of a junction). ``unavailable[s, a]`` marks ids that are no pair of the domain
    (exit states, Hanoi moves from an empty peg); ``truth_forbidden[s, a]`` the pairs the
    ground truth forbids.
    """

    logic: LogicDomain
    domain: Domain
    states: tuple[Any, ...]
    actions: tuple[Any, ...]
    _state_ids: dict[Any, int] = field(repr=False)

    @property
    def name(self) -> str:
        return self.domain.name

    @property
    def mdp(self) -> TabularMDP:
        return self.domain.mdp

    @property
    def unavailable(self) -> np.ndarray:
        return self.domain.unavailable

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
        """Pairs the domain's ground truth forbids (never an unavailable id), from the model."""
        truth = np.zeros(self.unavailable.shape, dtype=bool)
        for (s, a) in np.argwhere(~self.unavailable):
            truth[s, a] = not self.logic.is_allowed(self.states[s], self.actions[a])
        return truth

    def facts(self, s: int, a: int) -> tuple[str, ...]:
        return self.domain.facts(s, a)

    def rule_mask(self, rules: Iterable[str] | str) -> np.ndarray:
        """Every pair a rule set forbids (see :meth:`symlearn.grounding.Domain.rule_mask`)."""
        return self.domain.rule_mask(rules if isinstance(rules, (str, Path)) else list(rules))

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
        model = self.logic.model
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
        model = self.logic.model
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
    """The bundled logic domain (``hanoi``, ``junction-*``) with its nominal tabular MDP."""
    domain = logic_domain(domain) if isinstance(domain, str) else domain
    model = domain.model
    if hasattr(model, "next_cell"):
        return _junction_mdp(domain)
    return _hanoi_mdp(domain)


def _grounded(logic: LogicDomain, mdp: TabularMDP, states: Sequence[Any], actions: Sequence[Any],
              unavailable: np.ndarray) -> LogicMDP:
    """Tabulate the model's facts by ids: every pair's context (Hanoi's move atom depends on
    the state: ``move(D, P)`` names the disk on top), every state's facts, one atom per action."""
    ids = {s: i for i, s in enumerate(states)}
    pair_facts = {(s, a): tuple(logic.facts(states[s], actions[a])) for s, a in np.argwhere(~unavailable).tolist()}
    state_facts = [tuple(logic.state_facts(x)) if not isinstance(x, _Exit) else (f"exit({x.side}).",) for x in states]
    atoms = [_action_atom(logic, states, unavailable, a) for a in range(len(actions))]
    grounding = FactGrounding(state_facts, atoms, pair_facts=pair_facts, source=str(logic.bk_path))
    domain = Domain(logic.name, background=Program.from_text(logic.background(), source=str(logic.bk_path)),
                    bias=logic.bias(), grounding=grounding, mdp=mdp, truth=logic.truth_path.read_text(encoding="utf-8"),
                    available=~unavailable, description=logic.description,
                    sources={"bias": str(logic.bias_path), "truth": str(logic.truth_path)})
    return LogicMDP(logic, domain, tuple(states), tuple(actions), ids)


def _action_atom(logic: LogicDomain, states: Sequence[Any], unavailable: np.ndarray, a: int) -> str:
    """A state-independent name for action ``a``: its atom where that is the same in every state
    (junction moves), else the model's name for the move (Hanoi ``move(0,2)``: peg to peg)."""
    model = logic.model
    found = {logic.action_fact(states[s], model.actions[a]).rstrip(".") for s in np.flatnonzero(~unavailable[:, a])}
    if len(found) == 1:
        return found.pop()
    return getattr(model.actions[a], "atom", f"action({a})")


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
    return _grounded(domain, mdp, states, actions, unavailable)


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
    return _grounded(domain, mdp, states, actions, unavailable)


__all__ = ["LogicMDP", "logic_mdp"]
