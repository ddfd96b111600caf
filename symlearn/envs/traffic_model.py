"""A car at a road junction on a grid: states, moves, the traffic rules as ground truth.

The grid has columns ``x = 1..size`` (west to east) and rows ``y = 1..size`` (south to north).
Two straight roads cross at the junction cell; the four *arms* are named after the side of the
junction they lie on (the arm ``north`` is the cells straight north of the junction) and the
junction cell itself is named ``zero``. The car moves one cell per step with the actions
``zero`` (stand still), ``north``, ``east``, ``south`` and ``west``; moving past the edge of the
grid at the end of a road means leaving the scene.

Three variants, as in the logic-constraint-inference experiments of the reference thesis:

* ``"lights"``: two-way roads and a traffic light with two phases. In phase ``tls0`` the
  north/south approaches are red, in phase ``tls1`` the east/west approaches are red.
* ``"priority"``: one-way roads and priority to the right. Traffic comes in on the ``west``,
  ``north`` and ``south`` arms and leaves on the ``east`` arm; ``car_on_right`` says a car
  with priority approaches from the right, and then the agent must stand still.
* ``"combined"``: the transfer target, by default on a larger 7 x 7 grid: the one-way roads and
  priority to the right of ``"priority"`` together with the traffic light of ``"lights"``, so
  every rule of both other variants holds and neither alone knows them all.

Ground-truth rules (``violations`` names the ones a state-action breaks):

* ``off_road``: the car is not on a road (every action is invalid there);
* ``leaves_road``: the move ends on a grid cell that is not road;
* ``red_light``: the car stands right before the junction and drives into it against red;
* ``wrong_way``: (one-way) the move goes against the direction of its road;
* ``priority``: a car on the right has priority and the car does not stand still.

On the logic side a state-action pair is the facts ``at(X,Y).``, ``tls0.`` or ``tls1.`` (lights),
``carOnTheRight.`` when it holds (priority) and ``go(A).``; ``background_kb/traffic/bk.lp``
derives ``onRoad(Arm)`` and ``beforeJunction(Arm)`` from ``at/2``.

>>> model = TrafficJunction("lights")
>>> model.road_of((3, 5)), model.before_junction((3, 4)), model.road_of((1, 1))
('north', 'north', None)
>>> state = JunctionState(3, 2, light=0)
>>> model.violations(state, "north")      # south approach, north/south red in phase tls0
['red_light']
>>> model.is_allowed(JunctionState(3, 2, light=1), "north")
True
>>> model.example_facts(state, "north")
['at(3,2).', 'tls0.', 'go(north).']
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from symlearn.envs.asp_constants import set_constants
from symlearn.errors import ModelError
from symlearn.resources import background_kb_path

Cell = tuple[int, int]

ACTIONS: tuple[str, ...] = ("zero", "north", "east", "south", "west")
ARMS: tuple[str, ...] = ("north", "east", "south", "west")
STEP: dict[str, Cell] = {"zero": (0, 0), "north": (0, 1), "east": (1, 0), "south": (0, -1), "west": (-1, 0)}
OPPOSITE: dict[str, str] = {"north": "south", "south": "north", "east": "west", "west": "east"}
VARIANTS: tuple[str, ...] = ("lights", "priority", "combined")
#: Default grid size of each variant (the combined transfer target is larger).
DEFAULT_SIZE: dict[str, int] = {"lights": 5, "priority": 5, "combined": 7}

#: Arms whose approach is red in each light phase (index = phase, fact ``tls<phase>``).
RED_ARMS: tuple[frozenset[str], ...] = (frozenset({"north", "south"}), frozenset({"east", "west"}))

#: One-way flow of the priority variant: the direction traffic moves on each arm, and the
#: exits from the junction cell.
ONE_WAY_FLOW: dict[str, str] = {"west": "east", "north": "south", "south": "north", "east": "east"}
ONE_WAY_EXITS: frozenset[str] = frozenset({"east"})

#: How often a car with priority approaches from the right (the observation is redrawn each step).
CAR_ON_RIGHT_PROBABILITY = 0.3


@dataclass(frozen=True, order=True)
class JunctionState:
    """The car's cell and what it observes.

    ``light`` is the traffic-light phase (0 or 1) where there is a light, else ``None``;
    ``car_on_right`` says a car with priority approaches from the right.
    """

    x: int
    y: int
    light: int | None = None
    car_on_right: bool = False

    @property
    def cell(self) -> Cell:
        return (self.x, self.y)

    def __str__(self) -> str:
        parts = [f"({self.x},{self.y})"]
        if self.light is not None:
            parts.append(f"tls{self.light}")
        if self.car_on_right:
            parts.append("carOnTheRight")
        return " ".join(parts)


class TrafficJunction:
    """One junction on a ``size`` x ``size`` grid, roads crossing at ``junction``.

    The default is the thesis layout: 5 x 5 with the junction at (3, 3). Every cell is a state
    (off-road cells too, so a rule-free agent can go there), combined with the light phase
    (``lights``) or the car-on-the-right flag (``priority``): 5 x 5 x 2 = 50 states, 250 pairs.
    """

    def __init__(self, variant: str = "lights", size: int | None = None, junction: Cell | None = None) -> None:
        if variant not in VARIANTS:
            raise ModelError(f"unknown junction variant {variant!r}", hint=f"use one of {', '.join(VARIANTS)}")
        size = DEFAULT_SIZE[variant] if size is None else size
        if size < 3:
            raise ModelError(f"a junction grid needs size >= 3, got {size}")
        junction = ((size + 1) // 2, (size + 1) // 2) if junction is None else tuple(junction)
        if not all(1 < c < size for c in junction):
            raise ModelError(f"junction {junction} must lie strictly inside the 1..{size} grid")
        self.variant = variant
        self.size = size
        self.junction: Cell = junction
        self.has_lights = variant in ("lights", "combined")
        self.one_way = variant in ("priority", "combined")
        self.has_priority = variant in ("priority", "combined")
        self.actions = ACTIONS

    # --- geometry ----------------------------------------------------------------------------
    def in_grid(self, cell: Cell) -> bool:
        return 1 <= cell[0] <= self.size and 1 <= cell[1] <= self.size

    def road_of(self, cell: Cell) -> str | None:
        """The arm the cell lies on, ``"zero"`` for the junction, ``None`` off the road."""
        (x, y), (jx, jy) = cell, self.junction
        if not self.in_grid(cell):
            return None
        if (x, y) == (jx, jy):
            return "zero"
        if x == jx:
            return "north" if y > jy else "south"
        if y == jy:
            return "east" if x > jx else "west"
        return None

    def before_junction(self, cell: Cell) -> str | None:
        """The arm whose cell next to the junction this is, else ``None``."""
        arm = self.road_of(cell)
        if arm in (None, "zero"):
            return None
        dx, dy = STEP[arm]
        return arm if (cell[0] - dx, cell[1] - dy) == self.junction else None

    def next_cell(self, cell: Cell, action: str) -> Cell | None:
        """Where the action leads, or ``None`` when it leaves the grid."""
        dx, dy = STEP[self._action(action)]
        nxt = (cell[0] + dx, cell[1] + dy)
        return nxt if self.in_grid(nxt) else None

    def allowed_directions(self, cell: Cell) -> frozenset[str]:
        """Directions of travel the roads permit from an on-road cell (all four if two-way)."""
        arm = self.road_of(cell)
        if arm is None:
            return frozenset()
        if not self.one_way:
            return frozenset(ARMS)
        return ONE_WAY_EXITS if arm == "zero" else frozenset({ONE_WAY_FLOW[arm]})

    # --- state space -------------------------------------------------------------------------
    @cached_property
    def _states(self) -> tuple[JunctionState, ...]:
        cells = list(itertools.product(range(1, self.size + 1), repeat=2))
        lights = (0, 1) if self.has_lights else (None,)
        cars = (False, True) if self.has_priority else (False,)
        return tuple(JunctionState(x, y, light=p, car_on_right=c) for (x, y) in cells for p in lights for c in cars)

    def states(self) -> tuple[JunctionState, ...]:
        return self._states

    @cached_property
    def _index(self) -> dict[JunctionState, int]:
        return {s: i for i, s in enumerate(self._states)}

    def state_index(self, state: JunctionState) -> int:
        try:
            return self._index[state]
        except KeyError:
            raise ModelError(f"{state} is not a state of the {self.variant} junction") from None

    def available_actions(self, state: JunctionState) -> tuple[str, ...]:
        """All five actions, everywhere (off-road moves are forbidden, not unavailable)."""
        return self.actions

    def state_actions(self) -> Iterator[tuple[JunctionState, str]]:
        """Every state-action pair (all five actions are available everywhere)."""
        for state in self._states:
            for action in self.actions:
                yield state, action

    # --- ground truth ------------------------------------------------------------------------
    def violations(self, state: JunctionState, action: str) -> list[str]:
        """Names of the ground-truth rules the pair breaks (empty when it is allowed)."""
        action = self._action(action)
        cell = state.cell
        if self.road_of(cell) is None:
            return ["off_road"]
        broken = []
        nxt = self.next_cell(cell, action)
        if nxt is not None and self.road_of(nxt) is None:
            broken.append("leaves_road")
        if self.one_way and action != "zero" and action not in self.allowed_directions(cell):
            broken.append("wrong_way")
        arm = self.before_junction(cell)
        if (self.has_lights and arm is not None and nxt == self.junction
                and arm in RED_ARMS[self._light(state)]):
            broken.append("red_light")
        if state.car_on_right and action != "zero":
            broken.append("priority")
        return broken

    def is_allowed(self, state: JunctionState, action: str) -> bool:
        return not self.violations(state, action)

    def allowed_mask(self) -> np.ndarray:
        """Boolean ``[S, A]`` of the ground truth, in ``states()`` x ``actions`` order."""
        return np.array([[self.is_allowed(s, a) for a in self.actions] for s in self._states], dtype=bool)

    # --- expert ------------------------------------------------------------------------------
    def entries(self) -> list[Cell]:
        """Road ends at the edge of the grid where traffic may come in."""
        ends = []
        for arm in ARMS:
            dx, dy = STEP[arm]
            cell = self.junction
            while self.in_grid((cell[0] + dx, cell[1] + dy)):
                cell = (cell[0] + dx, cell[1] + dy)
            if not self.one_way or ONE_WAY_FLOW[arm] == OPPOSITE[arm]:
                ends.append(cell)
        return ends

    def expert_episode(self, rng: np.random.Generator, max_steps: int = 40,
                       stop_probability: float = 0.2) -> list[tuple[JunctionState, str]]:
        """A rule-abiding drive from a random entry through the junction and off the grid.

        The observation (light phase or car on the right) is redrawn every step; the car heads
        for a random exit other than where it came in, waits when a rule or ``stop_probability``
        says so, and never breaks a rule.
        """
        entry = self.entries()[int(rng.integers(len(self.entries())))]
        entry_arm = self.road_of(entry)
        exits = [a for a in ARMS if a != entry_arm and (not self.one_way or a in ONE_WAY_EXITS)]
        goal_arm = exits[int(rng.integers(len(exits)))]
        cell: Cell | None = entry
        steps: list[tuple[JunctionState, str]] = []
        while cell is not None and len(steps) < max_steps:
            state = self._observe(cell, rng)
            wanted = self._route_step(cell, entry_arm, goal_arm)
            action = wanted if self.is_allowed(state, wanted) and rng.random() >= stop_probability else "zero"
            steps.append((state, action))
            cell = self.next_cell(cell, action)
        return steps

    def _observe(self, cell: Cell, rng: np.random.Generator) -> JunctionState:
        light = int(rng.integers(2)) if self.has_lights else None
        car = bool(rng.random() < CAR_ON_RIGHT_PROBABILITY) if self.has_priority else False
        return JunctionState(*cell, light=light, car_on_right=car)

    def observation_distribution(self) -> list[tuple[int | None, bool, float]]:
        """The (light, car on the right, probability) draws of :meth:`_observe`, redrawn each step."""
        lights = [(0, 0.5), (1, 0.5)] if self.has_lights else [(None, 1.0)]
        cars = ([(False, 1 - CAR_ON_RIGHT_PROBABILITY), (True, CAR_ON_RIGHT_PROBABILITY)]
                if self.has_priority else [(False, 1.0)])
        return [(light, car, pl * pc) for light, pl in lights for car, pc in cars]

    def _route_step(self, cell: Cell, entry_arm: str, goal_arm: str) -> str:
        arm = self.road_of(cell)
        if arm == entry_arm:
            return OPPOSITE[entry_arm]  # towards the junction
        return goal_arm  # at the junction or already on the exit arm

    # --- rendering as ASP facts --------------------------------------------------------------
    def state_facts(self, state: JunctionState) -> list[str]:
        facts = [f"at({state.x},{state.y})."]
        if self.has_lights:
            facts.append(f"tls{self._light(state)}.")
        if state.car_on_right:
            facts.append("carOnTheRight.")
        return facts

    def action_fact(self, state: JunctionState, action: str) -> str:
        """``go(A).`` (the state is not needed; the signature matches the other domain models)."""
        return f"go({self._action(action)})."

    def example_facts(self, state: JunctionState, action: str) -> list[str]:
        return [*self.state_facts(state), self.action_fact(state, action)]

    def background(self) -> str:
        """``background_kb/traffic/bk.lp`` with its geometry constants set to this grid."""
        return set_constants(background_kb_path("traffic", "bk.lp").read_text(encoding="utf-8"),
                             {"size": self.size, "jx": self.junction[0], "jy": self.junction[1]})

    # --- helpers -----------------------------------------------------------------------------
    def _action(self, action: str) -> str:
        if action not in STEP:
            raise ModelError(f"unknown action {action!r}", hint=f"use one of {', '.join(ACTIONS)}")
        return action

    def _light(self, state: JunctionState) -> int:
        if state.light not in (0, 1):
            raise ModelError(f"state {state} needs a light phase 0 or 1 in the {self.variant} junction")
        return state.light
