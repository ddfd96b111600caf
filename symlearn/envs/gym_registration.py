"""Register the bundled environments with gymnasium as ``symlearn/<name>-v0``.

``import symlearn.envs`` calls :func:`register_when_gymnasium_loads`, so after it
``gymnasium.make("symlearn/junction-lights-v0")`` works whatever the import order, and
``gymnasium.make("symlearn.envs:symlearn/junction-lights-v0")`` works with no import at all
(gymnasium imports the module before the ``:``).

``import symlearn.envs`` must stay light (no gymnasium, no numpy), yet ``gymnasium.register``
needs gymnasium. So: if gymnasium is loaded already, register now; otherwise put a one-shot
finder on ``sys.meta_path`` that registers right after gymnasium itself has loaded. (Gymnasium
1.x has no plugin entry points any more, so a package cannot register without being imported.)
Registration stores only the ``"module:attribute"`` entry points of
:mod:`~symlearn.envs.registry`; nothing of ours is imported until ``gymnasium.make``.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import sys

from symlearn.envs.registry import gym_entries


def register_gymnasium_envs() -> list[str]:
    """Register every bundled environment (imports gymnasium); returns the ids."""
    import gymnasium

    ids = []
    for gym_id, factory in gym_entries().items():
        if gym_id not in gymnasium.registry:  # registering twice would only log an override warning
            # The environments end their own episodes (max_steps), so no TimeLimit on top.
            gymnasium.register(id=gym_id, entry_point=factory.target, kwargs=dict(factory.kwargs))
        ids.append(gym_id)
    return ids


def register_when_gymnasium_loads() -> None:
    """Register now if gymnasium is loaded, else as soon as it is (see the module docstring)."""
    gymnasium = sys.modules.get("gymnasium")
    if gymnasium is not None and hasattr(gymnasium, "register"):
        register_gymnasium_envs()
    elif not any(isinstance(finder, _AfterGymnasiumLoads) for finder in sys.meta_path):
        sys.meta_path.insert(0, _AfterGymnasiumLoads())


class _AfterGymnasiumLoads(importlib.abc.MetaPathFinder):
    """Finds ``gymnasium`` with the ordinary finders and registers once its module has run."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "gymnasium":
            return None
        sys.meta_path.remove(self)  # one shot, and the search below must not find us again
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None:
            return spec
        run_module = spec.loader.exec_module

        def run_then_register(module):
            run_module(module)
            register_gymnasium_envs()

        # Only this spec's loader instance is patched; gymnasium keeps its real loader otherwise.
        spec.loader.exec_module = run_then_register
        return spec
