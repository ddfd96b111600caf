"""A user's ``step`` checked where a wrong value would otherwise surface deep inside a learner.

``_check_returns`` (:mod:`symlearn.recipes.environments`) looks at one reset and one step when a
user's environment is first built; a reward that goes wrong later (``None`` on the step a branch
forgot to return one, text, ``nan``) reached ``float()`` in the recorder or PPO's buffer and stopped
the command with ``internal error: TypeError``. :class:`CheckedRewards` reads each step's reward as
one finite number and refuses anything else in one line naming the environment and the step.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium
import numpy as np

from symlearn.errors import DataError


def _as_number(reward: Any) -> float | None:
    """``reward`` as a float, or None where it is no single real number."""
    if type(reward) is float:   # the usual case first: no numpy round trip per step
        return reward
    if isinstance(reward, (bool, np.bool_, int, float, np.integer, np.floating)):
        return float(reward)
    if reward is None or isinstance(reward, (str, bytes)):
        return None
    try:   # a 0-d or one-entry array or list: one number, as float() of it in the learners read it
        found = np.asarray(reward)
    except (TypeError, ValueError):
        return None
    if found.size == 1 and found.dtype.kind in "biuf":
        return float(found.reshape(-1)[0])
    return None


class CheckedRewards(gymnasium.Wrapper):
    """``env`` whose step rewards are each one finite number (returned as a float), else a
    one-line :class:`DataError` naming ``display``, the step within its episode and the value."""

    def __init__(self, env: gymnasium.Env, display: str) -> None:
        super().__init__(env)
        self._display = display
        self._step = 0

    def reset(self, **kwargs: Any) -> Any:
        self._step = 0
        return self.env.reset(**kwargs)

    def step(self, action: Any) -> Any:
        observation, reward, terminated, truncated, info = self.env.step(action)
        self._step += 1
        value = _as_number(reward)
        if value is None or not math.isfinite(value):
            shown = " ".join(repr(reward).split())[:80]
            what = "not finite" if value is not None else f"a {type(reward).__name__}, not a number"
            raise DataError(f"{self._display}: step {self._step} of an episode returned the reward {shown} "
                            f"({what})", hint="step must return (observation, reward, terminated, truncated, "
                                              "info) with the reward one finite float on every step")
        return observation, value, terminated, truncated, info


__all__ = ["CheckedRewards"]
