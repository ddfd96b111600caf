"""The bundled demonstrators behind one calling convention, so the registry can name them.

Every function here is ``expert(n, seed=0, env_kwargs=None, **fixed)``: ``n`` demonstrations (episodes) of
the entry's scripted expert in the environment built with ``env_kwargs`` (the user's
``--env-kwargs``), generated from ``seed``;
``fixed`` are the registry entry's own arguments. What comes back is what the entry's learners read:

* continuous-constraint and ICRL environments: :class:`~symlearn.data.Demonstrations` whose
  states are the environment's features (``info["features"]``) or observations;
* specification tasks: discrete state-id demonstrations of the optimal product policy;
* sub-goal tasks (``blocks-place-K``, ``blocks-stack-R``): a list of ``(T, 3 * blocks)`` frame
  arrays (NaN where the camera missed a block);
* rendered block tasks (``blockworld-*``): image demonstrations from the front camera (one per
  ordering of the task; ``n`` does not apply and is ignored).

The registry (:mod:`~symlearn.envs.registry`) refers to these as ``"module:attribute"``
strings; nothing here is imported until an expert is asked for.
"""

from __future__ import annotations

from typing import Any

from symlearn.errors import DataError


def _no_kwargs(name: str, kwargs: dict[str, Any] | None) -> None:
    # These demonstrators drive one fixed environment; a variant they were not written for
    # would silently give demonstrations of the wrong world.
    if kwargs:
        raise DataError(f"the scripted expert of {name} drives the default environment only, "
                        f"not one built with {', '.join(sorted(kwargs))}",
                        hint="drop --env-kwargs, or record your own demonstrations and give --demos")


def toy_navigation(n: int, seed: int = 0, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.toy_navigation import ToyNavigationEnv, expert_demonstrations

    return expert_demonstrations(n, seed=seed, env=ToyNavigationEnv(**env_kwargs) if env_kwargs else None)


def safenav(n: int, seed: int = 0, *, agent: str, task: str, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.safenav_expert import expert_demonstrations

    _no_kwargs(f"safenav-{agent}-{task}", env_kwargs)
    return expert_demonstrations(agent, task, n, seed=seed)


def driving(n: int, seed: int = 0, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.driving.expert import expert_demonstrations

    _no_kwargs("driving", env_kwargs)
    return expert_demonstrations(n, seed=seed)


def driving_constrained(n: int, seed: int = 0, *, constraint: str, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.driving.env import DrivingEnv
    from symlearn.envs.driving.expert import constrained_demonstrations

    env = DrivingEnv(**{"constraint": constraint, **(env_kwargs or {})})
    return constrained_demonstrations(n, seed=seed, constraint=constraint, env=env)


def blocked_point(n: int, seed: int = 0, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations

    return expert_demonstrations(n, seed=seed, env=BlockedPoint(**(env_kwargs or {})))


def spec_task(n: int, seed: int = 0, *, task: str, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task

    _no_kwargs(task, env_kwargs)
    return expert_demonstrations(get_task(task), n, seed=seed)


def block_world(n: int, seed: int = 0, *, kind: str, size: int, env_kwargs: dict[str, Any] | None = None) -> list:
    from symlearn.envs.block_world import Demonstrator, place_task, stack_task

    _no_kwargs(f"blocks-{kind}-{size}", env_kwargs)
    task = place_task(size) if kind == "place" else stack_task(size)
    runs, _ = Demonstrator(task, seed=seed).demonstrations(n)
    return runs


def rendered_blocks(n: int, seed: int = 0, *, task: str, env_kwargs: dict[str, Any] | None = None):
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations

    _no_kwargs(f"blockworld-{task.replace('-', '')}", env_kwargs)
    return demonstrations(task, seed=seed).front


def block_world_task(*, kind: str, size: int):
    """The :class:`~symlearn.envs.block_world.BlockTask` of a sub-goal entry (its feature names
    and default feature subsets)."""
    from symlearn.envs.block_world import place_task, stack_task

    return place_task(size) if kind == "place" else stack_task(size)


__all__ = ["block_world", "block_world_task", "blocked_point", "driving", "rendered_blocks", "safenav",
           "spec_task", "toy_navigation"]
