"""A gymnasium environment in product with a reward machine, for policy-gradient training.

Continuous observations have no table to hold ``Q[o, u, a]``, so the product is made an
environment of its own: the observation is the environment's (flattened to float32; a ``Dict`` or
``Tuple`` of numeric parts as ``gymnasium.spaces.flatten`` flattens it) followed by
a one-hot code of the machine state ``u``, the reward is the machine's for the label of the new
observation, and the episode ends when the environment's does or the machine ends (the task was
completed or can no longer be). Any policy-gradient learner then trains on it (our
:func:`~symlearn.rl.ppo.train_ppo`). Counterfactual replay does not apply: PPO learns from the
states its own policy visits. :attr:`ProductEnv.word` is the label word of the current episode.

>>> import gymnasium as gym
>>> from symlearn.logic.automata.reward_machine import RewardMachine
>>> right = lambda obs, info, where, env: {"right"} if obs[0] > 0.1 else set()
>>> env = ProductEnv(gym.make("CartPole-v1"), right,
...                  RewardMachine.from_formula("F right"))
>>> obs, _ = env.reset(seed=0)
>>> obs.shape, env.observation_space.shape
((6,), (6,))
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.rl.product_q_learning import MachineColumns

__all__ = ["ProductEnv"]


class ProductEnv(gym.Wrapper):
    """``ProductEnv(env, labeler, machine)``; ``labeler(observation, info, where, env=unwrapped)`` -> names."""

    def __init__(self, env: Any, labeler: Callable[..., frozenset], machine) -> None:
        super().__init__(env)
        self.labeler = labeler
        self.machine = machine
        self.n_u = int(machine.n_states)
        self._read = MachineColumns(machine)
        space = env.observation_space
        # a Dict/Tuple of numeric parts (a goal-conditioned robot's observation, achieved_goal,
        # desired_goal) is flattened as gymnasium flattens it; the labeler still sees it whole
        self._parts = space if isinstance(space, (gym.spaces.Dict, gym.spaces.Tuple)) else None
        size = gym.spaces.flatdim(space) if self._parts is not None else int(np.prod(space.shape or (1,)))
        self.observation_space = gym.spaces.Box(-np.inf, np.inf, shape=(size + self.n_u,), dtype=np.float32)
        self.u = int(machine.initial)
        self.word: list[frozenset] = []

    def _observation(self, observation: Any) -> np.ndarray:
        code = np.zeros(self.n_u, dtype=np.float32)
        code[self.u] = 1.0
        if self._parts is not None:
            observation = gym.spaces.flatten(self._parts, observation)
        return np.concatenate([np.asarray(observation, dtype=np.float32).reshape(-1), code])

    def reset(self, **kwargs):
        observation, info = self.env.reset(**kwargs)
        label = frozenset(self.labeler(observation, info, "reset", env=self.env.unwrapped))
        self.word = [label]
        self.u = int(self._read(label).next_u[int(self.machine.initial), 0])
        return self._observation(observation), info

    def step(self, action):
        observation, _reward, terminated, truncated, info = self.env.step(action)
        label = frozenset(self.labeler(observation, info, f"step {len(self.word)}", env=self.env.unwrapped))
        self.word.append(label)
        tables = self._read(label)
        reward = float(tables.reward[self.u, 0])
        machine_done = bool(tables.done[self.u, 0])
        self.u = int(tables.next_u[self.u, 0])
        return self._observation(observation), reward, bool(terminated) or machine_done, truncated, info
