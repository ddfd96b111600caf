"""Demonstrations for a resolved environment: the user's file, the bundled expert, or a trained one.

One function answers "where do the demonstrations come from" for every ``learn`` command:
``--demos FILE`` when given; else the registry entry's scripted expert; else, where the entry
allows it (``trained_expert``: the blocked MuJoCo robots, PointCircle), a PPO-Lagrangian expert
trained on the environment's true cost (minutes, cached; thesis chapter 2's experts). A user's
environment has no expert, and the message says to give ``--demos``.

The demonstrations returned say where they came from in ``metadata["source"]`` (the file's path,
``"20 expert episodes of toy-navigation"``, ...): learners that write a header into their
artefact name it there (:class:`~symlearn.learners.trees.OneClassTreeConstraint`'s DNF file), so
the file ``learn ... -o`` writes through ``learner.save`` says what it was learned from.

A ``--demos`` file whose metadata names the environment it was recorded in (``metadata["env"]``,
what :func:`symlearn.data.record` stores: the gymnasium id, ``Name-vN``) and names another than
``--env`` is still read -- a user may relabel data on purpose, and the columns are checked by the
learner anyway -- but :func:`check_recorded_env` says so in one ``warning:`` note.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from symlearn.errors import DataError
from symlearn.recipes.environments import EnvTarget, record_hint


def demonstrations(target: EnvTarget | None, demos: str | Path | None, n_demos: int, *, seed: int = 0,
                   expert_steps: int = 1_000_000, expert_cache: str | None = None,
                   note: Callable[[str], None] | None = None) -> Any:
    """The demonstrations a learner reads, their ``metadata["source"]`` saying where from (see
    the module doc); a ``--demos`` file recorded in another environment than ``target`` is read
    with a warning through ``note`` (:func:`check_recorded_env`)."""
    if demos is not None:
        from symlearn.data import load

        loaded = load(demos)
        check_recorded_env(target, loaded, demos, note)
        earlier = loaded.metadata.get("source")  # a file we wrote may say how it was recorded
        return with_source(loaded, str(demos) if not isinstance(earlier, str) else f"{demos} ({earlier})")
    if target is None:
        raise DataError("give your demonstrations with --demos FILE")
    if target.has_expert:
        return with_source(target.expert_demonstrations(n_demos, seed=seed),
                           f"{n_demos} expert episodes of {target.display}")
    if target.trains_expert:
        return with_source(trained_expert(target, n_demos, seed=seed, steps=expert_steps, cache=expert_cache,
                                          note=note),
                           f"{n_demos} episodes of a PPO-Lagrangian expert trained on {target.display}")
    raise DataError(f"{target.display} has no expert: give your demonstrations with --demos FILE",
                    hint=record_hint(target))


#: a gymnasium id as ``record`` stores it (``spec.id``): optional namespace, name, ``-v`` version; an
#: environment built without a spec is stored by its class name, which says too little to compare
_GYM_ID = re.compile(r"(?:[\w.-]+/)?[\w.-]+-v\d+")


def recorded_env(demos: Any) -> str | None:
    """The gymnasium id the demonstrations say they were recorded in (``metadata["env"]``), or
    None when they name none, or name it otherwise (a class name, a description)."""
    metadata = getattr(demos, "metadata", None)
    env = metadata.get("env") if isinstance(metadata, dict) else None
    return env.strip() if isinstance(env, str) and _GYM_ID.fullmatch(env.strip()) else None


def check_recorded_env(target: EnvTarget | None, demos: Any, path: str | Path,
                       note: Callable[[str], None] | None = None) -> bool:
    """Whether ``demos`` (read from ``path``) were recorded in ``target``'s environment as far as
    their metadata tells; when they name another gymnasium id, one ``warning:`` line through
    ``note`` (a :class:`UserWarning` without one). Never an error: relabelling may be meant."""
    recorded = recorded_env(demos)
    if target is None or recorded is None:
        return True
    known = {target.display, target.name, *(i for i in (target.gym_id, getattr(target.entry, "gym_id", None)) if i)}
    if recorded in known:
        return True
    message = (f"warning: {path} was recorded in {recorded} (its metadata), not in {target.display} (--env); "
               f"reading its columns as {target.display}'s")
    if note is not None:
        note(message)
    else:
        warnings.warn(message, UserWarning, stacklevel=2)
    return False


def with_source(demos: Any, source: str) -> Any:
    """``demos`` with ``metadata["source"] = source`` (the trajectories shared, the rest of the
    metadata kept)."""
    from symlearn.data import Demonstrations

    return Demonstrations(demos, metadata={**demos.metadata, "source": source})


def trained_expert(target: EnvTarget, n: int, *, seed: int = 0, steps: int = 1_000_000, cache: str | None = None,
                   note: Callable[[str], None] | None = None) -> Any:
    """``n`` episodes of a PPO-Lagrangian expert trained on ``target``'s true cost, cached under
    ``cache`` (default ``~/.cache/symlearn/experts``; ``"none"``: not cached)."""
    from symlearn.rl.lagrangian_expert import default_cache_dir, lagrangian_expert

    if n < 1:
        raise DataError(f"--n-demos must be at least 1, got {n}")
    cache = cache or default_cache_dir()
    cache = None if str(cache).lower() == "none" else cache
    say = note or (lambda _text: None)
    where = f"cached in {cache}" if cache else "not cached"
    say(f"{target.display} has no scripted expert: PPO-Lagrangian on its true cost, {steps} steps ({where})")
    with warnings.catch_warnings(record=True) as caught:  # an expert that still violates: say so as a note
        warnings.simplefilter("always", RuntimeWarning)
        demos, _ = lagrangian_expert(target.make, n, steps=steps, seed=seed,
                                     key={"env": target.display, "kwargs": target.kwargs}, cache_dir=cache)
    for w in caught:
        say(f"warning: {w.message}")
    return demos


__all__ = ["check_recorded_env", "demonstrations", "recorded_env", "trained_expert", "with_source"]
