"""Demo pipeline: continuous constraints as a DNF formula on the thesis' toy (section 4.3).

A point agent goes from (0.1, 0.1) to (0.9, 0.9); the safe set is the L-shaped union of
[0.1, 0.7] x [0.1, 0.3] and [0.7, 0.9] x [0.1, 0.9]. Expert demonstrations follow the L; a
one-class tree fitted to their positions gives safe boxes, whose complement is the learned DNF.
The formula then is the cost of a PPO-Lagrangian agent (cost limit 0), trained beside plain PPO
in the same run, and rules the agent never ran into are pruned. The pictures show the true safe
set, the learned boxes, the demonstrations and both trained agents' routes, and the constrained
agent's training (return, cost, multiplier). ``benchmarks/toy_dnf.py`` runs the same over seeds.
"""

from __future__ import annotations

import numpy as np

from symlearn.demo.registry import DemoContext, Pipeline, Section

#: PPO settings of the toy's agents (plain and constrained alike); see ``toy_ppo_config``
TOY_PPO = {"learning_rate": 1e-3, "log_std_init": -1.0, "normalize_observations": True, "normalize_values": True}
#: PPO-Lagrangian: never enter the learned unsafe set (cost limit 0), scale-free multiplier starting at 1
TOY_LAGRANGIAN = {"cost_limit": 0.0, "update": "adam", "lr": 0.035, "adam_beta2": 0.999, "advantage_scale": "returns",
                  "init": 1.0, "cost_estimate": "episodes"}


def toy_ppo_config(seed: int, **overrides):
    """The PPO settings for the toy (``docs/BENCHMARKS.md``, "The thesis' toy end to end"): CleanRL's defaults
    except observation and value normalisation (off by default in
    :class:`~symlearn.rl.ppo.PPOConfig`), a starting action noise of ``exp(-1)`` = 0.37 instead of
    1 (a step of full noise is a third of the safe corridor's width) and a learning rate of
    ``1e-3`` (at ``2.5e-4`` the noise shrinks too slowly for 100k steps)."""
    from symlearn.rl.ppo import PPOConfig

    return PPOConfig(seed=seed, **{**TOY_PPO, **overrides})


def toy_lagrangian(**overrides):
    """PPO-Lagrangian for the toy: cost limit 0, Adam multiplier, ``advantage_scale="returns"`` and
    ``init=1`` (in those units: cost-to-go weighs as much as reward-to-go from the start, before
    the agent settles on the diagonal)."""
    from symlearn.rl.ppo import LagrangianConfig

    return LagrangianConfig(**{**TOY_LAGRANGIAN, **overrides})


_FEATURES = ["x", "y"]


def _plot_safe_set(path, boxes, demos, paths: dict) -> None:
    from matplotlib.patches import Circle, Rectangle

    from symlearn.demo.continuous_common import pyplot, save_png
    from symlearn.envs.toy_navigation import GOAL, SAFE_RECTANGLES

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(4.6, 4.6), dpi=110)
    ax.add_patch(Rectangle((0, 0), 1, 1, color="#f2c4c4", zorder=0))
    for x0, x1, y0, y1 in SAFE_RECTANGLES:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="white", zorder=1))
    for k, box in enumerate(boxes):
        (x0, y0), (x1, y1) = box.lower, box.upper
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=2, ec="#2a7f3f", zorder=3,
                               label="learned safe boxes" if k == 0 else None))
    for k, t in enumerate(demos):
        xy = np.asarray(t.states)
        ax.plot(xy[:, 0], xy[:, 1], color="#3060a0", lw=0.5, alpha=0.4, zorder=2,
                label="demonstrations" if k == 0 else None)
    for (name, colour), path_xy in paths.items():
        xy = np.asarray(path_xy)
        ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=2.2, zorder=5, label=name)
    ax.add_patch(Circle(GOAL, 0.05, fill=False, ec="#d08a00", lw=1.2, zorder=4))
    ax.set(xlim=(0, 1), ylim=(0, 1), xlabel="x (feature 0)", ylabel="y (feature 1)", aspect="equal")
    ax.set_title("true unsafe set (red), learned boxes, greedy routes", fontsize=9)
    ax.legend(loc="upper left", fontsize=7, framealpha=0.9)
    fig.tight_layout()
    save_png(fig, path)


def _plot_training(path, curve, history) -> None:
    from symlearn.demo.continuous_common import plot_curves, pyplot, save_png

    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(10.5, 3.0), dpi=110)
    plot_curves(axes[0], curve, "return", color="#106030")
    axes[0].set_title("episode return", fontsize=9)
    plot_curves(axes[1], curve, "learned_cost", color="#106030", label="learned DNF cost")
    plot_curves(axes[1], curve, "true_cost", color="#c05000", ls="--", label="true cost")
    axes[1].set_yscale("symlog", linthresh=1.0)
    axes[1].set_title("cost per episode", fontsize=9)
    axes[1].legend(fontsize=7)
    axes[2].plot([h.steps for h in history], [h.multipliers[0] for h in history], color="#7030a0")
    axes[2].set_title("multiplier lambda", fontsize=9)
    for ax in axes:
        ax.set_xlabel("environment steps")
    fig.tight_layout()
    save_png(fig, path)


def run(context: DemoContext) -> Section:
    from symlearn.backends.dnf_cost import DnfCostWrapper, RuleStats
    from symlearn.demo.continuous_common import EpisodeLog, binned, episodes
    from symlearn.envs.toy_navigation import ToyNavigationEnv, expert_demonstrations, is_safe
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint
    from symlearn.rl.ppo import train_ppo

    n_demos = 10 if context.quick else 30
    lag_steps = 4096 if context.quick else 100_000
    ppo_steps = 4096 if context.quick else 40_000
    demos = expert_demonstrations(n_demos, seed=context.seed)
    learner = OneClassTreeConstraint(max_depth=3).fit(demos, _FEATURES)
    dnf = learner.dnf_
    dnf.save(context.path("dnf", "toy.dnf"), header=f"unsafe set learned from {n_demos} toy demonstrations")

    # agreement with the true unsafe set on a dense grid
    grid = (np.stack(np.meshgrid(np.linspace(0, 1, 101), np.linspace(0, 1, 101)), axis=-1)).reshape(-1, 2)
    truth = np.array([not is_safe(x, y) for x, y in grid])
    agreement = float(np.mean(dnf.evaluate(grid, _FEATURES) == truth))

    # PPO-Lagrangian on the learned formula (rule counts for pruning), plain PPO beside it
    stats = RuleStats(dnf, _FEATURES)
    log: list = []
    clock = [0]

    def constrained_env():
        return EpisodeLog(DnfCostWrapper(ToyNavigationEnv(), dnf, _FEATURES, stats=stats), log, clock)

    constrained = train_ppo(constrained_env, lag_steps, toy_ppo_config(context.seed), lagrangian=toy_lagrangian())
    plain = train_ppo(lambda: DnfCostWrapper(ToyNavigationEnv(), dnf, _FEATURES, track=False), ppo_steps,
                      toy_ppo_config(context.seed))

    def position(env, info):
        return info["features"]

    rows, routes = [], {}
    agent_stats = RuleStats(dnf, _FEATURES)  # what the trained constrained agent runs into
    for name, colour, result in (("PPO (no cost)", "#c05000", plain),
                                 ("PPO-Lagrangian, learned DNF", "#106030", constrained)):
        env = DnfCostWrapper(ToyNavigationEnv(), dnf, _FEATURES, track=False)
        greedy, paths = episodes(result.policy, env, 1, deterministic=True, seed=context.seed + 1,
                                 position=position, keep=1)
        env = DnfCostWrapper(ToyNavigationEnv(), dnf, _FEATURES,
                             stats=agent_stats if result is constrained else None, track=result is constrained)
        sampled, _ = episodes(result.policy, env, 20, deterministic=False, seed=context.seed + 100,
                              position=position)
        rows.append((name, greedy, sampled))
        routes[(name + " (greedy)", colour)] = paths[0]
    _plot_safe_set(context.path("dnf", "toy_safe_set.png"), learner.safe_boxes_, demos, routes)
    _plot_training(context.path("dnf", "toy_training.png"), binned(log, constrained.steps, 20),
                   constrained.history)

    pruned, verdicts = stats.prune(1e-3)
    pruned.save(context.path("dnf", "toy.pruned.dnf"), header="rules the agent ran into while training")
    agent_pruned, agent_verdicts = agent_stats.prune(1e-3)
    table = "\n".join(
        f"| {n} | {g['return']:.2f} | {'yes' if g['terminal_rate'] == 1 else 'no'} | {g['true_cost']:.0f} | "
        f"{g['length']:.0f} | {s['return']:.2f} | {s['terminal_rate']:.0%} | {s['true_cost']:.1f} | "
        f"{s['learned_cost']:.1f} |" for n, g, s in rows)
    verdict_rows = "\n".join(
        f"| `{v.rule}` | {v.evaluated} | {v.fired} | {v.ratio:.4f} | {'kept' if v.kept else 'pruned'} | "
        f"{a.fired} / {a.evaluated} | {'kept' if a.kept else 'pruned'} |" for v, a in zip(verdicts, agent_verdicts))
    (_, greedy_lag, sampled_lag), (_, greedy_ppo, _) = rows[1], rows[0]
    solved = greedy_lag["terminal_rate"] == 1 and greedy_lag["true_cost"] == 0
    figures = {"demonstrations": n_demos, "rules": len(dnf), "safe_boxes": len(learner.safe_boxes_),
               "grid_agreement": round(agreement, 4), "training_steps": lag_steps, "ppo_training_steps": ppo_steps,
               "ppo_lag_return": round(greedy_lag["return"], 3), "ppo_lag_true_cost": greedy_lag["true_cost"],
               "ppo_lag_reaches_goal": bool(greedy_lag["terminal_rate"] == 1),
               "ppo_lag_sampled_true_cost": round(sampled_lag["true_cost"], 2),
               "ppo_lag_sampled_goal_rate": sampled_lag["terminal_rate"],
               "ppo_return": round(greedy_ppo["return"], 3), "ppo_true_cost": greedy_ppo["true_cost"],
               "ppo_reaches_goal": bool(greedy_ppo["terminal_rate"] == 1),
               "multiplier": round(float(constrained.multipliers[0]), 3), "solved": bool(solved),
               "rules_after_pruning": len(pruned), "rules_after_pruning_trained_agent": len(agent_pruned)}
    outcome = ("goes along the L to the goal without leaving the true safe set" if solved else
               "does not yet go to the goal along the L without leaving the true safe set at this budget"
               + (" (quick settings: far too few steps)" if context.quick else ""))
    plain_outcome = (f"plain PPO cuts the corner ({greedy_ppo['true_cost']:.0f} truly unsafe steps)"
                     if greedy_ppo["true_cost"] > 0 else "plain PPO happens to stay in the true safe set")
    markdown = f"""
The thesis' toy (section 4.3): {n_demos} expert runs along the L-shaped safe set. A one-class
tree (max depth 3) finds {len(learner.safe_boxes_)} safe boxes; the learned unsafe set, one rule
per line in `dnf/toy.dnf`, agrees with the true one on {agreement:.1%} of a 101 x 101 grid
(the boxes follow the data, so they stop where the demonstrations stop).

```
{dnf}
```

![toy safe set and routes](dnf/toy_safe_set.png)

PPO-Lagrangian on the learned formula (cost 1 per step in the learned unsafe set, cost limit 0,
{lag_steps} steps) beside plain PPO ({ppo_steps} steps), both with the toy's PPO settings
(observation and value normalisation, scale-free multiplier; `docs/BENCHMARKS.md`, "The thesis'
toy end to end", has the same over 15 seeds and why). Greedy: one episode of the mean action;
sampled: 20 episodes of the stochastic policy; true cost = steps outside the true safe set. The constrained agent {outcome}; {plain_outcome}.

| agent | greedy return | reaches goal | true cost | length | sampled return | goal rate | true cost | learned cost |
|---|---|---|---|---|---|---|---|---|
{table}

![PPO-Lagrangian training](dnf/toy_training.png)

Rule statistics (rules evaluated in ascending number of atoms; a rule whose fired/evaluated ratio
is below 0.001 is pruned): during the whole PPO-Lagrangian training (the thesis' procedure,
`dnf/toy.pruned.dnf`), and over the 20 sampled episodes of the trained agent. The start
(0.1, 0.1) lies on the data's lower bounds and the goal circle crosses the upper ones, so an agent
that wobbles at the start or overshoots at the goal keeps the bound rules alive; the thesis'
example, which keeps only the rule of the forbidden block, assumes an agent that never goes
near them.

| rule | evaluated | fired | ratio | verdict (training) | trained agent: fired / evaluated | verdict |
|---|---|---|---|---|---|---|
{verdict_rows}
"""
    files = ["dnf/toy.dnf", "dnf/toy.pruned.dnf", "dnf/toy_safe_set.png", "dnf/toy_training.png"]
    return Section("Continuous constraints as DNF (the thesis' toy)", markdown, figures, files)


PIPELINE = Pipeline("dnf", "Learn the toy's unsafe set as a DNF formula, train PPO-Lagrangian on it, prune", run)
