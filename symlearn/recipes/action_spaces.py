"""``MultiDiscrete`` and ``MultiBinary`` actions as one ``Discrete`` of their combinations.

symlearn's PPO (``train --algo ppo|ppo-lag``, the policies of ``learn icrl``) acts in ``Box`` and
``Discrete`` spaces. An environment whose action is a few small choices at once (``MultiDiscrete
([3, 3])``: steer and throttle; ``MultiBinary(4)``: four switches) is seen through
:class:`JointDiscreteActions`: action ``k`` of ``Discrete(prod(nvec))`` is the combination
``numpy.unravel_index(k, nvec)`` (plus the space's ``start``; row-major, the last entry fastest),
so the policy is the exact joint distribution over combinations. :meth:`~JointDiscreteActions.index_of`
maps a recorded action back, so demonstrations recorded in the environment itself fit the view.
More than :data:`MAX_JOINT_ACTIONS` combinations are refused (stable-baselines3's PPO acts in
such spaces as they are: ``train --algo sb3-ppo``).

>>> import gymnasium as gym
>>> from gymnasium import spaces
>>> class Two(gym.Env):
...     observation_space, action_space = spaces.Discrete(1), spaces.MultiDiscrete([2, 3], start=[0, -1])
>>> env = JointDiscreteActions(Two())
>>> env.action_space, env.action(5).tolist(), env.index_of([1, 1])
(Discrete(6), [1, 1], 5)
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.errors import DataError

#: the most combinations a MultiDiscrete/MultiBinary action space may have to be seen as one Discrete
MAX_JOINT_ACTIONS = 4096


def _choices(space: spaces.Space) -> tuple[np.ndarray, np.ndarray]:
    """``(nvec, start)``, flattened, of a MultiDiscrete or MultiBinary space."""
    if isinstance(space, spaces.MultiBinary):
        n = int(np.prod(space.shape, dtype=np.int64))
        return np.full(n, 2, dtype=np.int64), np.zeros(n, dtype=np.int64)
    nvec = np.asarray(space.nvec, dtype=np.int64).reshape(-1)
    start = np.asarray(getattr(space, "start", np.zeros_like(nvec)), dtype=np.int64).reshape(-1)
    return nvec, start


class JointDiscreteActions(gym.ActionWrapper):
    """``env`` with its MultiDiscrete or MultiBinary action space seen as ``Discrete(prod(nvec))``."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        original = env.action_space
        if not isinstance(original, (spaces.MultiDiscrete, spaces.MultiBinary)):
            raise DataError(f"only MultiDiscrete and MultiBinary action spaces have combinations, got {original}")
        self._nvec, self._start = _choices(original)
        self._shape, self._dtype = tuple(original.shape), original.dtype
        combinations = int(np.prod(self._nvec.astype(object)))  # Python ints: no overflow
        if combinations > MAX_JOINT_ACTIONS:
            raise DataError(f"the action space {original} has {combinations} combinations of actions, more than "
                            f"symlearn's PPO enumerates ({MAX_JOINT_ACTIONS})",
                            hint="train --algo sb3-ppo acts in it as it is")
        self.action_space = spaces.Discrete(combinations)

    def action(self, action: Any) -> np.ndarray:
        values = np.array(np.unravel_index(int(action), tuple(self._nvec)), dtype=np.int64) + self._start
        return values.reshape(self._shape).astype(self._dtype)

    def index_of(self, action: Any) -> int:
        """The ``Discrete`` id of one action of the environment's own space (as recorded)."""
        values = np.asarray(action).reshape(-1)
        if values.size != self._nvec.size or not np.all(values == np.round(values)):
            raise DataError(f"action {np.asarray(action).tolist()} is not one of {self.env.action_space}")
        shifted = values.astype(np.int64) - self._start
        if np.any(shifted < 0) or np.any(shifted >= self._nvec):
            raise DataError(f"action {np.asarray(action).tolist()} is outside {self.env.action_space}")
        return int(np.ravel_multi_index(tuple(shifted), tuple(self._nvec)))


class FlatBoxActions(gym.ActionWrapper):
    """``env`` with a ``Box`` action space of any shape but 1-D (a scalar ``Box(-1, 1, ())``, a
    matrix ``Box(-1, 1, (2, 3))``) seen as the flat ``Box`` of its entries, row-major: symlearn's
    PPO samples one Gaussian vector, and the environment gets it reshaped to its own shape. The
    bounds and dtype stay those of each entry, so nothing about the actions changes but their
    arrangement (recorded demonstrations store the same flat vector, :mod:`symlearn.data.recording`)."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        original = env.action_space
        if not isinstance(original, spaces.Box) or len(original.shape) == 1:
            raise DataError(f"only Box action spaces of other than one dimension are flattened, got {original}")
        self._shape = tuple(original.shape)
        self.action_space = spaces.Box(original.low.reshape(-1), original.high.reshape(-1), dtype=original.dtype)

    def action(self, action: Any) -> np.ndarray:
        return np.asarray(action, dtype=self.env.action_space.dtype).reshape(self._shape)


def policy_actions(env: gym.Env) -> gym.Env:
    """``env`` seen through the action view symlearn's PPO acts in: :class:`JointDiscreteActions`
    for MultiDiscrete/MultiBinary, :class:`FlatBoxActions` for a ``Box`` not 1-D; ``env`` itself
    otherwise."""
    space = env.action_space
    if isinstance(space, spaces.Box) and len(space.shape) != 1:
        return FlatBoxActions(env)
    return joint_discrete_actions(env)


def joint_discrete_actions(env: gym.Env) -> gym.Env:
    """:class:`JointDiscreteActions` over ``env`` when it acts in a MultiDiscrete or MultiBinary
    space; ``env`` itself otherwise."""
    if isinstance(env.action_space, (spaces.MultiDiscrete, spaces.MultiBinary)):
        return JointDiscreteActions(env)
    return env


def find_joint_actions(env: Any) -> JointDiscreteActions | None:
    """The :class:`JointDiscreteActions` among ``env``'s wrappers, or None."""
    while env is not None:
        if isinstance(env, JointDiscreteActions):
            return env
        env = getattr(env, "env", None)
    return None


__all__ = ["FlatBoxActions", "JointDiscreteActions", "policy_actions", "MAX_JOINT_ACTIONS", "find_joint_actions", "joint_discrete_actions"]
