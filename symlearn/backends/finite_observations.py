"""Refuse an observation that is not finite, at the step that produced it.

A NaN in an observation reaches a policy network as NaN logits; stable-baselines3 then fails deep
inside torch's distribution checks with a tensor dump. :class:`FiniteObservations` checks every
observation ``reset``/``step`` returns (numeric arrays; others pass) and raises a one-line
:class:`~symlearn.errors.DataError` naming the step, as our PPO's rollouts do.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.errors import DataError


class FiniteObservations(gym.Wrapper):
    """``env``, with every numeric observation checked to be finite."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._steps = 0

    def _checked(self, observation: Any) -> Any:
        array = np.asarray(observation) if not isinstance(observation, (dict, tuple)) else None
        if array is not None and array.dtype.kind == "f" and not np.isfinite(array).all():
            raise DataError(f"the observation is not finite (NaN or inf): {array.tolist()} (step {self._steps})",
                            hint="an environment must observe finite numbers on every step")
        return observation

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        return self._checked(observation), info

    def step(self, action: Any):
        self._steps += 1
        observation, reward, terminated, truncated, info = self.env.step(action)
        return self._checked(observation), reward, terminated, truncated, info


__all__ = ["FiniteObservations"]
