"""Reward machines: guarded automata whose transitions emit rewards.

``step(u, label) -> (u', r)`` reads the label an environment's labelling function produced.
A label no edge matches keeps the machine where it is with ``default_reward`` (the implicit
self-loop of the reward-machine literature). Terminal states end an episode; stepping from one
stays there with reward 0.

:meth:`RewardMachine.from_dfa` compiles a task automaton: reward ``reward`` on every transition
that enters an accepting state from a non-accepting one, terminal states are the absorbing
ones (all edges loop; this covers "done forever" and the rejecting sink), and with
``shaping=True`` potential-based shaping is added to every edge,
``F(u, u') = gamma * phi(u') - phi(u)`` with ``phi(u) = scale * (d_max + 1 - d(u))``, where
``d(u)`` is the graph distance from ``u`` to acceptance and ``d_max`` its largest finite value.
States that can never accept get ``phi = 0``. The potential is non-negative on purpose: with
``gamma < 1`` a negative potential would pay ``(1 - gamma) * |phi|`` for standing still, whereas
this one charges for waiting, pays for progress and penalises entering a dead state. Shaping
terms are folded into the stored rewards and the potential is kept in :attr:`potential`;
:func:`task_potential` computes it for any task automaton (a wrapper shaping at run time uses it).
:meth:`RewardMachine.from_formula` compiles an LTLf task the same way, through its minimal DFA.

>>> from symlearn.logic.automata import DFA
>>> from symlearn.logic.guards import Guard
>>> a = Guard.var("a")
>>> task = DFA({"a"}, 2, 0, [1], {0: [(~a, 0), (a, 1)], 1: [(Guard.true(), 1)]})
>>> rm = RewardMachine.from_dfa(task)
>>> rm.step(0, set()), rm.step(0, {"a"}), sorted(rm.terminal)
((0, 0.0), (1, 1.0), [1])
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from symlearn.errors import ModelError
from symlearn.logic.automata.base import (
    GuardedAutomaton, check_alphabet, check_n_states, check_names, check_state, weighted_edges,
)
from symlearn.logic.automata.dfa import DFA
from symlearn.logic.guards import Guard


class RewardMachine(GuardedAutomaton):
    """States ``0..n_states-1``, guarded edges ``(guard, target, reward)``; immutable."""

    __slots__ = ("alphabet", "n_states", "initial", "terminal", "accepting", "state_names", "default_reward",
                 "gamma", "potential", "_edges")
    _what = "reward machine"

    def __init__(
        self,
        alphabet: Iterable[str],
        n_states: int,
        initial: int,
        transitions: Mapping[int, Sequence[tuple[Guard | str, int, float]]],
        terminal: Iterable[int] = (),
        accepting: Iterable[int] = (),
        state_names: Sequence[str] | None = None,
        *,
        default_reward: float = 0.0,
        gamma: float | None = None,
        potential: Sequence[float] | None = None,
    ) -> None:
        n_states = check_n_states(n_states, "reward machine")
        alphabet = check_alphabet(alphabet)
        edges = weighted_edges(transitions, n_states, alphabet, "reward machine", "reward", _number)
        if potential is not None:
            potential = tuple(_number(v, "potential") for v in potential)
            if len(potential) != n_states:
                raise ModelError(f"{len(potential)} potentials for {n_states} states")
        self._init_fields(
            alphabet=alphabet,
            n_states=n_states,
            initial=check_state(initial, n_states, "initial state"),
            terminal=frozenset(check_state(q, n_states, "terminal state") for q in terminal),
            accepting=frozenset(check_state(q, n_states, "accepting state") for q in accepting),
            state_names=check_names(state_names, n_states),
            default_reward=_number(default_reward, "default reward"),
            gamma=None if gamma is None else _number(gamma, "gamma"),
            potential=potential,
            _edges=tuple(tuple(row) for row in edges),
        )

    @classmethod
    def from_formula(cls, formula, **options) -> RewardMachine:
        """The reward machine of an LTLf task (text or a parsed formula): its minimal DFA through
        :meth:`from_dfa` (``options`` are those of ``from_dfa``: reward, shaping, gamma, ...).

        >>> rm = RewardMachine.from_formula("F a")
        >>> rm.run([set(), {"a"}])
        ([0, 0, 1], [0.0, 1.0])
        """
        from symlearn.logic.ltlf import parse, to_dfa

        return cls.from_dfa(to_dfa(parse(formula) if isinstance(formula, str) else formula), **options)

    @classmethod
    def from_dfa(cls, dfa: DFA, *, reward: float = 1.0, shaping: bool = False, gamma: float = 0.99,
                 scale: float = 1.0, minimize: bool = True, terminal_on_acceptance: bool = False) -> RewardMachine:
        """Compile a task DFA (see the module docstring for the exact rewards and potentials)."""
        if not 0 < gamma <= 1:
            raise ModelError(f"gamma must be in (0, 1], got {gamma}")
        dfa = dfa.minimize() if minimize else dfa.complete()
        potential = task_potential(dfa, scale)
        terminal = {q for q in dfa.states if all(t == q for _, t in dfa.successors(q))}
        if terminal_on_acceptance:
            terminal |= set(dfa.accepting)
        transitions = {}
        for q in dfa.states:
            row = []
            for guard, target in dfa.successors(q):
                r = reward if (target in dfa.accepting and q not in dfa.accepting) else 0.0
                if shaping:
                    r += gamma * potential[target] - potential[q]
                row.append((guard, target, r))
            transitions[q] = row
        return cls(dfa.alphabet, dfa.n_states, dfa.initial, transitions, terminal, dfa.accepting, dfa.state_names,
                   gamma=gamma if shaping else None, potential=potential if shaping else None)

    # -- running ----------------------------------------------------------------------------
    def step(self, state: int, label) -> tuple[int, float]:
        """``(next state, reward)`` after reading ``label`` in ``state``."""
        if state in self.terminal:
            return state, 0.0
        for guard, target, reward in self._edges[state]:
            if guard.evaluate(label):
                return target, reward
        return state, self.default_reward

    def run(self, word) -> tuple[list[int], list[float]]:
        """States visited and rewards received reading ``word`` (stops at a terminal state)."""
        states, rewards, u = [self.initial], [], self.initial
        for label in word:
            if u in self.terminal:
                break
            u, r = self.step(u, label)
            states.append(u)
            rewards.append(r)
        return states, rewards

    def is_terminal(self, state: int) -> bool:
        return state in self.terminal

    @property
    def dfa(self) -> DFA:
        """The underlying automaton with the accepting states (edge rewards dropped)."""
        merged: dict[int, list] = {q: [(g, t) for g, t, _ in row] for q, row in enumerate(self._edges)}
        return DFA(self.alphabet, self.n_states, self.initial, self.accepting, merged, self.state_names)

    # -- formats ----------------------------------------------------------------------------
    def to_dot(self, title: str | None = None, *, unicode: bool = False) -> str:
        from symlearn.logic.automata.dot_export import reward_machine_to_dot

        return reward_machine_to_dot(self, title=title, unicode=unicode)

    def to_text(self) -> str:
        """The text format of the public reward-machines code (see ``rm_text_import``)."""
        from symlearn.logic.automata.rm_text_import import to_rm_text

        return to_rm_text(self)

    @classmethod
    def from_text(cls, text: str, *, source: str | None = None, unmatched: str = "terminal") -> RewardMachine:
        """Read the reward-machines text format (see ``rm_text_import`` for ``unmatched``)."""
        from symlearn.logic.automata.rm_text_import import parse_rm_text

        return parse_rm_text(text, source=source, unmatched=unmatched)

    def to_dict(self) -> dict:
        from symlearn.logic.automata.json_format import header, write_transitions

        document = header("reward_machine", self)
        document["terminal"] = sorted(self.terminal)
        document["default_reward"] = self.default_reward
        if self.potential is not None:
            document["shaping"] = {"gamma": self.gamma, "potential": list(self.potential)}
        document["transitions"] = write_transitions(self, "reward")
        return document

    @classmethod
    def from_dict(cls, document, *, source: str | None = None) -> RewardMachine:
        from symlearn.logic.automata.json_format import construct, read_header, read_transitions

        reader, f = read_header(document, "reward_machine", source)
        terminal = reader.list_of(document, "", "terminal", "int")
        default = reader.get(document, "", "default_reward", "number", optional=True, default=0.0)
        shaping = reader.get(document, "", "shaping", "dict", optional=True)
        gamma = potential = None
        if shaping is not None:
            gamma = reader.get(shaping, "shaping", "gamma", "number")
            potential = reader.list_of(shaping, "shaping", "potential", "number")
        transitions = read_transitions(reader, document, "reward")
        return construct(reader, lambda: cls(
            f["alphabet"], f["n_states"], f["initial"], transitions, terminal, f["accepting"], f["state_names"],
            default_reward=default, gamma=gamma, potential=potential))

    def _key(self):
        return (self.alphabet, self.n_states, self.initial, self.terminal, self.accepting, self.state_names,
                self.default_reward, self.gamma, self.potential, self._edges)

    def __repr__(self) -> str:
        return (f"RewardMachine({self.n_states} states, {self.n_edges} edges, initial {self.initial}, "
                f"terminal {sorted(self.terminal)})")


def task_potential(automaton: GuardedAutomaton, scale: float = 1.0) -> list[float]:
    """The shaping potential of every state: ``scale * (d_max + 1 - d(u))`` with ``d(u)`` the
    graph distance to acceptance (0 where acceptance is unreachable; see the module docstring).

    Works on a DFA or a reward machine (the distances ignore the rewards).
    """
    from symlearn.logic.automata.operations import distances_to_acceptance

    dfa = automaton.dfa if isinstance(automaton, RewardMachine) else automaton
    distance = distances_to_acceptance(dfa)
    finite = [d for d in distance if d is not None]
    worst = (max(finite) if finite else 0) + 1
    return [0.0 if d is None else scale * (worst - d) for d in distance]


def _number(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value or value in (
            float("inf"), float("-inf")):
        raise ModelError(f"{what} must be a finite number, got {value!r}")
    return float(value)
