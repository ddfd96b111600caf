"""Record demonstrations by running a policy in a gymnasium-style environment."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import inspect

import numpy as np

from symlearn.data.demonstrations import Demonstrations
from symlearn.data.kinds import NonFiniteValues
from symlearn.data.flat_observations import has_parts, is_symbolic_mapping, observation_columns
from symlearn.data.trajectory import Trajectory
from symlearn.errors import DataError, SymlearnError
from symlearn.progress import progress

Policy = Callable[[Any], Any]
Labeler = Callable[..., Iterable[str]]  # (observation, info) -> names, or (observation) -> names

DEFAULT_MAX_STEPS = 10_000


def _plain(value: Any) -> Any:
    """Observation or action as a value the data model accepts (numpy scalars -> Python)."""
    if isinstance(value, np.generic) or (isinstance(value, np.ndarray) and value.ndim == 0):
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
    observation: Callable[[Any], Any] | None = None,
    metadata: Mapping[str, Any] | None = None,
    desc: str = "recording",
) -> Demonstrations:
    """Run ``policy`` for ``n_episodes`` and return the episodes as demonstrations.

    ``policy`` maps an observation to an action, or is ``"random"`` (the seeded action space
    samples). ``labeler(observation, info)`` returns the propositions true at a step, given the
    observation and the ``info`` dict ``reset``/``step`` returned with it (a labeler taking one
    argument gets the observation only, one taking three also the unwrapped environment, for
    what neither shows); the labels are stored with the trajectory, so learners
    can work from the file alone. Episode ``i`` is
    reset with its own seed drawn from ``seed``, so one episode can be replayed alone; the seed,
    and whether the episode terminated or was truncated, go into the trajectory's ``info``.
    ``max_steps`` caps episodes without a time limit of their own. ``observation`` maps each
    observation to what is stored (e.g. ``lambda o: o["image"]`` for a dict holding an image,
    which a trajectory cannot store as it is); policy and labeler see the observation itself.
    Without it, a ``Dict``/``Tuple`` observation holding vectors or nested parts is stored as one
    vector per step, its columns named in ``metadata["feature_names"]`` (``pos[0]``,
    ``arm.joint[1]``: :mod:`symlearn.data.flat_observations`, the names ``train`` reports in
    ``info["features"]``); a flat dict of numbers is stored as it is.
    """
    if n_episodes < 1:
        raise SymlearnError(f"n_episodes must be at least 1, got {n_episodes}")
    if not (hasattr(env, "reset") and hasattr(env, "step")):
        raise SymlearnError(f"{type(env).__name__} is not an environment (needs reset() and step())")
    if isinstance(policy, str):
        if policy != "random":
            raise SymlearnError(f"unknown policy {policy!r}", hint="pass a callable or 'random'")
        policy = _random_policy(env, seed)
    stored_action = _check_action_space(getattr(env, "action_space", None))
    spec = getattr(env, "spec", None)
    limit = max_steps or getattr(spec, "max_episode_steps", None) or DEFAULT_MAX_STEPS
    episode_seeds = np.random.SeedSequence(seed).generate_state(n_episodes).tolist()

    trajectories = []
    flat = _FlatStates()
    for episode_seed in progress(episode_seeds, total=n_episodes, desc=desc, unit="episode"):
        trajectories.append(_run_episode(env, policy, int(episode_seed), limit, labeler, observation or flat,
                                         stored_action))
    meta = {"env": getattr(spec, "id", type(env).__name__), "seed": seed, "n_episodes": n_episodes}
    if flat.names is not None:
        meta["feature_names"] = flat.names
    meta.update(metadata or {})
    return Demonstrations(trajectories, metadata=meta)


def _check_action_space(space: Any) -> Callable[[Any], Any]:
    """What a trajectory stores of one action of ``space``: a ``Box`` of other than one dimension
    (``Box(-1, 1, (2, 3))``, a scalar ``Box(-1, 1, ())``) as its flat vector, row-major -- the actions symlearn's PPO samples
    for it (:class:`symlearn.recipes.action_spaces.FlatBoxActions`), so recorded and trained
    actions are one kind of thing; any other action as it is. Refuses, before any episode runs,
    the rest a trajectory cannot store (one id or 1-D vector per action): composite actions and
    ``MultiDiscrete``/``MultiBinary`` arrays of two or more dimensions, where the episodes would
    otherwise all run before the first one failed to store."""
    if space is not None and (hasattr(space, "spaces") or hasattr(space, "feature_space")
                              or hasattr(space, "node_space")):
        # a Tuple/Dict of parts (a Sequence, a Graph): the first step stopped with numpy's
        # "setting an array element with a sequence ... inhomogeneous shape", an internal error
        described = " ".join(str(space).split())
        raise DataError(f"the action space {described} acts in composite values; demonstrations store one id or "
                        "1-D vector per action",
                        hint="wrap the environment in a gymnasium ActionWrapper whose action space is one Box, "
                             "Discrete, MultiDiscrete or MultiBinary (a Tuple(Discrete(2), Box(-1, 1, (1,))) as "
                             "Box(-1, 1, (2,)), say)")
    shape = getattr(space, "shape", None)
    if space is None or shape is None:
        return lambda action: action
    if len(shape) != 1 and hasattr(space, "low") and hasattr(space, "high"):   # a Box (no gymnasium import)
        return lambda action: np.asarray(action).reshape(-1)   # a scalar Box's too: a vector of one
    if len(shape) < 2:
        return lambda action: action
    described = " ".join(str(space).split())  # MultiDiscrete's repr spans lines
    raise DataError(f"the action space {described} acts in arrays of shape {tuple(shape)}; demonstrations store one "
                    f"id or 1-D vector per action",
                    hint="wrap the environment in a gymnasium ActionWrapper whose action space is the flat "
                         "Box or MultiDiscrete (reshape each action to the environment's shape)")


class UnstorableObservations(DataError):
    """The observations hold a part a trajectory cannot store as it is (an image inside a ``Dict``,
    MiniGrid's); ``record(..., observation=...)`` chooses what to keep instead."""


class _FlatStates:
    """What ``record`` stores of an observation when the caller chose nothing: the observation
    itself, except a ``Dict``/``Tuple`` holding vectors or nested parts, which becomes one vector
    with a name per column (:mod:`symlearn.data.flat_observations`: the names Minari reading gives
    and ``train --cost`` reports in ``info["features"]``). A flat mapping of numbers stays a
    symbolic state."""

    def __init__(self) -> None:
        self.names: list[str] | None = None

    def __call__(self, observation: Any) -> Any:
        nested = has_parts(observation) and not isinstance(observation, list)  # a list is stored as given
        if not nested or is_symbolic_mapping(observation):
            return observation
        try:
            vector, names = observation_columns(observation, "the observation")
        except DataError as exc:
            keys = ", ".join(map(str, observation)) if isinstance(observation, Mapping) else ""
            raise UnstorableObservations(f"the observations cannot be stored as they are: {exc.message}",
                                         hint="choose what to keep with record(..., observation=lambda o: o[KEY])"
                                              + (f"; keys: {keys}" if keys else "")) from None
        if self.names is None:
            self.names = names
        elif names != self.names:
            raise DataError(f"the observation's entries changed between steps: {names} after {self.names}",
                            hint="an observation space keeps its keys and shapes")
        return vector


def _names(found: Any) -> list[str]:
    if isinstance(found, (str, bytes)) or not isinstance(found, Iterable):
        raise SymlearnError(f"the labeler returned {type(found).__name__} {found!r}; it must return a list or "
                            f"set of proposition names")
    return sorted(found)


def _random_policy(env: Any, seed: int | None) -> Policy:
    space = env.action_space
    space.seed(seed)
    return lambda _observation: space.sample()


def labeler_arity(labeler: Callable[..., Any]) -> int:
    """How many arguments a labeler takes: 1 (the observation), 2 (observation, info) or 3
    (observation, info, env) -- the positional parameters it accepts, at most 3."""
    try:
        parameters = list(inspect.signature(labeler).parameters.values())
    except (TypeError, ValueError):  # a builtin without a signature: the one-argument form
        return 1
    if any(p.kind is p.VAR_POSITIONAL for p in parameters):
        return 2
    positional = [p for p in parameters if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return max(1, min(3, len(positional)))


def _run_episode(env: Any, policy: Policy, seed: int, limit: int, labeler: Labeler | None,
                 stored: Callable[[Any], Any] | None,
                 stored_action: Callable[[Any], Any] = lambda action: action) -> Trajectory:
    keep = stored or (lambda value: value)
    observation, info = env.reset(seed=seed)
    arity = labeler_arity(labeler) if labeler is not None else 0
    unwrapped = getattr(env, "unwrapped", env)
    states, actions, rewards = [_plain(keep(observation))], [], []
    labels = [] if labeler is not None else None
    terminated = truncated = False
    while True:
        if labels is not None:  # labelled while the live observation and its info are at hand
            arguments = (observation, info, unwrapped)[:arity]
            labels.append(_names(labeler(*arguments)))
        if terminated or truncated or len(actions) >= limit:
            break
        action = _plain(policy(observation))
        observation, reward, terminated, truncated, info = env.step(action)
        actions.append(_plain(stored_action(action)))
        rewards.append(float(reward))
        states.append(_plain(keep(observation)))
    truncated = truncated or not terminated
    info = {"seed": seed, "terminated": bool(terminated), "truncated": bool(truncated)}
    try:
        return Trajectory(states, actions, rewards, labels, info)
    except NonFiniteValues as exc:   # the environment's observation: say which episode, and what to do
        raise DataError(f"the environment observed {exc.value} at step {exc.step} of the episode of seed {seed}",
                        hint="an environment must observe finite numbers on every step (train refuses them "
                             "too): replace NaN or infinity in the observation before returning it") from None
    except DataError as exc:
        if not isinstance(states[0], Mapping):
            raise
        keys = ", ".join(map(str, states[0]))  # a dict observation holding arrays (MiniGrid's image)
        raise UnstorableObservations(f"the observations cannot be stored as they are: {exc.message}",
                                     hint="choose what to keep with record(..., observation=lambda o: o[KEY]); "
                                          f"keys: {keys}") from None
