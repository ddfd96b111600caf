"""Record demonstrations by running a policy in a gymnasium-style environment."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from symlearn.data.demonstrations import Demonstrations
from symlearn.data.trajectory import Trajectory
from symlearn.errors import SymlearnError
from symlearn.progress import progress

Policy = Callable[[Any], Any]
Labeler = Callable[[Any], Iterable[str]]

DEFAULT_MAX_STEPS = 10_000


def _plain(value: Any) -> Any:
    """Observation or action as a value the data model accepts (numpy scalars -> Python)."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    return value


def record(
    env: Any,
    policy: Policy | str,
    n_episodes: int,
    seed: int | None = None,
    *,
    max_steps: int | None = None,
    labeler: Labeler | None = None,
    metadata: Mapping[str, Any] | None = None,
    desc: str = "recording",
) -> Demonstrations:
    """Run ``policy`` for ``n_episodes`` and return the episodes as demonstrations.

    ``policy`` maps an observation to an action, or is ``"random"`` (the seeded action space
    samples). ``labeler`` maps an observation to the propositions true in it. Episode ``i`` is
    reset with its own seed drawn from ``seed``, so one episode can be replayed alone; the seed,
    and whether the episode terminated or was truncated, go into the trajectory's ``info``.
    ``max_steps`` caps episodes without a time limit of their own.
    """
    if n_episodes < 1:
        raise SymlearnError(f"n_episodes must be at least 1, got {n_episodes}")
    if not (hasattr(env, "reset") and hasattr(env, "step")):
        raise SymlearnError(f"{type(env).__name__} is not an environment (needs reset() and step())")
    if isinstance(policy, str):
        if policy != "random":
            raise SymlearnError(f"unknown policy {policy!r}", hint="pass a callable or 'random'")
        policy = _random_policy(env, seed)
    spec = getattr(env, "spec", None)
    limit = max_steps or getattr(spec, "max_episode_steps", None) or DEFAULT_MAX_STEPS
    episode_seeds = np.random.SeedSequence(seed).generate_state(n_episodes).tolist()

    trajectories = []
    for episode_seed in progress(episode_seeds, total=n_episodes, desc=desc, unit="episode"):
        trajectories.append(_run_episode(env, policy, int(episode_seed), limit, labeler))
    meta = {"env": getattr(spec, "id", type(env).__name__), "seed": seed, "n_episodes": n_episodes}
    meta.update(metadata or {})
    return Demonstrations(trajectories, metadata=meta)


def _random_policy(env: Any, seed: int | None) -> Policy:
    space = env.action_space
    space.seed(seed)
    return lambda _observation: space.sample()


def _run_episode(env: Any, policy: Policy, seed: int, limit: int, labeler: Labeler | None) -> Trajectory:
    observation, _ = env.reset(seed=seed)
    states, actions, rewards = [_plain(observation)], [], []
    terminated = truncated = False
    while not (terminated or truncated) and len(actions) < limit:
        action = _plain(policy(observation))
        observation, reward, terminated, truncated, _ = env.step(action)
        actions.append(action)
        rewards.append(float(reward))
        states.append(_plain(observation))
    truncated = truncated or not terminated
    labels = [list(labeler(s)) for s in states] if labeler else None
    info = {"seed": seed, "terminated": bool(terminated), "truncated": bool(truncated)}
    return Trajectory(states, actions, rewards, labels, info)
