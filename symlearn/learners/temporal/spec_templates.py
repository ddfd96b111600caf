"""Formula templates ``F p``, ``G p``, ``p T q`` (and their negations), instantiated and scored
on many traces at once.

A trace is reduced to where each *atom* (a candidate proposition) holds: its first and last
position and whether it holds throughout. Every template is then a comparison of those bounds,
so all ``P + P + P*(P-1)`` instantiations are decided on all traces with a few numpy
operations, without building formulas:

* ``F p``   holds iff ``p`` occurs;
* ``G p``   holds iff ``p`` holds at every position;
* ``p T q`` = ``F(p & X F q)`` holds iff the first ``p`` comes strictly before the last ``q``.

Why not the core's :mod:`symlearn.logic.ltlf.vectorized`: every instantiation is a comparison of
per-trace bounds, so all of them are decided at once; evaluating the formulas one by one with
:func:`~symlearn.logic.ltlf.vectorized.evaluate` gives the same counts 314x slower (10 100
instantiations over 100 atoms, 100 traces of 60 steps; ``python benchmarks/ltl_evaluators.py``,
docs/BENCHMARKS.md).

A negated template holds exactly where the template does not, and splits expert and nominal
traces the same way, so it has the same information gain: :func:`best_candidate` keeps the
polarity the experts agree with (``!F p`` is written ``G !p`` and ``!G p`` as ``F !p``).

>>> import numpy as np
>>> atoms = np.array([[1, 0], [0, 0], [0, 1]], dtype=bool)       # 3 states, atoms p and q
>>> b = TraceBounds.from_traces([np.array([0, 1, 2]), np.array([2, 0])], atoms)
>>> b.satisfies("T", 0, 1).tolist(), b.satisfies("F", 1).tolist()
([True, False], [True, True])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from symlearn.logic.ltlf.ast import Always, Eventually, Formula, Not, Prop, Then

TEMPLATES = ("F", "G", "T")
ARITY = {"F": 1, "G": 1, "T": 2}


def instantiate(template: str, names: Sequence[str], negated: bool = False) -> Formula:
    """The formula of a template over proposition ``names``, negation pushed inside when it reads better."""
    props = [Prop(n) for n in names]
    if template == "F":
        return Always(Not(props[0])) if negated else Eventually(props[0])
    if template == "G":
        return Eventually(Not(props[0])) if negated else Always(props[0])
    if template == "T":
        formula = Then(props[0], props[1])
        return Not(formula) if negated else formula
    raise ValueError(f"unknown template {template!r}; known: {', '.join(TEMPLATES)}")


@dataclass(frozen=True)
class TraceBounds:
    """Per trace and atom: first and last position where the atom holds, and whether it always holds.

    ``first`` is ``inf`` and ``last`` is ``-1`` where the atom never holds.
    """

    first: np.ndarray  # (n_traces, P) float
    last: np.ndarray  # (n_traces, P) float
    always: np.ndarray  # (n_traces, P) bool

    @classmethod
    def from_traces(cls, traces: Sequence[np.ndarray], atom_of_state: np.ndarray) -> TraceBounds:
        """``traces`` are state sequences; ``atom_of_state[s, p]`` says whether atom ``p`` holds in ``s``."""
        n, n_atoms = len(traces), atom_of_state.shape[1]
        first = np.full((n, n_atoms), np.inf)
        last = np.full((n, n_atoms), -1.0)
        always = np.zeros((n, n_atoms), dtype=bool)
        for i, states in enumerate(traces):
            held = atom_of_state[np.asarray(states, dtype=np.int64)]  # (T, P)
            seen = held.any(axis=0)
            first[i, seen] = held[:, seen].argmax(axis=0)
            last[i, seen] = len(held) - 1 - held[::-1, seen].argmax(axis=0)
            always[i] = held.all(axis=0)
        return cls(first, last, always)

    def __len__(self) -> int:
        return self.first.shape[0]

    def subset(self, rows: np.ndarray) -> TraceBounds:
        return TraceBounds(self.first[rows], self.last[rows], self.always[rows])

    def satisfies(self, template: str, p: int, q: int | None = None) -> np.ndarray:
        """Verdicts of one instantiation on every trace."""
        if template == "F":
            return np.isfinite(self.first[:, p])
        if template == "G":
            return self.always[:, p].copy()
        return self.first[:, p] < self.last[:, q]

    def counts(self, template: str) -> np.ndarray:
        """How many traces satisfy each instantiation: ``(P,)`` for F and G, ``(P, P)`` for T."""
        if template == "F":
            return np.isfinite(self.first).sum(axis=0)
        if template == "G":
            return self.always.sum(axis=0)
        n_atoms = self.first.shape[1]
        total = np.zeros((n_atoms, n_atoms), dtype=np.int64)
        for first, last in zip(self.first, self.last):
            total += first[:, None] < last[None, :]
        return total


def entropy(p: np.ndarray) -> np.ndarray:
    """Binary entropy in bits, elementwise (0 at 0 and 1)."""
    p = np.clip(np.asarray(p, dtype=np.float64), 0.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = -(p * np.log2(p) + (1 - p) * np.log2(1 - p))
    return np.nan_to_num(h, nan=0.0)


def information_gain(expert_sat: np.ndarray, nominal_sat: np.ndarray, n_expert: int, n_nominal: int) -> np.ndarray:
    """Entropy of the expert/nominal split minus the weighted entropy after splitting on satisfaction.

    ``expert_sat`` / ``nominal_sat`` count the expert / nominal traces satisfying each candidate.

    >>> float(information_gain(np.array([10]), np.array([0]), 10, 10)[0])
    1.0
    """
    ke = np.asarray(expert_sat, dtype=np.float64)
    kn = np.asarray(nominal_sat, dtype=np.float64)
    total = n_expert + n_nominal
    sat = ke + kn
    unsat = total - sat
    with np.errstate(divide="ignore", invalid="ignore"):
        h_sat = entropy(np.where(sat > 0, ke / sat, 0.0))
        h_unsat = entropy(np.where(unsat > 0, (n_expert - ke) / unsat, 0.0))
    before = float(entropy(np.array(n_expert / total)))
    return before - (sat / total) * h_sat - (unsat / total) * h_unsat


@dataclass(frozen=True)
class Choice:
    """The best instantiated template of one search."""

    template: str
    atoms: tuple[int, ...]
    negated: bool
    gain: float
    expert_rate: float  # fraction of expert traces satisfying the chosen polarity
    nominal_rate: float
    n_candidates: int


def best_candidate(expert: TraceBounds, nominal: TraceBounds, *, preference: np.ndarray | None = None,
                   exclude: set[tuple[str, tuple[int, ...], bool]] = frozenset(),
                   min_expert_rate: float = 0.0) -> Choice | None:
    """The instantiation with the highest information gain, in the polarity the experts satisfy.

    Only instantiations that at least ``min_expert_rate`` of the expert traces satisfy compete:
    a formula some experts violate is unlikely to be part of their task, yet a rare detail
    that only some experts show and the nominal agent never does can have a high gain.

    Ties (within 1e-9) go to the simpler template (``F``, ``G`` before ``T``), then to the atoms
    with the larger ``preference`` (a score per atom, e.g. how far into unexplored territory the
    experts reach it), then to the lower atom index. ``exclude`` lists ``(template, atoms,
    negated)`` already chosen.
    """
    ne, nn = len(expert), len(nominal)
    n_atoms = expert.first.shape[1]
    pref = np.zeros(n_atoms) if preference is None else np.asarray(preference, dtype=np.float64)
    rows = []  # (gain, -arity, preference, -index, template, atoms, negated, ke, kn)
    total = 0
    for template in TEMPLATES:
        ke = expert.counts(template).astype(np.float64)
        kn = nominal.counts(template).astype(np.float64)
        gain = information_gain(ke, kn, ne, nn)
        negated = ke / ne < kn / nn
        expert_rate = np.where(negated, ne - ke, ke) / ne
        gain = np.where(expert_rate >= min_expert_rate - 1e-12, gain, -np.inf)
        if template == "T":
            np.fill_diagonal(gain, -np.inf)
            score = (pref[:, None] + pref[None, :]) / 2
        else:
            score = pref
        total += int(np.isfinite(gain).sum())
        for (template_, atoms, neg) in exclude:
            if template_ == template:
                gain[atoms] = -np.inf
        flat_gain = gain.ravel()
        if not np.isfinite(flat_gain).any():
            continue
        best_gain = flat_gain.max()
        tied = np.flatnonzero(flat_gain >= best_gain - 1e-9)
        pick = tied[np.lexsort((tied, -score.ravel()[tied]))[0]]
        atoms = tuple(int(i) for i in np.unravel_index(pick, gain.shape))
        neg = bool(negated.ravel()[pick])
        k_e, k_n = ke.ravel()[pick], kn.ravel()[pick]
        if neg:
            k_e, k_n = ne - k_e, nn - k_n
        rows.append((round(float(best_gain), 9), -ARITY[template], float(score.ravel()[pick]), -pick,
                     template, atoms, neg, k_e / ne, k_n / nn))
    if not rows:
        return None
    g, _, _, _, template, atoms, neg, er, nr = max(rows, key=lambda r: r[:3])
    return Choice(template, atoms, neg, float(g), float(er), float(nr), total)


def novelty_depth(expert_traces: Sequence[np.ndarray], atom_of_state: np.ndarray, covered: np.ndarray) -> np.ndarray:
    """Per atom: how many steps, on average over expert traces, from where the experts meet it
    to the nearest step in a state the nominal agent also visited (``covered[s]``).

    A large value marks a place deep inside behaviour the nominal agent has not shown yet;
    the candidate search uses it to break ties between equally informative atoms.
    """
    n_atoms = atom_of_state.shape[1]
    total = np.zeros(n_atoms)
    for states in expert_traces:
        states = np.asarray(states, dtype=np.int64)
        hit = covered[states]
        n = len(states)
        idx = np.arange(n)
        before = np.where(hit, idx, -np.inf)
        before = np.maximum.accumulate(before)
        after = np.where(hit, idx, np.inf)
        after = np.minimum.accumulate(after[::-1])[::-1]
        depth = np.minimum(idx - before, after - idx)
        depth = np.where(np.isfinite(depth), depth, n)
        held = atom_of_state[states]  # (T, P)
        total += np.where(held.any(axis=0), (held * depth[:, None]).max(axis=0), 0.0)
    return total / max(1, len(expert_traces))
