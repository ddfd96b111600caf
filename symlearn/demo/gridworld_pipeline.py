"""Demo pipeline: learning the forbidden block of a stochastic gridworld from demonstrations.

An expert that is optimal under the true constraints is recorded in the gridworld with
stochasticity 0.3. MCE-ICRL learns a cost per cell; maximum-likelihood constraint inference
learns forbidden state-action pairs. Both learned constraint maps are written as text and as a
picture (DOT, and SVG when Graphviz is installed); the learned policies are run in the true
environment next to the expert, and the ML constraint set shields a Q-learning agent.
"""

from __future__ import annotations

import html
import warnings

import numpy as np

from symlearn.atomic import write_text
from symlearn.demo.registry import DemoContext, Pipeline, Section
from symlearn.rendering import dot_available, render_dot

STOCHASTICITY = 0.3


def cost_map_text(env, cost: np.ndarray, threshold: float, headed_for: np.ndarray | None = None) -> str:
    """One line per row: the learned cost of each cell, ``*`` after cells above ``threshold``
    and ``!`` after truly forbidden cells (S start, G goal). ``headed_for``: cells the expert
    heads for (an MCE-ICRL learner's ``headed_for_``), marked ``~`` instead of ``*`` when above
    the threshold -- costly, but not forbidden."""
    height, width = env.shape
    lines = []
    for r in range(height):
        cells = []
        for c in range(width):
            s = r * width + c
            tag = "S" if s == env.start_state else "G" if s == env.goal_state else " "
            above = " " if cost[s] <= threshold else "~" if headed_for is not None and headed_for[s] else "*"
            mark = above + ("!" if env.forbidden_states[s] else " ")
            cells.append(f"{tag}{cost[s]:6.2f}{mark}")
        lines.append(" ".join(cells))
    return "\n".join(lines) + "\n"


def _wrap(title: str, width: int = 36) -> list[str]:
    """The title in lines of at most about ``width`` characters (broken at spaces)."""
    lines, line = [], ""
    for word in title.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return lines + ([line] if line else [])


def constraint_map_dot(env, cost: np.ndarray, title: str) -> str:
    """The grid as one HTML-table node: darker red = higher learned cost, thick border = truly
    forbidden cell. Whole-number values (counts) print without decimals; the title is the
    table's first row, wrapped, so it is never wider than the picture (SVG viewers cut a graph
    label that is)."""
    top = float(cost.max()) or 1.0
    counts = bool(np.all(np.asarray(cost) == np.round(cost)))
    height, width = env.shape
    rows = []
    for r in range(height):
        cells = []
        for c in range(width):
            s = r * width + c
            shade = int(255 - 200 * min(cost[s] / top, 1.0))
            colour = f"#ff{shade:02x}{shade:02x}"
            value = f"{int(round(cost[s]))}" if counts else f"{cost[s]:.1f}"
            text = "S" if s == env.start_state else "G" if s == env.goal_state else value
            border = "3" if env.forbidden_states[s] else "1"
            cells.append(f'<td width="36" height="36" fixedsize="true" bgcolor="{colour}" border="{border}">'
                         f'{text}</td>')
        rows.append("<tr>" + "".join(cells) + "</tr>")
    heading = "<br/>".join(html.escape(line) for line in _wrap(title, max(20, 4 * width + 4)))
    caption = f'<tr><td colspan="{width}" border="0" cellpadding="4"><font point-size="12">{heading}</font></td></tr>'
    table = '<table border="0" cellspacing="2">' + caption + "".join(rows) + "</table>"
    return (f"digraph constraints {{\n  fontname=\"Helvetica\";\n"
            f"  grid [shape=plaintext, fontname=\"Helvetica\", label=<{table}>];\n}}\n")


def run(context: DemoContext) -> Section:
    from symlearn.backends import Shield
    from symlearn.data import record
    from symlearn.envs.gridworld import StochasticGridworld, make_gridworld
    from symlearn.learners.constraints.mce_icrl import MCEICRL
    from symlearn.learners.constraints.ml_constraint_inference import MLConstraintInference
    from symlearn.rl.q_learning import q_learning
    from symlearn.rl.tabular import sample_rollouts

    n_demos = 20 if context.quick else 50
    iterations = 100 if context.quick else 300
    episodes = 200 if context.quick else 1000
    env = StochasticGridworld(STOCHASTICITY)
    mdp = env.to_tabular()
    expert = env.expert_policy()
    demos = record(env, lambda s: int(expert[s]), n_demos, seed=context.seed, max_steps=env.max_steps,
                   desc="gridworld expert")
    demos.save(context.path("gridworld", "expert_demos.jsonl"))

    mce = MCEICRL(n_iterations=iterations).fit(demos, mdp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ml = MLConstraintInference(horizon=50, rationality=3.0).fit(demos, mdp)

    rng = np.random.default_rng(context.seed)
    rows = {}
    for name, policy in (("expert", np.eye(4)[expert]), ("MCE-ICRL", mce.policy_), ("ML inference", ml.policy_)):
        rollouts = sample_rollouts(mdp, policy, episodes, env.max_steps, rng)
        rows[name] = (float(rollouts.returns().mean()), float(rollouts.fraction_in(env.forbidden_states).mean()))

    ml_cells = np.array([ml.constraints_[s].sum() for s in range(env.n_states)], dtype=float)
    files = ["gridworld/expert_demos.jsonl"]
    text = (f"# MCE-ICRL learned cost per cell (lambda), p = {STOCHASTICITY}; * = above threshold "
            f"{mce.threshold}, ! = truly forbidden\n" + cost_map_text(env, mce.lambda_, mce.threshold)
            + "\n# ML constraint inference: forbidden actions per cell (of 4)\n"
            + cost_map_text(env, ml_cells, 3.5)
            + "\n# ground truth\n" + env.render_text() + "\n")
    write_text(context.path("gridworld", "constraint_map.txt"), text)
    files.append("gridworld/constraint_map.txt")
    for stem, values, title in (("mce_cost", mce.lambda_, "MCE-ICRL cost per cell"),
                                ("ml_constraints", ml_cells, "ML inference: forbidden actions per cell")):
        dot = constraint_map_dot(env, values, f"{title} (p = {STOCHASTICITY}; thick border = truly forbidden)")
        write_text(context.path("gridworld", f"{stem}.dot"), dot)
        files.append(f"gridworld/{stem}.dot")
        if dot_available():
            render_dot(dot, context.path("gridworld", f"{stem}.svg"))
            files.append(f"gridworld/{stem}.svg")

    n_q = 50 if context.quick else 300
    plain = q_learning(make_gridworld(STOCHASTICITY), n_q, learning_rate=0.5, discount=0.95, seed=context.seed)
    shielded = q_learning(Shield(make_gridworld(STOCHASTICITY), ml.constraints_, seed=context.seed), n_q,
                          learning_rate=0.5, discount=0.95, seed=context.seed)

    figures = {
        "stochasticity": STOCHASTICITY, "demonstrations": n_demos,
        "violation_rate": {k: v[1] for k, v in rows.items()}, "reward": {k: v[0] for k, v in rows.items()},
        "mce_iterations": mce.n_iter_, "mce_cells_marked": int(mce.constraint_map_.sum()),
        "mce_forbidden_cells_marked": int(mce.constraint_map_[env.forbidden_states].sum()),
        "ml_constraints": int(ml.constraints_.sum()), "ml_stopped_because": ml.stopped_because_,
        "q_learning_violations": {"plain": int(plain.violations.sum()), "ml_shield": int(shielded.violations.sum())},
    }
    table = "\n".join(f"| {name} | {reward:.1f} | {rate:.3f} |" for name, (reward, rate) in rows.items())
    markdown = f"""
Gridworld 7 x 7, stochasticity {STOCHASTICITY} (a chosen move is replaced by a random neighbouring
cell with that probability), {n_demos} expert demonstrations. MCE-ICRL ran {mce.n_iter_} dual
iterations and marks {figures['mce_cells_marked']} cells as constrained, {figures['mce_forbidden_cells_marked']}
of the 12 forbidden ones among them; ML constraint inference forbade {figures['ml_constraints']}
state-action pairs (stopped: {ml.stopped_because_}). Policies run in the true environment
({episodes} episodes each):

| policy | reward | violation rate |
|---|---|---|
{table}

`gridworld/constraint_map.txt` holds both learned maps as text; `mce_cost.dot` and
`ml_constraints.dot` draw them. Q-learning for {n_q} episodes: {figures['q_learning_violations']['plain']}
steps in forbidden cells unshielded, {figures['q_learning_violations']['ml_shield']} behind the shield
built from the ML constraint set (violations that remain come from random slips).
"""
    return Section("Constraint learning in a stochastic gridworld", markdown, figures, files)


PIPELINE = Pipeline("gridworld", "Learn the forbidden block of a stochastic gridworld (MCE-ICRL, ML inference)", run)
