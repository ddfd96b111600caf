"""The bundled logic domains: a finite model plus its background knowledge, bias and truth.

A :class:`LogicDomain` ties a Python domain model (states, actions, ground truth, facts) to the
files in ``background_kb/<folder>/``:

* ``bk.lp`` -- background knowledge; with one example's facts it has one answer set (its
  ``#const`` sizes are set to the model's by ``model.background()``);
* ``space*.lp`` -- a generator whose answer sets (with ``bk.lp``) are all state-action pairs;
* ``bias*.las`` -- mode declarations of the hypothesis space;
* ``truth*.lp`` -- the ground-truth rules, as constraints over the background predicates.

>>> d = logic_domain("hanoi")
>>> d.name, len(d.pairs()), sum(ok for _, ok in d.pairs())
('hanoi', 216, 114)
>>> len(d.forbidden_pairs(d.truth_path))
102
>>> d.pairs()[0][0]
('at(0,2,0).', 'at(1,2,1).', 'at(2,2,2).', 'move(2,0).')
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.envs.registry import Kind, get, names
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
        """The background knowledge for this domain's model (``bk.lp`` sized to the model)."""
        return self.model.background()

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

    @cached_property
    def _by_facts(self) -> dict[frozenset[str], tuple[Any, Any]]:
        return {frozenset(self.facts(s, a)): (s, a) for s, a in self.state_actions()}

    @cached_property
    def context_signatures(self) -> frozenset[tuple[str, int]]:
        """``(name, arity)`` of the predicates that appear in example contexts."""
        return frozenset(_signature(fact.rstrip(".")) for facts in self._by_facts for fact in facts)

    def decode(self, atoms: Iterable[str]) -> tuple[Any, Any]:
        """The state-action pair an interpretation describes (atoms of other predicates ignored).

        This is the inverse of :meth:`facts`; it raises :class:`ModelError` for an
        interpretation that is no pair of the domain.
        """
        keep = self.context_signatures
        facts = frozenset(f"{a}." for a in map(str, atoms) if _signature(a) in keep)
        try:
            return self._by_facts[facts]
        except KeyError:
            raise ModelError(f"{' '.join(sorted(facts))} is no state-action pair of {self.name}") from None

    def forbidden_pairs(self, rules: Iterable[str] | str | Path) -> list[tuple[Any, Any]]:
        """Every state-action pair that ``rules`` (text, rule list or ``.lp`` path) forbid.

        Enumerates the answer sets of ``bk.lp`` + ``space*.lp`` that the rules remove and maps
        them back to model pairs, in model order.
        """
        from symlearn.logic.asp import Hypothesis, Program

        background = Program.from_text(self.background(), source=str(self.bk_path))
        if isinstance(rules, Path):
            hypothesis = Hypothesis.from_lp(rules, background=background)
        elif isinstance(rules, str):
            hypothesis = Hypothesis.from_text(rules, background=background)
        else:
            hypothesis = Hypothesis(list(rules), background=background)
        found = hypothesis.forbidden_interpretations(Program.from_file(self.space_path),
                                                     show=sorted(self.context_signatures))
        pairs = {self.decode(atoms) for atoms in found}
        return [pair for pair in self.state_actions() if pair in pairs]

    def expert_pairs(self, n_episodes: int, rng: np.random.Generator) -> list[tuple[Any, Any]]:
        """State-action pairs of ``n_episodes`` rule-abiding expert episodes, in visiting order."""
        found = []
        for _ in range(n_episodes):
            found.extend(self.model.expert_episode(rng))
        return found


def _signature(atom: str) -> tuple[str, int]:
    from symlearn.logic.asp.clingo_adapter import parse_term

    symbol = parse_term(atom)
    return symbol.name, len(symbol.arguments)


def hanoi_domain() -> LogicDomain:
    """Towers of Hanoi (registry entry ``hanoi``)."""
    from symlearn.envs.hanoi_model import HanoiModel

    return LogicDomain("hanoi", "hanoi", "bk.lp", "space.lp", "bias.las", "truth.lp", HanoiModel(),
                       "Towers of Hanoi, 3 disks on 3 pegs: no disk on a smaller disk")


def junction_domain(variant: str) -> LogicDomain:
    """The traffic junction ``variant`` (registry entries ``junction-<variant>``); its files
    live in ``background_kb/traffic/``."""
    from symlearn.envs.traffic_model import TrafficJunction

    what = {"lights": "traffic-light junction, two-way roads",
            "priority": "junction with priority to the right, one-way roads",
            "combined": "junction with a traffic light, priority to the right and one-way roads"}[variant]
    model = TrafficJunction(variant)
    return LogicDomain(f"junction-{variant}", "traffic", "bk.lp", f"space_{variant}.lp",
                       f"bias_{variant}.las", f"truth_{variant}.lp", model, f"{model.size} x {model.size} {what}")


#: The bundled logic domains: the registry entries that have ASP facts (kind ``rules``).
DOMAIN_NAMES: tuple[str, ...] = names(Kind.RULES)


def logic_domain(name: str) -> LogicDomain:
    """The bundled domain called ``name`` (one of :data:`DOMAIN_NAMES`); an unknown name raises
    :class:`~symlearn.errors.UnknownNameError` listing them."""
    return get(name, Kind.RULES, what="logic domain").domain()
