"""What ``symlearn train`` constrains or penalises: a learned DNF, a learned neural cost, or the
environment's own ``info["cost"]`` -- in the two forms its trainers take.

Our PPO takes a cost for a whole rollout at once (``rollout_cost``, :class:`~symlearn.rl.ppo.Rollout`
in, ``[T, N]`` or ``[T, N, k]`` out); a stable-baselines3 learner takes it one step at a time
(``step_cost(observation, action, next_observation, info)``, through
:class:`~symlearn.backends.lagrangian.StepCostWrapper`). Both are built here from the same
artefact, checked once against the environment:

* a DNF formula needs the names of the environment's features (``--features a,b``, the
  environment's ``feature_names``, or the keys of a dict ``info["features"]``), and reads them
  from ``info["features"]`` when the environment reports them, else from the observation;
* a neural cost must have been learned for the environment's observation and action spaces.

The environment's ``info["cost"]`` stays the ground truth either way: it is what evaluation
reports, never what a learned cost is trained against.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.errors import DataError, SymlearnError


@dataclass
class TrainingCost:
    """A learned cost in the forms the trainers take; ``kind`` is ``"dnf"`` or ``"neural"``."""

    kind: str
    rollout_cost: Any             # Rollout -> [T, N] or [T, N, k]
    step_cost: Any                # (observation, action, next_observation, info) -> vector
    n_costs: int
    stats: Any = None             # RuleStats of a DNF (for --prune)
    wrap: Any = None              # env -> env making info["features"] a vector (dict features), or None
    expert_level: float | None = None   # a neural cost's charge on its demonstrations per episode (default limit)
    charges_nothing: bool = False       # a neural cost whose weights lambda are all 0: 0 everywhere
    # a DNF file's held-out check (learn dnf --validation): its per_demonstration is what the formula
    # charges an unseen expert episode, the false-alarm floor train adds to a budget
    validation: Any = None


class _DictFeatures:
    """Makes a dict ``info["features"]`` the vector of its values in ``names`` order."""

    def __init__(self, names: tuple[str, ...]) -> None:
        self.names = names

    def __call__(self, env: Any) -> Any:
        from symlearn.backends.lagrangian import FeatureVectorWrapper

        return FeatureVectorWrapper(env, self.names)


def training_cost(path: str, target: Any, *, features: str | None = None, per_rule: bool = False,
                  depth_weight: float = 0.0) -> TrainingCost:
    """The cost in ``path`` (``.dnf`` text or ``.safetensors``) checked against ``target``'s
    environment; ``depth_weight`` shapes a DNF cost by the depth of the violation
    (:mod:`symlearn.backends.dnf_depth`)."""
    if str(path).endswith(".safetensors"):
        return _neural(path, target)
    return _dnf(path, target, features, per_rule, depth_weight)


def _neural(path: str, target: Any) -> TrainingCost:
    from symlearn.learners.neural import NeuralCost

    env = target.make()
    try:
        cost = NeuralCost.load(path, env)   # refuses a cost learned for other spaces
    finally:
        env.close()

    return TrainingCost("neural", cost.cost_fn(), cost.step_cost(), 1, expert_level=cost.expert_level,
                        charges_nothing=not bool(np.any(cost.lambdas.numpy())))


def _dnf(path: str, target: Any, features: str | None, per_rule: bool, depth_weight: float) -> TrainingCost:
    from symlearn.backends.dnf_cost import DnfRolloutCost, FormulaCost, RuleStats
    from symlearn.logic.dnf import load

    dnf = load(path)
    env = target.make()
    try:
        # names counted against the columns; learn dnf's own x0 .. x{k-1} where nothing names them
        found = target.features(env, override=features, numbered=True)
        _, info = env.reset(seed=0)
        space = env.observation_space
        view = _view_columns(env)
    finally:
        env.close()
    if found is not None and view is not None and not set(dnf.features) <= set(found.names) \
            and set(dnf.features) <= set(view):
        # learned from demonstrations of the policy's numeric view (`data record` of a Dict
        # observation holding a picture stores that view): read the view, by the names record gave it
        found = replace(found, names=view, source="observation", named=True)
    if found is not None and not found.named and not set(dnf.features) <= set(found.names):
        where = 'info["features"]' if found.source == "info" else "the observation"
        raise DataError(f"{target.display} names no features and the formula reads {', '.join(sorted(dnf.features))}"
                        f", but {where} has {len(found.names)} unnamed column(s), read as "
                        f"{', '.join(found.names)}", file=str(path),
                        hint="learn the formula from states with those columns (with --inputs to pick some), "
                             "or name the columns (--features a,b,..., a feature_names attribute or an "
                             "info['features'] dict)")
    if found is None:
        raise DataError(f"{target.display} names no features, so the formula's {', '.join(sorted(dnf.features))} "
                        "cannot be read there", file=str(path),
                        hint="give the observation's column names with --features a,b,... (or a feature_names "
                             "attribute / info['features'] dict in the environment)")
    names, source = found.names, found.source
    try:
        stats = RuleStats(dnf, names)
    except DataError as exc:
        raise DataError(exc.message, file=str(path), hint=exc.hint) from None
    wrap = _DictFeatures(names) if source == "info" and isinstance(info.get("features"), dict) else None
    # evaluated once per rollout over all its steps (the same costs and rule counts as the
    # per-step form, a fraction of its overhead)
    rollout = DnfRolloutCost(dnf, names, source=source, per_rule=per_rule, stats=stats, depth_weight=depth_weight,
                             observation_space=space)
    formula = FormulaCost(dnf, names, per_rule=per_rule, stats=stats, depth_weight=depth_weight)

    def step_cost(observation: Any, action: Any, next_observation: Any, info: dict[str, Any]) -> np.ndarray:
        raw = info["features"] if source == "info" else next_observation
        costs, _ = formula(np.asarray(raw, dtype=np.float64).reshape(1, -1))
        return np.asarray(costs[0], dtype=np.float64).reshape(-1)

    n = len(dnf.conjunctions) if per_rule else 1
    return TrainingCost("dnf", rollout, step_cost, n, stats=stats, wrap=wrap, validation=_recorded_validation(path))


def _recorded_validation(path: str):
    """The held-out check a ``.dnf`` text file's header records, or None (a JSON formula has no header)."""
    from symlearn.input_limits import read_input_text
    from symlearn.learners.validation import rule_file_validation

    if str(path).endswith(".json"):
        return None
    try:
        return rule_file_validation(read_input_text(Path(path), what="rule file"))
    except DataError as exc:
        raise DataError(exc.message, file=str(path), hint=exc.hint) from None


def _view_columns(env: Any) -> tuple[str, ...] | None:
    """The names of the numeric view's columns (:class:`~symlearn.recipes.spaces.NumericObservations`
    among ``env``'s wrappers), or None where the environment is seen as it is."""
    while env is not None:
        names = vars(env).get("column_names") if hasattr(env, "__dict__") else None
        if names is not None:
            return tuple(names)
        env = getattr(env, "env", None)
    return None


def penalised(cost: TrainingCost) -> Any:
    """``rollout -> reward - cost`` (summed over rules) for PPO without a multiplier."""
    def reward(rollout: Any) -> np.ndarray:
        c = np.asarray(cost.rollout_cost(rollout), dtype=np.float64)
        return rollout.rewards - (c.sum(axis=2) if c.ndim == 3 else c)
    reward.info_keys = getattr(cost.rollout_cost, "info_keys", ())  # type: ignore[attr-defined]
    return reward


def refused_without_cost(target: Any, algo: str, steps: int) -> SymlearnError:
    """The one-line refusal of ``--algo ALGO`` without ``--cost`` on an environment whose first
    ``steps`` (its first rollout) reported no ``info["cost"]`` -- decided from the steps training
    took, since an environment may report a cost only on the steps that pay it."""
    return SymlearnError(f"--algo {algo} without --cost constrains the environment's info['cost'], and "
                         f"{target.display} reports none in the first rollout ({steps} steps)",
                         hint="report info['cost'] on the steps that pay it (a step without it costs 0), give a "
                              "learned cost with --cost RULES.dnf|COST.safetensors, or train --algo "
                              + algo.removesuffix("-lag"))


__all__ = ["TrainingCost", "penalised", "refused_without_cost", "training_cost"]
