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

from collections.abc import Sequence
from typing import Any, Literal

import gymnasium as gym
import numpy as np

from symlearn.backends.rules import action_mask, allowed_function, rules_allowed
from symlearn.errors import SymlearnError
from symlearn.logic.asp import Hypothesis

Mode = Literal["replace", "refuse", "raise"]


class Shield(gym.Wrapper):
    """``Shield(env, constraints, mode="replace", refusal_reward=0.0, state_of=None, action_atoms=None, seed=None)``.

    ``constraints`` is one of:

    * a forbidden ``(S, A)`` mask: the observation is the state id (a ``Discrete`` observation
      space), or ``state_of`` maps an observation to one -- anything else is refused here;
    * an ASP rule set (:class:`~symlearn.logic.asp.Hypothesis`, e.g. ``Hypothesis.from_lp``): it
      decides on state facts and action atoms, so the shield needs both -- the facts from
      ``state_of(observation)`` or else from the environment's ``info["state_facts"]`` (the
      junction environments report them), the atoms (``go(north)``, one per action id) from
      ``action_atoms`` or else the environment's ``action_atoms`` attribute; without atoms it is
      refused here. Each distinct (facts, action) pair is decided by clingo once;
    * an object with ``allowed(state, action)`` or such a callable, ``action`` an int and
      ``state`` what ``state_of`` makes of the observation (default: the observation itself);
      an ``allowed`` that fails on a state is reported as a :class:`~symlearn.errors.SymlearnError`.
    """

    def __init__(
        self,
        env: gym.Env,
        constraints: Any,
        *,
        mode: Mode = "replace",
        refusal_reward: float = 0.0,
        state_of: Any = None,
        action_atoms: Sequence[str] | None = None,
        seed: int | None = None,
    ) -> None:
        super().__init__(env)
        if not isinstance(env.action_space, gym.spaces.Discrete):
            raise SymlearnError(f"a shield needs a Discrete action space, the environment's is {env.action_space}")
        if mode not in ("replace", "refuse", "raise"):
            raise SymlearnError(f"unknown shield mode {mode!r}", hint="use 'replace', 'refuse' or 'raise'")
        if state_of is not None and not callable(state_of):
            raise SymlearnError(f"state_of must be callable, got {state_of!r}")
        self.n_actions = int(env.action_space.n)
        discrete = isinstance(env.observation_space, gym.spaces.Discrete)
        self._facts_from_info = False
        if isinstance(constraints, Hypothesis):
            atoms = action_atoms if action_atoms is not None else getattr(env.unwrapped, "action_atoms", None)
            if atoms is None:
                raise SymlearnError("a shield on ASP rules needs the action atom of every action id",
                                    hint="give action_atoms=['go(north)', ...], or turn the rules into a forbidden "
                                         "mask first (symlearn.backends.masks.env_mask)")
            atoms = tuple(str(a).strip().rstrip(".") for a in atoms)
            if len(atoms) != self.n_actions:
                raise SymlearnError(f"{len(atoms)} action atoms for {self.n_actions} actions")
            self.allowed = rules_allowed(constraints, atoms)
            self._facts_from_info = state_of is None
        elif not callable(constraints) and not hasattr(constraints, "allowed"):
            if not discrete and state_of is None:
                raise SymlearnError(f"a forbidden (S, A) mask needs integer observations, the environment's are "
                                    f"{env.observation_space}", hint="give state_of=observation -> state id")
            n_states = int(env.observation_space.n) if discrete and state_of is None else None
            self.allowed = allowed_function(constraints, self.n_actions, n_states)
        else:
            self.allowed = allowed_function(constraints, self.n_actions)
        if action_atoms is not None and not isinstance(constraints, Hypothesis):
            raise SymlearnError("action_atoms apply to ASP rules (a Hypothesis), not to this constraint set")
        self.mode = mode
        self.refusal_reward = float(refusal_reward)
        self.state_of = state_of or (lambda observation: observation)
        self.rng = np.random.default_rng(seed)
        self.interventions = 0
        self._observation: Any = None
        self._state: Any = None
        self._mask = np.ones(self.n_actions, dtype=np.int8)

    def _state_from(self, observation: Any, info: dict[str, Any]) -> Any:
        if not self._facts_from_info:
            return self.state_of(observation)
        if "state_facts" not in info:
            raise SymlearnError("the shield's ASP rules decide on state facts, and the environment reports no "
                                "info['state_facts']", hint="give state_of=observation -> facts")
        return tuple(info["state_facts"])

    def _annotate(self, observation: Any, info: dict[str, Any]) -> dict[str, Any]:
        self._observation = observation
        self._state = self._state_from(observation, info)
        try:
            mask = action_mask(self.allowed, self._state, self.n_actions)
        except SymlearnError:
            raise
        except Exception as exc:  # a user's rule set: say what it was asked, not a traceback inside it
            raise SymlearnError(f"the shield's constraints failed on state {self._state!r}: "
                                f"{type(exc).__name__}: {exc}",
                                hint="state_of must turn an observation into what allowed(state, action) "
                                     "takes") from None
        return self._annotated(info, mask)

    def _annotated(self, info: dict[str, Any], mask: np.ndarray) -> dict[str, Any]:
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
            if self.mode == "refuse":  # nothing moved: the same state, the same mask
                info = self._annotated({"shield": "refused"}, self._mask)
                return self._observation, self.refusal_reward, False, False, info
            action = int(self.rng.choice(np.flatnonzero(self._mask)))
            verdict = "replaced"
        observation, reward, terminated, truncated, info = self.env.step(action)
        info = self._annotate(observation, info)
        if verdict:
            info["shield"] = verdict
            info["shield_action"] = action
        return observation, reward, terminated, truncated, info
