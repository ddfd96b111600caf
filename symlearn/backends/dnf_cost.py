"""A learned DNF constraint as the cost of a constrained RL agent, with rule pruning.

:class:`DnfCostWrapper` adds ``info["cost"]`` to every step of any gymnasium environment: 1 (or
``violation_cost``) when the DNF formula holds on the features of the state the step reached,
0 otherwise (the Safety-Gym convention: the cost of entering an unsafe region). With
``per_rule=True`` the cost is a vector with one entry per conjunction, so PPO-Lagrangian can
keep one multiplier per rule.

Features come from ``info["features"]`` (the SafeNav and toy environments report them), from
the observation itself, or from a callable ``features(observation, info) -> vector``; names are
matched to the formula's by a :class:`~symlearn.grounding.FeatureMap` or a list of names.

**Pruning** (thesis section 4.3.4). Every step evaluates the conjunctions in ascending number of
atoms and stops at the first that fires, so a short rule is preferred to a long one describing
the same violation. :class:`RuleStats` counts, per conjunction, how often it was evaluated and
how often it fired; after training, :meth:`RuleStats.prune` drops the rules whose fired /
evaluated ratio stayed below a threshold (the thesis uses 0.001): a rule the reward-seeking
agent never ran into describes a region it had no reason to visit, so it is probably not a real
constraint. The report says, per rule, the counts, the ratio and the verdict. The thesis counts
the whole training; :meth:`RuleStats.snapshot` / :meth:`RuleStats.since` give the counts of a
later part only (the trained agent), :meth:`RuleStats.reset` starts again.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np

from symlearn.errors import DataError, SymlearnError


def _names(features: Any) -> tuple[str, ...]:
    names = getattr(features, "names", features)
    if names is None:
        raise SymlearnError("the cost wrapper needs the feature names (a FeatureMap or a list)")
    return tuple(names)


def _by_name(raw: Any, names: tuple[str, ...]) -> Any:
    """A dict ``info["features"]`` (name -> number) as the vector of its values in ``names``
    order: a dict is read by its names, never by its key order, which an environment may build
    differently on every step; anything else is returned as it is."""
    if isinstance(raw, np.ndarray) and raw.dtype == object and raw.shape == ():   # as a rollout holds it
        raw = raw.item()
    if not isinstance(raw, Mapping):
        return raw
    keys = {str(k): v for k, v in raw.items()}
    missing = [n for n in names if n not in keys]
    if missing:
        raise DataError(f"info['features'] has no feature {missing[0]!r}", hint="it has: " + ", ".join(keys))
    return [keys[n] for n in names]


@dataclass(frozen=True)
class RuleVerdict:
    rule: str
    evaluated: int
    fired: int
    ratio: float
    kept: bool

    def as_dict(self) -> dict[str, Any]:
        return {"rule": self.rule, "evaluated": self.evaluated, "fired": self.fired, "ratio": self.ratio,
                "kept": self.kept}


class RuleStats:
    """Per-conjunction evaluation and firing counts under ascending-complexity evaluation."""

    def __init__(self, dnf: Any, features: Any) -> None:
        self.dnf = dnf
        self.feature_names = _names(features)
        unknown = sorted(set(dnf.features) - set(self.feature_names))
        if unknown:
            raise DataError(f"the formula uses feature {unknown[0]!r}, which the environment does not provide",
                            hint="features: " + ", ".join(self.feature_names))
        sizes = [len(c.atoms) for c in dnf.conjunctions]
        # stable: among rules of one size, the file's order decides
        self.order = np.argsort(np.asarray(sizes, dtype=np.int64), kind="stable")
        self._rank = np.empty(len(sizes), dtype=np.int64)     # rule -> its position in that order
        self._rank[self.order] = np.arange(len(sizes))
        # the same rules in that order, for evaluators whose output count_ordered reads directly
        self.ordered_dnf = type(dnf)(tuple(dnf.conjunctions[i] for i in self.order))
        self.evaluated = np.zeros(len(sizes), dtype=np.int64)
        self.fired = np.zeros(len(sizes), dtype=np.int64)

    def update(self, features: np.ndarray) -> np.ndarray:
        """Evaluate and count one batch ``[N, k]``; returns which rules hold, ``[N, m]`` in the
        formula's order."""
        X = np.atleast_2d(np.asarray(features, dtype=np.float64))
        if not np.isfinite(X).all():
            raise DataError("features must be finite (found NaN or inf)")
        fires = self.dnf.evaluate(X, self.feature_names, per_conjunction=True)
        self.count(fires)
        return fires

    def count(self, fires: np.ndarray) -> None:
        """Count a precomputed ``[N, m]`` matrix of which rules hold (formula order)."""
        fires = np.asarray(fires, dtype=bool)
        # the first firing rule in ascending-complexity order: the least rank among the fired ones
        self.count_first(self._first(fires, lambda hit: np.where(hit, self._rank, len(self.order)).min(axis=1)))

    def count_ordered(self, fires: np.ndarray) -> None:
        """:meth:`count` for a matrix whose columns are already in ascending-complexity order (the
        columns of :attr:`ordered_dnf`): the first firing rule is a row's first ``True``."""
        self.count_first(self._first(np.asarray(fires, dtype=bool), lambda hit: hit.argmax(axis=1)))

    def _first(self, fires: np.ndarray, position: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """Per row the sorted position of its first firing rule, ``m`` where none fired; only the
        rows some rule fired on are ranked (``position`` of those rows)."""
        first = np.full(len(fires), len(self.order), dtype=np.int64)
        hit = fires.any(axis=1)
        if hit.any():
            first[hit] = position(fires[hit])
        return first

    def count_first(self, first: np.ndarray) -> None:
        """Count points given, per point, the position (in ascending-complexity order, i.e. the
        column of :attr:`ordered_dnf`) of the first rule that fired on it, ``m`` when none did:
        rules before that position were evaluated and did not fire, the rule at it fired."""
        first = np.asarray(first, dtype=np.int64)
        m = len(self.order)
        if len(first) == 1:     # one step (the cost wrapper's case): touch only the rules evaluated
            f = int(first[0])
            self.evaluated[self.order[:f + 1]] += 1
            if f < m:
                self.fired[self.order[f]] += 1
            return
        # a rule at sorted position p is evaluated by every point whose first firing rule is at p or
        # later: a reverse cumulative sum of the first-firing histogram, O(N + m) rather than O(N m)
        at = np.bincount(first, minlength=m + 1)
        self.evaluated[self.order] += np.cumsum(at[::-1])[::-1][:m]
        self.fired[self.order] += at[:m]

    def ratios(self) -> np.ndarray:
        return self.fired / np.maximum(self.evaluated, 1)

    def reset(self) -> None:
        """Forget the counts (e.g. to count only what a trained agent does)."""
        self.evaluated[:] = 0
        self.fired[:] = 0

    def snapshot(self) -> tuple[np.ndarray, np.ndarray]:
        """The counts so far, ``(evaluated, fired)`` (copies), for :meth:`since`."""
        return self.evaluated.copy(), self.fired.copy()

    def since(self, snapshot: tuple[np.ndarray, np.ndarray]) -> RuleStats:
        """A new :class:`RuleStats` holding only the counts made after ``snapshot`` (e.g. the last
        part of training, when the agent has learned)."""
        evaluated, fired = snapshot
        if np.shape(evaluated) != self.evaluated.shape or np.shape(fired) != self.fired.shape:
            raise SymlearnError("the snapshot belongs to another formula")
        window = RuleStats(self.dnf, self.feature_names)
        window.evaluated = self.evaluated - np.asarray(evaluated, dtype=np.int64)
        window.fired = self.fired - np.asarray(fired, dtype=np.int64)
        return window

    def prune(self, threshold: float = 1e-3, *, min_evaluations: int = 1) -> tuple[Any, list[RuleVerdict]]:
        """The formula without the rules whose fired/evaluated ratio is below ``threshold``
        (rules evaluated fewer than ``min_evaluations`` times are dropped too: nothing supports
        them), and a verdict per rule in the formula's order."""
        if not 0 <= threshold <= 1:
            raise SymlearnError(f"the pruning threshold must lie in [0, 1], got {threshold}")
        ratios = self.ratios()
        keep = (ratios >= threshold) & (self.evaluated >= min_evaluations)
        verdicts = [RuleVerdict(str(c), int(e), int(f), float(r), bool(k))
                    for c, e, f, r, k in zip(self.dnf.conjunctions, self.evaluated, self.fired, ratios, keep)]
        pruned = type(self.dnf)(tuple(c for c, k in zip(self.dnf.conjunctions, keep) if k))
        return pruned, verdicts


class FormulaCost:
    """The cost of a DNF formula on points ``[N, k]``, with the pruning counts: what
    :class:`DnfCostWrapper` computes for one step and :class:`DnfRolloutCost` for a whole rollout.

    Calling it returns ``(costs, totals)``: ``costs`` is ``[N]`` (``violation_cost`` where the
    formula holds, times ``1 + depth_weight x`` the point's depth in the unsafe set where
    ``depth_weight > 0``: :mod:`~symlearn.backends.dnf_depth`), or ``[N, m]`` with ``per_rule``
    (one column per conjunction, formula order);
    ``totals`` is ``[N]``, the sum over rules. With ``track``, :attr:`stats` counts every point
    in ascending complexity; the rules are evaluated pre-sorted by size (:attr:`RuleStats.ordered_dnf`),
    so a point's first firing rule is the kernels' ``first`` without an ``[N, m]`` matrix.
    """

    def __init__(self, dnf: Any, features: Any, *, violation_cost: float = 1.0, per_rule: bool = False,
                 track: bool = True, stats: RuleStats | None = None, depth_weight: float = 0.0) -> None:
        if stats is not None and stats.dnf != dnf:
            raise SymlearnError("the shared rule statistics belong to another formula")
        if isinstance(depth_weight, bool) or not isinstance(depth_weight, (int, float)) or \
                not 0.0 <= float(depth_weight) < math.inf:
            raise SymlearnError(f"depth_weight must be a finite number >= 0, got {depth_weight!r}")
        self.dnf = dnf
        self.violation_cost, self.per_rule, self.track = float(violation_cost), per_rule, track
        self.stats = stats if stats is not None else RuleStats(dnf, features)
        self.feature_names = self.stats.feature_names
        self._evaluate = dnf.evaluator(self.feature_names)   # names resolved once, not every call
        self._evaluate_ordered = self.stats.ordered_dnf.evaluator(self.feature_names)
        self.depth_weight = float(depth_weight)
        self._depth = None
        if self.depth_weight:
            from symlearn.backends.dnf_depth import ViolationDepth

            self._depth = ViolationDepth(dnf, self.feature_names)

    def __call__(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        costs, totals = self._binary(X)
        if self._depth is None:
            return costs, totals
        # 1 + weight x depth on the unsafe points (dnf_depth's module doc); safe points stay 0
        factor = 1.0 + self.depth_weight * self._depth(np.asarray(X, dtype=np.float64))
        costs = costs * (factor[:, None] if costs.ndim == 2 else factor)
        return costs, (costs.sum(axis=1) if costs.ndim == 2 else costs)

    def _binary(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        X = np.asarray(X, dtype=np.float64)
        if X.shape[1] != len(self.feature_names):
            raise DataError(f"expected {len(self.feature_names)} features ({', '.join(self.feature_names)}), "
                            f"got {X.shape[1]}")
        if not math.isfinite(X.sum()) and not np.isfinite(X).all():   # one sum, unless suspect
            raise DataError("features must be finite (found NaN or inf)")
        if self.track and not self.per_rule:   # the first firing rule in ascending complexity decides
            first = self._evaluate_ordered.first(X)
            self.stats.count_first(first)
            costs = self.violation_cost * (first < len(self.stats.order)).astype(np.float64)
            return costs, costs
        if self.track or self.per_rule:
            ordered = self._evaluate_ordered(X, per_conjunction=True)
            if self.track:
                self.stats.count_ordered(ordered)
            if self.per_rule:   # back to the formula's order
                costs = self.violation_cost * ordered[:, self.stats._rank].astype(np.float64)
                return costs, costs.sum(axis=1)
            fired = ordered.any(axis=1)
        else:
            fired = self._evaluate(X)
        costs = self.violation_cost * fired.astype(np.float64)
        return costs, costs


class DnfCostWrapper(gym.Wrapper):
    """``DnfCostWrapper(env, dnf, features, source="info", violation_cost=1.0, per_rule=False,
    penalty=0.0, track=True, depth_weight=0.0)`` (see the module docstring; ``depth_weight``:
    :class:`FormulaCost`).

    ``source``: ``"info"`` (``info["features"]``), ``"observation"``, or a callable
    ``(observation, info) -> vector``. ``penalty`` subtracts ``penalty * cost`` (summed over
    rules) from the reward, for learners that know no cost. ``stats`` holds the
    :class:`RuleStats` of every step since the wrapper was built (``track=False`` skips them);
    pass one ``stats`` object to several wrappers (vectorised training) to count them together.
    """

    def __init__(self, env: gym.Env, dnf: Any, features: Any, *, source: str | Callable = "info",
                 violation_cost: float = 1.0, per_rule: bool = False, penalty: float = 0.0,
                 track: bool = True, stats: RuleStats | None = None, depth_weight: float = 0.0) -> None:
        super().__init__(env)
        if not (source in ("info", "observation") or callable(source)):
            raise SymlearnError(f"unknown feature source {source!r}", hint="use 'info', 'observation' or a callable")
        self.cost = FormulaCost(dnf, features, violation_cost=violation_cost, per_rule=per_rule, track=track,
                                stats=stats, depth_weight=depth_weight)
        self.dnf, self.source, self.penalty = dnf, source, float(penalty)
        self.stats, self.feature_names = self.cost.stats, self.cost.feature_names

    def _features(self, observation: Any, info: dict[str, Any]) -> np.ndarray:
        if self.source == "info":
            if "features" not in info:
                raise DataError("the environment reports no info['features']",
                                hint="use source='observation' or a callable")
            raw = _by_name(info["features"], self.feature_names)
        elif self.source == "observation":
            raw = observation
        else:
            raw = self.source(observation, info)
        return np.asarray(raw, dtype=np.float64).reshape(1, -1)

    def step(self, action: Any):
        observation, reward, terminated, truncated, info = self.env.step(action)
        costs, totals = self.cost(self._features(observation, info))
        total = float(totals[0])
        info = dict(info)
        if "cost" in info:
            info["env_cost"] = info["cost"]  # the environment's own (ground-truth) cost stays readable
        info["cost"] = costs[0] if self.cost.per_rule else total
        return observation, reward - self.penalty * total, terminated, truncated, info


class DnfRolloutCost:
    """The cost of :class:`DnfCostWrapper`, computed for a whole PPO rollout at once: pass it as
    ``train_ppo(..., cost_fn=DnfRolloutCost(dnf, names))``.

    Same semantics as the wrapper (:class:`FormulaCost`: the formula on the features of the state
    each step reached; ``violation_cost``; ``per_rule``; the :class:`RuleStats` counts, in
    ascending complexity), but one vectorised evaluation of ``T x N`` points per rollout instead
    of a Python call per step: the per-step wrapper cannot stay within a few percent of a fast
    environment's step (a wrapper call alone costs about a microsecond), a rollout-sized
    evaluation does.

    ``source``: ``"info"`` (``info["features"]``, recorded by PPO for every step) or
    ``"observation"`` (the reached observation as the policy sees it, flattened to float32). Give
    ``observation_space`` where it is ``Discrete``: the policy sees its one-hot vector, the formula
    reads the state's id (``cell == 5``), as :class:`DnfCostWrapper` does.
    """

    def __init__(self, dnf: Any, features: Any, *, source: str = "info", violation_cost: float = 1.0,
                 per_rule: bool = False, track: bool = True, stats: RuleStats | None = None,
                 depth_weight: float = 0.0, observation_space: Any = None) -> None:
        if source not in ("info", "observation"):
            raise SymlearnError(f"unknown feature source {source!r}", hint="use 'info' or 'observation'")
        self.cost = FormulaCost(dnf, features, violation_cost=violation_cost, per_rule=per_rule, track=track,
                                stats=stats, depth_weight=depth_weight)
        self.dnf, self.source = dnf, source
        self.stats, self.feature_names = self.cost.stats, self.cost.feature_names
        self._id_start = int(observation_space.start) if isinstance(observation_space, gym.spaces.Discrete) else None
        # what train_ppo records from every step's info for us
        self.info_keys = ("features",) if source == "info" else ()

    def __call__(self, rollout: Any) -> np.ndarray:
        raw = rollout.info["features"] if self.source == "info" else rollout.next_obs
        if raw.dtype == object:   # dicts name -> number, recorded as they came: read by name
            raw = np.array([[_by_name(d, self.feature_names) for d in row] for row in raw], dtype=np.float64)
        if self.source == "observation" and self._id_start is not None:   # one-hot rows back to ids
            raw = raw.argmax(axis=-1)[..., None] + self._id_start
        shape = raw.shape[:2]
        costs, _ = self.cost(np.asarray(raw, dtype=np.float64).reshape(shape[0] * shape[1], -1))
        return costs.reshape(*shape, *costs.shape[1:])


__all__ = ["DnfCostWrapper", "DnfRolloutCost", "FormulaCost", "RuleStats", "RuleVerdict"]
