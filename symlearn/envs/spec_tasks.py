"""The task-specification benchmark: eight named tasks in the office and craft worlds.

Each task pairs an environment factory with its ground-truth LTLf formula (thesis Table 5.1,
``T`` is "then"). The labeling is the environment's own (:attr:`LabelledGridEnv.labeling`).

>>> task = get_task("office-1")
>>> task.formula, task.env_name
('(f T g) & G !n', 'office')
>>> sorted(TASKS)[:2]
['craft-1', 'craft-2']
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from difflib import get_close_matches
from typing import Any

from symlearn.errors import DataError


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


def _office(**kwargs: Any):
    from symlearn.envs.office_world import make_office_world

    return make_office_world(**kwargs)


def _craft(seed: int = 0, **kwargs: Any):
    from symlearn.envs.craft_world import make_craft_world

    return make_craft_world(seed=seed, **kwargs)


def _build() -> dict[str, SpecTask]:
    from symlearn.envs import craft_world, office_world

    words = {
        "office-1": "fetch coffee, then deliver it to g, never touching a decoration",
        "office-2": "fetch mail, then deliver it to g, never touching a decoration",
        "office-3": "fetch coffee and mail (any order), then deliver both to g, avoiding decorations",
        "office-4": "visit offices a, b, c, d in this order, avoiding decorations",
        "craft-1": "get a, then use it at c",
        "craft-2": "get a and f, then use both at e",
        "craft-3": "get a, f and c, then use them at b",
        "craft-4": "get a and f, use them at e, then go to g",
    }
    tasks = {name: SpecTask(name, "office", formula, _office, words[name])
             for name, formula in office_world.TASKS.items()}
    tasks.update({name: SpecTask(name, "craft", formula, _craft, words[name])
                  for name, formula in craft_world.TASKS.items()})
    return tasks


TASKS: dict[str, SpecTask] = _build()


def get_task(name: str) -> SpecTask:
    """The task called ``name`` (case-insensitive), or a :class:`DataError` listing the names."""
    key = str(name).strip().lower()
    if key in TASKS:
        return TASKS[key]
    close = get_close_matches(key, list(TASKS), n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    raise DataError(f"unknown environment/task {name!r}",
                    hint=hint + "known tasks: " + ", ".join(sorted(TASKS)))
