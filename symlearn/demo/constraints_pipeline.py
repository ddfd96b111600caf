"""Demo pipeline: from demonstrations to rules to a shielded agent (Hanoi and traffic junctions).

For each domain a bundled rule-abiding expert is recorded, logic constraint inference
alternates maximum-likelihood inference and ILP induction, and the learned rules are written as
an editable ``.lp`` file and scored against the ground truth over every state-action pair. In
the junctions a Q-learning agent is then trained with and without the learned rules as a
shield, and its rule violations are counted (the safety claim of the method).
"""

from __future__ import annotations

import numpy as np

from symlearn.demo.registry import DemoContext, Pipeline, Section

# (environment, demonstrations, iterations) -- full run / quick run
_FULL = [("hanoi", 20, 10), ("junction-lights", 100, 20), ("junction-priority", 100, 20)]
_QUICK = [("hanoi", 10, 5), ("junction-priority", 50, 10)]


def run(context: DemoContext) -> Section:
    from symlearn.envs.constraint_envs import constraint_setting
    from symlearn.learners.constraints.logic_constraint_inference import LogicConstraintInference

    rows, figures, files, learned = [], {}, [], {}
    for name, n_demos, iterations in (_QUICK if context.quick else _FULL):
        setting = constraint_setting(name)
        demos = setting.expert(n_demos, context.seed)
        demos_file = f"constraints/{name}_demos.jsonl"
        demos.save(context.path(*demos_file.split("/")))
        learner = LogicConstraintInference(iterations=iterations).fit(demos, setting.logic)
        rules_file = f"constraints/{name}_rules.lp"
        learner.to_lp(context.path(*rules_file.split("/")))
        files += [demos_file, rules_file]
        scores = learner.score()
        inference = sum(h.inference_seconds for h in learner.history_)
        induction = sum(h.induction_seconds for h in learner.history_)
        learned[name] = (learner, setting.logic)
        rules_md = "<br>".join(f"`{r}`" for r in learner.rules_) or "(none)"
        rows.append(f"| {name} | {n_demos} | {len(learner.history_)} | {rules_md} | {scores['forbidden']} | "
                    f"{scores['fpr']:.3f} | {scores['fnr']:.3f} | {scores['accuracy']:.3f} | "
                    f"{inference:.1f} / {induction:.1f} |")
        figures[f"{name}_rules"] = len(learner.rules_)
        figures[f"{name}_accuracy"] = round(scores["accuracy"], 3)
        figures[name] = {"rules": learner.rules_, "iterations": len(learner.history_), **scores,
                         "inference_seconds": round(inference, 3), "induction_seconds": round(induction, 3)}

    shield_md = _shielded_q_learning(context, learned, figures)
    markdown = f"""
Rules learned from expert demonstrations alone (logic constraint inference: each iteration
infers the most likely constraint under the rule-free MaxEnt planner, then induces ASP rules
with demonstrated pairs as positive and inferred constraints as negative examples). FPR =
allowed pairs wrongly forbidden / allowed pairs; FNR = forbidden pairs wrongly allowed /
forbidden pairs; over every state-action pair of the domain. Rules: `constraints/*_rules.lp`.

| environment | demonstrations | iterations | learned rules | forbidden pairs | FPR | FNR | accuracy | inference / induction s |
|---|---|---|---|---|---|---|---|---|
{chr(10).join(rows)}
{shield_md}"""
    return Section("Constraints from demonstrations: rules and a shielded agent", markdown, figures, files)


def _shielded_q_learning(context: DemoContext, learned: dict, figures: dict) -> str:
    """Plain vs rule-shielded Q-learning in each junction whose rules were learned above
    (``learned``: name -> (fitted learner, its LogicMDP))."""
    from symlearn.backends.masks import env_mask
    from symlearn.backends.shield import Shield
    from symlearn.envs.junction_env import JunctionEnv
    from symlearn.rl.q_learning import q_learning

    episodes = 150 if context.quick else 400
    lines = []
    for name, (learner, lm) in learned.items():
        if not name.startswith("junction-"):
            continue
        variant = name.removeprefix("junction-")
        plain = q_learning(JunctionEnv(variant), episodes, seed=context.seed)
        mask = env_mask(lm.mdp, learner.rule_constraints_, JunctionEnv(variant).state_names,
                        unavailable=lm.unavailable)
        shielded = q_learning(Shield(JunctionEnv(variant), mask, seed=context.seed), episodes, seed=context.seed)
        row = {"episodes": episodes, "plain_violations": int(plain.violations.sum()),
               "shielded_violations": int(shielded.violations.sum()),
               "plain_final_cost": float(np.mean(-plain.returns[-20:])),
               "shielded_final_cost": float(np.mean(-shielded.returns[-20:]))}
        figures[f"{name}_q_learning"] = row
        figures[f"{name}_shielded_violations"] = row["shielded_violations"]
        lines.append(f"| {name} | {episodes} | {row['plain_violations']} | {row['shielded_violations']} | "
                     f"{row['plain_final_cost']:.1f} | {row['shielded_final_cost']:.1f} |")
    if not lines:
        return ""
    return ("\nQ-learning (epsilon 0.05, learning rate 0.9, discount 0.75; cost = L1 distance to the goal, "
            "+10 per broken rule), plain and shielded by the learned rules:\n\n"
            "| environment | episodes | violations (plain) | violations (shielded) | final cost (plain) | "
            "final cost (shielded) |\n|---|---|---|---|---|---|\n" + "\n".join(lines) + "\n")


PIPELINE = Pipeline("constraints", "Constraints from demonstrations: rules and a shielded agent", run)
