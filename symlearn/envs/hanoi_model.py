"""Towers of Hanoi as a finite model: configurations, moves of top disks, the ground-truth rule.

Disks are numbered from the largest (0) to the smallest (``n_disks - 1``); pegs from 0 to
``n_pegs - 1``. A configuration lists, for every peg, its disks from the bottom up. The nominal
(rule-free) game lets any top disk move to any other peg, so a larger disk may end up on a
smaller one; the ground truth forbids exactly the moves whose resulting configuration has a disk
lying on a smaller disk.

The logic side sees a state-action pair as facts: ``at(D, X, Y)`` puts disk ``D`` on peg ``X`` at
height ``Y`` (0 is the bottom slot) and ``move(D, P)`` moves disk ``D`` (a top disk) to peg ``P``.
``background_kb/hanoi/bk.lp`` derives ``on(D1, D2)`` (``D1`` directly on ``D2``) in the
configuration the move leads to.

>>> model = HanoiModel()
>>> start = model.initial_state()
>>> start.slots
((0, 0), (0, 1), (0, 2))
>>> model.moves(start)
[HanoiMove(source=0, target=1), HanoiMove(source=0, target=2)]
>>> model.is_allowed(start, HanoiMove(0, 1))
True
>>> after = model.apply(start, HanoiMove(0, 1))
>>> model.is_allowed(after, HanoiMove(0, 1))   # disk 1 onto the smaller disk 2
False
>>> model.example_facts(after, HanoiMove(0, 2))
['at(0,0,0).', 'at(1,0,1).', 'at(2,1,0).', 'move(1,2).']
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from symlearn.envs.asp_constants import set_constants
from symlearn.errors import ModelError
from symlearn.resources import background_kb_path

Slot = tuple[int, int]


@dataclass(frozen=True, order=True)
class HanoiState:
    """A configuration: ``pegs[p]`` are the disks on peg ``p`` from the bottom up."""

    pegs: tuple[tuple[int, ...], ...]

    @property
    def n_disks(self) -> int:
        return sum(len(peg) for peg in self.pegs)

    @property
    def slots(self) -> tuple[Slot, ...]:
        """``(peg, height)`` of every disk, indexed by disk number."""
        found: dict[int, Slot] = {}
        for x, peg in enumerate(self.pegs):
            for y, disk in enumerate(peg):
                found[disk] = (x, y)
        return tuple(found[d] for d in range(len(found)))

    def top(self, peg: int) -> int | None:
        stack = self.pegs[peg]
        return stack[-1] if stack else None

    def is_ordered(self) -> bool:
        """True when no disk lies on a smaller one (larger disks have smaller numbers)."""
        return all(a < b for peg in self.pegs for a, b in zip(peg, peg[1:]))

    def __str__(self) -> str:
        return " | ".join(" ".join(str(d) for d in peg) or "-" for peg in self.pegs)

    @classmethod
    def from_slots(cls, slots: Sequence[Slot], n_pegs: int = 3) -> HanoiState:
        """The configuration in which disk ``d`` sits at ``slots[d] = (peg, height)``.

        Raises :class:`ModelError` when two disks share a slot, a peg is out of range or a
        disk floats above an empty slot.
        """
        pegs: list[dict[int, int]] = [{} for _ in range(n_pegs)]
        for disk, (x, y) in enumerate(slots):
            if not 0 <= x < n_pegs:
                raise ModelError(f"disk {disk} is on peg {x}, but pegs are 0..{n_pegs - 1}")
            if y in pegs[x]:
                raise ModelError(f"disks {pegs[x][y]} and {disk} share slot ({x}, {y})")
            pegs[x][y] = disk
        for x, peg in enumerate(pegs):
            if sorted(peg) != list(range(len(peg))):
                raise ModelError(
                    f"peg {x} has disks at heights {sorted(peg)}: a disk floats above an empty slot",
                    hint="heights on each peg must be 0, 1, 2, ... from the bottom",
                )
        return cls(tuple(tuple(peg[y] for y in range(len(peg))) for peg in pegs))


@dataclass(frozen=True, order=True)
class HanoiMove:
    """Move the top disk of peg ``source`` onto peg ``target``."""

    source: int
    target: int

    def __str__(self) -> str:
        return f"move top of peg {self.source} to peg {self.target}"

    @property
    def atom(self) -> str:
        """A state-independent ASP name of the move (the ``move(D, P)`` fact depends on the state)."""
        return f"move_peg({self.source},{self.target})"


class HanoiModel:
    """The finite Towers of Hanoi domain (default: 3 disks, 3 pegs).

    ``states()`` enumerates every physical configuration (stacks without gaps, in any order),
    which is the state space of the nominal MDP; ``ordered_states()`` the ones the rules allow.
    The action set is fixed (every ordered pair of distinct pegs); an action is *available*
    when its source peg holds a disk.
    """

    def __init__(self, n_disks: int = 3, n_pegs: int = 3) -> None:
        if n_disks < 1 or n_pegs < 2:
            raise ModelError(f"Hanoi needs at least 1 disk and 2 pegs, got {n_disks} and {n_pegs}")
        self.n_disks = n_disks
        self.n_pegs = n_pegs

    # --- state and action spaces -------------------------------------------------------------
    @cached_property
    def actions(self) -> tuple[HanoiMove, ...]:
        return tuple(HanoiMove(s, t) for s, t in itertools.permutations(range(self.n_pegs), 2))

    @cached_property
    def _states(self) -> tuple[HanoiState, ...]:
        found = []
        for order in itertools.permutations(range(self.n_disks)):
            for assignment in itertools.product(range(self.n_pegs), repeat=self.n_disks):
                pegs = [[] for _ in range(self.n_pegs)]
                for disk, peg in zip(order, assignment):
                    pegs[peg].append(disk)
                found.append(HanoiState(tuple(tuple(p) for p in pegs)))
        return tuple(sorted(set(found)))

    def states(self) -> tuple[HanoiState, ...]:
        """Every configuration, sorted (60 for 3 disks on 3 pegs)."""
        return self._states

    def ordered_states(self) -> tuple[HanoiState, ...]:
        """The configurations with no disk on a smaller one (27 for 3 disks on 3 pegs)."""
        return tuple(s for s in self._states if s.is_ordered())

    @cached_property
    def _index(self) -> dict[HanoiState, int]:
        return {s: i for i, s in enumerate(self._states)}

    def state_index(self, state: HanoiState) -> int:
        try:
            return self._index[state]
        except KeyError:
            raise ModelError(f"{state} is not a configuration of {self.n_disks} disks on {self.n_pegs} pegs") from None

    def initial_state(self, peg: int = 0) -> HanoiState:
        """All disks on ``peg``, largest at the bottom."""
        pegs = [() for _ in range(self.n_pegs)]
        pegs[peg] = tuple(range(self.n_disks))
        return HanoiState(tuple(pegs))

    def goal_state(self) -> HanoiState:
        return self.initial_state(self.n_pegs - 1)

    def is_available(self, state: HanoiState, move: HanoiMove) -> bool:
        return move.source != move.target and bool(state.pegs[move.source])

    def moves(self, state: HanoiState) -> list[HanoiMove]:
        """The available moves (source peg not empty), in the fixed action order."""
        return [m for m in self.actions if self.is_available(state, m)]

    available_actions = moves

    def state_actions(self) -> Iterator[tuple[HanoiState, HanoiMove]]:
        """Every available state-action pair of the nominal game (216 for 3 disks, 3 pegs)."""
        for state in self._states:
            for move in self.moves(state):
                yield state, move

    # --- dynamics and ground truth -----------------------------------------------------------
    def apply(self, state: HanoiState, move: HanoiMove) -> HanoiState:
        """The configuration after ``move`` (which must be available)."""
        if not self.is_available(state, move):
            raise ModelError(f"cannot {move} in {state}: peg {move.source} is empty")
        pegs = [list(p) for p in state.pegs]
        pegs[move.target].append(pegs[move.source].pop())
        return HanoiState(tuple(tuple(p) for p in pegs))

    def moved_disk(self, state: HanoiState, move: HanoiMove) -> int:
        disk = state.top(move.source)
        if disk is None:
            raise ModelError(f"cannot {move} in {state}: peg {move.source} is empty")
        return disk

    def is_allowed(self, state: HanoiState, move: HanoiMove) -> bool:
        """Ground truth: the move is allowed iff it leaves no disk on a smaller disk."""
        return self.apply(state, move).is_ordered()

    def transition_matrix(self) -> np.ndarray:
        """Deterministic nominal transitions ``T[s, a, s']``; unavailable moves stay put."""
        n_s, n_a = len(self._states), len(self.actions)
        table = np.zeros((n_s, n_a, n_s))
        for i, state in enumerate(self._states):
            for a, move in enumerate(self.actions):
                nxt = self.apply(state, move) if self.is_available(state, move) else state
                table[i, a, self._index[nxt]] = 1.0
        return table

    def allowed_mask(self) -> np.ndarray:
        """Boolean ``[S, A]``: available and allowed by the ground truth."""
        mask = np.zeros((len(self._states), len(self.actions)), dtype=bool)
        for i, state in enumerate(self._states):
            for a, move in enumerate(self.actions):
                mask[i, a] = self.is_available(state, move) and self.is_allowed(state, move)
        return mask

    def expert_episode(self, rng: np.random.Generator, start: HanoiState | None = None,
                       max_steps: int = 50) -> list[tuple[HanoiState, HanoiMove]]:
        """A rule-abiding random walk from ``start`` that ends at the goal configuration.

        Each step picks uniformly among the allowed moves that bring the goal strictly closer
        (shortest legal distance), so every demonstrated pair obeys the rules.
        """
        state = self.initial_state() if start is None else start
        distance = self._legal_distance
        if state not in distance:
            raise ModelError(f"{state} breaks the rules; an expert cannot start there")
        steps = []
        while state != self.goal_state() and len(steps) < max_steps:
            options = [m for m in self.moves(state)
                       if self.is_allowed(state, m) and distance[self.apply(state, m)] < distance[state]]
            move = options[int(rng.integers(len(options)))]
            steps.append((state, move))
            state = self.apply(state, move)
        return steps

    @cached_property
    def _legal_distance(self) -> dict[HanoiState, int]:
        goal = self.goal_state()
        distance = {goal: 0}
        frontier = [goal]
        while frontier:  # legal moves are reversible, so BFS from the goal gives distances to it
            nxt = []
            for state in frontier:
                for move in self.moves(state):
                    if self.is_allowed(state, move):
                        other = self.apply(state, move)
                        if other not in distance:
                            distance[other] = distance[state] + 1
                            nxt.append(other)
            frontier = nxt
        return distance

    def background(self) -> str:
        """``background_kb/hanoi/bk.lp`` with its size constants set to this game."""
        return set_constants(background_kb_path("hanoi", "bk.lp").read_text(encoding="utf-8"),
                             {"disks": self.n_disks, "pegs": self.n_pegs})

    # --- rendering as ASP facts --------------------------------------------------------------
    def state_facts(self, state: HanoiState) -> list[str]:
        """``at(D,X,Y).`` for every disk, sorted by disk."""
        return [f"at({d},{x},{y})." for d, (x, y) in enumerate(state.slots)]

    def action_fact(self, state: HanoiState, move: HanoiMove) -> str:
        """``move(D,P).``: the top disk ``D`` of the source peg goes to peg ``P``."""
        return f"move({self.moved_disk(state, move)},{move.target})."

    def example_facts(self, state: HanoiState, move: HanoiMove) -> list[str]:
        return [*self.state_facts(state), self.action_fact(state, move)]
