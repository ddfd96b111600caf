"""A stochastic gridworld with a block of forbidden cells, for inverse constrained RL.

The agent walks from a fixed start to a fixed goal; each step costs ``-1`` and entering the goal
earns ``+1`` instead (the episode then ends); episodes are cut after 200 steps. With
probability ``stochasticity`` the chosen move is ignored and the agent goes to a uniformly
chosen neighbouring cell (one of the up to four cells next to it on the grid). Moves into the
outer wall leave the agent where it is. The forbidden cells are not walls: the agent can enter
them, and every step that ends in one counts as a constraint violation.

The default layout (7 x 7, start bottom-left, goal bottom-right, a 4 x 3 block between them
reaching the bottom row) makes the unconstrained shortest path run straight through the block,
so a constraint-free planner and a constraint-abiding expert behave very differently; the
thesis specifies the layout only as a figure, so its exact cell positions are our choice.

The environment exposes its exact model (``env.P`` in the toy-text convention and
:meth:`StochasticGridworld.to_tabular`), its ground truth (:attr:`forbidden_states`,
:meth:`constraint_mask`) and an expert that is optimal under the true constraints.

>>> env = StochasticGridworld(stochasticity=0.0)
>>> mdp = env.to_tabular()
>>> mdp.n_states, mdp.n_actions, env.state_name(env.start_state), env.state_name(env.goal_state)
(49, 4, 'r6c0', 'r6c6')
>>> print(env.render_text())
. . . . . . .
. . . . . . .
. . . . . . .
. . X X X . .
. . X X X . .
. . X X X . .
S . X X X . G
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP

ACTIONS: tuple[str, ...] = ("up", "right", "down", "left")
_MOVES = ((-1, 0), (0, 1), (1, 0), (0, -1))

DEFAULT_SHAPE = (7, 7)
DEFAULT_START = (6, 0)
DEFAULT_GOAL = (6, 6)
DEFAULT_FORBIDDEN = tuple((r, c) for r in range(3, 7) for c in range(2, 5))


class StochasticGridworld(gym.Env):
    """Gymnasium environment; observations and actions are integer ids (``r * width + c``).

    ``info`` of every step carries ``violation`` (the step ended in a forbidden cell).
    """

    metadata = {"render_modes": ["ansi"]}

    def __init__(
        self,
        stochasticity: float = 0.0,
        *,
        shape: tuple[int, int] = DEFAULT_SHAPE,
        start: tuple[int, int] = DEFAULT_START,
        goal: tuple[int, int] = DEFAULT_GOAL,
        forbidden: Iterable[tuple[int, int]] = DEFAULT_FORBIDDEN,
        max_steps: int = 200,
        step_reward: float = -1.0,
        goal_reward: float = 1.0,
        render_mode: str | None = None,
    ) -> None:
        if not 0.0 <= stochasticity <= 1.0:
            raise SymlearnError(f"stochasticity must lie in [0, 1], got {stochasticity}")
        height, width = shape
        if height < 1 or width < 1 or height * width < 2:
            raise SymlearnError(f"the grid needs at least two cells, got shape {shape}")
        self.shape = (int(height), int(width))
        self.stochasticity = float(stochasticity)
        from symlearn.envs.blocked_point import EPISODE_STEPS_RULE, episode_steps_ok

        if not episode_steps_ok(max_steps):
            raise SymlearnError(f"max_steps must be {EPISODE_STEPS_RULE}, got {max_steps!r}")
        self.max_steps = int(max_steps)
        self.step_reward = float(step_reward)
        self.goal_reward = float(goal_reward)
        self.render_mode = render_mode
        self.start_state = self.cell_state(start)
        self.goal_state = self.cell_state(goal)
        if self.start_state == self.goal_state:
            raise SymlearnError("start and goal must be different cells")
        blocked = np.zeros(self.n_states, dtype=bool)
        for cell in forbidden:
            blocked[self.cell_state(cell)] = True
        if blocked[self.start_state] or blocked[self.goal_state]:
            raise SymlearnError("the start and goal cells cannot be forbidden")
        blocked.setflags(write=False)
        self.forbidden_states = blocked
        self.observation_space = spaces.Discrete(self.n_states)
        self.action_space = spaces.Discrete(len(ACTIONS))
        self._transitions = self._build_transitions()
        self.P = self._toy_text_model()
        self.initial_state_distrib = np.eye(self.n_states)[self.start_state]
        self._state = self.start_state
        self._steps = 0

    # --- geometry ---------------------------------------------------------------------------
    @property
    def n_states(self) -> int:
        return self.shape[0] * self.shape[1]

    def cell_state(self, cell: tuple[int, int]) -> int:
        r, c = (int(x) for x in cell)
        if not (0 <= r < self.shape[0] and 0 <= c < self.shape[1]):
            raise SymlearnError(f"cell {cell} lies outside the {self.shape[0]} x {self.shape[1]} grid")
        return r * self.shape[1] + c

    def state_cell(self, state: int) -> tuple[int, int]:
        self._check_state(state)
        return divmod(int(state), self.shape[1])

    def state_name(self, state: int) -> str:
        r, c = self.state_cell(state)
        return f"r{r}c{c}"

    def _check_state(self, state: Any) -> None:
        if not isinstance(state, (int, np.integer)) or not 0 <= int(state) < self.n_states:
            raise SymlearnError(f"state {state!r} is outside the gridworld (0..{self.n_states - 1})")

    def _target(self, state: int, move: int) -> int:
        r, c = divmod(state, self.shape[1])
        dr, dc = _MOVES[move]
        nr, nc = r + dr, c + dc
        if 0 <= nr < self.shape[0] and 0 <= nc < self.shape[1]:
            return nr * self.shape[1] + nc
        return state

    def neighbours(self, state: int) -> list[int]:
        """The cells next to ``state`` on the grid (the outcomes of a random move)."""
        return sorted({t for t in (self._target(state, m) for m in range(4)) if t != state})

    # --- the exact model ----------------------------------------------------------------------
    def _build_transitions(self) -> np.ndarray:
        S, A, p = self.n_states, len(ACTIONS), self.stochasticity
        P = np.zeros((S, A, S))
        for s in range(S):
            if s == self.goal_state:
                P[s, :, s] = 1.0
                continue
            around = self.neighbours(s)
            for a in range(A):
                P[s, a, self._target(s, a)] += 1.0 - p
                for n in around:
                    P[s, a, n] += p / len(around)
        return P

    def _toy_text_model(self) -> dict[int, dict[int, list[tuple[float, int, float, bool]]]]:
        model: dict[int, dict[int, list[tuple[float, int, float, bool]]]] = {}
        for s in range(self.n_states):
            model[s] = {}
            for a in range(len(ACTIONS)):
                row = self._transitions[s, a]
                if s == self.goal_state:
                    model[s][a] = [(1.0, s, 0.0, True)]
                    continue
                model[s][a] = [
                    (float(row[t]), int(t), self._reward(int(t)), int(t) == self.goal_state)
                    for t in np.flatnonzero(row)
                ]
        return model

    def _reward(self, next_state: int) -> float:
        return self.goal_reward if next_state == self.goal_state else self.step_reward

    def to_tabular(self) -> TabularMDP:
        """The exact model: the goal is terminal (an absorbing self-loop with no reward)."""
        S = self.n_states
        entering_goal = self._transitions[:, :, self.goal_state]
        rewards = self.goal_reward * entering_goal + self.step_reward * (1.0 - entering_goal)
        rewards[self.goal_state] = 0.0
        terminal = np.zeros(S, dtype=bool)
        terminal[self.goal_state] = True
        names = tuple(self.state_name(s) for s in range(S))
        return TabularMDP(self._transitions, rewards, self.initial_state_distrib, terminal,
                          names, ACTIONS, goals=(self.goal_state,), name="gridworld")

    # --- ground truth -------------------------------------------------------------------------
    def constraint_mask(self) -> np.ndarray:
        """True constraints as a forbidden (S, A) mask: every move whose intended cell is
        forbidden (from inside the block too, so an agent that slipped in may only leave)."""
        targets = np.array([[self._target(s, a) for a in range(len(ACTIONS))] for s in range(self.n_states)])
        mask = self.forbidden_states[targets]
        mask[self.goal_state] = False
        return mask

    def expert_policy(self, *, discount: float = 0.99, violation_penalty: float = 100.0) -> np.ndarray:
        """A deterministic expert that is optimal under the true constraints: value iteration
        where every step pays ``violation_penalty`` times its probability of ending in a
        forbidden cell, so the expert never walks into the block and keeps its distance when
        slips could carry it in."""
        from dataclasses import replace

        from symlearn.rl.tabular import value_iteration

        mdp = self.to_tabular()
        risk = mdp.transitions[:, :, self.forbidden_states].sum(axis=2)
        penalised = replace(mdp, rewards=mdp.rewards - violation_penalty * risk)
        return value_iteration(penalised, discount=discount).policy.astype(np.int64)

    def maxent_expert_policy(self, horizon: int = 60, rationality: float = 3.0) -> np.ndarray:
        """A stochastic expert (rows of ``pi[s, a]``): the goal-conditioned maximum-entropy
        policy of the model restricted by the true constraints. It spreads over all
        near-optimal valid paths, which is the demonstrator maximum-likelihood constraint
        inference assumes. ``rationality`` scales the reward: with four actions and a step reward
        of -1 the number of long paths grows faster than their weight shrinks, so an unscaled
        MaxEnt walker wanders; at 3 it heads for the goal along the many shortest paths."""
        from symlearn.rl.maxent import maxent_backward_pass

        mdp = self.to_tabular()
        return maxent_backward_pass(mdp, [self.goal_state], horizon, reward=rationality * mdp.rewards,
                                    allowed=~self.constraint_mask()).policy

    # --- gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self._state = self.start_state
        self._steps = 0
        return self._state, {"violation": False}

    def step(self, action: Any):
        if not self.action_space.contains(action):
            raise SymlearnError(f"action {action!r} is not available (actions are 0..{len(ACTIONS) - 1}: "
                                f"{', '.join(ACTIONS)})")
        if self._state == self.goal_state:
            raise SymlearnError("the episode has ended; call reset()")
        row = self._transitions[self._state, int(action)]
        nxt = int(self.np_random.choice(self.n_states, p=row))
        self._state = nxt
        self._steps += 1
        terminated = nxt == self.goal_state
        truncated = not terminated and self._steps >= self.max_steps
        violation = bool(self.forbidden_states[nxt])
        return nxt, self._reward(nxt), terminated, truncated, {"violation": violation}

    def render(self) -> str | None:
        return self.render_text(agent=self._state)

    def render_text(self, *, marks: np.ndarray | None = None, agent: int | None = None) -> str:
        """The grid as text: ``S`` start, ``G`` goal, ``X`` forbidden (or ``marks`` when given,
        a boolean per state, e.g. a learned constraint map), ``A`` the agent."""
        shown = self.forbidden_states if marks is None else np.asarray(marks, bool)
        if shown.shape != (self.n_states,):
            raise ModelError(f"marks must have one entry per state ({self.n_states}), got {shown.shape}")
        rows = []
        for r in range(self.shape[0]):
            cells = []
            for c in range(self.shape[1]):
                s = r * self.shape[1] + c
                cell = "X" if shown[s] else "."
                if s == self.start_state:
                    cell = "S"
                if s == self.goal_state:
                    cell = "G"
                if agent is not None and s == agent:
                    cell = "A"
                cells.append(cell)
            rows.append(" ".join(cells))
        return "\n".join(rows)


def make_gridworld(stochasticity: float = 0.0, **kwargs: Any) -> gym.Env:
    """The gridworld wrapped in gymnasium's ``TimeLimit`` (``max_steps``, default 200)."""
    env = StochasticGridworld(stochasticity, **kwargs)
    return gym.wrappers.TimeLimit(env, max_episode_steps=env.max_steps)
