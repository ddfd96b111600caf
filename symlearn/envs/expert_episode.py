"""One episode of a scripted expert recorded as feature states: what the SafeNav and driving
experts share (both record ``info["features"]`` of every state reached, the expert's actions,
rewards and per-state labels)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np


def record_episode(env: Any, act: Callable[[], np.ndarray], seed: int,
                   label: Callable[[dict[str, Any]], tuple[str, ...]],
                   start: Callable[[], Any] | None = None) -> tuple[np.ndarray, np.ndarray, list, list, dict]:
    """``(states, actions, rewards, labels, last_info)`` of one episode from ``env.reset(seed=seed)``
    until it terminates or is truncated; ``start()`` runs right after the reset (an expert that
    reads the new scene), ``act()`` gives the next action, ``label(info)`` the labels of the state
    an ``info`` describes."""
    _, info = env.reset(seed=seed)
    if start is not None:
        start()
    states, actions, rewards, labels = [info["features"]], [], [], [label(info)]
    done = False
    while not done:
        action = np.asarray(act(), dtype=np.float64)
        _, reward, terminated, truncated, info = env.step(action)
        done = terminated or truncated
        states.append(info["features"])
        actions.append(action)
        rewards.append(reward)
        labels.append(label(info))
    return np.array(states), np.array(actions), rewards, labels, info
