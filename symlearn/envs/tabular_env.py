"""A gymnasium environment that plays any :class:`~symlearn.mdp.TabularMDP`.

The tabular model is what the learners work on; this environment lets an RL agent (tabular
Q-learning, a shielded agent) act in the same model, so rules learned on a user's domain can be
tried by an agent without writing a simulator:

* observation = state id (``Discrete(S)``), action = action id (``Discrete(A)``);
* ``reset`` draws the start from ``mdp.initial``, ``step`` the next state from
  ``mdp.transitions[s, a]``, both with the environment's generator (seeded by ``reset(seed=)``);
* reward ``mdp.rewards[s, a]`` (a :class:`TabularMDP` given ``(S, A, S)`` rewards keeps their
  expectation under the transitions, so the agent is paid that expectation);
* ``terminated`` on entering a terminal state, ``truncated`` after ``max_steps`` steps;
* ``info``: ``state_name`` always; ``action_name`` after a step; ``violation`` when a forbidden
  ``(S, A)`` mask is given as ``violations`` (only reported, never enforced: enforcing is the job
  of :class:`~symlearn.backends.shield.Shield`).

A :class:`~symlearn.grounding.Domain` (anything with a ``.mdp``) may be passed instead of the model.

>>> import numpy as np
>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((2, 2, 2)); P[0, 0, 0] = P[0, 1, 1] = P[1, :, 1] = 1
>>> mdp = TabularMDP(P, np.array([[-1.0, 5.0], [0.0, 0.0]]), [1, 0], [False, True], ("start", "goal"))
>>> env = TabularEnv(mdp, violations=np.array([[False, True], [False, False]]))
>>> env.reset(seed=0)
(0, {'state_name': 'start'})
>>> state, reward, terminated, truncated, info = env.step(1)
>>> state, reward, terminated, truncated, info["violation"], info["state_name"]
(1, 5.0, True, False, True, 'goal')
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.errors import ModelError, SymlearnError
from symlearn.mdp import TabularMDP


class TabularEnv(gym.Env):
    """``TabularEnv(mdp, max_steps=100, violations=None, render_mode=None)`` (see the module docstring)."""

    metadata = {"render_modes": ["ansi"], "render_fps": 4}

    def __init__(self, mdp: Any, *, max_steps: int = 100, violations: np.ndarray | None = None,
                 render_mode: str | None = None) -> None:
        self.mdp = _as_mdp(mdp)
        if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 1:
            raise SymlearnError(f"max_steps must be a positive integer, got {max_steps!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise SymlearnError(f"unknown render mode {render_mode!r}", hint="use 'ansi' or None")
        self.max_steps = int(max_steps)
        self.render_mode = render_mode
        self.violations = None if violations is None else _check_mask(violations, self.mdp)
        self.observation_space = spaces.Discrete(self.mdp.n_states)
        self.action_space = spaces.Discrete(self.mdp.n_actions)
        self._state: int | None = None  # the last observation; None before the first reset
        self._running = False  # an episode is under way (reset called, not yet ended)
        self._steps = 0

    def to_tabular(self) -> TabularMDP:
        """The model played (the convention :meth:`TabularMDP.from_gymnasium` reads)."""
        return self.mdp

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._state = self.mdp.sample_initial(self.np_random)
        self._steps = 0
        self._running = True
        return self._state, {"state_name": self.mdp.state_names[self._state]}

    def step(self, action: Any):
        if not self._running:
            raise SymlearnError("no episode is running", hint="call reset() before step() and after an episode ends")
        if isinstance(action, bool) or not isinstance(action, (int, np.integer)) \
                or not 0 <= int(action) < self.mdp.n_actions:
            raise ModelError(f"action {action!r} is outside 0..{self.mdp.n_actions - 1}")
        s, a = self._state, int(action)
        nxt = self.mdp.sample_next(s, a, self.np_random)
        self._steps += 1
        terminated = bool(self.mdp.terminal[nxt])
        # A step that ends in a terminal state is terminated, not truncated, even on the last step.
        truncated = not terminated and self._steps >= self.max_steps
        info: dict[str, Any] = {"state_name": self.mdp.state_names[nxt], "action_name": self.mdp.action_names[a]}
        if self.violations is not None:
            info["violation"] = bool(self.violations[s, a])
        self._state = nxt
        self._running = not (terminated or truncated)
        return nxt, float(self.mdp.rewards[s, a]), terminated, truncated, info

    def render(self) -> str | None:
        if self.render_mode != "ansi":
            return None
        if self._state is None:
            return "(not reset)\n"
        return f"state {self._state} ({self.mdp.state_names[self._state]}), step {self._steps}/{self.max_steps}\n"

    def __repr__(self) -> str:
        return f"TabularEnv({self.mdp.n_states} states x {self.mdp.n_actions} actions, max_steps={self.max_steps})"


def _as_mdp(value: Any) -> TabularMDP:
    if isinstance(value, TabularMDP):
        return value
    inner = getattr(value, "mdp", None)  # a Domain or a bundled wrapper (LogicMDP)
    if isinstance(inner, TabularMDP):
        return inner
    raise ModelError(f"TabularEnv needs a TabularMDP (or an object with .mdp), got {type(value).__name__}",
                     hint="build one with symlearn.mdp.TabularMDP(...) or Domain.from_folder(DIR)")


def _check_mask(mask: Any, mdp: TabularMDP) -> np.ndarray:
    array = np.asarray(mask)
    if array.shape != (mdp.n_states, mdp.n_actions):
        raise ModelError(f"violations must be a boolean (S, A) = {(mdp.n_states, mdp.n_actions)} mask, "
                         f"got shape {array.shape}")
    if array.dtype != bool:
        raise ModelError(f"violations must be boolean, got {array.dtype}",
                         hint="a forbidden mask such as domain.truth_forbidden")
    return array.copy()


__all__ = ["TabularEnv"]
