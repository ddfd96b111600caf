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
terms are folded into the stored rewards and the potential is kept in :attr:`potential`.

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
from pathlib import Path

from symlearn.errors import ModelError
from symlearn.logic.automata.dfa import DFA, as_guard, check_alphabet, check_deterministic, check_state
from symlearn.logic.guards import Guard


class RewardMachine:
    """States ``0..n_states-1``, guarded edges ``(guard, target, reward)``; immutable."""

    __slots__ = ("alphabet", "n_states", "initial", "terminal", "accepting", "state_names", "default_reward",
                 "gamma", "potential", "_edges")

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
        if isinstance(n_states, bool) or not isinstance(n_states, int) or n_states < 1:
            raise ModelError(f"a reward machine needs at least one state, got n_states={n_states!r}")
        alphabet = check_alphabet(alphabet)
        edges: list[list[tuple[Guard, int, float]]] = [[] for _ in range(n_states)]
        for source, row in transitions.items():
            check_state(source, n_states, "reward machine transition source")
            for edge in row:
                if not isinstance(edge, (tuple, list)) or len(edge) != 3:
                    raise ModelError(f"reward machine edge {edge!r} from state {source} is not (guard, target, reward)")
                guard = as_guard(edge[0])
                target = check_state(edge[1], n_states, f"reward machine transition target (from state {source})")
                reward = _number(edge[2], f"reward of edge {source} -> {target}")
                unknown = guard.propositions - alphabet
                if unknown:
                    raise ModelError(f"reward machine guard {str(guard)!r} on state {source} uses {sorted(unknown)} "
                                     f"outside the alphabet {sorted(alphabet)}")
                if not guard.is_false():
                    edges[source].append((guard, target, reward))
        for source, row in enumerate(edges):
            row.sort(key=lambda e: (e[0].sort_key, e[1]))
            check_deterministic(source, row, "reward machine")
        if state_names is not None:
            state_names = tuple(str(n) for n in state_names)
            if len(state_names) != n_states:
                raise ModelError(f"{len(state_names)} state names for {n_states} states")
        if potential is not None:
            potential = tuple(_number(v, "potential") for v in potential)
            if len(potential) != n_states:
                raise ModelError(f"{len(potential)} potentials for {n_states} states")
        set_ = object.__setattr__
        set_(self, "alphabet", alphabet)
        set_(self, "n_states", n_states)
        set_(self, "initial", check_state(initial, n_states, "initial state"))
        set_(self, "terminal", frozenset(check_state(q, n_states, "terminal state") for q in terminal))
        set_(self, "accepting", frozenset(check_state(q, n_states, "accepting state") for q in accepting))
        set_(self, "state_names", state_names)
        set_(self, "default_reward", _number(default_reward, "default reward"))
        set_(self, "gamma", None if gamma is None else _number(gamma, "gamma"))
        set_(self, "potential", potential)
        set_(self, "_edges", tuple(tuple(row) for row in edges))

    def __setattr__(self, name, value):
        raise AttributeError("RewardMachine is immutable")

    @classmethod
    def from_dfa(cls, dfa: DFA, *, reward: float = 1.0, shaping: bool = False, gamma: float = 0.99,
                 scale: float = 1.0, minimize: bool = True, terminal_on_acceptance: bool = False) -> RewardMachine:
        """Compile a task DFA (see the module docstring for the exact rewards and potentials)."""
        from symlearn.logic.automata.operations import distances_to_acceptance

        if not 0 < gamma <= 1:
            raise ModelError(f"gamma must be in (0, 1], got {gamma}")
        dfa = dfa.minimize() if minimize else dfa.complete()
        distance = distances_to_acceptance(dfa)
        finite = [d for d in distance if d is not None]
        worst = (max(finite) if finite else 0) + 1
        potential = [0.0 if d is None else scale * (worst - d) for d in distance]
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

    def edges(self):
        """Every edge as ``(source, guard, target, reward)``."""
        for source, row in enumerate(self._edges):
            for guard, target, r in row:
                yield source, guard, target, r

    def successors(self, state: int):
        return self._edges[state]

    @property
    def transitions(self) -> dict[int, list[tuple[Guard, int, float]]]:
        return {q: list(row) for q, row in enumerate(self._edges)}

    @property
    def states(self) -> range:
        return range(self.n_states)

    @property
    def n_edges(self) -> int:
        return sum(len(row) for row in self._edges)

    @property
    def dfa(self) -> DFA:
        """The underlying automaton with the accepting states (edge rewards dropped)."""
        merged: dict[int, list] = {q: [(g, t) for g, t, _ in row] for q, row in enumerate(self._edges)}
        return DFA(self.alphabet, self.n_states, self.initial, self.accepting, merged, self.state_names)

    # -- formats ----------------------------------------------------------------------------
    def to_dot(self, title: str | None = None, *, unicode: bool = False) -> str:
        from symlearn.logic.automata.dot_export import reward_machine_to_dot

        return reward_machine_to_dot(self, title=title, unicode=unicode)

    def _repr_svg_(self) -> str | None:
        from symlearn.rendering import dot_to_svg_text

        return dot_to_svg_text(self.to_dot())

    def render(self, path: str | Path) -> Path:
        from symlearn.rendering import render_dot

        return render_dot(self.to_dot(), path)

    def to_text(self) -> str:
        """The text format of the public reward-machines code (see ``rm_text_import``)."""
        from symlearn.logic.automata.rm_text_import import to_rm_text

        return to_rm_text(self)

    @classmethod
    def from_text(cls, text: str, *, source: str | None = None) -> RewardMachine:
        from symlearn.logic.automata.rm_text_import import parse_rm_text

        return parse_rm_text(text, source=source)

    def to_dict(self) -> dict:
        from symlearn.logic.automata.json_format import header

        document = header("reward_machine", self)
        document["terminal"] = sorted(self.terminal)
        document["default_reward"] = self.default_reward
        if self.potential is not None:
            document["shaping"] = {"gamma": self.gamma, "potential": list(self.potential)}
        document["transitions"] = [{"source": s, "target": t, "guard": str(g), "reward": r}
                                   for s, g, t, r in self.edges()]
        return document

    def to_json(self) -> str:
        from symlearn.logic.automata.json_format import dumps

        return dumps(self.to_dict())

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
        transitions: dict[int, list] = {}
        for s, g, t, r in read_transitions(reader, document, "reward"):
            transitions.setdefault(s, []).append((g, t, r))
        return construct(reader, lambda: cls(
            f["alphabet"], f["n_states"], f["initial"], transitions, terminal, f["accepting"], f["state_names"],
            default_reward=default, gamma=gamma, potential=potential))

    @classmethod
    def from_json(cls, text, *, source: str | None = None) -> RewardMachine:
        from symlearn.logic.automata.json_format import loads

        return cls.from_dict(text if isinstance(text, Mapping) else loads(text, source=source), source=source)

    def save(self, path: str | Path) -> Path:
        from symlearn.atomic import write_text

        return write_text(path, self.to_json())

    def _key(self):
        return (self.alphabet, self.n_states, self.initial, self.terminal, self.accepting, self.state_names,
                self.default_reward, self.gamma, self.potential, self._edges)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, RewardMachine) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return (f"RewardMachine({self.n_states} states, {self.n_edges} edges, initial {self.initial}, "
                f"terminal {sorted(self.terminal)})")


def _number(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value or value in (
            float("inf"), float("-inf")):
        raise ModelError(f"{what} must be a finite number, got {value!r}")
    return float(value)
