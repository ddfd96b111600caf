"""The bundled logic domains: a finite model plus its background knowledge, bias and truth.

A :class:`LogicDomain` ties a Python domain model (states, actions, ground truth, facts) to the
files in ``background_kb/<folder>/``:

* ``bk.lp`` -- background knowledge; with one example's facts it has one answer set;
* ``space*.lp`` -- a generator whose answer sets (with ``bk.lp``) are all state-action pairs;
* ``bias*.las`` -- mode declarations of the hypothesis space;
* ``truth*.lp`` -- the ground-truth rules, as constraints over the background predicates.

>>> d = logic_domain("hanoi")
>>> d.name, len(d.pairs()), sum(ok for _, ok in d.pairs())
('hanoi', 216, 114)
>>> d.pairs()[0][0]
('at(0,2,0).', 'at(1,2,1).', 'at(2,2,2).', 'move(2,0).')
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import ModelError
from symlearn.resources import background_kb_path

Facts = tuple[str, ...]


@dataclass(frozen=True)
class LogicDomain:
    """A finite domain with everything the ILP side needs. Build with :func:`logic_domain`."""

    name: str
    folder: str
    bk_file: str
    space_file: str
    bias_file: str
    truth_file: str
    model: Any
    description: str

    # --- files -------------------------------------------------------------------------------
    def path(self, file: str) -> Path:
        return background_kb_path(self.folder, file)

    @property
    def bk_path(self) -> Path:
        return self.path(self.bk_file)

    @property
    def space_path(self) -> Path:
        return self.path(self.space_file)

    @property
    def bias_path(self) -> Path:
        return self.path(self.bias_file)

    @property
    def truth_path(self) -> Path:
        return self.path(self.truth_file)

    def background(self) -> str:
        return self.bk_path.read_text(encoding="utf-8")

    def bias(self) -> str:
        return self.bias_path.read_text(encoding="utf-8")

    # --- state-action pairs ------------------------------------------------------------------
    def state_actions(self) -> Iterator[tuple[Any, Any]]:
        return self.model.state_actions()

    def facts(self, state: Any, action: Any) -> Facts:
        """The example context of a pair: state facts, then the action fact."""
        return tuple(self.model.example_facts(state, action))

    def state_facts(self, state: Any) -> Facts:
        return tuple(self.model.state_facts(state))

    def action_fact(self, state: Any, action: Any) -> str:
        return self.model.action_fact(state, action)

    def is_allowed(self, state: Any, action: Any) -> bool:
        return self.model.is_allowed(state, action)

    @cached_property
    def _pairs(self) -> tuple[tuple[Facts, bool], ...]:
        return tuple((self.facts(s, a), self.is_allowed(s, a)) for s, a in self.state_actions())

    def pairs(self) -> tuple[tuple[Facts, bool], ...]:
        """Every state-action pair as (facts, allowed by the ground truth), in model order."""
        return self._pairs

    def expert_pairs(self, n_episodes: int, rng: np.random.Generator) -> list[tuple[Any, Any]]:
        """State-action pairs of ``n_episodes`` rule-abiding expert episodes, in visiting order."""
        found = []
        for _ in range(n_episodes):
            found.extend(self.model.expert_episode(rng))
        return found


def _hanoi() -> LogicDomain:
    from symlearn.envs.hanoi_model import HanoiModel

    return LogicDomain("hanoi", "hanoi", "bk.lp", "space.lp", "bias.las", "truth.lp", HanoiModel(),
                       "Towers of Hanoi, 3 disks on 3 pegs: no disk on a smaller disk")


def _traffic(variant: str) -> Callable[[], LogicDomain]:
    def build() -> LogicDomain:
        from symlearn.envs.traffic_model import TrafficJunction

        what = {"lights": "traffic-light junction, two-way roads",
                "priority": "junction with priority to the right, one-way roads"}[variant]
        return LogicDomain(f"traffic-{variant}", "traffic", "bk.lp", f"space_{variant}.lp",
                           f"bias_{variant}.las", f"truth_{variant}.lp", TrafficJunction(variant),
                           f"5 x 5 {what}")
    return build


_DOMAINS: dict[str, Callable[[], LogicDomain]] = {
    "hanoi": _hanoi,
    "traffic-lights": _traffic("lights"),
    "traffic-priority": _traffic("priority"),
}

DOMAIN_NAMES: tuple[str, ...] = tuple(_DOMAINS)


def logic_domain(name: str) -> LogicDomain:
    """The bundled domain called ``name`` (one of :data:`DOMAIN_NAMES`)."""
    try:
        return _DOMAINS[name]()
    except KeyError:
        raise ModelError(f"unknown logic domain {name!r}", hint=f"use one of {', '.join(DOMAIN_NAMES)}") from None
