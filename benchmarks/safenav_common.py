"""What the SafeNav experiments of thesis section 4.4 share (``safenav_transfer.py``, ``safenav_depth_sweep.py``).

* :func:`learn_rules`: expert demonstrations (the scripted expert of
  :mod:`symlearn.envs.safenav_expert`) -> :class:`~symlearn.learners.trees.OneClassTreeConstraint`
  -> the DNF of the unsafe set over the thesis' 20 features.
* :class:`FastRules`: the formula bound to the feature order once (``DNF.evaluator``), evaluated
  on *one* point per environment step in a few microseconds; :meth:`FastRules.check` compares
  it against ``DNF.evaluate`` on a sample before every run. (The recorded results were produced
  with an earlier per-atom numpy evaluator here, checked the same way; ``DNF.evaluate`` then cost
  250-660 us per single point.)
* :class:`Tracked`: a gymnasium wrapper that sets ``info["cost"]`` (the learned formula's
  cost, as :class:`symlearn.backends.dnf_cost.DnfCostWrapper` does, or the environment's own
  ground-truth cost when no formula is given), keeps the ground truth as ``info["env_cost"]``,
  counts rule evaluations/firings into a :class:`symlearn.backends.dnf_cost.RuleStats` (in
  batches: the same counts as per step) and records every finished episode (step of its end,
  return, ground-truth cost, formula cost) in a shared :class:`Recorder`.
* :func:`run`: one training run described by a JSON-able spec (PPO, PPO-Lagrangian on the true
  cost or on a formula), with a binned training curve, a final evaluation and the rule counts.
* :func:`expert_rows`: the scripted expert's reward and costs on the evaluation seeds.
* :class:`ResultLog`: per-run results in a JSONL file, rewritten atomically after each run (a
  crash loses at most the runs under way); finished runs are skipped on restart.

Every worker runs with one torch thread (``PPOConfig.torch_threads=1``, plus
``torch.set_num_threads(1)`` at worker start).
"""

from __future__ import annotations

import json
import math
import os
import platform
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from symlearn.atomic import write_text

TASKS = (("point", "goal"), ("point", "push"), ("car", "goal"), ("car", "push"))
NAMES = {task: f"{a.capitalize()}{t.capitalize()}" for task in TASKS for a, t in [task]}
EVAL_SEED = 100_000  # evaluation episodes use seeds EVAL_SEED + i (never a demonstration or training seed)


def task_key(agent: str, task: str) -> str:
    return f"{agent}-{task}"


def parse_key(key: str) -> tuple[str, str]:
    agent, task = key.split("-")
    return agent, task


# --------------------------------------------------------------------------------------------------
# rules


@lru_cache(maxsize=None)
def demonstrations(agent: str, task: str, n: int, seed: int):
    from symlearn.envs.safenav_expert import expert_demonstrations

    return expert_demonstrations(agent, task, n, seed=seed)


@lru_cache(maxsize=None)
def learn_rules(agent: str, task: str, depth: int, n_demos: int, demo_seed: int,
                inputs: tuple[str, ...] | None = None, validation: float | None = None):
    """``(dnf, info)``: the one-class tree's unsafe-set formula from ``n_demos`` expert episodes
    (``inputs``: the features its rules may test, ``OneClassTreeConstraint(inputs=...)``; all 20 when ``None``).
    ``validation``: hold out that share of the episodes as ``learn dnf --validation`` does (whole
    episodes, ``holdout(..., seed=0)``), learn from the rest and put the held-out check in
    ``info["validation"]`` (its ``per_demonstration``: the formula's false-alarm floor per episode)."""
    from symlearn.envs.safenav.observation import FEATURE_NAMES
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint, feature_matrix
    from symlearn.learners.validation import holdout, unsafe_states_report

    demos = demonstrations(agent, task, n_demos, demo_seed)
    held = None
    if validation is not None:
        demos, held = holdout(demos, validation, seed=0)
    start = time.perf_counter()
    tree = OneClassTreeConstraint(max_depth=depth, random_state=0,
                                  inputs=list(inputs) if inputs else None).fit(demos, list(FEATURE_NAMES))
    dnf = tree.dnf_
    info = {"source": task_key(agent, task), "depth": depth, "n_demos": n_demos, "demo_seed": demo_seed,
            "inputs": list(inputs) if inputs else None,
            "points": int(sum(len(t.states) for t in demos)), "leaves": len(tree.safe_boxes_),
            "conjunctions": len(dnf.conjunctions), "atoms": int(sum(len(c.atoms) for c in dnf.conjunctions)),
            "fit_seconds": time.perf_counter() - start,
            "expert_return": float(np.mean([sum(t.rewards) for t in demos])),
            "expert_cost": float(np.mean([t.info["cost"] for t in demos]))}
    if held is not None:
        states = [feature_matrix(type(held)([t]), list(FEATURE_NAMES))[0] for t in held]
        info["validation"] = unsafe_states_report(tree.predict, states, list(FEATURE_NAMES), validation,
                                                  len(demos)).as_dict()
    return dnf, info




class FastRules:
    """Which conjunctions of ``dnf`` hold on one feature vector: ``DNF.evaluator`` bound once."""

    def __init__(self, dnf: Any, names: Iterable[str]) -> None:
        self.dnf = dnf
        self.names = tuple(names)
        missing = sorted(set(dnf.features) - set(self.names))
        if missing:
            raise ValueError(f"the formula uses unknown features {missing}")
        self.m = len(dnf.conjunctions)
        self._evaluate = dnf.evaluator(self.names)

    def fires(self, x: np.ndarray) -> np.ndarray:
        """``[m]`` booleans in the formula's order for one vector ``x`` of ``len(names)`` features."""
        return np.asarray(self._evaluate(np.asarray(x, dtype=np.float64)[None, :], per_conjunction=True))[0]

    def check(self, X: np.ndarray) -> None:
        """Raise unless :meth:`fires` agrees with ``DNF.evaluate`` on every row of ``X``."""
        expected = self.dnf.evaluate(np.asarray(X, dtype=np.float64), self.names, per_conjunction=True)
        got = np.array([self.fires(row) for row in np.asarray(X, dtype=np.float64)]).reshape(expected.shape)
        if not np.array_equal(expected, got):
            bad = int(np.argwhere(expected != got)[0][0])
            raise AssertionError(f"FastRules disagrees with DNF.evaluate on row {bad}")


@lru_cache(maxsize=None)
def probe_points(agent: str, task: str, n_demos: int, demo_seed: int, n_random: int = 3000,
                 seed: int = 0) -> np.ndarray:
    """Points to check :class:`FastRules` on: demonstrated features, random-policy features and
    jittered copies of both (so thresholds are crossed both ways)."""
    from symlearn.envs.safenav.env import SafeNavEnv

    demos = demonstrations(agent, task, n_demos, demo_seed)
    X = np.vstack([np.asarray(t.states) for t in demos])
    rng = np.random.default_rng(seed)
    env = SafeNavEnv(agent, task)
    env.reset(seed=seed)
    rows = []
    for _ in range(n_random):
        _, _, _, trunc, info = env.step(rng.uniform(-1, 1, 2))
        rows.append(info["features"])
        if trunc:
            env.reset()
    R = np.array(rows)
    pick = X[rng.choice(len(X), size=min(len(X), 3000), replace=False)]
    both = np.vstack([pick, R])
    jitter = both + rng.normal(0.0, 0.05, both.shape) * (np.abs(both) + 0.1)
    return np.vstack([both, jitter])


# --------------------------------------------------------------------------------------------------
# the wrapper that reports costs and records episodes


@dataclass
class Recorder:
    """Episodes finished in any of the wrapped copies: ``(end step, return, true cost, formula cost)``."""

    steps: int = 0
    episodes: list[tuple[int, float, float, float]] = field(default_factory=list)


def make_tracked(env: Any, rules: FastRules | None, recorder: Recorder, stats: Any | None = None,
                 batch: int = 4096, features: list | None = None):
    import gymnasium as gym

    class Tracked(gym.Wrapper):
        """``info["cost"]`` = the formula's cost (or the true cost without ``rules``); see the module docstring."""

        def __init__(self) -> None:
            super().__init__(env)
            self._buffer: list[np.ndarray] = []
            self._ret = self._true = self._dnf = 0.0

        def reset(self, **kwargs):
            self._ret = self._true = self._dnf = 0.0
            return self.env.reset(**kwargs)

        def step(self, action):
            obs, reward, terminated, truncated, info = self.env.step(action)
            true_cost = float(info["cost"])
            info = dict(info)
            info["env_cost"] = true_cost
            if features is not None:
                features.append(np.array(info["features"], dtype=np.float64))
            if rules is not None:
                fires = rules.fires(np.asarray(info["features"], dtype=np.float64))
                cost = 1.0 if fires.any() else 0.0
                info["cost"] = cost
                if stats is not None:
                    self._buffer.append(fires)
                    if len(self._buffer) >= batch:
                        self.flush()
            else:
                cost = math.nan
            recorder.steps += 1
            self._ret += float(reward)
            self._true += true_cost
            self._dnf += cost
            if terminated or truncated:
                recorder.episodes.append((recorder.steps, self._ret, self._true, self._dnf))
                self._ret = self._true = self._dnf = 0.0
            return obs, reward, terminated, truncated, info

        def flush(self) -> None:
            if self._buffer and stats is not None:
                stats.count(np.array(self._buffer))
            self._buffer = []

        def close(self) -> None:
            self.flush()
            super().close()

    return Tracked()


# --------------------------------------------------------------------------------------------------
# one run


@dataclass(frozen=True)
class Budget:
    steps: int
    eval_episodes: int = 10
    curve_bins: int = 20
    n_envs: int = 4
    n_steps: int = 256
    batch_size: int = 256
    n_epochs: int = 5


SETTINGS = ("legacy", "defaults")


def ppo_config(budget: Budget, seed: int, normalize: bool = False, settings: str = "legacy"):
    """``normalize``: standardised observations and PopArt-scaled critics (PPOConfig's
    ``normalize_observations`` / ``normalize_values``). ``settings="defaults"``: ``PPOConfig(seed=seed)``
    as a user gets it (its ``None`` settings resolved by ``train_ppo``; the budget's rollout sizes
    and ``normalize`` are not used)."""
    from symlearn.rl.ppo import PPOConfig

    if settings == "defaults":
        return PPOConfig(seed=seed, torch_threads=1)
    if settings != "legacy":
        raise ValueError(f"settings must be one of {SETTINGS}, got {settings!r}")
    return PPOConfig(n_envs=budget.n_envs, n_steps=budget.n_steps, batch_size=budget.batch_size,
                     n_epochs=budget.n_epochs, learning_rate=3e-4, seed=seed, torch_threads=1,
                     normalize_observations=normalize, normalize_values=normalize, log_std_init=0.0)


def lagrangian_config(cost_limit: float, multiplier_lr: float, advantage_scale: str = "raw",
                      settings: str = "legacy", init: float | None = None):
    """``settings="defaults"``: ``LagrangianConfig(cost_limit=cost_limit)``, the library's defaults
    (``multiplier_lr`` and ``advantage_scale`` are not used; ``init``, where given, replaces the
    default start of the multiplier)."""
    from symlearn.rl.ppo import LagrangianConfig

    if settings == "defaults":
        return LagrangianConfig(cost_limit=cost_limit, **({} if init is None else {"init": init}))
    if settings != "legacy":
        raise ValueError(f"settings must be one of {SETTINGS}, got {settings!r}")
    return LagrangianConfig(cost_limit=cost_limit, update="adam", lr=multiplier_lr, adam_beta2=0.999,
                            advantage_scale=advantage_scale, init=0.0,
                            cost_estimate="episodes")  # the recorded tables' rule and start


def _binned(episodes: list[tuple[int, float, float, float]], total: int, bins: int) -> dict[str, list]:
    edges = np.linspace(0, total, bins + 1)
    rows = np.array(episodes, dtype=np.float64).reshape(-1, 4)
    out: dict[str, list] = {"steps": [], "return": [], "true_cost": [], "dnf_cost": [], "episodes": []}
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = rows[(rows[:, 0] > lo) & (rows[:, 0] <= hi)]
        out["steps"].append(int(hi))
        out["episodes"].append(int(len(sel)))
        for key, col in (("return", 1), ("true_cost", 2), ("dnf_cost", 3)):
            value = float(np.mean(sel[:, col])) if len(sel) else math.nan
            out[key].append(None if not math.isfinite(value) else value)
    return out


def _stats(values: Iterable[float]) -> dict[str, float | None]:
    v = np.asarray(list(values), dtype=np.float64)
    v = v[np.isfinite(v)]
    if not len(v):
        return {"mean": None, "sd": None}
    return {"mean": float(v.mean()), "sd": float(v.std(ddof=0))}


def run(spec: dict[str, Any]) -> dict[str, Any]:
    """One training run. ``spec``: ``id``, ``algo`` (``ppo`` | ``ppo-lag``), ``target`` (key),
    ``cost`` (``"true"`` | ``"dnf"`` | ``"none"``), for ``dnf`` the rules as text (``rules``) or
    ``source``/``depth``/``n_demos``/``demo_seed``; ``seed``, ``budget`` (:class:`Budget` fields),
    ``cost_limit``, ``multiplier_lr``. Returns the spec plus results (JSON-able)."""
    import torch

    from symlearn.backends.dnf_cost import RuleStats
    from symlearn.envs.safenav.env import SafeNavEnv
    from symlearn.envs.safenav.observation import FEATURE_NAMES
    from symlearn.logic.dnf import parse
    from symlearn.rl.ppo import evaluate, train_ppo

    torch.set_num_threads(1)
    started = time.perf_counter()
    budget = Budget(**spec["budget"])
    agent, task = parse_key(spec["target"])
    rules = stats = dnf = None
    if spec["cost"] == "dnf":
        if spec.get("rules") is not None:
            dnf = parse(spec["rules"])
        else:
            dnf, _ = learn_rules(*parse_key(spec["source"]), spec["depth"], spec["n_demos"], spec["demo_seed"],
                                 tuple(spec["inputs"]) if spec.get("inputs") else None, spec.get("validation"))
        rules = FastRules(dnf, FEATURE_NAMES)
        check_on = spec.get("source") or spec["target"]
        rules.check(probe_points(*parse_key(check_on), spec["n_demos"], spec["demo_seed"], n_random=1500))
        stats = RuleStats(dnf, FEATURE_NAMES)
    recorder = Recorder()
    wrappers: list[Any] = []

    def env_fn():
        w = make_tracked(SafeNavEnv(agent, task), rules, recorder, stats)
        wrappers.append(w)
        return w

    lagrangian = None
    if spec["algo"] == "ppo-lag":
        lagrangian = lagrangian_config(spec["cost_limit"], spec["multiplier_lr"],
                                       spec.get("advantage_scale", "raw"), spec.get("settings", "legacy"),
                                       spec.get("multiplier_init"))
    config = ppo_config(budget, spec["seed"], spec.get("normalize", False), spec.get("settings", "legacy"))
    result = train_ppo(env_fn, budget.steps, config, lagrangian=lagrangian)
    for w in wrappers:
        w.flush()
    train_seconds = time.perf_counter() - started
    curve = _binned(recorder.episodes, result.steps, budget.curve_bins)
    last = [e for e in recorder.episodes if e[0] > 0.9 * result.steps]  # the last 10 % of training

    evaluation = {}
    eval_features: list[np.ndarray] = []
    for mode, deterministic in (("stochastic", False), ("greedy", True)):
        rec = Recorder()
        env = make_tracked(SafeNavEnv(agent, task), rules, rec, None,
                           features=eval_features if mode == "stochastic" else None)
        evaluate(result.policy, env, budget.eval_episodes, seed=EVAL_SEED, deterministic=deterministic)
        evaluation[mode] = {"return": _stats(e[1] for e in rec.episodes),
                            "true_cost": _stats(e[2] for e in rec.episodes),
                            "dnf_cost": _stats(e[3] for e in rec.episodes) if rules is not None else None,
                            "episodes": len(rec.episodes)}
    monitor = dnf
    if monitor is None and spec.get("monitor_depth"):  # a baseline: the target's own learned formula, not trained on
        monitor, _ = learn_rules(agent, task, spec["monitor_depth"], spec["n_demos"], spec["demo_seed"])
    out = dict(spec)
    if monitor is not None and eval_features:
        out["unsafe_breakdown"] = unsafe_breakdown(monitor, np.array(eval_features))
    out.update({
        "steps": int(result.steps), "train_seconds": train_seconds, "seconds": time.perf_counter() - started,
        "steps_per_second": result.steps / train_seconds,
        "final_multipliers": [float(x) for x in np.atleast_1d(result.multipliers)],
        "last10": {"return": _stats(e[1] for e in last), "true_cost": _stats(e[2] for e in last),
                   "dnf_cost": _stats(e[3] for e in last) if rules is not None else None, "episodes": len(last)},
        "eval": evaluation, "curve": curve,
        "multiplier_curve": [h.multipliers[0] if h.multipliers else 0.0
                             for h in result.history[:: max(1, len(result.history) // budget.curve_bins)]],
        "machine": platform.node(),
        "resolved_config": {"ppo": _config_dict(config.resolved()),
                            "lagrangian": _config_dict(lagrangian) if lagrangian is not None else None},
    })
    if stats is not None:
        out["rule_counts"] = {"evaluated": stats.evaluated.tolist(), "fired": stats.fired.tolist()}
        out["n_rules"] = len(dnf.conjunctions)
    return out


FEATURE_GROUPS = {"a": "acceleration", "v": "velocity", "d": "lidar"}


def unsafe_breakdown(dnf: Any, X: np.ndarray, top: int = 8) -> dict[str, Any]:
    """Why ``dnf`` calls the states ``X`` (one row per step, the 20 SafeNav features) unsafe: the
    share of steps it fires on; per feature group (acceleration ``a_*``, velocity ``v_*``, lidar
    ``d_*``) the share of steps on which a one-atom conjunction of that group fires (the formula's
    bounding box of the demonstrations: ``v_x > 1.0`` etc.); the share on which only conjunctions of
    several atoms fire; per feature, the one-atom conjunctions' share; and the ``top`` conjunctions
    by the share of steps they fire on."""
    from symlearn.envs.safenav.observation import FEATURE_NAMES

    fires = np.asarray(dnf.evaluate(np.asarray(X, dtype=np.float64), FEATURE_NAMES, per_conjunction=True), dtype=bool)
    unsafe = fires.any(axis=1)
    single = [i for i, c in enumerate(dnf.conjunctions) if len(c.atoms) == 1]
    groups: dict[str, np.ndarray] = {}
    per_feature: dict[str, float] = {}
    for i in single:
        feature = _feature(dnf, i)
        group = FEATURE_GROUPS.get(feature.split("_")[0], "other")
        groups[group] = groups.get(group, np.zeros(len(X), dtype=bool)) | fires[:, i]
        per_feature[feature] = float(np.mean(fires[:, [j for j in single if _feature(dnf, j) == feature]].any(axis=1)))
    any_single = fires[:, single].any(axis=1) if single else np.zeros(len(X), dtype=bool)
    share = fires.mean(axis=0)
    order = np.argsort(-share)[:top]
    return {"steps": int(len(X)), "unsafe_share": float(unsafe.mean()),
            "one_atom_share_by_group": {g: float(v.mean()) for g, v in sorted(groups.items())},
            "only_multi_atom_share": float(np.mean(unsafe & ~any_single)),
            "one_atom_share_by_feature": dict(sorted(per_feature.items(), key=lambda kv: -kv[1])),
            "top_conjunctions": [{"rule": str(dnf.conjunctions[i]), "share": float(share[i])}
                                 for i in order if share[i] > 0]}


def _feature(dnf: Any, i: int) -> str:
    return dnf.conjunctions[i].atoms[0].feature


def _config_dict(config: Any) -> dict[str, Any]:
    """A frozen config dataclass as JSON-able settings (tuples as lists)."""
    from dataclasses import asdict

    return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(config).items()}


def prune_counts(dnf: Any, evaluated: list[int], fired: list[int], threshold: float):
    """The thesis' pruning applied to recorded counts: ``(pruned dnf, verdicts)`` via ``RuleStats.prune``."""
    from symlearn.backends.dnf_cost import RuleStats
    from symlearn.envs.safenav.observation import FEATURE_NAMES

    stats = RuleStats(dnf, FEATURE_NAMES)
    stats.evaluated[:] = np.asarray(evaluated, dtype=np.int64)
    stats.fired[:] = np.asarray(fired, dtype=np.int64)
    return stats.prune(threshold)


# --------------------------------------------------------------------------------------------------
# the scripted expert on the evaluation seeds


def expert_rows(target: str, rule_sets: dict[str, Any], episodes: int) -> dict[str, Any]:
    """The scripted expert on ``target``'s evaluation seeds: reward, true cost, and the cost each
    formula in ``rule_sets`` (name -> DNF) would charge it (its false alarms on unseen episodes)."""
    from symlearn.envs.safenav.env import SafeNavEnv
    from symlearn.envs.safenav.observation import FEATURE_NAMES
    from symlearn.envs.safenav_expert import SafeNavExpert

    agent, task = parse_key(target)
    env = SafeNavEnv(agent, task)
    expert = SafeNavExpert(env, rng=np.random.default_rng(0))
    compiled = {name: FastRules(dnf, FEATURE_NAMES) for name, dnf in rule_sets.items()}
    returns, true_costs, dnf_costs = [], [], {name: [] for name in rule_sets}
    for i in range(episodes):
        env.reset(seed=EVAL_SEED + i)
        expert.reset()
        total, cost, fired = 0.0, 0.0, {name: 0.0 for name in rule_sets}
        done = False
        while not done:
            _, r, term, trunc, info = env.step(expert())
            total += r
            cost += info["cost"]
            for name, rules in compiled.items():
                fired[name] += float(rules.fires(info["features"]).any())
            done = term or trunc
        returns.append(total)
        true_costs.append(cost)
        for name in rule_sets:
            dnf_costs[name].append(fired[name])
    return {"target": target, "return": _stats(returns), "true_cost": _stats(true_costs),
            "dnf_cost": {name: _stats(v) for name, v in dnf_costs.items()}, "episodes": episodes}


# --------------------------------------------------------------------------------------------------
# results on disk


class ResultLog:
    """Finished runs, one JSON object per line; the whole file is rewritten atomically per run."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.rows: dict[str, dict[str, Any]] = {}
        if self.path.exists():
            for n, line in enumerate(self.path.read_text().splitlines(), 1):
                if line.strip():
                    try:
                        row = json.loads(line)
                    except json.JSONDecodeError:
                        print(f"{self.path}:{n}: unreadable line skipped", flush=True)
                        continue
                    self.rows[row["id"]] = row

    def done(self, run_id: str) -> bool:
        return run_id in self.rows

    def add(self, row: dict[str, Any]) -> None:
        self.rows[row["id"]] = row
        write_text(self.path, "".join(json.dumps(r, allow_nan=False, default=_json_default) + "\n"
                                      for r in self.rows.values()))


def _json_default(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON: {type(value).__name__}")


def clean(value: Any) -> Any:
    """NaN/inf -> None, numpy -> Python, recursively (JSON without NaN)."""
    if isinstance(value, dict):
        return {k: clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [clean(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def run_all(specs: list[dict[str, Any]], log: ResultLog, workers: int,
            on_result: Callable[[dict[str, Any]], None] | None = None) -> None:
    """Run the specs not yet in ``log`` on ``workers`` processes (fork; one torch thread each),
    in the given order, logging each as it finishes."""
    import multiprocessing as mp

    todo = [s for s in specs if not log.done(s["id"])]
    print(f"{len(specs) - len(todo)} of {len(specs)} runs already done; {len(todo)} to go on {workers} worker(s)",
          flush=True)
    if not todo:
        return
    preload()
    started = time.perf_counter()
    failed = []

    def report(i: int, row: dict[str, Any]) -> None:
        if "error" in row:  # not logged: the next start of the script retries it
            failed.append(row["id"])
            print(f"[{i}/{len(todo)}] {row['id']} FAILED:\n{row['error']}", flush=True)
            return
        log.add(clean(row))
        ev = row["eval"]["stochastic"]
        elapsed = time.perf_counter() - started
        print(f"[{i}/{len(todo)} {elapsed / 60:5.1f} min] {row['id']}: return {ev['return']['mean']:.2f}, "
              f"true cost {ev['true_cost']['mean']:.1f}"
              + (f", formula cost {ev['dnf_cost']['mean']:.1f}" if ev.get("dnf_cost") else "")
              + f" ({row['steps_per_second']:.0f} steps/s, {row['seconds']:.0f} s)", flush=True)
        if on_result is not None:
            on_result(row)

    if workers <= 1:
        for i, spec in enumerate(todo, 1):
            report(i, safe_run(spec))
    else:
        with mp.get_context("fork").Pool(workers, initializer=_worker_init, maxtasksperchild=4) as pool:
            for i, row in enumerate(pool.imap_unordered(safe_run, todo), 1):
                report(i, row)
    if failed:
        print(f"{len(failed)} run(s) failed (start the script again to retry them): {failed}", flush=True)


def safe_run(spec: dict[str, Any]) -> dict[str, Any]:
    """:func:`run`, with a failure returned as ``{"id", "error"}`` instead of ending the whole pool."""
    import traceback

    try:
        return run(spec)
    except Exception:  # noqa: BLE001 -- reported and retried on the next start
        return {"id": spec["id"], "error": traceback.format_exc()}


def preload() -> None:
    """Import everything a run needs in the parent, so forked workers share one version of the code
    (other people edit the working tree while a benchmark runs) and start fast."""
    import torch

    torch.set_num_threads(1)
    import symlearn.backends.dnf_cost  # noqa: F401
    import symlearn.envs.safenav.env  # noqa: F401
    import symlearn.envs.safenav_expert  # noqa: F401
    import symlearn.learners.trees.one_class_tree  # noqa: F401
    import symlearn.logic.dnf  # noqa: F401
    import symlearn.rl.ppo  # noqa: F401


def _worker_init() -> None:
    import torch

    torch.set_num_threads(1)
    try:
        os.nice(0)
    except OSError:
        pass
