"""A shield: a gymnasium wrapper that keeps an agent inside learned constraints.

Every ``reset`` and ``step`` reports ``info["action_mask"]`` (int8, 1 = allowed) for the new
observation, so a masked learner (:func:`symlearn.rl.q_learning.q_learning`, or any library
that reads action masks) never proposes a forbidden action. An agent that does anyway meets
``mode``:

* ``"replace"`` (default): the action is replaced by an allowed one (drawn with the wrapper's
  seeded generator) and the step goes ahead; ``info["shield"] = "replaced"``.
* ``"refuse"``: the environment does not move; the agent gets the same observation back with
  ``refusal_reward`` and ``info["shield"] = "refused"``.
* ``"raise"``: a :class:`~symlearn.errors.SymlearnError`.

A state where nothing is allowed (a dead end of the constraint set) lets every action through,
flagged with ``info["shield_dead_end"] = True`` -- blocking forever would hide the problem.

>>> from symlearn.envs.gridworld import make_gridworld, StochasticGridworld
>>> from symlearn.rl.q_learning import q_learning
>>> shielded = Shield(make_gridworld(0.0), StochasticGridworld(0.0).constraint_mask())
>>> result = q_learning(shielded, n_episodes=300, learning_rate=0.5, discount=0.95, seed=0)
>>> int(result.violations.sum()), float(result.returns[-20:].max())   # around the block: 14 steps
(0, -12.0)
"""

from __future__ import annotations

from typing import Any, Literal

import gymnasium as gym
import numpy as np

from symlearn.backends.rules import action_mask, allowed_function
from symlearn.errors import SymlearnError

Mode = Literal["replace", "refuse", "raise"]


class Shield(gym.Wrapper):
    """``Shield(env, constraints, mode="replace", refusal_reward=0.0, seed=None)``.

    ``constraints``: a forbidden ``(S, A)`` mask, an object with ``allowed(state, action)``
    (an ASP hypothesis behind a state translation), or such a callable. ``state_of`` maps an
    observation to what ``allowed`` expects (default: the observation itself).
    """

    def __init__(
        self,
        env: gym.Env,
        constraints: Any,
        *,
        mode: Mode = "replace",
        refusal_reward: float = 0.0,
        state_of: Any = None,
        seed: int | None = None,
    ) -> None:
        super().__init__(env)
        if not isinstance(env.action_space, gym.spaces.Discrete):
            raise SymlearnError("a shield needs a Discrete action space")
        if mode not in ("replace", "refuse", "raise"):
            raise SymlearnError(f"unknown shield mode {mode!r}", hint="use 'replace', 'refuse' or 'raise'")
        self.n_actions = int(env.action_space.n)
        n_states = int(env.observation_space.n) if isinstance(env.observation_space, gym.spaces.Discrete) else None
        self.allowed = allowed_function(constraints, self.n_actions, n_states if state_of is None else None)
        self.mode = mode
        self.refusal_reward = float(refusal_reward)
        self.state_of = state_of or (lambda observation: observation)
        self.rng = np.random.default_rng(seed)
        self.interventions = 0
        self._observation: Any = None
        self._mask = np.ones(self.n_actions, dtype=np.int8)

    def _annotate(self, observation: Any, info: dict[str, Any]) -> dict[str, Any]:
        self._observation = observation
        mask = action_mask(self.allowed, self.state_of(observation), self.n_actions)
        dead_end = not mask.any()
        self._mask = np.ones_like(mask) if dead_end else mask
        info = dict(info)
        info["action_mask"] = self._mask.copy()
        info["shield_dead_end"] = dead_end
        return info

    def action_masks(self) -> np.ndarray:
        """The current mask (the method name some masked-policy libraries look for)."""
        return self._mask.astype(bool)

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        return observation, self._annotate(observation, info)

    def step(self, action: Any):
        if not self.action_space.contains(action):
            raise SymlearnError(f"action {action!r} is not available (0..{self.n_actions - 1})")
        verdict = None
        if not self._mask[int(action)]:
            self.interventions += 1
            if self.mode == "raise":
                raise SymlearnError(f"the shield forbids action {action} in state {self._observation!r}")
            if self.mode == "refuse":
                info = self._annotate(self._observation, {"shield": "refused"})
                return self._observation, self.refusal_reward, False, False, info
            action = int(self.rng.choice(np.flatnonzero(self._mask)))
            verdict = "replaced"
        observation, reward, terminated, truncated, info = self.env.step(action)
        info = self._annotate(observation, info)
        if verdict:
            info["shield"] = verdict
            info["shield_action"] = action
        return observation, reward, terminated, truncated, info
