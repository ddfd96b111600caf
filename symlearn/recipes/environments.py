"""One way to name an environment: a bundled name, a gymnasium id, or ``module:EnvId``.

Every command that takes ``--env`` resolves it here, so all of them accept the same three forms:

* a bundled name (``toy-navigation``, ``office-1``; ``symlearn envs`` lists them), built from its
  registry entry (:mod:`symlearn.envs.registry`), which also names its expert and features;
* any id in gymnasium's registry (``CartPole-v1``, ``symlearn/toy-navigation-v0``), or one the
  installed package named by its stem registers on import (``MiniGrid-Empty-5x5-v0``: ``minigrid``
  is imported, as for ``minigrid:MiniGrid-Empty-5x5-v0``);
* ``module:EnvId`` -- gymnasium's ``make`` convention: ``module`` is imported (the current
  directory first, as for ``python -m``), and importing it must register ``EnvId``.

``--env-kwargs`` (a JSON object) is checked against the environment's constructor before
anything is built; an unknown key is an error naming the constructor's parameters.

>>> target = resolve_env("toy-navigation")
>>> target.entry.name, target.has_expert, target.feature_names()
('toy-navigation', True, ('x', 'y'))
>>> resolve_env("toy-navigaton")  # doctest: +ELLIPSIS
Traceback (most recent call last):
symlearn.errors.UnknownNameError: unknown environment 'toy-navigaton' (hint: did you mean 'toy-navigation'? ...)
"""

from __future__ import annotations

import importlib
import inspect
import json
import os
import re
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from difflib import get_close_matches
from pathlib import Path
from typing import Any

from symlearn.envs.registry import ENTRIES, Entry, Kind
from symlearn.envs.registry import get as get_entry
from symlearn.envs.registry import names as entry_names
from symlearn.errors import DataError, SymlearnError, UnknownNameError, clipped

#: keywords ``gymnasium.make`` itself takes, accepted for every gymnasium id
_MAKE_KEYWORDS = ("render_mode", "max_episode_steps", "disable_env_checker")


# --- --env-kwargs ------------------------------------------------------------------------------


def parse_env_kwargs(value: str | Mapping[str, Any] | None, *, flag: str = "--env-kwargs") -> dict[str, Any]:
    """``value`` as a dict: ``None`` -> ``{}``, a mapping as it is, a string read as strictly as a
    file (an object; duplicate keys, NaN, oversized numbers and deep nesting refused:
    :func:`symlearn.json_document.load_option_json`)."""
    if value is None:
        return {}
    if isinstance(value, Mapping):
        return dict(value)
    from symlearn.json_document import load_option_json

    try:
        return load_option_json(str(value), flag)
    except DataError as exc:
        raise DataError(exc.message, file=exc.file, line=exc.line, column=exc.column,
                        hint=exc.hint or 'give a JSON object, e.g. \'{"wall": -3.0}\'') from None


def _parameters(constructor: Callable[..., Any]) -> tuple[list[str], bool]:
    """(keyword parameter names, whether it takes ``**kwargs``) of a constructor."""
    try:
        signature = inspect.signature(constructor)
    except (TypeError, ValueError):
        return [], True  # a builtin or C extension: nothing to check against
    names = [n for n, p in signature.parameters.items() if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)
             and n != "self"]
    open_ended = any(p.kind == p.VAR_KEYWORD for p in signature.parameters.values())
    return names, open_ended


def _check_keys(kwargs: Mapping[str, Any], known: Sequence[str], open_ended: bool, display: str) -> None:
    if open_ended:
        return
    unknown = [key for key in kwargs if key not in known]
    if unknown:
        close = get_close_matches(unknown[0], list(known), n=1)
        raise DataError(f"unknown --env-kwargs key {unknown[0]!r} for {display}",
                        hint=(f"did you mean {close[0]!r}? " if close else "")
                        + ("its parameters: " + ", ".join(known) if known else "it takes no parameters"))


def record_hint(target: Any) -> str:
    """How to record demonstrations in ``target`` (an :class:`EnvTarget`) when it has no expert:
    the command as well as the Python call, since a user of the command line may not know it."""
    return (f"record them with `symlearn data record --env {target.name} --policy AGENT.safetensors -o demos.npz` "
            "-- a policy `symlearn train -o` saved, or `random` for aimless episodes -- or with "
            "symlearn.data.record(env, policy, n) in Python")


def _placeholder(name: str) -> str:
    # a required render_mode is gymnasium's to fill (make(..., render_mode=None)): null (no
    # rendering) is what training and recording want
    return "null" if name == "render_mode" else "..."


def _missing_hint(exc: BaseException, kwargs: Mapping[str, Any]) -> str | None:
    """For a constructor that lacks required arguments (``__init__(self, size)`` built without
    one), the ``--env-kwargs`` that gives them: Python names them in its message only."""
    # only the quoted names right after "missing N required ...: " -- gymnasium appends "... with
    # kwargs ({'speed': 0.1})", whose keys are not missing (they were named twice in the hint)
    found = re.search(r"missing \d+ required (?:positional |keyword-only )?arguments?: "
                      r"((?:'[A-Za-z_][A-Za-z0-9_]*'(?:,? and |, )?)+)", str(exc))
    if not isinstance(exc, TypeError) or found is None:
        return None
    names = [n for n in re.findall(r"'([A-Za-z_][A-Za-z0-9_]*)'", found.group(1)) if n not in kwargs]
    if not names:
        return None
    given = ", ".join([*(f'"{k}": {json.dumps(v)}' for k, v in kwargs.items()), *(f'"{k}": {_placeholder(k)}' for k in names)])
    return f"give {' and '.join(names)} in --env-kwargs '{{{given}}}'"


# --- features ----------------------------------------------------------------------------------


def parse_feature_names(text: str | Sequence[str], *, flag: str = "--features") -> tuple[str, ...]:
    """``"a,b"`` (or a sequence) as names: none empty, none twice."""
    names = [n.strip() for n in (text.split(",") if isinstance(text, str) else text)]
    if not names or any(not n for n in names):
        raise DataError(f"{flag}: every name must be non-empty, got {text!r}", hint="e.g. --features x,y")
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise DataError(f"{flag} names {name!r} twice", hint="give each column one name")
        seen.add(name)
    return tuple(names)


@dataclass(frozen=True)
class Features:
    """Where an environment's features come from and what they are called.

    ``source`` is ``"info"`` (``info["features"]``, a vector or a dict) or ``"observation"``
    (the flattened observation); ``names`` has one entry per column; ``named`` is False where
    nothing named them and they are the numbered ``x0 .. x{k-1}`` (``features(numbered=True)``).
    """

    names: tuple[str, ...]
    source: str
    named: bool = True


def _width(vector: Any) -> int | None:
    import numpy as np

    try:
        array = np.asarray(vector, dtype=np.float64)
    except (TypeError, ValueError):
        return None
    return int(array.size)


# --- the target --------------------------------------------------------------------------------


class CostWatch:
    """Whether any step of the environments it watches reported ``info["cost"]``.

    An environment may put ``info["cost"]`` only on the steps that pay it (a hazard hit), so
    whether it reports a ground-truth cost is read from every step it is seen to take -- training
    and evaluation alike -- not from its first: :attr:`seen` turns true at the first step whose
    ``info["cost"]`` is not None, and the steps without one then cost 0. ``EnvTarget.watched(watch)``
    builds every environment with this watch inside its other wrappers."""

    def __init__(self) -> None:
        self.seen = False

    def wrap(self, env: Any) -> Any:
        import gymnasium

        watch = self

        class CostWatched(gymnasium.Wrapper):
            """Tells the watch when a step reports ``info["cost"]``; changes nothing."""

            def step(self, action: Any):
                result = self.env.step(action)
                if not watch.seen:
                    info = result[-1]
                    watch.seen = isinstance(info, Mapping) and info.get("cost") is not None
                return result

        return CostWatched(env)


def features_and_observation(info: Any, observation: Any,
                             names: Sequence[str] | None = None) -> tuple[Any, Any] | None:
    """``info["features"]`` (a dict of named numbers or a vector) and ``observation`` as flat
    float vectors, or None where there are no features or either is not numbers (a ``Dict``
    observation, text): what tells whether an environment's features are its observation.
    ``names``: the order to read a dict's values in (a dict's own key order may change from step
    to step, and every cost reads it by name); keys other than ``names`` keep the dict's order."""
    import numpy as np

    raw = info.get("features") if isinstance(info, Mapping) else None
    if raw is None:
        return None
    if isinstance(raw, Mapping) and names is not None and set(map(str, raw)) == set(names):
        raw = {name: {str(k): v for k, v in raw.items()}[name] for name in names}
    try:
        values = np.asarray(list(raw.values()) if isinstance(raw, Mapping) else raw, dtype=np.float64).reshape(-1)
        return values, np.asarray(observation, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        return None


def _features_after_step(env: Any) -> bool:
    """Whether one step (a sampled action, after the reset just made) reports ``info["features"]``."""
    try:
        info = env.step(env.action_space.sample())[-1]
    except Exception:   # the environment's own failure is the command's to report, where it happens
        return False
    return isinstance(info, Mapping) and "features" in info


def same_numbers(a: Any, b: Any) -> bool:
    """Two flat vectors of one length and equal up to float noise."""
    import numpy as np

    return a.shape == b.shape and bool(np.allclose(a, b))


@dataclass
class EnvTarget:
    """A resolved ``--env``: how to build it, and what symlearn knows about it.

    ``entry`` is the bundled registry entry (``None`` for a user's environment), ``gym_id`` the
    gymnasium id (``None`` for a bundled entry without one, e.g. a sub-goal task), ``kwargs`` the
    checked ``--env-kwargs``.
    """

    name: str
    entry: Entry | None
    gym_id: str | None
    kwargs: dict[str, Any] = field(default_factory=dict)
    #: build through :func:`~symlearn.recipes.spaces.numeric_observations` (see :meth:`as_numeric`)
    numeric: bool = False
    #: with :attr:`numeric`, a MultiDiscrete/MultiBinary action space is also seen as one Discrete
    #: of its combinations (:mod:`symlearn.recipes.action_spaces`), for symlearn's PPO
    joint_actions: bool = False
    #: every environment built is watched for ``info["cost"]`` (see :meth:`watched`)
    watch: CostWatch | None = field(default=None, compare=False, repr=False)

    @property
    def display(self) -> str:
        return self.entry.name if self.entry is not None else self.name

    @property
    def bundled(self) -> bool:
        return self.entry is not None

    def has_kind(self, kind: Kind) -> bool:
        return self.entry is not None and kind in self.entry.kinds

    # building ----------------------------------------------------------------------------------

    def make(self) -> Any:
        """A fresh environment (a bundled one built directly, others through ``gymnasium.make``;
        seen through the numeric view of its observations when :attr:`numeric` is set)."""
        env = self._build()
        if self.watch is not None:  # innermost: the views' own attributes stay on the outside
            env = self.watch.wrap(env)
        if self.numeric:
            from symlearn.recipes.spaces import numeric_observations

            env = numeric_observations(env)
        if self.joint_actions:
            from symlearn.recipes.action_spaces import policy_actions

            env = policy_actions(env)
        return env

    def as_numeric(self, actions: bool = False) -> EnvTarget:
        """The same environment, observed as one ``Box`` (or ``Discrete``) that PPO and learned
        costs read, whatever it observes (MiniGrid's ``Dict`` with a text field, a goal-conditioned
        ``Dict``); an environment that observes a ``Box`` or ``Discrete`` is unchanged. With
        ``actions``, a ``MultiDiscrete``/``MultiBinary`` action space is seen as one ``Discrete``
        of its combinations (what symlearn's PPO acts in)."""
        from dataclasses import replace

        return replace(self, numeric=True, joint_actions=bool(actions))

    def watched(self, watch: CostWatch) -> EnvTarget:
        """The same environment, every copy built watched by ``watch`` (:class:`CostWatch`): after
        training and evaluating, ``watch.seen`` says whether any step reported ``info["cost"]``."""
        from dataclasses import replace

        return replace(self, watch=watch)

    def with_joint_actions(self) -> EnvTarget:
        """The same environment, observations unchanged, a ``MultiDiscrete``/``MultiBinary`` action
        space seen as one ``Discrete`` of its combinations (``learn spec``: its labeling reads the
        environment's own observations, its policies act in Box or Discrete spaces)."""
        from dataclasses import replace

        return replace(self, joint_actions=True)

    def _build(self) -> Any:
        if self.entry is not None:
            if self.entry.env is None:
                raise DataError(f"{self.display} has no gymnasium environment "
                                f"(it is a {', '.join(k.label for k in sorted(self.entry.kinds))})")
            build = lambda: self.entry.make_env(**self.kwargs)  # noqa: E731
        else:
            import gymnasium

            build = lambda: gymnasium.make(self.gym_id, **self.kwargs)  # noqa: E731
        try:
            env = build()
        except SymlearnError:
            raise
        except (TypeError, ValueError) as exc:  # a value of the wrong type ("wall": "left")
            raise DataError(f"--env-kwargs does not fit {self.display}: {type(exc).__name__}: {exc}"
                            if self.kwargs else f"building {self.display} failed: {type(exc).__name__}: {exc}",
                            hint=_missing_hint(exc, self.kwargs) or "check the environment's parameters") from None
        except ImportError as exc:
            missing = getattr(exc, "name", None) or str(exc)
            raise DataError(f"building {self.display} needs {missing}, which is not installed",
                            hint="see `symlearn doctor` for the optional extras") from None
        except Exception as exc:  # the user's own environment failed: say so in one line
            raise DataError(f"building {self.display} failed: {type(exc).__name__}: {exc}") from None
        if self.entry is None:
            _check_spaces(env, self.display)
            _check_reset_signature(env, self.display)
            _check_returns(build, self.display, (self.gym_id, repr(sorted(self.kwargs.items()))))
            from symlearn.recipes.step_checks import CheckedRewards

            env = CheckedRewards(env, self.display)   # a reward gone wrong later is one line, not a TypeError
        return env

    @property
    def env_fn(self) -> Callable[[], Any]:
        """A zero-argument constructor (for vectorised training)."""
        return self.make



    # names -------------------------------------------------------------------------------------

    @contextmanager
    def _probe(self, env: Any = None) -> Iterator[Any]:
        """``env``, or a fresh environment closed afterwards, to look at before any work."""
        if env is not None:
            yield env
            return
        env = self.make()
        try:
            yield env
        finally:
            env.close()

    def features(self, env: Any = None, override: str | Sequence[str] | None = None, *,
                 numbered: bool = False) -> Features | None:
        """The features a constraint reads: ``info["features"]`` where the environment reports
        them, else the observation; named by ``override`` (``--features``), else the keys of a
        dict ``info["features"]``, else the environment's ``feature_names`` attribute, else the
        entry's names. When nothing names them: ``None``, or with ``numbered`` the names
        ``learn dnf`` gives such columns, ``x0 .. x{k-1}`` (``named=False``). The count is checked."""
        with self._probe(env) as env:
            _, info = env.reset(seed=0)
            in_info = isinstance(info, Mapping) and "features" in info
            raw = info["features"] if in_info else None
            if in_info and isinstance(raw, Mapping):
                names = tuple(str(k) for k in raw)
                width = len(names)
                declared = _declared_names(env, self.entry)
                if declared is not None and sorted(declared) == sorted(names):
                    # the same names in the order the environment declares (a dict's key order
                    # is how it happened to be built, and may differ between steps)
                    names = declared
            else:
                width = _width(raw) if in_info else _feature_width(env)
                names = None
            declared_here = False   # named by the environment's feature_names: the error names it
            if override is not None:
                names = parse_feature_names(override)
            elif names is None:
                names = _declared_names(env, self.entry)
                declared_here = names is not None and self.entry is None
            if declared_here and len(set(names)) != len(names):
                repeated = sorted({n for n in names if names.count(n) > 1})
                raise DataError(f"{self.display}'s feature_names repeat {', '.join(repeated)}: "
                                f"{', '.join(names)}", hint="give each column its own name in feature_names, "
                                                            "or name them with --features a,b,...")
            if names is None:
                if not numbered or not width:
                    return None
                return Features(tuple(f"x{i}" for i in range(width)), "info" if in_info else "observation",
                                named=False)
            if width is not None and len(names) != width:
                if not in_info and _features_after_step(env):
                    # reported by step only: the names were put on the observation, and the hint
                    # (--features a,b) pointed away from what was missing
                    raise DataError(f"{self.display} reports info[\"features\"] after step but not after reset; "
                                    "where the features come from is read from reset's info",
                                    hint="return the features of the start state in reset's info too: "
                                         "return observation, {\"features\": ...}")
                where = 'info["features"]' if in_info else "the observation"
                counted = f"{len(names)} feature names ({', '.join(names)})"
                if declared_here:
                    counted = f"feature_names gives {counted}"
                raise DataError(f"{counted} for {width} columns of {where} "
                                f"of {self.display}", hint="give one name per column with --features a,b,..."
                                + (" or in the environment's feature_names" if declared_here else ""))
            return Features(tuple(names), "info" if in_info else "observation")

    def feature_names(self, env: Any = None, override: str | Sequence[str] | None = None) -> tuple[str, ...] | None:
        """The names of :meth:`features` (a sub-goal task's frame columns where there is no
        environment); ``None`` when nothing names them."""
        if self.entry is not None and env is None and (self.entry.env is None or self.entry.features):
            # named by the registry: no environment needs building (highway-env's takes seconds)
            return parse_feature_names(override) if override is not None else self.entry.feature_names()
        found = self.features(env, override)
        return None if found is None else found.names

    def observation_names(self, env: Any) -> tuple[str, ...] | None:
        """Names of the flattened observation's entries: ``observation_names``, else the
        feature names when there is one per observation entry (the common case of features
        that are the observation; a different count names something else)."""
        names = getattr(env.unwrapped, "observation_names", None)
        if names is not None:
            return tuple(names)
        from symlearn.recipes.spaces import find_numeric_view

        # the flattened view's names, also under a wrapper that sees MultiDiscrete actions as one Discrete
        view = getattr(find_numeric_view(env), "column_names", None)
        if view is not None and len(view) == observation_width(env):
            return tuple(view)
        found = self.features(env)
        if found is None:
            return None
        if found.source == "observation":
            return found.names
        if len(found.names) != observation_width(env):
            return None
        # info["features"] names its own numbers: they name the observation's entries only where
        # they are the observation (features (pos, vel) of an observation (vel, pos) name neither)
        observation, info = env.reset(seed=0)
        pair = features_and_observation(info, observation, found.names)
        return found.names if pair is not None and same_numbers(*pair) else None

    def reports_cost(self, env: Any = None, max_steps: int = 1000) -> bool:
        """Whether the environment reports a ground-truth cost (``info["cost"]``; the
        safety-gymnasium convention) on any step of one episode of random actions (at most
        ``max_steps``). A quick look only: an environment that reports a cost only on the steps
        that pay it may not show one here -- the commands decide from the steps training and
        evaluation take (:class:`CostWatch`). Where none is reported, costs are "n/a", never 0."""
        with self._probe(env) as env:
            env.reset(seed=0)
            env.action_space.seed(0)
            for _ in range(max_steps):
                _, _, terminated, truncated, info = env.step(env.action_space.sample())
                if isinstance(info, Mapping) and info.get("cost") is not None:
                    return True
                if terminated or truncated:
                    return False
            return False

    # experts -----------------------------------------------------------------------------------

    @property
    def has_expert(self) -> bool:
        """Whether a bundled scripted expert exists (a trained one is :attr:`trains_expert`)."""
        return self.entry is not None and self.entry.expert is not None

    @property
    def trains_expert(self) -> bool:
        """Whether a PPO-Lagrangian expert can be trained on the entry's true cost instead."""
        return self.entry is not None and self.entry.trained_expert

    def expert_demonstrations(self, n: int, seed: int = 0) -> Any:
        """``n`` demonstrations of the bundled scripted expert (in the ``--env-kwargs`` variant)."""
        if n < 1:
            raise DataError(f"--n-demos must be at least 1, got {n}")
        if not self.has_expert:
            raise DataError(f"{self.display} has no expert: give your demonstrations with --demos FILE",
                            hint=record_hint(self))
        return self.entry.expert(n, seed=seed, env_kwargs=dict(self.kwargs))


def _check_spaces(env: Any, display: str) -> None:
    """Every command reads ``observation_space`` and ``action_space`` before the first ``reset``; an
    environment that sets them later (in ``reset``) stopped with ``internal error: AttributeError``.
    Refused here in one line naming the class's file and line."""
    inner = getattr(env, "unwrapped", env)
    missing = [name for name in ("observation_space", "action_space") if getattr(inner, name, None) is None]
    if missing:
        try:
            where = {"file": inspect.getsourcefile(type(inner)), "line": inspect.getsourcelines(type(inner))[1]}
        except (TypeError, OSError):
            where = {}
        raise DataError(f"{display}: {type(inner).__name__} has no {' or '.join(missing)} once built", hint="set self.observation_space and self.action_space in __init__: they are read "
                                      "before the first reset", **where)


def _check_reset_signature(env: Any, display: str) -> None:
    """gymnasium's wrappers call ``reset(seed=..., options=...)``; a user's ``reset`` without those
    keywords (the pre-0.26 gym API) fails deep inside a learner with a TypeError that names no file
    of the user's: refuse it here, in one line naming the method's file and line."""
    reset = getattr(type(getattr(env, "unwrapped", env)), "reset", None)
    try:
        parameters = inspect.signature(reset).parameters
    except (TypeError, ValueError):   # a builtin or C extension: nothing to read
        return
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values()):
        return
    missing = [name for name in ("seed", "options") if name not in parameters]
    if missing:
        try:
            where = {"file": inspect.getsourcefile(reset), "line": inspect.getsourcelines(reset)[1]}
        except (TypeError, OSError):
            where = {}
        raise DataError(f"{display}: reset() takes no {' or '.join(repr(m) for m in missing)} argument, and "
                        "gymnasium calls reset(seed=..., options=...)",
                        hint="define reset(self, seed=None, options=None) and call super().reset(seed=seed)", **where)


#: the (id, kwargs) of users' environments whose reset and step returns were checked in this process
_RETURNS_CHECKED: set[tuple[Any, str]] = set()


def _check_returns(build: Callable[[], Any], display: str, key: tuple[Any, str]) -> None:
    """A user's ``reset`` must return ``(observation, info)`` and ``step`` five values (gymnasium's
    API since 0.26); the old gym API's observation alone and ``(observation, reward, done, info)``
    fail deep inside a learner as an unrelated IndexError or broadcast error. One reset and one
    step of a separate copy, once per environment and process, say so in one line instead. An
    exception the copy raises is left to the command, which reports it where it happens."""
    if key in _RETURNS_CHECKED:
        return
    _RETURNS_CHECKED.add(key)
    try:
        env = build()
    except Exception:
        return
    raw = getattr(env, "unwrapped", env)   # gymnasium's own wrappers (TimeLimit) would unpack the values first
    try:
        found = raw.reset(seed=0)
        if isinstance(found, tuple) and len(found) == 2 and not isinstance(found[1], Mapping):
            # two values, the second no dict ("returned a tuple of 2, not (observation, info)" read
            # as if the count were wrong)
            raise DataError(f"{display}: reset() returned (observation, {_shape_of(found[1])}), not (observation, "
                            "info) with info a dict", hint="return observation, {} (an empty dict where there is "
                                                           "nothing to report)")
        if not (isinstance(found, tuple) and len(found) == 2 and isinstance(found[1], Mapping)):
            raise DataError(f"{display}: reset() returned {_shape_of(found)}, not (observation, info)",
                            hint="gymnasium's API: return observation, {} (info a dict)")
        _check_box_size(raw.observation_space, found[0], display, "reset()")
        found = raw.step(raw.action_space.sample())
        if isinstance(found, tuple) and len(found) == 5 and not isinstance(found[4], Mapping):
            raise DataError(f"{display}: step() returned info as {_shape_of(found[4])}, not a dict",
                            hint="return observation, reward, terminated, truncated, {} (an empty dict where there "
                                 "is nothing to report)")
        if not (isinstance(found, tuple) and len(found) == 5):
            raise DataError(f"{display}: step() returned {_shape_of(found)}, not (observation, reward, terminated, "
                            "truncated, info)", hint="gymnasium's API: the old done is terminated (the task ended) "
                                                     "or truncated (a time limit)")
        _check_box_size(raw.observation_space, found[0], display, "step()")
    except SymlearnError:
        _RETURNS_CHECKED.discard(key)
        raise
    except Exception:
        pass
    finally:
        try:
            env.close()
        except Exception:
            pass


def _check_box_size(space: Any, observation: Any, display: str, where: str) -> None:
    """A ``Box`` observation must hold as many numbers as the space declares: PPO's buffers are
    sized from the space, and an observation of 3 numbers for a ``(2,)`` space stopped training
    with an internal "could not broadcast" error (gymnasium only warns). Shapes that hold the
    same numbers (a list, a float for ``(1,)``) are left alone, as the learners read them."""
    shape = getattr(space, "shape", None)
    if type(space).__name__ != "Box" or shape is None:
        return
    import numpy as np   # here: the commands that never build an environment start without numpy

    try:
        size = np.asarray(observation, dtype=float).size
    except (TypeError, ValueError):
        size = None
    if size != int(np.prod(shape, dtype=np.int64)):
        shown = _shape_of(observation) if size is None else f"an observation of shape {np.shape(observation)}"
        raise DataError(f"{display}: {where} returned {shown}, but its observation_space is "
                        f"{' '.join(str(space).split())}",
                        hint="return observations of the declared shape, or declare the shape they have")


def _shape_of(value: Any) -> str:
    if value is None:
        return "None"
    return f"a tuple of {len(value)}" if isinstance(value, tuple) else f"one {type(value).__name__}"


def observation_width(env: Any) -> int | None:
    """Entries of the flattened observation (``None`` for a space without a shape, e.g.
    ``Discrete``; 1 for a scalar ``Box``)."""
    from gymnasium import spaces   # imported already: the environment is gymnasium's

    space = getattr(env, "observation_space", None)
    shape = getattr(space, "shape", None)
    if shape == () and isinstance(space, spaces.Box):   # a subclass of Box is one too
        return 1
    if not shape:
        return None
    width = 1
    for dim in shape:
        width *= int(dim)
    return width


def _feature_width(env: Any) -> int | None:
    """Columns of the observation as features: its flattened width, and 1 for a ``Discrete``
    observation, whose one number (the state's index) is a feature as a scalar ``Box`` is; so
    it gets the default name ``x0`` where a ``Box`` gets ``x0, x1, ...`` (labelings, DNF rules)."""
    from gymnasium import spaces

    width = observation_width(env)
    if width is None and isinstance(getattr(env, "observation_space", None), spaces.Discrete):
        return 1
    return width


def _declared_names(env: Any, entry: Entry | None) -> tuple[str, ...] | None:
    try:   # a property or method of the user's: its exception is theirs, in one located line
        names = getattr(env.unwrapped, "feature_names", None)
        if callable(names):
            names = names()
    except Exception as exc:  # noqa: BLE001
        raise DataError(f"reading {type(env.unwrapped).__name__}.feature_names raised {type(exc).__name__}: {exc}",
                        hint="feature_names must give the column names without raising (before and after reset)",
                        **_innermost_frame(exc)) from None
    if isinstance(names, str):  # feature_names = "xy" is one name, not the names "x" and "y"
        names = (names,)
    if names is not None:
        return tuple(str(n) for n in names)
    return entry.feature_names() if entry is not None else None


# --- resolution --------------------------------------------------------------------------------


def resolve_env(name: str, kwargs: str | Mapping[str, Any] | None = None, *, kind: Kind | None = None,
                what: str | None = None) -> EnvTarget:
    """The environment named ``name`` (see the module doc), with ``kwargs`` checked.

    ``kind``: a bundled name must be an entry of that kind (a user's environment is taken as
    it is); ``what`` names the thing in messages (default "environment").
    """
    if not isinstance(name, str) or not name.strip():
        raise DataError("--env is empty", hint="a bundled name (symlearn envs), a gymnasium id, or module:EnvId")
    name = name.strip()
    kwargs = parse_env_kwargs(kwargs)
    if ":" in name:
        return _from_module(name, kwargs)
    key = name.lower()
    if key in entry_names():
        entry = get_entry(key, kind, what=what) if kind is not None else get_entry(key)
        return _bundled(name, entry, kwargs)
    gymnasium = _gymnasium()
    import symlearn.envs  # noqa: F401 -- registers the symlearn/ ids

    if name in gymnasium.registry:
        bundled = _entry_with_gym_id(name)
        if bundled is not None:  # symlearn/toy-navigation-v0: the entry, with its expert
            return _bundled(name, bundled, kwargs)
        return _registered(name, name, kwargs)
    registering = _registering_package(name)
    if registering is not None:
        try:  # MiniGrid-Empty-5x5-v0 is minigrid's: as if the user had written minigrid:MiniGrid-Empty-5x5-v0
            return _from_module(f"{registering}:{name}", kwargs)
        except UnknownNameError:  # the package registers no such id: the name is unknown after all
            pass
    raise _unknown(name, gymnasium, kind, what)


def _registering_package(name: str) -> str | None:
    """The installed package an unknown gymnasium id is probably registered by on import
    (``MiniGrid-Empty-5x5-v0`` -> ``minigrid``, ``highway-v0`` -> ``highway_env``), or None: only
    for a name shaped like an id (``Name-vN``) that is no misspelling of a bundled name. A
    misspelt registered id is tried too: its stem rarely names a package, and where it does the
    package is imported, registers other ids, and "did you mean" follows (a closeness test
    first would turn real ids away: ``Zorkland-v0`` is "close" to ``Broken-v0``)."""
    if not re.fullmatch(r"[A-Za-z][\w.]*(-[\w.]+)*-v\d+", name):
        return None
    if get_close_matches(name.lower(), list(entry_names()), n=1):
        return None
    return _installed_package(name.split("-")[0].lower())


def _entry_with_gym_id(gym_id: str) -> Entry | None:
    """The bundled entry a gymnasium id names (the first, for a world several tasks share)."""
    return next((e for e in ENTRIES if e.gym_id == gym_id), None)


def _bundled(name: str, entry: Entry, kwargs: dict[str, Any]) -> EnvTarget:
    if kwargs:
        if entry.env is None:
            raise DataError(f"{entry.name} has no environment to pass --env-kwargs to")
        known, _ = _parameters(entry.env.resolve())
        # Our own factories name every keyword they take (a robot's extra ``**kwargs`` are
        # passed on unchecked by MuJoCo, so a misspelt key would silently do nothing).
        _check_keys(kwargs, known, False, entry.name)
        _check_types(kwargs, entry.env.resolve(), entry.name)
    return EnvTarget(name, entry, entry.gym_id, kwargs)


def _check_types(kwargs: Mapping[str, Any], constructor: Callable[..., Any], display: str) -> None:
    """A bundled environment's keyword of a number, text or flag default given a value of another
    JSON type (``{"max_steps": "10"}``): one line, where the constructor would compare a string
    with a number and fail as an internal error."""
    import numbers

    try:
        parameters = inspect.signature(constructor).parameters
    except (TypeError, ValueError):
        return
    for key, value in kwargs.items():
        default = parameters[key].default if key in parameters else inspect.Parameter.empty
        if isinstance(default, bool):
            expected, fits = "true or false", isinstance(value, bool)
        elif isinstance(default, numbers.Real):
            expected, fits = "a number", isinstance(value, numbers.Real) and not isinstance(value, bool)
        elif isinstance(default, str):
            expected, fits = "a string", isinstance(value, str)
        else:
            continue  # no default, or None: the constructor's own checks decide
        if not fits:
            raise DataError(f"--env-kwargs {key!r} of {display} must be {expected} (default {default!r}), "
                            f"not {clipped(json.dumps(value))}",
                            hint=f"e.g. '{{\"{key}\": {json.dumps(default)}}}'")


def _registered(name: str, gym_id: str, kwargs: dict[str, Any], display: str | None = None) -> EnvTarget:
    gymnasium = _gymnasium()
    spec = gymnasium.spec(gym_id)
    if kwargs:
        constructor = spec.entry_point
        if isinstance(constructor, str):
            from gymnasium.envs.registration import load_env_creator

            try:
                constructor = load_env_creator(constructor)
            except Exception as exc:  # the id's module itself is broken
                raise DataError(f"{gym_id}'s entry point {spec.entry_point!r} does not load: "
                                f"{type(exc).__name__}: {exc}") from None
        known, open_ended = _parameters(constructor)
        known = [*known, *(k for k in _MAKE_KEYWORDS if k not in known)]
        _check_keys(kwargs, known, open_ended, display or gym_id)
    return EnvTarget(name, None, gym_id, kwargs)


def _from_module(name: str, kwargs: dict[str, Any]) -> EnvTarget:
    module, _, env_id = name.partition(":")
    module, env_id = module.strip(), env_id.strip()
    if not module or not env_id:
        raise DataError(f"--env {name!r}: write module:EnvId", hint="e.g. --env my_robot:MyRobot-v0")
    gymnasium = _gymnasium()
    before = set(gymnasium.registry)
    _import_user_module(module)
    import symlearn.envs  # noqa: F401 -- `symlearn.envs:symlearn/toy-navigation-v0` works too

    if env_id not in gymnasium.registry:
        class_id = _registered_class(module, env_id, gymnasium)
        if class_id is not None:
            return _registered(name, class_id, kwargs, display=name)   # the user's name, not our id
        added = sorted(set(gymnasium.registry) - before)
        own = added or sorted(i for i, s in gymnasium.registry.items() if _defined_in(s.entry_point, module))
        own = [i for i in own if not i.startswith(f"{module}/")]   # the ids module:ClassName registered
        classes = _env_classes(module, gymnasium)
        close = get_close_matches(env_id, own + classes or list(gymnasium.registry), n=1)
        hint = (f"did you mean {module}:{close[0]}? " if close else "") + (
            f"it registers: {', '.join(own[:10])}" if own else
            "it registered no gymnasium id: call gymnasium.register(id=..., entry_point=...) at import, "
            "or name a gymnasium.Env class it defines (module:ClassName)") + (
            f"; its gymnasium.Env classes: {', '.join(classes[:10])}" if classes else "")
        raise UnknownNameError(f"module {module!r} did not register the gymnasium id {env_id!r} "
                               f"and defines no gymnasium.Env class of that name", hint=hint)
    bundled = _entry_with_gym_id(env_id)
    if bundled is not None:
        return _bundled(name, bundled, kwargs)
    return _registered(name, env_id, kwargs)


def _registered_class(module: str, name: str, gymnasium: Any) -> str | None:
    """The gymnasium id under which ``module``'s ``gymnasium.Env`` class ``name`` is registered
    for ``module:ClassName`` (registered here, once, as ``module/ClassName``), or None where the
    module defines no such class. A module that only defines its class is as usable as one that
    registers it; the id gets no time limit, as the class has none (episodes end when it says)."""
    found = getattr(sys.modules.get(module), name, None)
    if not (inspect.isclass(found) and issubclass(found, gymnasium.Env)):
        if found is not None and callable(found):
            raise UnknownNameError(f"{module}:{name} is {'a class' if inspect.isclass(found) else 'a function'} "
                                   f"but no gymnasium.Env class, and no registered gymnasium id",
                                   hint=f"register it: gymnasium.register(id={name + '-v0'!r}, entry_point={name}) "
                                        f"in {module}, then --env {module}:{name}-v0")
        return None
    gym_id = f"{module}/{name}"
    if gym_id not in gymnasium.registry:
        gymnasium.register(id=gym_id, entry_point=found)
    return gym_id


def _env_classes(module: str, gymnasium: Any) -> list[str]:
    """Names of the ``gymnasium.Env`` classes ``module`` itself defines (not those it imports)."""
    found = vars(sys.modules.get(module) or object())
    return sorted(k for k, v in found.items() if inspect.isclass(v) and issubclass(v, gymnasium.Env)
                  and getattr(v, "__module__", None) == module)


def _defined_in(entry_point: Any, module: str) -> bool:
    where = entry_point.split(":")[0] if isinstance(entry_point, str) else getattr(entry_point, "__module__", "")
    return where == module or str(where).startswith(module + ".")


def _import_user_module(module: str) -> None:
    if module.endswith(".py") or "/" in module or "\\" in module:  # a file's path, not a module's name
        path = Path(module)
        name = path.stem if path.suffix == ".py" else path.name
        folder = str(path.parent) if str(path.parent) not in ("", ".") else "its folder"
        raise UnknownNameError(f"--env takes a module's name, not a file: {module!r}",
                               hint=f"run from {folder} with --env {name}:..., or add that folder to PYTHONPATH")
    # As for `python -m`: the current directory is importable.
    cwd = os.getcwd()
    if cwd not in sys.path and "" not in sys.path:
        sys.path.insert(0, cwd)
    try:
        importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and (module == exc.name or module.startswith(exc.name + ".")):
            raise UnknownNameError(f"no module named {module!r} (for --env {module}:...)",
                                   hint=f"run from the folder that holds {module.split('.')[0]}.py, or add it to "
                                        "PYTHONPATH; a package must be installed") from None
        raise DataError(f"importing module {module!r} failed: ModuleNotFoundError: {exc}",
                        hint=f"{module} needs a package that is not installed") from None
    except SymlearnError:
        raise
    except SyntaxError as exc:
        raise DataError(f"importing module {module!r} failed: SyntaxError: {exc.msg}", file=exc.filename,
                        line=exc.lineno, column=exc.offset) from None
    except BaseException as exc:  # noqa: BLE001 -- the module's own error, in one line
        if isinstance(exc, KeyboardInterrupt):
            raise
        where = _innermost_frame(exc)
        raise DataError(f"importing module {module!r} failed: {type(exc).__name__}: {exc}", **where) from None


def _innermost_frame(exc: BaseException) -> dict[str, Any]:
    tb = exc.__traceback__
    last = None
    while tb is not None:
        last = tb
        tb = tb.tb_next
    if last is None:
        return {}
    return {"file": last.tb_frame.f_code.co_filename, "line": last.tb_lineno}


def _unknown(name: str, gymnasium: Any, kind: Kind | None, what: str | None) -> UnknownNameError:
    bundled = [e.name for e in ENTRIES if kind is None or kind in e.kinds]
    close = get_close_matches(name.lower(), bundled, n=1)
    hint = f"did you mean {close[0]!r}? " if close else gymnasium_id_hint(name)
    if kind is not None:
        hint += f"bundled: {', '.join(bundled)}; or "
    hint += "a bundled name (symlearn envs), a gymnasium id, or module:EnvId"
    return UnknownNameError(f"unknown {what or 'environment'} {name!r}", hint=hint)


def gymnasium_id_hint(name: str) -> str:
    """What an unknown environment name probably meant among gymnasium ids (the start of a hint,
    ending in a space; ``""`` when nothing): the closest registered id, else, for a name shaped
    like an id, the ``package:ID`` that registers it on import (``highway_env:highway-v0`` where
    that package is installed)."""
    from difflib import SequenceMatcher, get_close_matches

    gymnasium = _gymnasium()
    ids = [i for i in gymnasium.registry if not i.startswith("symlearn/")]
    close = get_close_matches(name.strip(), ids, n=1)
    shaped = "-" in name and "/" not in name and ":" not in name
    package = name.split("-")[0].lower()
    found = _installed_package(package) if shaped else None
    # an installed package named by the id's stem beats a loose likeness to some registered id
    # (a user module's 'Corridor-v0' was offered for 'zorkworld-v0' beside zorkworld_env); a
    # near-spelling of a registered id (a typo) still wins
    if close and (found is None or SequenceMatcher(None, name.strip(), close[0]).ratio() >= 0.8):
        return f"did you mean {close[0]!r}? "
    if found is not None:  # highway-v0 is registered by importing highway_env
        return f"did you mean {found}:{name}? (its package registers it on import); "
    if not shaped:
        return ""
    return f"an id a package registers on import is named package:ID (e.g. {package}:{name}); "


def _installed_package(stem: str) -> str | None:
    """The installed module a gymnasium id's stem most likely names (``highway`` ->
    ``highway_env``), found without importing it; None when none is."""
    from importlib.util import find_spec

    for candidate in (stem, f"{stem}_env", f"gym_{stem}", f"{stem}_gym", f"{stem}_gymnasium"):
        if not candidate.isidentifier():
            continue
        try:
            if find_spec(candidate) is not None:
                return candidate
        except (ImportError, ValueError):  # a broken package is not a suggestion
            continue
    return None


def _gymnasium() -> Any:
    try:
        import gymnasium
    except ImportError:  # pragma: no cover - a core dependency
        raise DataError("gymnasium is not installed", hint="pip install gymnasium") from None
    return gymnasium


__all__ = ["CostWatch", "EnvTarget", "Features", "gymnasium_id_hint", "observation_width", "parse_env_kwargs",
           "parse_feature_names", "resolve_env"]
