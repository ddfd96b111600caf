"""Demo pipeline: a DNF constraint learned from SafeNav expert demonstrations shapes a PPO agent.

SafeNav PointGoal (``symlearn.envs.safenav``, Safety-Gym's PointGoal1 re-created in numpy): a
scripted expert that knows the hazards drives to goals without entering one. A one-class tree
fitted to the thesis' 20 features of its states (acceleration, velocity, 16 hazard lidar bins)
gives the unsafe set as a DNF formula; PPO-Lagrangian is trained briefly with the formula as its
cost (1 per step in the learned unsafe set, cost limit 25 per 1,000-step episode, Safety-Gym's
usual budget), and plain PPO beside it in the same run. Reported: return and the *true* cost
(steps inside a hazard) during training and on unseen layouts, and the learned cost. A brief run:
the thesis trains for millions of steps (``benchmarks/safenav_transfer.py`` runs 250k).
"""

from __future__ import annotations

import numpy as np

from symlearn.demo.registry import DemoContext, Pipeline, Section

_COST_LIMIT = 25.0


def _plot(path, curves: dict, multipliers: list) -> None:
    from symlearn.demo.continuous_common import plot_curves, pyplot, save_png

    plt = pyplot()
    fig, axes = plt.subplots(1, 4, figsize=(13, 3.0), dpi=110)
    colours = {"PPO": "#c05000", "PPO-Lagrangian, learned DNF": "#106030"}
    for name, curve in curves.items():
        for ax, key in zip(axes[:3], ("return", "true_cost", "learned_cost")):
            plot_curves(ax, curve, key, color=colours[name], label=name, marker=".", ms=3)
    for ax, title in zip(axes[:3], ("episode return", "true cost / episode (steps in a hazard)",
                                    "learned DNF cost / episode")):
        ax.set_title(title, fontsize=9)
    axes[2].axhline(_COST_LIMIT, color="#888888", lw=0.8, ls=":", label="cost limit")
    axes[3].plot([s for s, _ in multipliers], [m for _, m in multipliers], color=colours["PPO-Lagrangian, learned DNF"])
    axes[3].set_title("multiplier lambda", fontsize=9)
    for ax in axes:
        ax.set_xlabel("environment steps")
    axes[0].legend(fontsize=7)
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    save_png(fig, path)


def run(context: DemoContext) -> Section:
    from symlearn.backends.dnf_cost import DnfCostWrapper
    from symlearn.demo.continuous_common import EpisodeLog, binned, episodes
    from symlearn.envs.safenav.env import SafeNavEnv
    from symlearn.envs.safenav.observation import FEATURE_NAMES
    from symlearn.envs.safenav_expert import expert_demonstrations
    from symlearn.learners.trees.one_class_tree import OneClassTreeConstraint
    from symlearn.rl.ppo import LagrangianConfig, PPOConfig, train_ppo

    quick = context.quick
    max_steps = 250 if quick else 1000
    n_demos = 2 if quick else 10
    steps = 4096 if quick else 50_000
    n_eval = 1 if quick else 3
    names = list(FEATURE_NAMES)

    demos = expert_demonstrations("point", "goal", n=n_demos, seed=context.seed, max_steps=max_steps)
    learner = OneClassTreeConstraint(max_depth=3).fit(demos, names)
    dnf = learner.dnf_
    dnf.save(context.path("safenav", "point_goal.dnf"),
             header=f"unsafe set learned from {n_demos} SafeNav point-goal expert episodes")
    expert_return = float(np.mean([np.sum(t.rewards) for t in demos]))
    expert_cost = float(np.mean([t.info["cost"] for t in demos]))

    # the same PPO for both; the learned formula is the cost of the constrained one
    config = PPOConfig(n_envs=4, n_steps=256, batch_size=256, n_epochs=5, learning_rate=3e-4,
                       normalize_values=True, normalize_observations=False, log_std_init=0.0, seed=context.seed)
    lagrangian = LagrangianConfig(cost_limit=_COST_LIMIT, update="adam", lr=0.035, adam_beta2=0.999,
                                  advantage_scale="returns", init=0.0,
                                  cost_estimate="episodes")
    curves, results, multipliers = {}, {}, []
    for name, constrained in (("PPO", False), ("PPO-Lagrangian, learned DNF", True)):
        log: list = []
        clock = [0]

        def env_fn(log=log, clock=clock):
            return EpisodeLog(DnfCostWrapper(SafeNavEnv("point", "goal", max_steps=max_steps), dnf, names,
                                             track=False), log, clock)

        def record(iteration, _policy, constrained=constrained):
            if constrained:
                multipliers.append((iteration.steps, iteration.multipliers[0]))

        result = train_ppo(env_fn, steps, config, lagrangian=lagrangian if constrained else None, callback=record)
        curves[name] = binned(log, result.steps, 10)
        env = DnfCostWrapper(SafeNavEnv("point", "goal", max_steps=max_steps), dnf, names, track=False)
        evaluation, _ = episodes(result.policy, env, n_eval, deterministic=False, seed=100_000 + context.seed,
                                 position=lambda env, info: ())
        results[name] = (result, evaluation)
    _plot(context.path("safenav", "training.png"), curves, multipliers)

    def last(curve, key):
        values = [v for v in curve[key] if v is not None]
        return values[-1] if values else float("nan")

    rows = "\n".join(
        f"| {name} | {last(curves[name], 'return'):.2f} | {last(curves[name], 'true_cost'):.1f} | "
        f"{last(curves[name], 'learned_cost'):.0f} | {ev['return']:.2f} | {ev['true_cost']:.1f} | "
        f"{ev['learned_cost']:.0f} |" for name, (_, ev) in results.items())
    (_, ppo_eval), (lag_result, lag_eval) = results["PPO"], results["PPO-Lagrangian, learned DNF"]
    shown = "\n".join(str(c) for c in dnf.conjunctions[:8])
    share = ppo_eval["learned_cost"] / max(ppo_eval["length"], 1)
    lower = [what for what, key in (("learned cost", "learned_cost"), ("true cost", "true_cost"))
             if lag_eval[key] < ppo_eval[key]]
    verdict = (f"PPO-Lagrangian ends with a lower {' and a lower '.join(lower)} than plain PPO "
               f"(return {lag_eval['return']:.1f} vs {ppo_eval['return']:.1f})." if lower else
               f"PPO-Lagrangian is not safer than plain PPO at this budget (return {lag_eval['return']:.1f} vs "
               f"{ppo_eval['return']:.1f}).")
    figures = {"demonstrations": n_demos, "episode_steps": max_steps, "rules": len(dnf),
               "safe_boxes": len(learner.safe_boxes_), "training_steps": steps, "eval_episodes": n_eval,
               "expert_return": round(expert_return, 3), "expert_true_cost": expert_cost,
               "ppo_return": round(ppo_eval["return"], 3), "ppo_true_cost": ppo_eval["true_cost"],
               "ppo_learned_cost": ppo_eval["learned_cost"],
               "ppo_lag_return": round(lag_eval["return"], 3), "ppo_lag_true_cost": lag_eval["true_cost"],
               "ppo_lag_learned_cost": lag_eval["learned_cost"],
               "multiplier": round(float(lag_result.multipliers[0]), 4)}
    markdown = f"""
SafeNav PointGoal (Safety-Gym's PointGoal1 in numpy, {max_steps}-step episodes): {n_demos} episodes
of the scripted expert (return {expert_return:.1f}, {expert_cost:.0f} steps in a hazard per episode)
give {sum(len(t.states) for t in demos)} states of the thesis' 20 features; a one-class tree (max
depth 3) covers them with {len(learner.safe_boxes_)} boxes, and the unsafe set is a DNF formula of
{len(dnf)} rules (`safenav/point_goal.dnf`; the first ones below: bounds on acceleration and
velocity, then lidar readings the expert never had).

```
{shown}
...
```

{steps} steps each, the same PPO (value normalisation; `advantage_scale="returns"` for the
multiplier), cost limit {_COST_LIMIT:g} learned-cost steps per episode. True cost = steps inside a
hazard; evaluation on {n_eval} unseen layouts with the stochastic policy. {verdict} A brief run:
the formula learned from {n_demos} episodes calls {share:.0%} of plain PPO's evaluation steps unsafe
(mostly by its bounds on acceleration and velocity), and {steps} steps are far from the millions the
thesis trains for (`benchmarks/safenav_transfer.py` for the full experiment).

| agent | return (last training episodes) | true cost | learned cost | return (evaluation) | true cost | learned cost |
|---|---|---|---|---|---|---|
{rows}

![training curves](safenav/training.png)
"""
    files = ["safenav/point_goal.dnf", "safenav/training.png"]
    return Section("A learned DNF constraint on SafeNav PointGoal (brief PPO-Lagrangian run)", markdown, figures,
                   files)


PIPELINE = Pipeline("safenav", "Learn a DNF from SafeNav expert demonstrations, train PPO-Lagrangian on it briefly",
                    run)
