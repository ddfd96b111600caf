"""The tabular MDP protocol that exact algorithms (value iteration, MaxEnt passes, constraint
inference) work on.

``transitions[s, a, s']`` is the probability of reaching ``s'``; ``rewards[s, a]`` the expected
immediate reward; ``initial[s]`` the start distribution; ``terminal[s]`` marks states where an
episode ends (their rows are kept stochastic, usually as self-loops, so tensors stay square).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from symlearn.errors import ModelError

_TOLERANCE = 1e-8


@dataclass(frozen=True, eq=False)
class TabularMDP:
    """A finite MDP with named states and actions and optional goal conditioning.

    ``name`` (optional) says which world the model is (``"gridworld"``): what files learned in it
    name as their domain (a constraint set's ``"domain"``); derived models keep it.

    >>> P = np.zeros((2, 1, 2)); P[0, 0, 1] = P[1, 0, 1] = 1
    >>> mdp = TabularMDP(P, rewards=np.array([[0.0], [1.0]]), initial=[1, 0], terminal=[False, True])
    >>> mdp.n_states, mdp.n_actions, mdp.state_names
    (2, 1, ('0', '1'))
    """

    transitions: np.ndarray
    rewards: np.ndarray
    initial: np.ndarray
    terminal: np.ndarray
    state_names: tuple[str, ...] = field(default=())
    action_names: tuple[str, ...] = field(default=())
    goals: tuple[int, ...] = field(default=())
    name: str | None = None

    def __post_init__(self) -> None:
        P = np.asarray(self.transitions, dtype=np.float64)
        if P.ndim != 3 or P.shape[0] != P.shape[2] or 0 in P.shape:
            raise ModelError(f"transitions must have shape (S, A, S) with S, A > 0, got {P.shape}")
        S, A, _ = P.shape
        if not np.isfinite(P).all() or (P < 0).any():
            raise ModelError("transition probabilities must be finite and non-negative")
        sums = P.sum(axis=2)
        bad = np.argwhere(np.abs(sums - 1.0) > 1e-6)
        if len(bad):
            s, a = bad[0]
            raise ModelError(f"transition probabilities of state {s}, action {a} sum to {sums[s, a]:.6g}, not 1")
        R = np.asarray(self.rewards, dtype=np.float64)
        if R.shape == (S, A, S):  # reward on (s, a, s'): take its expectation under P
            R = (P * R).sum(axis=2)
        if R.shape != (S, A):
            raise ModelError(f"rewards must have shape (S, A) = {(S, A)} or (S, A, S), got {R.shape}")
        if not np.isfinite(R).all():
            raise ModelError("rewards must be finite")
        mu = np.asarray(self.initial, dtype=np.float64)
        if mu.shape != (S,) or (mu < 0).any() or abs(mu.sum() - 1.0) > 1e-6:
            # say which of the three it is: a vector of the right length that sums to 2 is not "of length S"
            found = (f"got shape {mu.shape}" if mu.shape != (S,) else "it has a negative entry" if (mu < 0).any()
                     else f"it sums to {mu.sum():.6g}, not 1")
            raise ModelError(f"initial must be a probability vector of length {S}: {found}")
        term = np.asarray(self.terminal, dtype=bool)
        if term.shape != (S,):
            raise ModelError(f"terminal must be a boolean vector of length {S}, got shape {term.shape}")
        names_s = tuple(str(n) for n in self.state_names) or tuple(str(s) for s in range(S))
        names_a = tuple(str(n) for n in self.action_names) or tuple(str(a) for a in range(A))
        for what, names, size in (("state", names_s, S), ("action", names_a, A)):
            if len(names) != size:
                raise ModelError(f"{len(names)} {what} names for {size} {what}s")
            if len(set(names)) != size:
                raise ModelError(f"{what} names must be unique")
        goals = tuple(int(g) for g in self.goals)
        if any(not 0 <= g < S for g in goals):
            raise ModelError(f"goal states must be in 0..{S - 1}, got {goals}")
        for name, value in (("transitions", P), ("rewards", R), ("initial", mu), ("terminal", term)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "state_names", names_s)
        object.__setattr__(self, "action_names", names_a)
        object.__setattr__(self, "goals", goals)
        if self.name is not None and not (isinstance(self.name, str) and self.name.strip()):
            raise ModelError(f"name must be a non-empty string or None, got {self.name!r}")

    # --- sizes and names --------------------------------------------------------------------
    @property
    def n_states(self) -> int:
        return self.transitions.shape[0]

    @property
    def n_actions(self) -> int:
        return self.transitions.shape[1]

    def state_index(self, name: str | int) -> int:
        return _index(name, self.state_names, "state")

    def action_index(self, name: str | int) -> int:
        return _index(name, self.action_names, "action")

    # --- dynamics ------------------------------------------------------------------------------
    def successors(self, state: int, action: int) -> dict[int, float]:
        """Reachable next states with their probabilities."""
        row = self.transitions[state, action]
        return {int(s): float(row[s]) for s in np.flatnonzero(row)}

    def sample_next(self, state: int, action: int, rng: np.random.Generator) -> int:
        return int(rng.choice(self.n_states, p=self.transitions[state, action]))

    def sample_initial(self, rng: np.random.Generator) -> int:
        return int(rng.choice(self.n_states, p=self.initial))

    # --- derived models --------------------------------------------------------------------
    def make_absorbing(self, states: Iterable[int]) -> TabularMDP:
        """Copy in which ``states`` are terminal self-loops with zero reward."""
        chosen = np.fromiter((int(s) for s in states), dtype=int)
        P = self.transitions.copy()
        R = self.rewards.copy()
        P[chosen] = 0.0
        P[chosen, :, chosen] = 1.0
        R[chosen] = 0.0
        terminal = self.terminal.copy()
        terminal[chosen] = True
        return replace(self, transitions=P, rewards=R, terminal=terminal)

    def with_goal(self, goals: int | str | Sequence[int | str], goal_reward: float | None = None) -> TabularMDP:
        """Goal-conditioned copy: the goal states become absorbing and terminal.

        With ``goal_reward``, every action that can enter a goal earns that reward times the
        probability of entering it (on top of the existing reward).
        """
        chosen = [self.state_index(g) for g in ([goals] if isinstance(goals, (int, str)) else goals)]
        if not chosen:
            raise ModelError("with_goal needs at least one goal state")
        model = self.make_absorbing(chosen)
        if goal_reward is not None:
            entering = self.transitions[:, :, chosen].sum(axis=2)
            entering[chosen] = 0.0
            model = replace(model, rewards=model.rewards + goal_reward * entering)
        return replace(model, goals=tuple(chosen))

    # --- construction from gymnasium -------------------------------------------------------
    @classmethod
    def from_gymnasium(
        cls,
        env: Any,
        *,
        state_names: Sequence[str] = (),
        action_names: Sequence[str] = (),
    ) -> TabularMDP:
        """Build from a discrete gymnasium environment that exposes its model.

        Two conventions are read: an environment with a ``to_tabular()`` method (symlearn's own
        environments) returns its model directly; otherwise the toy-text convention (FrozenLake,
        CliffWalking, Taxi): ``env.unwrapped.P[s][a]`` is a list of
        ``(probability, next_state, reward, terminated)`` and ``env.unwrapped.initial_state_distrib``
        the start distribution (where the environment has none, the frequencies of the states
        ``env.reset(seed=i)`` returns for ``i < 64``). A state entered with ``terminated=True`` is
        terminal.
        """
        inner = getattr(env, "unwrapped", env)
        own_model = getattr(inner, "to_tabular", None)
        if callable(own_model):
            mdp = own_model()
            if not isinstance(mdp, TabularMDP):
                raise ModelError(f"{type(inner).__name__}.to_tabular() returned {type(mdp).__name__}, not a TabularMDP")
            names = {}
            if state_names:
                names["state_names"] = tuple(state_names)
            if action_names:
                names["action_names"] = tuple(action_names)
            return replace(mdp, **names) if names else mdp
        model = getattr(inner, "P", None)
        if not isinstance(model, dict):
            raise ModelError(
                f"{type(inner).__name__} does not expose its transition model",
                hint="a tabular MDP needs env.unwrapped.P[s][a] = [(p, s', r, terminated), ...]",
            )
        try:
            S = int(inner.observation_space.n)
            A = int(inner.action_space.n)
        except AttributeError:
            raise ModelError("the environment's observation and action spaces must be Discrete") from None
        # a Discrete(n, start=k) space numbers its states k..k+n-1, and P is keyed by those ids;
        # the model's rows are 0..n-1 (P[0] was looked up, a KeyError), named by the ids
        s0 = int(getattr(inner.observation_space, "start", 0))
        a0 = int(getattr(inner.action_space, "start", 0))
        what = type(inner).__name__
        P = np.zeros((S, A, S))
        R = np.zeros((S, A))
        terminal = np.zeros(S, dtype=bool)
        for s in range(S):
            for a in range(A):
                try:
                    entries = model[s0 + s][a0 + a]
                except (KeyError, IndexError, TypeError):
                    raise ModelError(f"{what}.P has no entry for state {s0 + s}, action {a0 + a}",
                                     hint=f"P[s][a] for every state id s = {s0}..{s0 + S - 1} and action a = "
                                          f"{a0}..{a0 + A - 1} of its spaces") from None
                for prob, nxt, reward, done in entries:
                    j = int(nxt) - s0
                    if not 0 <= j < S:
                        raise ModelError(f"{what}.P[{s0 + s}][{a0 + a}] leads to state {nxt}, not one of the "
                                         f"observation space's ids {s0}..{s0 + S - 1}")
                    P[s, a, j] += prob
                    R[s, a] += prob * reward
                    if done:
                        terminal[j] = True
        # Terminal states end the episode in the environment; make them explicit self-loops.
        P[terminal] = 0.0
        for s in np.flatnonzero(terminal):
            P[s, :, s] = 1.0
        R[terminal] = 0.0
        initial = getattr(inner, "initial_state_distrib", None)
        if initial is None:   # not every toy-text-style world keeps it: read it off the environment's resets
            initial = _reset_distribution(env, S, s0)
        if s0 and not state_names:
            state_names = [str(s0 + s) for s in range(S)]
        if a0 and not action_names:
            action_names = [str(a0 + a) for a in range(A)]
        return cls(P, R, np.asarray(initial, dtype=float), terminal, tuple(state_names), tuple(action_names))


RESETS = 64   # resets that estimate a start distribution the environment does not state


def _reset_distribution(env: Any, n_states: int, start: int = 0) -> np.ndarray:
    """The start distribution of a discrete world without ``initial_state_distrib``: how often
    ``env.reset(seed=i)``, ``i < RESETS``, returns each state (ids ``start..start+n_states-1``)."""
    counts = np.zeros(n_states)
    for seed in range(RESETS):
        observation, _ = env.reset(seed=seed)
        state = np.asarray(observation)
        if state.shape != () or state.dtype.kind not in "iu" or not 0 <= int(state) - start < n_states:
            raise ModelError(f"{type(getattr(env, 'unwrapped', env)).__name__}.reset() returned {observation!r}, "
                             f"not a state {start}..{start + n_states - 1} of its model P",
                             hint="give the start distribution as env.unwrapped.initial_state_distrib")
        counts[int(state) - start] += 1
    return counts / RESETS


def _index(name: str | int, names: tuple[str, ...], what: str) -> int:
    if isinstance(name, (int, np.integer)):
        if not 0 <= int(name) < len(names):
            raise ModelError(f"{what} {name} is out of range 0..{len(names) - 1}")
        return int(name)
    try:
        return names.index(name)
    except ValueError:
        raise ModelError(f"unknown {what} {name!r}") from None
