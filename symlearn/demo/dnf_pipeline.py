"""Demo pipeline: continuous constraints as a DNF formula on the thesis' toy (section 4.3).

A point agent goes from (0.1, 0.1) to (0.9, 0.9); the safe set is the L-shaped union of
[0.1, 0.7] x [0.1, 0.3] and [0.7, 0.9] x [0.1, 0.9]. Expert demonstrations follow the L; a
one-class tree fitted to their positions gives safe boxes, whose complement is the learned DNF.
The formula then is the cost of a PPO-Lagrangian agent, and rules the agent never ran into are
pruned. The picture shows the true safe set, the learned boxes and the demonstrations.
"""

from __future__ import annotations

import numpy as np

from symlearn.demo.registry import DemoContext, Pipeline, Section


def _plot(path, boxes, demos, safe_rectangles, goal) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    from symlearn.atomic import write_bytes

    fig, ax = plt.subplots(figsize=(4.2, 4.2), dpi=110)
    ax.add_patch(Rectangle((0, 0), 1, 1, color="#f2c4c4", zorder=0))
    for x0, x1, y0, y1 in safe_rectangles:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="white", zorder=1))
    for k, box in enumerate(boxes):
        (x0, y0), (x1, y1) = box.lower, box.upper
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=2, ec="#2a7f3f", zorder=3,
                               label="learned safe boxes" if k == 0 else None))
    for k, t in enumerate(demos):
        xy = np.asarray(t.states)
        ax.plot(xy[:, 0], xy[:, 1], color="#3060a0", lw=0.7, alpha=0.6, zorder=2,
                label="demonstrations" if k == 0 else None)
    ax.plot(*goal, marker="*", ms=12, color="#d08a00", zorder=4, label="goal")
    ax.set(xlim=(0, 1), ylim=(0, 1), xlabel="x (feature 0)", ylabel="y (feature 1)", aspect="equal",
           title="true unsafe set (red), learned safe boxes")
    ax.legend(loc="upper left", fontsize=7, framealpha=0.9)
    fig.tight_layout()
    import io

    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    write_bytes(path, buffer.getvalue())


def run(context: DemoContext) -> Section:
    from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
    from symlearn.envs.toy_navigation import GOAL, SAFE_RECTANGLES, ToyNavigationEnv, expert_demonstrations
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, evaluate, train_ppo

    n_demos = 10 if context.quick else 30
    steps = 4096 if context.quick else 40_000
    demos = expert_demonstrations(n_demos, seed=context.seed)
    learner = OneClassTreeConstraint(max_depth=3).fit(demos, ["x", "y"])
    dnf = learner.dnf_
    dnf.save(context.path("dnf", "toy.dnf"), header=f"unsafe set learned from {n_demos} toy demonstrations")
    _plot(context.path("dnf", "toy_safe_set.png"), learner.safe_boxes_, demos, SAFE_RECTANGLES, GOAL)

    # agreement with the true unsafe set on a dense grid
    grid = (np.stack(np.meshgrid(np.linspace(0, 1, 101), np.linspace(0, 1, 101)), axis=-1)).reshape(-1, 2)
    from symlearn.envs.toy_navigation import is_safe

    truth = np.array([not is_safe(x, y) for x, y in grid])
    agreement = float(np.mean(dnf.evaluate(grid, ["x", "y"]) == truth))

    stats = RuleStats(dnf, ["x", "y"])
    env_fn = lambda: DnfCostWrapper(ToyNavigationEnv(), dnf, ["x", "y"], stats=stats)  # noqa: E731
    lagrangian = LagrangianConfig(cost_limit=0.0, update="adam", lr=0.035)
    constrained = train_ppo(env_fn, steps, PPOConfig(seed=context.seed), lagrangian=lagrangian)
    plain = train_ppo(ToyNavigationEnv, steps, PPOConfig(seed=context.seed))
    rows = []
    for name, result in (("PPO (no cost)", plain), ("PPO-Lagrangian, learned DNF", constrained)):
        ep = evaluate(result.policy, ToyNavigationEnv(), 10, seed=context.seed + 1)
        rows.append((name, float(ep.returns.mean()), float(ep.costs.sum(axis=1).mean()), float(ep.lengths.mean())))
    pruned, verdicts = stats.prune(1e-3)
    pruned.save(context.path("dnf", "toy.pruned.dnf"), header="rules the agent ran into while training")
    table = "\n".join(f"| {n} | {r:.2f} | {c:.1f} | {length:.0f} |" for n, r, c, length in rows)
    verdict_rows = "\n".join(f"| `{v.rule}` | {v.evaluated} | {v.fired} | {v.ratio:.4f} | "
                             f"{'kept' if v.kept else 'pruned'} |" for v in verdicts)
    figures = {"demonstrations": n_demos, "rules": len(dnf), "safe_boxes": len(learner.safe_boxes_),
               "grid_agreement": round(agreement, 4), "training_steps": steps,
               "ppo_lag_return": round(rows[1][1], 3), "ppo_lag_true_cost": rows[1][2],
               "ppo_return": round(rows[0][1], 3), "ppo_true_cost": rows[0][2],
               "rules_after_pruning": len(pruned)}
    markdown = f"""
The thesis' toy (section 4.3): {n_demos} expert runs along the L-shaped safe set. A one-class
tree (max depth 3) finds {len(learner.safe_boxes_)} safe boxes; the learned unsafe set, one rule
per line in `dnf/toy.dnf`, agrees with the true one on {agreement:.1%} of a 101 x 101 grid
(the boxes follow the data, so they stop where the demonstrations stop).

![toy safe set](dnf/toy_safe_set.png)

```
{dnf}
```

{steps} training steps each, greedy evaluation over 10 episodes, cost = the true cost (steps
outside the safe set). At this budget the PPO-Lagrangian agent (cost limit 0, Adam multiplier
updates) does not yet find the safe route to the goal; the thesis' constrained experiments are
open work (`docs/BENCHMARKS.md`).

| agent | return | true cost / episode | episode length |
|---|---|---|---|
{table}

Rule statistics during PPO-Lagrangian training (rules evaluated in ascending number of atoms; a
rule whose fired/evaluated ratio stays below 0.001 is pruned, `dnf/toy.pruned.dnf`):

| rule | evaluated | fired | ratio | verdict |
|---|---|---|---|---|
{verdict_rows}
"""
    files = ["dnf/toy.dnf", "dnf/toy.pruned.dnf", "dnf/toy_safe_set.png"]
    return Section("Continuous constraints as DNF (the thesis' toy)", markdown, figures, files)


PIPELINE = Pipeline("dnf", "Learn the toy's unsafe set as a DNF formula, train PPO-Lagrangian on it, prune", run)
