"""Logic-constrained Q-learning in the traffic junctions, and transfer of the learned rules.

The experiment of the reference thesis, sections 3.4.4 and 3.4.5. Once per junction
(``lights``, ``priority``): record expert demonstrations, run logic constraint inference
(maximum-likelihood inference + ILP induction per iteration) and, with the same number of
iterations, maximum-likelihood inference alone. ``--start`` (the learner's default, ``uniform``,
``demonstrations`` or a uniform share in [0, 1]) is where the logic learner's nominal MaxEnt
visitation starts
(``LogicConstraintInference(start=)``); the inference-only peer keeps ``MLConstraintInference``'s
own default (``demonstrations``, the thesis' maximum-likelihood objective). Then, for every seed, train three
epsilon-greedy tabular Q-learners in :class:`~symlearn.envs.junction_env.JunctionEnv`:

* ``QL``: no shield;
* ``C-QL``: shielded by the inference-only constraints (``MLConstraintInference.constraints_``);
* ``LC-QL``: shielded by the pairs the induced rules forbid (``rule_constraints_``), closed
  under the nominal MDP (a state where the rules forbid every action is empty, so the pairs
  entering it are forbidden too: the restriction step of the thesis' Algorithm 3.1);
* ``LC-QL raw``: the rules' pairs without that closure (reported to show why it is needed).

Transfer (combined 7 x 7 junction: one-way roads + priority + lights): the rules learned in
``lights`` (1) and ``priority`` (2) are plain rule text; ``logic_mdp("junction-combined")
.rule_mask(rules)`` translates them to the pairs of the combined domain (same ``bk.lp``, size 7:
the symbol grounding). Agents: QL, LC-QL(1), LC-QL(2), LC-QL(1+2).

Settings as in the thesis: epsilon 0.05 while training, greedy afterwards, learning rate 0.9,
discount 0.75, Q-table zero-initialised; reward = -(L1 distance to the goal) and -10 for a
step breaking a ground-truth rule. Each agent drives one route (entry -> exit arm end), seed
``i`` takes route ``i mod (number of routes)``, so all routes are covered.

Measured per method: P(at least one violation during training), P(at least one violation in
the greedy test rollouts) (both: the share of agents), violations per training episode, episodes
to convergence, final (greedy test) cost per episode, wall time. And Table 3.1's "empirical
probability of a rule violation" as mean ± sd over agents of a per-agent rate, in training and in
the greedy tests, for three rates (which one the thesis means is argued in docs/BENCHMARKS.md):
violations per episode, share of episodes with a violation, violations per step.

**Episodes to convergence** (per agent): the training cost of an episode is minus its return;
the agent has converged at the first episode where the moving *median* over ``WINDOW`` episodes
comes within ``max(10 %, 0.5)`` of its final level (median of the last 50 episodes); the median
ignores the occasional exploratory step (epsilon stays 0.05, and one violation costs 10).
Reported as the median and interquartile range over agents. The *curve* version: the first
episode where the mean cost over agents (moving mean) comes within 10 % of its last 50
episodes. Also the total training cost (area under the curve) and greedy tests after fewer
training episodes (``--test-at``; ``q_learning`` is prefix-consistent, so training ``k``
episodes with the same seed reproduces the first ``k`` of the long run).

    python benchmarks/shielded_q_learning.py                 # 60 seeds x 300 episodes
    python benchmarks/shielded_q_learning.py --quick         # 12 seeds x 150 episodes
    python benchmarks/shielded_q_learning.py --seeds 200 --episodes 400 --json out.json
    python benchmarks/shielded_q_learning.py --start demonstrations  # rules learned as in the thesis
"""

from __future__ import annotations

import argparse
import inspect
import json
import os
import platform
import sys
import time
import warnings

import numpy as np

from symlearn.backends import Shield
from symlearn.backends.masks import env_mask
from symlearn.envs.junction_env import JunctionEnv, routes
from symlearn.envs.logic_mdp import logic_mdp
from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference
from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
from symlearn.rl.q_learning import q_learning

WINDOW = 20
DEFAULT_START = inspect.signature(LogicConstraintInference).parameters["start"].default
SETTINGS = {"learning_rate": 0.9, "discount": 0.75, "epsilon": 0.05}


def junction_mask(lm, variant: str, forbidden: np.ndarray, close: bool = True) -> np.ndarray:
    """A junction domain's mask over the observation ids of that junction's environment."""
    return env_mask(lm.mdp, forbidden, JunctionEnv(variant).state_names, unavailable=lm.unavailable, close=close)


# --- learning the constraints ------------------------------------------------------------------
def learn_constraints(variant: str, n_demos: int, iterations: int, demo_seed: int,
                      start: str = DEFAULT_START) -> dict:
    lm = logic_mdp(f"junction-{variant}")
    demos = lm.expert_demonstrations(n_demos, seed=demo_seed)
    t0 = time.perf_counter()
    lc = LogicConstraintInference(iterations=iterations, start=start).fit(demos, lm.domain)
    lc_seconds = time.perf_counter() - t0
    t0 = time.perf_counter()
    # the domain's moves that do not exist are known constraints, as for the logic learner
    ml = MLConstraintInference(reward="sparse", horizon=lc.horizon, max_iterations=iterations,
                               min_visitation=lc.min_visitation).fit(demos, lm.domain)
    ml_seconds = time.perf_counter() - t0
    truth = lm.truth_forbidden
    valid = ~lm.unavailable
    rule_pairs = lc.rule_constraints_ & valid
    closed = junction_mask(lm, variant, lc.rule_constraints_)
    n = closed.shape[0]
    missed = truth & ~rule_pairs
    inference_only = ml.constraints_ & valid
    history = [h.as_dict() for h in lc.history_]
    return {
        "lm": lm, "rules": list(lc.rules_), "start": start, "n_demos": n_demos, "iterations_run": len(lc.history_),
        "stopped_because": lc.stopped_because_, "seconds_logic": lc_seconds, "seconds_ml": ml_seconds,
        "ml_iterations_run": len(ml.history_),
        "inference_seconds": [h["inference_seconds"] for h in history],
        "induction_seconds": [h["induction_seconds"] for h in history],
        "masks": {"C-QL": junction_mask(lm, variant, ml.constraints_, close=False),
                  "LC-QL": closed,
                  "LC-QL raw": junction_mask(lm, variant, lc.rule_constraints_, close=False)},
        "recovery": {
            "truth_forbidden": int(truth.sum()),
            "rules_forbid": int(rule_pairs.sum()), "rules_false_positive": int((rule_pairs & ~truth).sum()),
            "rules_missed": int(missed.sum()),
            "rules_missed_on_road_states": [f"{lm.states[s]} / {lm.actions[a]}" for s, a in np.argwhere(missed)
                                            if lm.logic.model.road_of(lm.states[s].cell) is not None],
            "closed_rules_forbid": int(closed.sum()),
            "closed_rules_missed": int((truth[:n] & ~closed).sum()),
            "closed_false_positive": int((closed & ~truth[:n]).sum()),
            "inference_only_forbid": int(inference_only.sum()),
            "inference_only_false_positive": int((inference_only & ~truth).sum()),
            "inference_only_missed": int((truth & ~inference_only).sum()),
        },
    }


# --- training and testing one agent ------------------------------------------------------------
def make_env(variant: str, route: tuple, mask: np.ndarray | None, seed: int, max_steps: int):
    env = JunctionEnv(variant, start=route[0], goal=route[1], max_steps=max_steps)
    return env if mask is None else Shield(env, mask, seed=seed)


def greedy_drives(env, q: np.ndarray, episodes: int, seed: int) -> dict:
    """Greedy (epsilon = 0) drives with the learned Q-table, ties broken at random, the shield's
    mask respected. Per drive: ``violations`` (steps breaking a ground-truth rule), ``steps``,
    ``cost`` (minus the return) and ``success`` (goal reached), as arrays."""
    rng = np.random.default_rng(seed)
    violations, steps, costs, successes = (np.zeros(episodes) for _ in range(4))
    seeds = np.random.SeedSequence(seed).generate_state(episodes).tolist()
    for i, episode_seed in enumerate(seeds):
        state, info = env.reset(seed=int(episode_seed))
        while True:
            mask = np.asarray(info.get("action_mask", np.ones(q.shape[1])), bool)
            values = np.where(mask, q[int(state)], -np.inf)
            action = int(rng.choice(np.flatnonzero(values == values.max())))
            state, reward, terminated, truncated, info = env.step(action)
            costs[i] -= reward
            steps[i] += 1
            violations[i] += bool(info["violation"])
            if terminated or truncated:
                successes[i] = bool(terminated)
                break
    return {"violations": violations, "steps": steps, "cost": costs, "success": successes}


def greedy_rollouts(env, q: np.ndarray, episodes: int, seed: int) -> tuple[int, float, float]:
    """:func:`greedy_drives` summed up: (violations, mean cost per episode, success rate)."""
    drives = greedy_drives(env, q, episodes, seed)
    return int(drives["violations"].sum()), float(drives["cost"].sum()) / episodes, float(drives["success"].mean())


def per_agent_rates(violations: np.ndarray, steps: np.ndarray) -> dict:
    """Table 3.1 candidates from one agent's per-episode violation counts and episode lengths:
    violations per episode, the share of episodes with at least one violation (the empirical
    probability of a violation per episode) and violations per step."""
    return {"per_episode": float(violations.mean()), "episode_share": float((violations > 0).mean()),
            "per_step": float(violations.sum() / max(steps.sum(), 1))}


def moving(values: np.ndarray, statistic=np.median) -> np.ndarray:
    """The statistic over each window of ``WINDOW`` consecutive episodes (index = last episode)."""
    windows = np.lib.stride_tricks.sliding_window_view(values, WINDOW, axis=-1)
    return statistic(windows, axis=-1)


def converged_at(costs: np.ndarray) -> int:
    """Episodes until the moving median of the training cost first comes within
    ``max(10 %, 0.5)`` of its final level (median of the last 50 episodes)."""
    mm = moving(costs)
    final = float(np.median(costs[-50:]))
    inside = np.flatnonzero(mm <= final + max(0.1 * abs(final), 0.5))
    return int(inside[0]) + WINDOW if inside.size else len(costs)


def curve_converged_at(costs: np.ndarray) -> int:
    """The same on the mean cost over agents (moving mean, within 10 % of the last 50 episodes)."""
    mean = costs.mean(axis=0)
    ma = moving(mean, np.mean)
    final = float(mean[-50:].mean())
    inside = np.flatnonzero(ma <= 1.1 * final)
    return int(inside[0]) + WINDOW if inside.size else len(mean)


def run_agent(variant: str, mask: np.ndarray | None, seed: int, episodes: int, test_episodes: int, max_steps: int,
              test_at: tuple[int, ...] = ()) -> dict:
    """One agent: seed ``seed`` drives route ``seed mod routes``; its training curve, greedy test
    and the greedy tests after the first ``test_at`` episodes."""
    env_routes = routes(JunctionEnv(variant).model)
    route = env_routes[seed % len(env_routes)]
    env = make_env(variant, route, mask, seed, max_steps)
    result = q_learning(env, episodes, seed=seed, **SETTINGS)
    drives = greedy_drives(make_env(variant, route, mask, seed + 10_000, max_steps), result.q_values,
                           test_episodes, seed + 10_000)
    v, c, s = int(drives["violations"].sum()), float(drives["cost"].mean()), float(drives["success"].mean())
    early = {}
    for k in test_at:
        if k >= episodes:
            continue
        # q_learning is prefix-consistent: k episodes with this seed = the first k above.
        q_k = q_learning(make_env(variant, route, mask, seed, max_steps), k, seed=seed, **SETTINGS).q_values
        early[k] = greedy_rollouts(make_env(variant, route, mask, seed + 10_000, max_steps), q_k, test_episodes,
                                   seed + 10_000)[:2]
    return {"costs": -result.returns, "train_violations": result.violations, "test_violations": v, "test_cost": c,
            "success": s, "converged_at": converged_at(-result.returns), "early": early,
            "rates": {"training": per_agent_rates(result.violations, result.lengths),
                      "test": per_agent_rates(drives["violations"], drives["steps"])}}


def run_agents(variant: str, masks: dict, seeds: int, episodes: int, test_episodes: int, max_steps: int,
               test_at: tuple[int, ...] = ()) -> dict:
    results = {}
    for method, mask in masks.items():
        t0 = time.perf_counter()
        agents = [run_agent(variant, mask, seed, episodes, test_episodes, max_steps, test_at) for seed in range(seeds)]
        costs, train_viol = [a["costs"] for a in agents], [a["train_violations"] for a in agents]
        test_viol, test_cost = [a["test_violations"] for a in agents], [a["test_cost"] for a in agents]
        success, conv = [a["success"] for a in agents], [a["converged_at"] for a in agents]
        early = {k: ([a["early"][k][0] for a in agents], [a["early"][k][1] for a in agents])
                 for k in test_at if k < episodes}
        costs_a, train_a, test_a = np.array(costs), np.array(train_viol), np.array(test_viol)
        per_agent = train_a.sum(axis=1)
        # Table 3.1's "empirical probability of a rule violation", mean ± sd (ddof 1) over agents of
        # a per-agent rate; which rate the thesis means is read in docs/BENCHMARKS.md.
        def mean_sd(values: list[float]) -> list[float]:
            return [float(np.mean(values)), float(np.std(values, ddof=1)) if len(values) > 1 else 0.0]

        rates = {phase: {name: mean_sd([a["rates"][phase][name] for a in agents])
                         for name in ("per_episode", "episode_share", "per_step")}
                 for phase in ("training", "test")}
        # another reading: violations per episode averaged over agents, mean ± sd over the episodes
        curve = train_a.mean(axis=0)
        rates["training"]["per_episode_over_episodes"] = mean_sd(curve.tolist())
        results[method] = {
            "agents": seeds,
            "p_violation_training": float((per_agent > 0).mean()),
            "p_violation_test": float((test_a > 0).mean()),
            "violations_per_training_episode": float(train_a.mean()),
            "table_3_1": rates,
            "training_violations_total": int(per_agent.sum()),
            "test_violations_total": int(test_a.sum()),
            "episodes_to_convergence_median": float(np.median(conv)),
            "episodes_to_convergence_iqr": [float(np.percentile(conv, 25)), float(np.percentile(conv, 75))],
            "curve_converged_at": curve_converged_at(costs_a),
            "training_cost_first_50": float(costs_a[:, :50].mean()),
            "training_cost_last_50": float(costs_a[:, -50:].mean()),
            "test_cost": float(np.mean(test_cost)),
            "test_success": float(np.mean(success)),
            "total_training_cost": float(costs_a.sum(axis=1).mean()),
            "early_tests": {str(k): {"p_violation_test": float((np.array(v) > 0).mean()), "test_cost": float(np.mean(c))}
                            for k, (v, c) in early.items()},
            "mean_cost_curve": costs_a.mean(axis=0).round(3).tolist(),
            "seconds": time.perf_counter() - t0,
        }
        print(f"  {variant:9s} {method:18s} P(viol) train {results[method]['p_violation_training']:.3f} "
              f"test {results[method]['p_violation_test']:.3f}  conv {results[method]['episodes_to_convergence_median']:.0f}"
              f"  test cost {results[method]['test_cost']:.2f}  ({results[method]['seconds']:.0f} s)",
              file=sys.stderr, flush=True)
    return results


def transfer_masks(r1: list[str], r2: list[str]) -> tuple[dict, dict]:
    """The rules of ``lights`` (1) and ``priority`` (2) translated to the combined junction:
    the agents' masks and how they compare with its truth."""
    target = logic_mdp("junction-combined")
    masks: dict = {"QL": None}
    recovery = {}
    for name, rules in (("LC-QL(1)", r1), ("LC-QL(2)", r2), ("LC-QL(1+2)", r1 + r2)):
        raw = target.rule_mask(rules) if rules else np.zeros_like(target.unavailable)
        closed = junction_mask(target, "combined", raw)
        masks[name] = closed
        n = closed.shape[0]
        truth = target.truth_forbidden[:n]
        recovery[name] = {"rules": len(rules), "forbid": int(closed.sum()),
                          "false_positive": int((closed & ~truth).sum()),
                          "missed": int((truth & ~closed).sum()), "truth_forbidden": int(truth.sum())}
    return masks, recovery


_LEARNED: dict = {}


def _learned(variant: str, demos: int, iterations: int, demo_seed: int, start) -> dict:
    """:func:`learn_constraints`, once per worker process (deterministic for these arguments;
    every agent of the variant needs it)."""
    key = (variant, demos, iterations, demo_seed, start)
    if key not in _LEARNED:
        _LEARNED[key] = learn_constraints(variant, demos, iterations, demo_seed, start)
    return _LEARNED[key]


def cell(junction: str, method: str, seed: int, episodes: int = 300, test_episodes: int = 20, max_steps: int = 50,
         test_at: list[int] | None = None, demos: int = 100, iterations: int = 20, demo_seed: int = 0,
         start: str | float = DEFAULT_START) -> dict:
    """One agent of ``benchmarks/sweeps/shielded_q_learning*.toml``: what :func:`run_agents`
    computes for agent ``seed`` of ``method`` in ``junction`` (``lights``, ``priority``, or
    ``combined`` for the transfer), as per-agent metrics whose mean over seeds is the script's
    number (``violated_training`` -> P(viol.) training, ...); ``training_cost`` is the curve."""
    test_at = tuple(test_at if test_at is not None else (10, 30))
    learned = {v: _learned(v, demos, iterations, demo_seed, start) for v in
               (("lights", "priority") if junction == "combined" else (junction,))}
    if junction == "combined":
        masks = transfer_masks(learned["lights"]["rules"], learned["priority"]["rules"])[0]
    else:
        masks = {"QL": None, **learned[junction]["masks"]}
    if method not in masks:
        raise ValueError(f"no method {method!r} in the {junction} junction (one of {', '.join(masks)})")
    agent = run_agent(junction, masks[method], seed, episodes, test_episodes, max_steps, test_at)
    costs = agent["costs"]
    metrics = {"violated_training": int(agent["train_violations"].sum() > 0),
               "violated_test": int(agent["test_violations"] > 0),
               "violations_per_training_episode": float(agent["train_violations"].mean()),
               "episodes_to_convergence": agent["converged_at"],
               "training_cost_first_50": float(costs[:50].mean()), "training_cost_last_50": float(costs[-50:].mean()),
               "total_training_cost": float(costs.sum()), "test_cost": float(agent["test_cost"]),
               "test_success": float(agent["success"]), "training_cost": [float(c) for c in costs]}
    for phase in ("training", "test"):  # Table 3.1's per-agent rates (mean ± sd over seeds = the script's)
        for name, value in agent["rates"][phase].items():
            metrics[f"{phase}_violations_{name}"] = value
    for k, (violations, cost) in agent["early"].items():
        metrics[f"violated_test_after_{k}"] = int(violations > 0)
        metrics[f"test_cost_after_{k}"] = float(cost)
    return metrics


def table(results: dict, title: str) -> str:
    lines = [f"### {title}", "",
             "| method | P(viol.) training | P(viol.) test | viol. / training episode | episodes to conv. (median [IQR]) "
             "| curve conv. | total training cost | training cost / episode, first 50 / last 50 | test cost / episode "
             "| test success |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for method, r in results.items():
        lo, hi = r["episodes_to_convergence_iqr"]
        lines.append(f"| {method} | {r['p_violation_training']:.3f} | {r['p_violation_test']:.3f} "
                     f"| {r['violations_per_training_episode']:.3f} | {r['episodes_to_convergence_median']:.0f} "
                     f"[{lo:.0f}, {hi:.0f}] | {r['curve_converged_at']} | {r['total_training_cost']:.0f} "
                     f"| {r['training_cost_first_50']:.1f} / {r['training_cost_last_50']:.1f} | {r['test_cost']:.2f} "
                     f"| {r['test_success']:.2f} |")
    early = sorted({k for r in results.values() for k in r["early_tests"]}, key=int)
    if early:
        lines += ["", "Greedy test after fewer training episodes (P(viol.) test / test cost per episode):", "",
                  "| method | " + " | ".join(f"after {k}" for k in early) + " |",
                  "|---|" + "---|" * len(early)]
        for method, r in results.items():
            cells = [f"{r['early_tests'][k]['p_violation_test']:.3f} / {r['early_tests'][k]['test_cost']:.1f}"
                     for k in early]
            lines.append(f"| {method} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


TABLE_3_1_STATISTICS = {"per_episode": "violations per episode",
                        "episode_share": "share of episodes with a violation",
                        "per_step": "violations per step"}


def table_3_1(out: dict) -> str:
    """Table 3.1's shape: method x (junction, training / test), mean ± sd over agents of each
    per-agent rate, then the thesis' share-of-agents reading (``P(viol.)``) for comparison."""
    junctions = list(out["junctions"])
    methods = [m for m in ("QL", "C-QL", "LC-QL") if all(m in out["junctions"][j] for j in junctions)]
    head = "| statistic | method | " + " | ".join(f"{j} {p}" for j in junctions for p in ("train", "test")) + " |"
    lines = ["### Table 3.1: empirical probability of a rule violation (mean ± sd over agents)", "", head,
             "|---|---|" + "---|" * (2 * len(junctions))]

    def fmt(pair):
        m, sd = pair
        return f"{m:.3g} ± {sd:.2g}"

    for key, label in TABLE_3_1_STATISTICS.items():
        for method in methods:
            cells = [fmt(out["junctions"][j][method]["table_3_1"][phase][key])
                     for j in junctions for phase in ("training", "test")]
            lines.append(f"| {label} | {method} | " + " | ".join(cells) + " |")
    for method in methods:
        cells = [fmt(out["junctions"][j][method]["table_3_1"]["training"]["per_episode_over_episodes"]) if phase ==
                 "training" else "n/a" for j in junctions for phase in ("training", "test")]
        lines.append(f"| violations per episode, sd over episodes | {method} | " + " | ".join(cells) + " |")
    for method in methods:
        cells = [f"{out['junctions'][j][method][f'p_violation_{phase}']:.3f}"
                 for j in junctions for phase in ("training", "test")]
        lines.append(f"| share of agents with any violation | {method} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="12 seeds, 150 episodes")
    parser.add_argument("--seeds", type=int, default=None, help="agents per method (default 60)")
    parser.add_argument("--episodes", type=int, default=None, help="training episodes (default 300)")
    parser.add_argument("--test-episodes", type=int, default=20, help="greedy test drives per agent")
    parser.add_argument("--max-steps", type=int, default=50)
    parser.add_argument("--test-at", default="10,30", help="also test greedily after these many episodes")
    parser.add_argument("--demos", type=int, default=100)
    parser.add_argument("--iterations", type=int, default=20)
    parser.add_argument("--demo-seed", type=int, default=0)
    parser.add_argument("--start", default=DEFAULT_START,
                        type=lambda x: x if x in ("uniform", "demonstrations") else float(x),
                        help=f"where the logic learner's nominal visitation starts: uniform, demonstrations or a "
                             f"uniform share in [0, 1] (default: the learner's, {DEFAULT_START})")
    parser.add_argument("--json", default=None, help="write all results (incl. mean cost curves) here")
    args = parser.parse_args(argv)
    seeds = args.seeds or (12 if args.quick else 60)
    test_at = tuple(int(k) for k in args.test_at.split(",") if k.strip())
    episodes = args.episodes or (150 if args.quick else 300)
    warnings.filterwarnings("ignore")
    os.environ.setdefault("TQDM_DISABLE", "1")
    started = time.perf_counter()

    learned = {}
    for variant in ("lights", "priority"):
        print(f"learning constraints: {variant}", file=sys.stderr, flush=True)
        learned[variant] = learn_constraints(variant, args.demos, args.iterations, args.demo_seed, args.start)

    out: dict = {"settings": {**SETTINGS, "seeds": seeds, "episodes": episodes, "test_episodes": args.test_episodes,
                              "max_steps": args.max_steps, "demos": args.demos, "iterations": args.iterations,
                              "demo_seed": args.demo_seed, "violation_cost": 10.0, "start": args.start,
                              "default_start": DEFAULT_START, "inference_only_start": "demonstrations"},
                 "machine": {"python": platform.python_version(), "platform": platform.platform(),
                             "cpus": os.cpu_count()},
                 "learning": {}, "junctions": {}, "transfer": {}}
    for variant, info in learned.items():
        inf, ind = np.array(info["inference_seconds"]), np.array(info["induction_seconds"])
        out["learning"][variant] = {k: v for k, v in info.items() if k not in ("lm", "masks")}
        out["learning"][variant]["mean_inference_seconds_per_iteration"] = float(inf.mean()) if inf.size else 0.0
        out["learning"][variant]["mean_induction_seconds_per_iteration"] = float(ind.mean()) if ind.size else 0.0

    for variant, info in learned.items():
        masks = {"QL": None, **info["masks"]}
        if np.array_equal(masks["LC-QL"], masks["LC-QL raw"]):
            del masks["LC-QL raw"]  # the closure added nothing: same agent
        out["junctions"][variant] = run_agents(variant, masks, seeds, episodes, args.test_episodes, args.max_steps,
                                               test_at)

    print("transfer: translating the rules to the combined junction", file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    transfer, transfer_recovery = transfer_masks(learned["lights"]["rules"], learned["priority"]["rules"])
    out["transfer_translation_seconds"] = time.perf_counter() - t0
    out["transfer_recovery"] = transfer_recovery
    out["transfer"] = run_agents("combined", transfer, seeds, episodes, args.test_episodes, args.max_steps,
                                 test_at)
    out["seconds"] = time.perf_counter() - started

    for variant, info in out["learning"].items():
        print(f"\n## {variant} (start={info['start']}): {len(info['rules'])} rules, {info['iterations_run']} iterations "
              f"({info['stopped_because']}), logic {info['seconds_logic']:.1f} s, inference-only {info['seconds_ml']:.1f} s; "
              f"per iteration: inference {info['mean_inference_seconds_per_iteration']:.2f} s, "
              f"induction {info['mean_induction_seconds_per_iteration']:.2f} s")
        for rule in info["rules"]:
            print(f"    {rule}")
        print(f"  recovery: {info['recovery']}")
    for variant, results in out["junctions"].items():
        print("\n" + table(results, f"{variant} junction ({seeds} agents x {episodes} episodes)"))
    print("\n" + table_3_1(out))
    print("\n" + table(out["transfer"], f"transfer to the combined junction ({seeds} agents x {episodes} episodes)"))
    print(f"  translation: {transfer_recovery}")
    print(f"\ntotal {out['seconds']:.0f} s")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
