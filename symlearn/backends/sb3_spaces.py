"""Spaces stable-baselines3 does not read as gymnasium defines them, made plain for it.

stable-baselines3 (2.x) one-hot encodes a ``Discrete`` observation as ids ``0..n-1`` and acts in
a ``Discrete`` space with ids ``0..n-1``: a space numbered from another ``start``
(``Discrete(8, start=2)``) breaks the encoding or sends actions outside the space. Its
``MlpPolicy`` flattens observations from their second dimension, so a scalar ``Box`` observation
(shape ``()``) fails. Its ``MultiBinary`` actions are floats (``[1., 0., 1.]``, the Bernoulli
samples), which an environment that counts with them turns into float observations.
:func:`sb3_spaces` wraps an environment with such spaces in :class:`SB3Spaces`: observation ids
shifted to start at 0, action ids shifted back to the environment's own, ``MultiBinary`` and
``MultiDiscrete`` actions cast to the space's dtype, a scalar observation as a vector of one
entry; other environments are returned unchanged. ``train --algo sb3-*`` uses it outside the cost wrappers, so a learned cost
reads the environment's own values; a policy saved from it loads on ``sb3_spaces(env)``.

>>> import gymnasium as gym
>>> from gymnasium import spaces
>>> class Offset(gym.Env):
...     observation_space, action_space = spaces.Discrete(4, start=2), spaces.Discrete(3, start=-1)
...     def reset(self, seed=None, options=None): return 2, {}
...     def step(self, action): return 5, 0.0, True, False, {"action": action}
>>> env = sb3_spaces(Offset())
>>> env.observation_space, env.action_space, env.reset()[0], env.step(0)[0], env.step(0)[-1]
(Discrete(4), Discrete(3), 0, 3, {'action': -1})
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces


def _offset(space: Any) -> int:
    return int(space.start) if isinstance(space, spaces.Discrete) else 0


def _scalar_box(space: Any) -> bool:
    return isinstance(space, spaces.Box) and space.shape == ()


def _integer_array(space: Any) -> bool:
    return isinstance(space, (spaces.MultiBinary, spaces.MultiDiscrete))


def env_action(space: Any, action: Any) -> Any:
    """``action`` as stable-baselines3 gives it, in ``space``'s own type: ``MultiBinary`` and
    ``MultiDiscrete`` actions as arrays of the space's dtype (SB3's Bernoulli samples are floats);
    other actions unchanged.

    >>> env_action(spaces.MultiBinary(3), np.array([1., 0., 1.], dtype=np.float32))
    array([1, 0, 1], dtype=int8)
    """
    if _integer_array(space):
        return np.asarray(action).astype(space.dtype)
    return action


def predicted_action(action: Any) -> Any:
    """An action from ``model.predict`` for one observation, as an environment takes it: SB3 gives
    a ``Discrete`` action as a 0-d array, which is unhashable, and gymnasium's toy-text worlds look
    their transitions up by it (``P[s][a]``: FrozenLake, Taxi, CliffWalking); training never shows
    this, since the vectorised environment hands each copy a numpy scalar. Arrays of actions are
    left as they are.

    >>> predicted_action(np.array(2)), predicted_action(np.array([0.5]))
    (2, array([0.5]))
    """
    array = np.asarray(action)
    return array.item() if array.shape == () else action


class SB3Spaces(gym.Wrapper):
    """``env`` with Discrete spaces numbered from 0, a scalar Box observation as shape ``(1,)`` and
    MultiBinary/MultiDiscrete actions cast to the space's dtype."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        observation, action = env.observation_space, env.action_space
        self._obs_start, self._act_start = _offset(observation), _offset(action)
        self._scalar = _scalar_box(observation)
        if self._obs_start:
            self.observation_space = spaces.Discrete(int(observation.n))
        elif self._scalar:
            self.observation_space = spaces.Box(np.reshape(observation.low, 1), np.reshape(observation.high, 1),
                                                dtype=observation.dtype)
        if self._act_start:
            self.action_space = spaces.Discrete(int(action.n))

    def observation(self, observation: Any) -> Any:
        """The environment's observation as stable-baselines3 is shown it."""
        if self._obs_start:
            return int(observation) - self._obs_start
        if self._scalar:
            return np.asarray(observation, dtype=self.observation_space.dtype).reshape(1)
        return observation

    def action(self, action: Any) -> Any:
        """stable-baselines3's action as the environment takes it (its own ids and dtype)."""
        if self._act_start:
            action = int(action) + self._act_start
        return env_action(self.env.action_space, action)

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        return self.observation(observation), info

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(self.action(action))
        return self.observation(observation), reward, terminated, truncated, info


def sb3_spaces(env: gym.Env) -> gym.Env:
    """:class:`SB3Spaces` over ``env`` where its spaces need it (module doc), else ``env``."""
    if (_offset(env.observation_space) or _offset(env.action_space) or _scalar_box(env.observation_space)
            or _integer_array(env.action_space)):
        return SB3Spaces(env)
    return env


__all__ = ["SB3Spaces", "env_action", "predicted_action", "sb3_spaces"]
