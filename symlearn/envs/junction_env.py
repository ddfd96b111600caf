"""The traffic junction as a gymnasium environment: drive a car from an entry to an exit.

:class:`JunctionEnv` runs the :class:`~symlearn.envs.traffic_model.TrafficJunction` model
(``"lights"``, ``"priority"``, ``"combined"``) as a tabular RL task, the setting of the
logic-constrained Q-learning experiments of the reference thesis (sections 3.4.4 and 3.4.5).

* **Observation**: ``Discrete(len(model.states()))``, the index of the
  :class:`~symlearn.envs.traffic_model.JunctionState` (cell, light phase, car on the right) in
  ``model.states()`` order. The light phase / car-on-the-right part is redrawn after every step
  with the probabilities of ``TrafficJunction._observe`` (``observation_distribution()``),
  from the environment's seeded generator.
* **Actions**: ``Discrete(5)`` in ``model.actions`` order (zero, north, east, south, west).
* **Route**: *fixed per environment instance* (``start`` and ``goal`` cells), so the
  observation does not need to encode the goal. The default is the first of :func:`routes`
  (an entry cell at the grid edge to the last cell of another arm, in the road's direction for
  one-way roads); the benchmark gives each trained agent one route.
* **Dynamics**: the car moves one cell; a move past the grid edge keeps it in place (it is not
  a rule violation in the model either: leaving the scene at the end of a road is allowed).
  Every action is available everywhere, off-road cells included, so an unconstrained agent
  *can* break the rules.
* **Reward**: ``-(L1 distance of the new cell to the goal)``, and ``-violation_cost`` (10)
  more when the pair breaks a ground-truth rule (``model.violations``). The episode terminates
  on reaching the goal and is truncated after ``max_steps`` steps.
* **info**: ``violation`` (bool), ``violations`` (rule names), ``facts`` (ASP facts of the
  state-action pair just taken, ``model.example_facts``), ``state_facts`` (facts of the new
  state), ``cell``, ``distance``. ``reset`` reports ``state_facts`` and ``cell``. ``action_atoms``
  holds the ASP atom of every action id (``go(north)``): with ``info["state_facts"]``, what
  :class:`~symlearn.backends.shield.Shield` needs to decide on learned rules directly.

Registered with gymnasium as ``symlearn/junction-<variant>-v0`` (see :mod:`symlearn.envs.registry`);
``gymnasium.make`` adds its checker wrappers, so build the class directly to get ``JunctionEnv``
itself.

**Constraint masks.** The observation ids are the first ``len(model.states())`` state ids of
:func:`~symlearn.envs.logic_mdp.logic_mdp` of the same variant (it appends four absorbing exit
states); ``state_names`` holds their names in id order, so
:func:`symlearn.backends.masks.env_mask` can check that both orders agree when it cuts a
domain's ``(S, A)`` mask down to the environment's ids (and closes it, the restriction step of
the thesis' Algorithm 3.1).

>>> env = JunctionEnv("lights", start=(3, 1), goal=(5, 3))
>>> obs, info = env.reset(seed=0)
>>> info["cell"], env.model.states()[obs].cell
((3, 1), (3, 1))
>>> _, reward, _, _, info = env.step(env.model.actions.index("east"))   # off the road
>>> info["cell"], reward, info["violations"]
((4, 1), -13.0, ['leaves_road'])
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.envs.traffic_model import ARMS, ONE_WAY_EXITS, STEP, Cell, JunctionState, TrafficJunction
from symlearn.errors import ModelError

VIOLATION_COST = 10.0


def arm_end(model: TrafficJunction, arm: str) -> Cell:
    """The last cell of ``arm`` (at the grid edge)."""
    dx, dy = STEP[arm]
    cell = model.junction
    while model.in_grid((cell[0] + dx, cell[1] + dy)):
        cell = (cell[0] + dx, cell[1] + dy)
    return cell


def routes(model: TrafficJunction) -> list[tuple[Cell, Cell]]:
    """Every valid ``(start, goal)``: an entry of the roads to the end of another arm that
    traffic may leave by (only the ``east`` arm on one-way roads)."""
    result = []
    for start in model.entries():
        entry_arm = model.road_of(start)
        for arm in ARMS:
            if arm != entry_arm and (not model.one_way or arm in ONE_WAY_EXITS):
                result.append((start, arm_end(model, arm)))
    return result


class JunctionEnv(gym.Env):
    """``JunctionEnv(variant="lights", start=None, goal=None, max_steps=50, size=None)``."""

    metadata = {"render_modes": ["ansi"]}

    def __init__(self, variant: str = "lights", start: Cell | None = None, goal: Cell | None = None,
                 max_steps: int = 50, *, size: int | None = None, violation_cost: float = VIOLATION_COST,
                 render_mode: str | None = None) -> None:
        self.model = TrafficJunction(variant, size=size)
        self.variant = variant
        default_start, default_goal = routes(self.model)[0]
        self.start = tuple(start) if start is not None else default_start
        self.goal = tuple(goal) if goal is not None else default_goal
        for name, cell in (("start", self.start), ("goal", self.goal)):
            if self.model.road_of(cell) is None:
                raise ModelError(f"the {name} cell {cell} is not on a road of the {variant} junction")
        if self.start == self.goal:
            raise ModelError("start and goal must differ")
        if max_steps < 1:
            raise ModelError(f"max_steps must be at least 1, got {max_steps}")
        self.max_steps = int(max_steps)
        self.violation_cost = float(violation_cost)
        self.render_mode = render_mode
        self.states: tuple[JunctionState, ...] = self.model.states()
        # The names a domain model gives these states (str of each), for checking id orders.
        self.state_names: tuple[str, ...] = tuple(map(str, self.states))
        self.actions: tuple[str, ...] = tuple(self.model.actions)
        # the ASP atom of each action id (the same in every state): what a shield on rules needs
        self.action_atoms: tuple[str, ...] = tuple(self.model.action_fact(self.states[0], a).rstrip(".")
                                                   for a in self.actions)
        self.observation_space = gym.spaces.Discrete(len(self.states))
        self.action_space = gym.spaces.Discrete(len(self.actions))
        self._observations = self.model.observation_distribution()
        self._obs_cumulative = np.cumsum([p for _, _, p in self._observations]).tolist()
        index = {s: i for i, s in enumerate(self.states)}
        self._ids_by_cell = {s.cell: [index[JunctionState(*s.cell, light=light, car_on_right=car)]
                                      for light, car, _ in self._observations] for s in self.states}
        # Tables computed once (a step is then a few look-ups): broken rules and facts of every pair.
        self._violations = [[tuple(self.model.violations(s, a)) for a in self.actions] for s in self.states]
        self._facts = [[tuple(self.model.example_facts(s, a)) for a in self.actions] for s in self.states]
        self._state_facts = [tuple(self.model.state_facts(s)) for s in self.states]
        self._cell = self.start
        self._state = 0
        self._steps = 0

    # --- helpers --------------------------------------------------------------------------
    def distance(self, cell: Cell) -> int:
        return abs(cell[0] - self.goal[0]) + abs(cell[1] - self.goal[1])

    def _observe(self, cell: Cell) -> int:
        draw = self.np_random.random()
        ids = self._ids_by_cell[cell]
        for k, bound in enumerate(self._obs_cumulative):
            if draw < bound:
                return ids[k]
        return ids[-1]

    def _move(self, cell: Cell, action: str) -> Cell:
        dx, dy = STEP[action]
        nxt = (cell[0] + dx, cell[1] + dy)
        return nxt if self.model.in_grid(nxt) else cell  # past the grid edge: stay in place

    def violation_mask(self) -> np.ndarray:
        """Forbidden ``(S, A)`` of the ground truth over the observation ids."""
        return np.array([[bool(v) for v in row] for row in self._violations])

    # --- gymnasium API --------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self._cell = self.start
        self._steps = 0
        self._state = self._observe(self._cell)
        return self._state, {"cell": self._cell, "state_facts": list(self._state_facts[self._state])}

    def step(self, action: Any):
        if not (isinstance(action, (int, np.integer)) and 0 <= action < len(self.actions)) \
                and not self.action_space.contains(action):
            raise ModelError(f"action {action!r} is not available (0..{len(self.actions) - 1})")
        a = int(action)
        name = self.actions[a]
        broken = self._violations[self._state][a]
        facts = list(self._facts[self._state][a])
        self._cell = self._move(self._cell, name)
        self._steps += 1
        self._state = self._observe(self._cell)
        distance = self.distance(self._cell)
        reward = -float(distance) - (self.violation_cost if broken else 0.0)
        terminated = self._cell == self.goal
        truncated = not terminated and self._steps >= self.max_steps
        info = {"violation": bool(broken), "violations": list(broken), "facts": facts,
                "state_facts": list(self._state_facts[self._state]),
                "cell": self._cell, "distance": distance}
        return self._state, reward, terminated, truncated, info

    def render(self) -> str | None:
        rows = []
        for y in range(self.model.size, 0, -1):
            row = ""
            for x in range(1, self.model.size + 1):
                cell = (x, y)
                row += ("A" if cell == self._cell else "G" if cell == self.goal
                        else "." if self.model.road_of(cell) is not None else "#")
            rows.append(row)
        return "\n".join(rows) + f"\n{self.states[self._state]}"


__all__ = ["JunctionEnv", "VIOLATION_COST", "arm_end", "routes"]
