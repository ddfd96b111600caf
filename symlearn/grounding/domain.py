"""A domain for learning constraints: background knowledge, mode bias, fact grounding, nominal model.

:class:`Domain` is everything a constraint learner needs to know about a finite world, and
nothing about where it came from: the bundled Hanoi and junction domains and a folder a user
wrote (:meth:`Domain.from_folder`, see ``docs/FORMATS.md``) are the same class.

* ``mdp``: the nominal :class:`~symlearn.mdp.TabularMDP` (no learned rule removes an action);
  action names are the ASP atoms of the actions, so demonstrations may name actions by atom.
* ``grounding``: a :class:`~symlearn.grounding.facts.FactGrounding`, the ASP facts of every
  state and action (the *example context* of a pair is state facts + action atom).
* ``background``: a clingo program that, with one pair's context, has exactly one answer set;
  ``bias``: the ILASP-style mode declarations (``#modeb``, ``#modec``, ``#constant``, ``#maxv``)
  that span the hypothesis space; ``truth``: optional ground-truth rules to score against;
  ``labeling`` (propositions, for specification learning) and ``feature_map`` (named numeric
  features of the states, for feature-based learners) are optional groundings.
* ``available``: optional ``(S, A)`` mask of moves that exist; pairs that are not available,
  and every pair of a terminal state, are *unavailable*: no example, no rule is about them.

What the learners ask of a domain: :meth:`ilp_task` (an ILP task over chosen pairs, built as
objects, never as text), :meth:`rule_mask` (every pair a rule set forbids, decided on the
answer sets of all pairs in one grounding), :attr:`truth_forbidden`, :meth:`episodes`
(demonstrations checked against the model).

>>> import numpy as np
>>> from symlearn.mdp import TabularMDP
>>> P = np.zeros((2, 2, 2)); P[0, 0, 1] = P[0, 1, 0] = P[1, :, 1] = 1
>>> mdp = TabularMDP(P, np.zeros((2, 2)), [1, 0], [False, True])
>>> d = Domain("toy", background="safe :- not alarm.", bias="#modeb(1, alarm). #modeb(1, go).",
...            grounding=FactGrounding({0: "alarm.", 1: ""}, ["go", "wait"]), mdp=mdp, truth=":- alarm, go.")
>>> d.truth_forbidden.astype(int).tolist()
[[1, 0], [0, 0]]
>>> d.rule_mask([":- go."]).astype(int).tolist()
[[1, 0], [0, 0]]
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterable, Sequence
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, ModelError, SymlearnError
from symlearn.grounding.facts import FactGrounding, Facts
from symlearn.mdp import TabularMDP

RulesLike = str | Sequence[str] | os.PathLike


class Domain:
    """A finite domain for constraint learning (see the module docstring)."""

    def __init__(self, name: str, *, background: Any, bias: str, grounding: FactGrounding, mdp: TabularMDP,
                 truth: str | None = None, labeling: Any = None, available: np.ndarray | None = None,
                 description: str = "", sources: dict[str, str] | None = None, feature_map: Any = None) -> None:
        from symlearn.logic.asp.program import Program, as_program

        self.name = str(name)
        self.description = description or self.name
        self.sources = dict(sources or {})
        self.background = background if isinstance(background, Program) else as_program(str(background))
        self.bias_text = bias
        self.grounding = grounding
        self.labeling = labeling
        self.feature_map = feature_map
        self.truth = truth
        if (grounding.n_states, grounding.n_actions) != (mdp.n_states, mdp.n_actions):
            raise DataError(f"the model has {mdp.n_states} states x {mdp.n_actions} actions, the fact grounding "
                            f"{grounding.n_states} x {grounding.n_actions}", file=self.sources.get("model"),
                            hint="model.npz, states.jsonl and actions.jsonl must describe the same ids")
        names = tuple(grounding.action_atoms)
        self.mdp = dataclasses.replace(mdp, action_names=names) if mdp.action_names != names else mdp
        if available is None:
            available = np.ones((mdp.n_states, mdp.n_actions), dtype=bool)
        available = np.asarray(available, dtype=bool)
        if available.shape != (mdp.n_states, mdp.n_actions):
            raise DataError(f"available must have shape {(mdp.n_states, mdp.n_actions)}, got {available.shape}",
                            file=self.sources.get("model"))
        unavailable = ~available | np.asarray(mdp.terminal, dtype=bool)[:, None]
        unavailable.setflags(write=False)
        self.unavailable = unavailable
        self._spaces: dict[int | None, Any] = {}  # hypothesis spaces by body length (space())

    # --- the pair space -----------------------------------------------------------------------
    @property
    def n_states(self) -> int:
        return self.mdp.n_states

    @property
    def n_actions(self) -> int:
        return self.mdp.n_actions

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.mdp.state_names or tuple(str(s) for s in range(self.n_states))

    @property
    def action_names(self) -> tuple[str, ...]:
        return self.mdp.action_names

    @property
    def known(self) -> np.ndarray:
        """Pairs forbidden in advance: moves that do not exist (never in terminal states)."""
        return self.unavailable & ~self.mdp.terminal[:, None]

    @cached_property
    def pair_ids(self) -> tuple[tuple[int, int], ...]:
        """Every available ``(s, a)`` in id order: the pairs rules are learned about."""
        return tuple((int(s), int(a)) for s, a in np.argwhere(~self.unavailable))

    def facts(self, s: int, a: int) -> Facts:
        if self.unavailable[s, a]:
            raise ModelError(f"ids ({s}, {a}) are no state-action pair of {self.name}")
        return self.grounding.facts(s, a)

    def describe_pair(self, s: int, a: int) -> str:
        return f"{self.state_names[s]} / {self.action_names[a]}"

    # --- ILP ----------------------------------------------------------------------------------
    @cached_property
    def bias(self):
        """The mode bias as an :class:`~symlearn.logic.ilp.task.ILPTask` without examples."""
        from symlearn.logic.ilp import parse_task

        source = self.sources.get("bias", f"<{self.name} bias>")
        task = parse_task(self.bias_text, source=source)
        if task.examples:
            first = task.examples[0]
            raise DataError(f"the bias file holds examples ({first.describe()}); it must hold mode declarations only",
                            file=source, line=first.line, hint="examples come from demonstrations")
        if task.modeh:
            # a rule with a head changes answer sets instead of removing pairs: the learners and
            # rule_mask work on integrity constraints only, so such a bias can never be used
            mode = task.modeh[0]
            raise DataError(f"the bias declares {mode}: a domain's rules are integrity constraints "
                            "(':- body.', the pairs they forbid), which have no head",
                            file=source, line=mode.line, column=mode.column,
                            hint="remove the #modeh declaration; #modeb literals make the constraints' bodies")
        return task

    @property
    def hypothesis_space(self):
        """The candidate rules of the bias at the ILP's default body length (:meth:`space`)."""
        return self.space()

    def space(self, max_body: int | None = None):
        """The candidate rules of the bias with at most ``max_body`` body literals (None: the ILP
        default, 3). Independent of the examples, so built once per length: a user whose rule joins
        two objects through their places (``:- put, at(P), hot(P), holding(O), fragile(O).``) needs
        5, and every learner of one fit asks for the same space."""
        from symlearn.logic.ilp.space import generate_space

        if max_body not in self._spaces:
            self._check_bias_has_modes()
            self._spaces[max_body] = generate_space(self.ilp_task([]), max_body=max_body)
        return self._spaces[max_body]

    def _check_bias_has_modes(self) -> None:
        if not self.bias.modeb and not self.bias.modec:
            # named here, not as the generated induction task, and only when rules are to be learned
            # (checking a folder or rules needs no bias)
            raise DataError("the bias declares no #modeb or #modec: no rule can be learned",
                            file=self.sources.get("bias", f"<{self.name} bias>"),
                            hint="add mode declarations such as #modeb(1, p(var(t))).")

    def examples(self, pairs: Iterable[tuple[int, int]], positive: bool, penalty: int | None = None,
                 prefix: str | None = None) -> list:
        """ILP examples (contexts = the pairs' facts), ids ``p1, p2, ...`` or ``n1, n2, ...``."""
        from symlearn.logic.asp.program import Program
        from symlearn.logic.ilp.task import Example

        prefix = prefix or ("p" if positive else "n")
        out = []
        for k, (s, a) in enumerate(pairs, start=1):
            context = Program.from_text(" ".join(self.facts(s, a)), source=f"<{self.describe_pair(s, a)}>")
            out.append(Example(f"{prefix}{k}", positive, context=context, penalty=penalty))
        return out

    def ilp_task(self, examples: list):
        """An ILP task over this domain's background and bias with the given examples."""
        bias = self.bias
        return dataclasses.replace(bias, background=self.background + bias.background, examples=list(examples),
                                   source=f"<{self.name} induction task>")

    def hypothesis(self, rules: RulesLike):
        """A :class:`~symlearn.logic.asp.Hypothesis` from rule text, a rule list or an ``.lp`` path."""
        from symlearn.logic.asp import Hypothesis

        background = self.background + self.bias.background
        if isinstance(rules, Hypothesis):
            return rules
        if isinstance(rules, os.PathLike):
            return Hypothesis.from_lp(rules, background=background)
        if isinstance(rules, str):
            return Hypothesis.from_text(rules, background=background)
        return Hypothesis(list(rules), background=background)

    @cached_property
    def _worlds(self) -> list:
        """The one answer set of background + context per available pair, as atoms tagged with
        the pair's index (one solve for all pairs)."""
        from symlearn.logic.asp import clingo_adapter as cl
        from symlearn.logic.asp.program import Program
        from symlearn.logic.ilp.encoding import ACTIVE, located_background

        if not self.pair_ids:
            return []
        # Contexts are ground facts already normalised by clingo's printer, so each is tagged as
        # text (``at(1,2).`` -> ``at(7,1,2).``) instead of parsing thousands of them again. The
        # background keeps its lines' origins, so clingo's errors on it (an unsafe variable) name
        # the user's file and line, not a line of the generated program.
        lines = []
        for index, (s, a) in enumerate(self.pair_ids):
            lines.append(f"{ACTIVE}({index}).")
            lines.extend(_tag_fact(fact, index) for fact in self.facts(s, a))
        program = located_background(self.ilp_task([])) + Program.from_text(
            "\n".join(lines), source=f"<{self.name} pair contexts>")
        outcome = cl.solve(program, max_models=2)
        if len(outcome.models) != 1:
            self._explain_bad_context()
        return [atom for atom in outcome.models[0] if atom.name != ACTIVE]

    def validate(self) -> Domain:
        """Check that every pair's context has exactly one answer set; return ``self``."""
        self._worlds  # noqa: B018 -- computing it is the check
        return self

    def _explain_bad_context(self) -> None:
        from symlearn.logic.asp.clingo_adapter import solve

        for index in range(len(self.pair_ids)):
            s, a = self.pair_ids[index]
            program = self.background + self.bias.background + " ".join(self.facts(s, a))
            n = len(solve(program, max_models=2).models)
            if n != 1:
                what = "makes the background unsatisfiable" if n == 0 else "gives more than one answer set"
                line = self.grounding.state_line(s)
                raise DataError(f"state {s} with action {self.action_names[a]!r}: its facts {what}",
                                file=self.sources.get("states"), line=line,
                                hint="with one state's facts and one action atom the background must have "
                                     "exactly one answer set")
        raise DataError(f"some state-action context of {self.name} does not have exactly one answer set")

    def rule_mask(self, rules: RulesLike) -> np.ndarray:
        """Boolean ``(S, A)``: every available pair on whose answer set some rule fires.

        Rules are integrity constraints (the hypotheses of constraint learning); one grounding of
        the tagged rules over the tagged answer sets of all pairs decides them all.
        """
        from symlearn.logic.asp import clingo_adapter as cl
        from symlearn.logic.asp.program import Program
        from symlearn.logic.ilp.encoding import ACTIVE

        hypothesis = self.hypothesis(rules)
        mask = np.zeros(self.unavailable.shape, dtype=bool)
        if not hypothesis.rules:
            return mask
        _check_constraints_only(hypothesis)
        # tagged with the rules' origins, so clingo's errors (an unsafe variable) name the rule
        # file's line and column, not a line of the generated program
        tagged = cl.tag_programs_located([(hypothesis.program(), "E__", (f"{ACTIVE}(E__)",))],
                                         constraint_head="fires__")[0]
        facts = "\n".join(f"{x}." for x in self._worlds)
        facts += "\n" + "\n".join(f"{ACTIVE}({i})." for i in range(len(self.pair_ids)))
        program = Program.from_text(facts, source="<answer sets>") + tagged
        for atom in cl.ground_atoms(program, [("fires__", 1)]):
            s, a = self.pair_ids[atom.arguments[0].number]
            mask[s, a] = True
        return mask

    @cached_property
    def defined_signatures(self) -> frozenset[tuple[str, int]]:
        """``(name, arity)`` of every predicate the background (and the bias file's background
        part) defines, some state's facts hold or some action atom is: what a rule or a mode
        declaration may use and still fire."""
        from symlearn.logic.asp.predicates import defined_signatures
        from symlearn.logic.asp.program import Program

        facts = sorted({fact for s, a in self.pair_ids for fact in self.facts(s, a)})
        return frozenset(defined_signatures([self.background + self.bias.background,
                                             Program.from_text(" ".join(facts), source=f"<{self.name} state facts>")]))

    def undefined_predicates(self, rules: str | os.PathLike[str]) -> list:
        """What clingo accepts in a rule file but can never mean: the predicates its bodies use that
        :attr:`defined_signatures` lacks (:class:`~symlearn.logic.asp.predicates.UndefinedPredicate`:
        a misspelt predicate makes a rule that never fires), then the arguments no pair's answer set
        matches (:class:`~symlearn.logic.asp.argument_values.UnmatchedArgument`: ``"explosive"`` for
        ``explosive``, or ``East``, a variable matching every value, for ``east``); each located in
        the file, with ``message()`` and ``as_dict()``."""
        from symlearn.logic.asp.argument_values import unmatched_arguments
        from symlearn.logic.asp.predicates import undefined_predicates
        from symlearn.logic.asp.program import Program

        program = Program.from_file(rules, expand=False)
        found = undefined_predicates(program, set(self.defined_signatures))
        return found + unmatched_arguments(program, self.argument_values)

    @cached_property
    def argument_values(self) -> dict:
        """``{(name, arity): [values at each position]}`` of every atom of every pair's answer set."""
        import clingo

        from symlearn.logic.asp.argument_values import argument_values

        # the answer sets' atoms carry the pair's index as their first argument: dropped here
        return argument_values(clingo.Function(a.name, a.arguments[1:], a.positive) for a in self._worlds
                               if a.arguments)

    def bias_warnings(self) -> list:
        """Mode declarations of the bias that can give no useful literal (a predicate defined
        nowhere, a ``const(t)`` without ``#constant``): see :mod:`symlearn.grounding.bias_check`."""
        from symlearn.grounding.bias_check import bias_warnings

        return bias_warnings(self)

    @cached_property
    def truth_forbidden(self) -> np.ndarray | None:
        """The pairs the ground-truth rules forbid, or None without truth."""
        if self.truth is None:
            return None
        from symlearn.logic.asp import Hypothesis

        # located in the folder's truth file, so an unsafe variable names its line there
        source = (self.sources or {}).get("truth", "<truth>")
        truth = Hypothesis.from_text(self.truth, source=source, background=self.background + self.bias.background)
        mask = self.rule_mask(truth)
        mask.setflags(write=False)
        return mask

    # --- demonstrations -----------------------------------------------------------------------
    def episodes(self, demonstrations: Any) -> list:
        """Demonstrations as checked integer episodes (state ids or names; action ids or atoms).

        An action atom is matched as ASP reads it, spaces ignored (``stack(b, a)`` is the action
        ``stack(b,a)``), as :meth:`~symlearn.grounding.facts.FactGrounding.action_index` does."""
        from symlearn.mdp.episodes import TabularEpisode, tabular_episodes

        items = demonstrations if isinstance(demonstrations, (list, tuple)) else list(demonstrations)
        if not all(isinstance(item, TabularEpisode) for item in items):
            items = [self._atoms_as_named(item) for item in items]
        return tabular_episodes(items, self.mdp)

    def _atoms_as_named(self, item: Any) -> Any:
        """``item`` with every action atom that is no action name exactly, but the atom of one
        up to spacing, replaced by that name (anything else is left for the checks to report)."""
        from types import SimpleNamespace

        states, actions = (item.states, item.actions) if hasattr(item, "states") else item
        if actions is None or isinstance(actions, np.ndarray) or not any(isinstance(a, str) for a in actions):
            return item
        names = set(self.action_names)
        spelled = {}
        for a in actions:
            if isinstance(a, str) and a not in names and a not in spelled:
                try:
                    spelled[a] = self.action_names[self.grounding.action_index(a)]
                except SymlearnError:
                    continue
        if not spelled:
            return item
        return SimpleNamespace(states=states, actions=[spelled.get(a, a) for a in actions],
                               info=getattr(item, "info", None))

    # --- files --------------------------------------------------------------------------------
    @classmethod
    def from_folder(cls, folder: str | os.PathLike[str], *, validate: bool = True,
                    allow_outside: bool = False) -> Domain:
        """Read a domain folder (``domain.toml`` + the files it names; see ``docs/FORMATS.md``);
        files outside the folder are refused unless ``allow_outside``."""
        from symlearn.grounding.domain_folder import read_domain_folder

        domain = read_domain_folder(Path(folder), allow_outside=allow_outside)
        return domain.validate() if validate else domain

    def save(self, folder: str | os.PathLike[str]) -> Path:
        """Write this domain as a folder that :meth:`from_folder` reads back."""
        from symlearn.grounding.domain_folder import write_domain_folder

        return write_domain_folder(self, Path(folder))

    def __repr__(self) -> str:
        return (f"Domain({self.name!r}: {self.n_states} states x {self.n_actions} actions, "
                f"{len(self.pair_ids)} pairs{', truth' if self.truth else ''})")


def _check_constraints_only(hypothesis) -> None:
    """Only integrity constraints forbid pairs: name the first rule with a head (file, line, column)."""
    from clingo.ast import ASTType

    for index, statement in enumerate(hypothesis.asts):
        head = statement.head
        if head.ast_type == ASTType.Literal and head.atom.ast_type == ASTType.BooleanConstant:
            continue
        where = hypothesis.origins[index] if hypothesis.origins and len(hypothesis.origins) == len(hypothesis.rules) \
            else (None, None, None)
        raise DataError(f"rule {hypothesis.rules[index]!r} has a head: only integrity constraints (':- body.') can "
                        "be turned into forbidden pairs", file=where[0], line=where[1], column=where[2],
                        hint="a rule with a head changes the answer sets rather than removing them; "
                             "write it as ':- body.'")


def _tag_fact(fact: str, tag: int) -> str:
    """``p(a,b).`` -> ``p(TAG,a,b).``, ``q.`` -> ``q(TAG).``, ``-p(a).`` -> ``-p(TAG,a).`` (a fact
    as clingo prints it: the name runs up to the first parenthesis)."""
    body = fact[:-1] if fact.endswith(".") else fact
    name, paren, rest = body.partition("(")
    return f"{name}({tag},{rest}." if paren else f"{name}({tag})."


def as_domain(value: Any) -> Domain:
    """``value`` if it is a :class:`Domain`, or its ``.domain`` (bundled wrappers carry one)."""
    if isinstance(value, Domain):
        return value
    inner = getattr(value, "domain", None)
    if isinstance(inner, Domain):
        return inner
    raise ModelError(f"{type(value).__name__} is not a Domain",
                     hint="build one with Domain(...) or Domain.from_folder(DIR); bundled: symlearn.envs.logic_mdp")


__all__ = ["Domain", "as_domain"]
