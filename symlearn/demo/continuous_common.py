"""Helpers of the continuous-constraint pipelines (``dnf``, ``safenav``): a log of the training
episodes, binned curves, evaluation episodes with trajectories, PNG output.

The pipelines import this module inside their ``run`` (it loads gymnasium and matplotlib).
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.atomic import write_bytes


class EpisodeLog(gym.Wrapper):
    """Logs every finished episode of the wrapped (cost-wrapped) environment as ``[end step over all
    copies, return, true cost, learned cost, reached a terminal state, length]``. The true cost is
    ``info["env_cost"]`` (the environment's own cost, which a :class:`~symlearn.backends.dnf_cost.DnfCostWrapper`
    keeps there), the learned one ``info["cost"]``. Copies share ``log`` and ``clock``."""

    def __init__(self, env: gym.Env, log: list, clock: list) -> None:
        super().__init__(env)
        self.log, self.clock = log, clock
        self._total = [0.0, 0.0, 0.0, 0]

    def reset(self, **kwargs: Any):
        self._total = [0.0, 0.0, 0.0, 0]
        return self.env.reset(**kwargs)

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        self.clock[0] += 1
        total = self._total
        total[0] += float(reward)
        total[1] += float(info.get("env_cost", 0.0))
        total[2] += float(np.sum(info.get("cost", 0.0)))
        total[3] += 1
        if terminated or truncated:
            self.log.append([self.clock[0], total[0], total[1], total[2], bool(terminated), total[3]])
        return observation, reward, terminated, truncated, info


def binned(log: list, total_steps: int, bins: int = 20) -> dict[str, list]:
    """Means of the logged episodes that ended in each of ``bins`` equal step ranges (None: none ended)."""
    rows = np.array(log, dtype=np.float64).reshape(-1, 6)
    edges = np.linspace(0, total_steps, bins + 1)
    out: dict[str, list] = {"steps": [int(e) for e in edges[1:]], "return": [], "true_cost": [], "learned_cost": [],
                            "terminal_rate": []}
    for lo, hi in zip(edges[:-1], edges[1:]):
        chosen = rows[(rows[:, 0] > lo) & (rows[:, 0] <= hi)]
        for key, column in (("return", 1), ("true_cost", 2), ("learned_cost", 3), ("terminal_rate", 4)):
            out[key].append(float(chosen[:, column].mean()) if len(chosen) else None)
    return out


def episodes(policy: Any, env: gym.Env, n: int, *, deterministic: bool, seed: int,
             position: Callable[[gym.Env, dict], Any], keep: int = 0) -> tuple[dict[str, float], list]:
    """``n`` episodes of ``policy`` on ``env`` (a cost wrapper around the environment): mean return,
    true and learned cost, share of episodes ending in a terminal state, length; and the first
    ``keep`` trajectories of ``position(env, info)``."""
    rng = np.random.default_rng(seed)
    rows, paths = [], []
    for episode in range(n):
        observation, info = env.reset(seed=seed + episode)
        path = [list(position(env, info))]
        total, true_cost, learned, length, done, terminated = 0.0, 0.0, 0.0, 0, False, False
        while not done:
            observation, reward, terminated, truncated, info = env.step(
                policy.act(observation, deterministic=deterministic, rng=rng))
            total += float(reward)
            true_cost += float(info.get("env_cost", 0.0))
            learned += float(np.sum(info.get("cost", 0.0)))
            length += 1
            path.append(list(position(env, info)))
            done = terminated or truncated
        rows.append((total, true_cost, learned, float(terminated), length))
        if episode < keep:
            paths.append(path)
    a = np.array(rows, dtype=np.float64)
    summary = {"return": float(a[:, 0].mean()), "true_cost": float(a[:, 1].mean()),
               "learned_cost": float(a[:, 2].mean()), "terminal_rate": float(a[:, 3].mean()),
               "length": float(a[:, 4].mean()), "episodes": n}
    return summary, paths


def save_png(fig: Any, path: str | Path) -> None:
    """Write a matplotlib figure as PNG atomically and close it."""
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


def pyplot():
    """matplotlib's pyplot on the Agg backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_curves(ax: Any, curve: dict[str, list], key: str, **style: Any) -> None:
    """One binned curve (bins without an ended episode left out)."""
    xs = [x for x, v in zip(curve["steps"], curve[key]) if v is not None and math.isfinite(v)]
    ys = [v for v in curve[key] if v is not None and math.isfinite(v)]
    ax.plot(xs, ys, **style)
