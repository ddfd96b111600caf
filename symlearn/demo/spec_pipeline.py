"""Demo pipeline: learn the Office-1 task specification from expert demonstrations.

Exact experts (value iteration on grid x task automaton) demonstrate "fetch coffee, then go to
the delivery office, never touching a decoration". The learner starts from ``true`` and a
random nominal policy and alternates information-gain template search with CRM Q-learning,
with the office's own propositions given.
"""

from __future__ import annotations

from symlearn.atomic import write_text
from symlearn.demo.registry import DemoContext, Pipeline, Section
from symlearn.rendering import dot_available, render_dot

TASK = "office-1"


def run(context: DemoContext) -> Section:
    from symlearn.envs.spec_experts import expert_demonstrations
    from symlearn.envs.spec_tasks import get_task
    from symlearn.learners.temporal.spec_from_demos import SpecLearner

    task = get_task(TASK)
    env = task.make_env()
    n_demos = 10 if context.quick else 50
    demos = expert_demonstrations(task, n_demos, seed=context.seed, env=env)
    demos.save(context.path("spec", "office1_expert.jsonl"))
    learner = SpecLearner(random_state=context.seed).fit(demos, env)

    files = ["spec/office1_expert.jsonl", "spec/office1.ltl", "spec/office1.labeling.json", "spec/office1.dot"]
    write_text(context.path("spec", "office1.ltl"), f"{learner.formula_}\n")
    learner.labeling_.save(context.path("spec", "office1.labeling.json"))
    dot = learner.dfa_.to_dot(title=str(learner.formula_))
    write_text(context.path("spec", "office1.dot"), dot)
    if dot_available():
        render_dot(dot, context.path("spec", "office1.svg"))
        files.append("spec/office1.svg")

    success = learner.success_rate(task.formula)
    rows = "\n".join(
        f"| {h['iteration']} | `{h['formula'] or '-'}` | {h['gain']:.3f} | {'added' if h['added'] else 'stop'} | "
        f"{h['seconds']:.2f} |" for h in learner.history_)
    figures = {
        "demonstrations": n_demos,
        "formula": str(learner.formula_),
        "ground_truth": task.formula,
        "success_rate": success,
        "entropy": round(learner.entropy_, 4),
        "iterations": learner.iterations_,
        "length": learner.length_,
        "pruned": learner.pruned_,
        "automaton_states": learner.dfa_.n_states,
        "seconds": round(learner.seconds_, 2),
    }
    markdown = f"""
Office world, task Office-1 (ground truth `{task.formula}`: coffee, then the delivery office,
never a decoration). {n_demos} demonstrations of an exact expert; propositions given.

| iteration | best template | information gain | | seconds |
|---|---|---|---|---|
{rows}

Learned specification: `{learner.formula_}` ({learner.length_} nodes, automaton with
{learner.dfa_.n_states} states, pruned: {', '.join(learner.pruned_) or 'nothing'}). The greedy
nominal policy trained on it by CRM Q-learning satisfies the ground truth in
{success:.0%} of rollouts (policy entropy {learner.entropy_:.3f}); {learner.seconds_:.1f} s in total.
The formula can be shorter than the ground truth when the environment makes a part of it
unavoidable on the shortest way. Files: `spec/office1.ltl`, the labeling as JSON and the
automaton as DOT/SVG.
"""
    return Section("Task specification from demonstrations (Office-1)", markdown, figures, files)


PIPELINE = Pipeline("spec", "Learn the Office-1 LTLf task specification from demonstrations", run)
