"""Demo pipeline: neural MCE-ICRL on BlockedPoint (thesis chapter 2, Algorithm 2.1, CI-sized).

A point mass is paid for distance along x, faster toward a wall at ``x = -3`` beyond which it
must not go. From the scripted expert's demonstrations (full speed away from the wall) MCE-ICRL
learns a cost ``lambda . phi`` over the entries of ``(x, y)`` its input selection keeps
(:mod:`symlearn.learners.neural.input_selection`) and a policy by PPO on ``r - C``; the section reports the
policy's reward and violation rate against the unconstrained (nominal) policy of the same run,
the cost's recovery of the true unsafe set (ROC AUC), the cost map over ``(x, y)`` and the
per-iteration reward, violation rate and multipliers. ``benchmarks/icrl_blocked_point.py`` runs
the same at full budget over seeds, with the baselines; it draws its figures with
:func:`plot_cost_maps` and :func:`plot_iterations` from here.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from symlearn.demo.registry import DemoContext, Pipeline, Section

#: PPO steps in all (1/8 nominal, the rest over the iterations), iterations, demonstrations
FULL = {"steps": 120_000, "iterations": 5, "demos": 20}
QUICK = {"steps": 4_096, "iterations": 2, "demos": 3}
EVAL_EPISODES = 20


def cost_map(cost: Any, x_range: tuple[float, float], y_range: tuple[float, float], n: int = 81,
             width: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The learned cost on an ``n x n`` grid of positions (other observation entries 0: a point at
    rest). Returns the x and y axes and the costs ``[len(y), len(x)]``."""
    xs, ys = np.linspace(*x_range, n), np.linspace(*y_range, n)
    grid = np.zeros((n * n, width), dtype=np.float32)
    gx, gy = np.meshgrid(xs, ys)
    grid[:, 0], grid[:, 1] = gx.ravel(), gy.ravel()
    return xs, ys, np.asarray(cost(grid), dtype=np.float64).reshape(n, n)


def plot_cost_maps(path: Any, costs: Mapping[str, Any], wall: float, expert_states: np.ndarray, *,
                   x_range: tuple[float, float] | None = None, y_range: tuple[float, float] = (-2.0, 2.0)) -> None:
    """One panel per learned cost: the cost over ``(x, y)`` (each normalised by its own maximum,
    so the panels compare shapes, not scales), the wall (the true boundary) and the expert's
    positions. ``x_range`` defaults to 3 beyond the wall to 0.5 beyond the expert's farthest x."""
    if x_range is None:
        x = expert_states[:, 0]
        x_range = (min(wall, float(x.min())) - 3.0, max(wall, float(x.max())) + 0.5)
    from symlearn.demo.continuous_common import pyplot, save_png

    plt = pyplot()
    fig, axes = plt.subplots(len(costs), 1, figsize=(7.0, 1.9 * len(costs) + 0.4), dpi=110, squeeze=False,
                             layout="constrained")  # room for the titles and the shared colour bar
    image = None
    for ax, (name, cost) in zip(axes[:, 0], costs.items()):
        xs, ys, values = cost_map(cost, x_range, y_range, width=int(np.prod(cost.observation_spec["shape"])))
        top = float(values.max())
        image = ax.imshow(values / top if top > 0 else values, origin="lower", aspect="auto", cmap="magma",
                          extent=(xs[0], xs[-1], ys[0], ys[-1]), vmin=0.0, vmax=1.0)
        ax.axvline(wall, color="#40c0ff", lw=1.5, ls="--", label=f"wall x = {wall:g}")
        ax.scatter(expert_states[:, 0], expert_states[:, 1], s=1, color="white", alpha=0.3, label="expert positions")
        ax.set(xlim=x_range, ylim=y_range)
        ax.set_title(f"{name}: learned cost (max {top:.3g})", fontsize=9)
        ax.set_ylabel("y")
    axes[-1, 0].set_xlabel("x")
    axes[0, 0].legend(loc="upper right", fontsize=7, framealpha=0.8)
    if image is not None:
        fig.colorbar(image, ax=axes[:, 0].tolist(), fraction=0.03, label="cost / max")
    save_png(fig, path)


def multiplier_of(record: Mapping[str, Any]) -> float | None:
    """The multiplier of an iteration record: MCE-ICRL's sum of ``lambda`` (the cost's scale),
    ME/VME-ICRL's PPO-Lagrangian multiplier; GACL has none."""
    if "lambdas" in record:
        return float(np.sum(record["lambdas"]))
    return None if record.get("multiplier") is None else float(record["multiplier"])


def plot_iterations(path: Any, histories: Mapping[str, Sequence[Sequence[Mapping[str, Any]]]]) -> None:
    """Reward, violation rate and multiplier over the iterations, one line per method (the mean
    over its runs, the range shaded). ``histories``: method -> runs -> iteration records (dicts)."""
    from symlearn.demo.continuous_common import pyplot, save_png

    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(11.0, 3.1), dpi=110)
    for name, runs in histories.items():
        if not runs:
            continue
        iterations = np.arange(1, min(len(r) for r in runs) + 1)
        for ax, key in zip(axes, ("reward", "violation_rate", "multiplier")):
            rows = [[multiplier_of(h) if key == "multiplier" else h[key] for h in r[:len(iterations)]] for r in runs]
            if any(v is None for row in rows for v in row):
                continue
            values = np.array(rows, dtype=np.float64)
            line, = ax.plot(iterations, values.mean(0), marker="o", ms=3, label=name)
            if len(runs) > 1:
                ax.fill_between(iterations, values.min(0), values.max(0), alpha=0.15, color=line.get_color())
    for ax, title in zip(axes, ("reward (sampled episodes)", "violation rate per step",
                                "lambda (MCE: sum) / Lagrange multiplier")):
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("iteration")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    save_png(fig, path)


def run(context: DemoContext) -> Section:
    from symlearn.envs.blocked_point import BlockedPoint, expert_demonstrations
    from symlearn.learners.neural import NeuralMCEICRL
    from symlearn.learners.neural.icrl_metrics import recovery
    from symlearn.rl.episode_metrics import episode_metrics
    from symlearn.rl.episodes import demonstration_batch, sample_episodes

    budget = QUICK if context.quick else FULL
    demos = expert_demonstrations(budget["demos"], seed=context.seed)
    nominal = budget["steps"] // 8
    learner = NeuralMCEICRL(n_iterations=budget["iterations"], nominal_steps=nominal,
                            policy_steps=(budget["steps"] - nominal) // budget["iterations"],
                            random_state=context.seed).fit(demos, BlockedPoint)  # the default inputs
    cost_path = learner.save(context.path("blockedpoint", "cost.safetensors"))

    def evaluate(policy: Any) -> Any:
        return episode_metrics(sample_episodes(policy, BlockedPoint, EVAL_EPISODES, seed=50_000 + context.seed,
                                               deterministic=True))

    learned, nominal_eval = evaluate(learner.policy_), evaluate(learner.nominal_policy_)
    expert = episode_metrics(demonstration_batch(demos))
    states = np.concatenate([np.asarray(t.states) for t in demos])
    env = BlockedPoint()
    rec = recovery(learner.cost_, env.is_unsafe, states, seed=context.seed)
    plot_cost_maps(context.path("blockedpoint", "cost_map.png"), {"MCE-ICRL": learner.cost_}, env.wall, states)
    plot_iterations(context.path("blockedpoint", "iterations.png"),
                    {"MCE-ICRL": [[h.as_dict() for h in learner.history_]]})
    timings = learner.result_.timings
    figures = {"demonstrations": budget["demos"], "steps": budget["steps"], "iterations": len(learner.history_),
               "expert_reward": round(expert.reward, 3), "reward": round(learned.reward, 3),
               "violation_rate": round(learned.violation_rate, 4),
               "feasible_reward": round(learned.feasible_reward, 3),
               "unconstrained_reward": round(nominal_eval.reward, 3),
               "unconstrained_violation_rate": round(nominal_eval.violation_rate, 4),
               "recovery_auc": _rounded(rec.as_dict()["auc"]), "recovery_iou": _rounded(rec.as_dict()["iou"]), "lambda": [round(float(x), 4) for x in learner.lambda_],
               "seconds": round(timings["total"], 1),
               "cost_share_of_policy_time": round(timings["cost"] / timings["policy"], 4)}
    rows = "\n".join(
        f"| {name} | {m.reward:.1f} | {m.violation_rate:.3f} | {m.feasible_reward:.1f} |"
        for name, m in (("expert (demonstrations)", expert), ("unconstrained PPO (nominal policy)", nominal_eval),
                        ("MCE-ICRL policy", learned)))
    note = " (quick settings: far too few steps for the policy to turn)" if context.quick else ""
    inputs = ", ".join(learner.result_.metrics["cost_inputs"]["names"])
    markdown = f"""
BlockedPoint (`symlearn learn icrl --env blocked-point`): a point mass paid for distance along x,
faster toward the wall at x = {env.wall:g}; the true constraint forbids x < {env.wall:g}. Neural
MCE-ICRL (thesis Algorithm 2.1) learned a cost over {inputs} (selected from the position x, y) from {budget["demos"]}
scripted expert episodes with {budget["steps"]} PPO steps ({nominal} nominal, then
{len(learner.history_)} iterations), in {timings["total"]:.0f} s{note}. Evaluation: {EVAL_EPISODES}
episodes of the mean action against the ground truth.

| policy | reward | violation rate | feasible reward |
|---|---|---|---|
{rows}

Recovery of the unsafe set by the learned cost, on states around the expert's: ROC AUC
{_shown(figures["recovery_auc"])}, IoU {_shown(figures["recovery_iou"])}. Multipliers
{", ".join(f"{x:.3g}" for x in learner.lambda_)}; the cost update took
{figures["cost_share_of_policy_time"]:.1%} of the policy update's time. The cost is
`blockedpoint/cost.safetensors` (+ `.json`), loadable with `NeuralCost.load` for a new agent.

![learned cost over (x, y)](blockedpoint/cost_map.png)

![reward, violation rate and lambda per iteration](blockedpoint/iterations.png)
"""
    files = [f"blockedpoint/{cost_path.name}", "blockedpoint/cost.json", "blockedpoint/cost_map.png",
             "blockedpoint/iterations.png"]
    return Section("Neural MCE-ICRL on BlockedPoint (thesis chapter 2)", markdown, figures, files)


def _rounded(x: float | None) -> float | None:
    return None if x is None else round(float(x), 4)


def _shown(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.3f}"


PIPELINE = Pipeline("blockedpoint", "Learn BlockedPoint's wall as a neural cost by MCE-ICRL; plot the cost map", run)
