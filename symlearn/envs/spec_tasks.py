"""The task-specification benchmark: eight named tasks in the office and craft worlds.

Each task pairs an environment factory with its ground-truth LTLf formula (thesis Table 5.1,
``T`` is "then"), both from the ``spec`` entries of :mod:`symlearn.envs.registry`. The labeling
is the environment's own (:attr:`LabelledGridEnv.labeling`).

>>> task = get_task("office-1")
>>> task.formula, task.env_name
('(f T g) & G !n', 'office')
>>> sorted(TASKS)[:2]
['craft-1', 'craft-2']
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from symlearn.envs.registry import Entry, Kind, entries, get


@dataclass(frozen=True)
class SpecTask:
    """One benchmark task: where it runs and what the expert is really doing."""

    name: str
    env_name: str
    formula: str
    factory: Callable[..., Any]
    description: str = ""

    def make_env(self, **kwargs: Any):
        return self.factory(**kwargs)

    def parsed_formula(self):
        from symlearn.logic.ltlf import parse

        return parse(self.formula)

    def listing(self) -> dict[str, Any]:
        """A JSON-ready row for ``symlearn envs``-style listings."""
        env = self.make_env()
        return {"name": self.name, "env": self.env_name, "formula": self.formula,
                "states": int(env.observation_space.n), "actions": int(env.action_space.n),
                "propositions": env.labeling.meanings, "description": self.description}


def _task(entry: Entry) -> SpecTask:
    return SpecTask(entry.name, entry.gym_name, entry.formula, entry.env, entry.description)


#: The specification tasks of the registry (:mod:`symlearn.envs.registry`), by name.
TASKS: dict[str, SpecTask] = {entry.name: _task(entry) for entry in entries(Kind.SPEC)}


def get_task(name: str) -> SpecTask:
    """The task called ``name`` (case-insensitive), or an
    :class:`~symlearn.errors.UnknownNameError` (a ``DataError``) naming the closest and the
    known tasks."""
    return TASKS[get(name, Kind.SPEC, what="environment/task").name]
