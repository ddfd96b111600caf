"""A numeric view of an environment whose observations are not one ``Box`` or ``Discrete``.

Our PPO and the learned costs read a flat vector per observation (or a ``Discrete`` index).
Third-party environments often observe more: MiniGrid's ``Dict(direction, image, mission)``
holds a text field; robotics suites return ``Dict(observation, achieved_goal, desired_goal)``.
:func:`numeric_observations` keeps every numeric part (``Box``, ``Discrete``, ``MultiBinary``,
``MultiDiscrete``, nested ``Dict``/``Tuple`` of those), drops the rest (text, graphs, sequences;
named in :attr:`NumericObservations.dropped`), and flattens what is kept with gymnasium's own
``flatten`` (``Discrete`` parts one-hot, ``Dict`` keys in sorted order), so a policy trained on
the view sees the same vector every time. An environment that is already ``Box`` or ``Discrete``
is returned unchanged.

A ``Dict`` or ``Tuple`` observation is also reported by name: ``info["features"]`` becomes
``{name: value}`` (where the environment reports no features of its own) with the names
:func:`~symlearn.data.record` and the Minari/imitation readers give its columns
(:mod:`symlearn.data.flat_observations`): a flat ``Dict`` of scalars by its keys (``cell``,
``key``), vector parts as ``pos[0]``, ``pos[1]``, nested parts as ``arm.joint[2]``; images are
left out. A DNF learned from those demonstrations (``cell < 3 & key > 0.5``, ``'pos[0]' > 0.3``)
then reads the same named values in ``train --cost``, not the one-hot columns the policy sees.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from symlearn.data.flat_observations import leaf_name, observation_features
from symlearn.errors import DataError

_NUMERIC = (spaces.Box, spaces.Discrete, spaces.MultiBinary, spaces.MultiDiscrete)


def _numeric_part(space: spaces.Space, path: str, dropped: list[str]) -> spaces.Space | None:
    """The numeric sub-space of ``space`` (``None`` when nothing numeric is left)."""
    if isinstance(space, _NUMERIC):
        return space
    if isinstance(space, spaces.Dict):
        kept = {}
        for key, sub in space.spaces.items():
            part = _numeric_part(sub, f"{path}{key}" if not path else f"{path}.{key}", dropped)
            if part is not None:
                kept[key] = part
        return spaces.Dict(kept) if kept else None
    if isinstance(space, spaces.Tuple):
        kept_t = [p for i, sub in enumerate(space.spaces)
                  if (p := _numeric_part(sub, f"{path}[{i}]", dropped)) is not None]
        if len(kept_t) != len(space.spaces):  # positions would shift: keep a Tuple only whole
            dropped.append(path or "observation")
            return None
        return spaces.Tuple(kept_t)
    dropped.append(path or "observation")
    return None


def _select(value: Any, kept: spaces.Space) -> Any:
    """The parts of an observation ``value`` that the numeric space ``kept`` holds."""
    if isinstance(kept, spaces.Dict):
        return {key: _select(value[key], sub) for key, sub in kept.spaces.items()}
    return value


def variable_size_parts(space: spaces.Space, path: str = "") -> list[str]:
    """The parts of ``space`` whose values have no fixed size (``Sequence``, ``Graph``), by path
    (``"observation"`` for the whole): what no demonstration column, policy input or cost input
    can hold. A ``Sequence`` of length 1 flattened like a Tuple looked like a vector until the
    length changed in the middle of a recording."""
    if isinstance(space, (spaces.Sequence, spaces.Graph)):
        return [path or "observation"]
    if isinstance(space, spaces.Dict):
        return [p for key, sub in space.spaces.items()
                for p in variable_size_parts(sub, f"{path}.{key}" if path else key)]
    if isinstance(space, spaces.Tuple):
        return [p for i, sub in enumerate(space.spaces) for p in variable_size_parts(sub, f"{path}[{i}]")]
    return []


def refuse_variable_size(space: spaces.Space, display: str) -> None:
    """A ``DataError`` for an observation space with a ``Sequence`` or ``Graph`` part, saying which
    part and what to do, before anything is recorded or trained."""
    parts = variable_size_parts(space)
    if parts:
        where = "" if parts == ["observation"] else f" (its part {', '.join(parts)})"
        raise DataError(f"{display} observes {space}{where}, whose values have no fixed size: symlearn records, "
                        "learns from and trains on fixed-size observations",
                        hint="wrap the environment in a gymnasium.ObservationWrapper whose observation_space is a "
                             "Box (pad or cut a Sequence to a fixed length; summarise a Graph in fixed features)")


class NumericObservations(gym.ObservationWrapper):
    """The numeric parts of ``env``'s observation, flattened to one ``Box`` (see the module doc)."""

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self.dropped: list[str] = []
        kept = _numeric_part(env.observation_space, "", self.dropped)
        if kept is None:
            refuse_variable_size(env.observation_space, "the environment")
            raise DataError(f"the observation space {env.observation_space} has no numeric part a policy or cost "
                            "could read", hint="wrap the environment in a gymnasium.ObservationWrapper whose "
                                               "observation_space is a Box or Discrete (text encoded as numbers, "
                                               "say); `symlearn data record` stores text observations as symbols")
        self._kept = kept
        flat = spaces.flatten_space(kept)
        self.observation_space = spaces.Box(flat.low.astype(np.float32), flat.high.astype(np.float32),
                                            dtype=np.float32)

        self.column_names = tuple(_view_names(kept, ()))   # one per entry of the flattened view
        # a Dict/Tuple is also reported by name (info["features"]), as record() names its columns
        self.named = isinstance(kept, (spaces.Dict, spaces.Tuple))

    def observation(self, observation: Any) -> np.ndarray:
        selected = _select(observation, self._kept)
        return np.asarray(spaces.flatten(self._kept, selected), dtype=np.float32)

    def from_columns(self, columns: Mapping[str, Any]) -> np.ndarray:
        """The view of an observation given as named columns -- a vector state that
        :func:`~symlearn.data.record` (or the Minari/imitation readers) stored with
        ``feature_names``, or a dict state -- rebuilt as the observation and flattened as
        :meth:`observation` does. A missing name is a ``DataError`` naming it."""
        return self.observation(_rebuild(self._kept, (), columns))

    def _named(self, observation: Any, info: dict) -> dict:
        if not self.named or not isinstance(info, dict) or "features" in info:
            return info
        features = observation_features(_select(observation, self._kept))
        if not features:
            return info
        info = dict(info)
        info["features"] = features
        return info

    def reset(self, **kwargs: Any):
        observation, info = self.env.reset(**kwargs)
        return self.observation(observation), self._named(observation, info)

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        return self.observation(observation), reward, terminated, truncated, self._named(observation, info)


def _rebuild(space: spaces.Space, path: tuple[str, ...], columns: Mapping[str, Any]) -> Any:
    """The observation of ``space`` whose leaves are named in ``columns`` (flat_observations' names)."""
    if isinstance(space, spaces.Dict):
        return {key: _rebuild(sub, path + (key,), columns) for key, sub in space.spaces.items()}
    if isinstance(space, spaces.Tuple):
        return tuple(_rebuild(sub, path + (f"_index_{i}",), columns) for i, sub in enumerate(space.spaces))
    name = leaf_name(path) if path else "observation"
    shape = tuple(space.shape or ())
    wanted = _record_names(space, path)   # the leaf's own columns
    missing = [w for w in wanted if w not in columns]
    if missing:
        raise DataError(f"the demonstrations name no column {missing[0]!r} of the observation's part {name!r}",
                        hint="known columns: " + ", ".join(list(columns)[:12]))
    values = np.asarray([columns[w] for w in wanted], dtype=np.float64)
    if isinstance(space, spaces.Discrete):
        return int(values[0])
    if isinstance(space, (spaces.MultiBinary, spaces.MultiDiscrete)):
        return values.reshape(shape).astype(np.int64)
    return values.reshape(shape).astype(space.dtype)


def _view_names(space: spaces.Space, path: tuple[str, ...]) -> list[str]:
    """A name per entry of ``spaces.flatten(space, ...)``: ``pos[0]``, a one-hot ``mode=2``."""
    if isinstance(space, spaces.Dict):
        return [n for key, sub in space.spaces.items() for n in _view_names(sub, path + (key,))]
    if isinstance(space, spaces.Tuple):
        return [n for i, sub in enumerate(space.spaces) for n in _view_names(sub, path + (f"_index_{i}",))]
    name = leaf_name(path) if path else "observation"
    if isinstance(space, spaces.Discrete):
        return [f"{name}={int(space.start) + v}" for v in range(int(space.n))]
    if isinstance(space, spaces.MultiDiscrete):
        return [f"{name}[{i}]={v}" for i, n in enumerate(np.asarray(space.nvec).reshape(-1)) for v in range(int(n))]
    size = int(np.prod(space.shape or ()))
    return [name] if not space.shape else [f"{name}[{i}]" for i in range(size)]


def _record_names(space: spaces.Space, path: tuple[str, ...] = ()) -> list[str]:
    """The names of the columns ``record()`` stores for one observation of a Dict/Tuple ``space``,
    in its order (:mod:`symlearn.data.flat_observations`: Dict keys sorted, Tuple entries by
    index, a scalar leaf one column, a vector leaf ``name[i]``)."""
    if isinstance(space, spaces.Dict):
        return [n for key in sorted(space.spaces) for n in _record_names(space.spaces[key], path + (key,))]
    if isinstance(space, spaces.Tuple):
        return [n for i, sub in enumerate(space.spaces) for n in _record_names(sub, path + (f"_index_{i}",))]
    name = leaf_name(path) if path else "observation"
    shape = tuple(space.shape or ())
    return [name] if not shape else [f"{name}[{i}]" for i in range(int(np.prod(shape)))]


def record_columns_width(space: spaces.Space) -> int:
    """How many columns ``record()`` stores for one observation of a Dict/Tuple ``space``."""
    return len(_record_names(space))


def from_record_columns(space: spaces.Space, row: Any) -> Any:
    """A Dict/Tuple observation of ``space`` rebuilt from the flat row ``record()`` stored for it
    without names (a Discrete leaf is one integer column there, where the numeric view one-hots it)."""
    values = np.asarray(row, dtype=np.float64).reshape(-1)
    names = _record_names(space)
    if len(values) != len(names):
        raise DataError(f"a row of {len(values)} numbers for an observation of {len(names)} columns")
    return _rebuild(space, (), dict(zip(names, values.tolist())))


def find_numeric_view(env: Any) -> NumericObservations | None:
    """The :class:`NumericObservations` among ``env``'s wrappers (under a joint-action wrapper,
    say: gymnasium's wrappers no longer hand their inner attributes on), or None."""
    while env is not None and not isinstance(env, NumericObservations):
        env = getattr(env, "env", None)
    return env


def numeric_observations(env: gym.Env) -> gym.Env:
    """``env`` itself when it observes a ``Box`` or ``Discrete``; else :class:`NumericObservations`."""
    if isinstance(env.observation_space, (spaces.Box, spaces.Discrete)):
        return env
    return NumericObservations(env)


__all__ = ["NumericObservations", "find_numeric_view", "from_record_columns", "numeric_observations",
           "record_columns_width", "refuse_variable_size", "variable_size_parts"]
