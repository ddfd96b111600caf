"""Write notebooks/07_spec_from_demonstrations.ipynb (without outputs): .venv/bin/python scripts/make_notebook_07.py"""
from pathlib import Path
import nbformat
from nbformat.v4 import new_notebook, new_markdown_cell, new_code_cell
cells = [
new_markdown_cell("""# Learning a task specification from demonstrations

An expert solves a task in the office world; we only see where it walked. `SpecLearner` recovers an
LTLf formula for the task by alternating two steps:

1. **inference**: among the templates `F p`, `G p`, `p T q` (and their negations) pick the one that best
   separates expert trajectories from trajectories of the current *nominal* policy, by information gain;
   conjoin it to the specification;
2. **policy update**: compile the specification to a DFA and a reward machine and train the nominal policy
   on it with Q-learning over (grid cell, machine state) using counterfactual experiences (CRM).

It starts from `true` and a random walk and stops when the best gain drops below 0.2."""),
new_code_cell("""import os
from symlearn.envs.spec_tasks import get_task
from symlearn.envs.spec_experts import expert_demonstrations
from symlearn.learners.temporal.spec_from_demos import SpecLearner

QUICK = os.environ.get("SYMLEARN_QUICK") == "1"
N_DEMOS = 10 if QUICK else 50
task = get_task("office-1")
env = task.make_env()
print(task.formula, "-", task.description)
print(env.render())"""),
new_markdown_cell("""Exact experts: value iteration on the product of the grid and the task automaton. They choose at random
among equally short solutions, so the demonstrations differ where the office allows it."""),
new_code_cell("""demos = expert_demonstrations(task, N_DEMOS, seed=0, env=env)
print(len(demos), "demonstrations; lengths", sorted({len(t) for t in demos}))
print("first one visits:", [env.cell_of(s) for s in demos[0].states])"""),
new_markdown_cell("## With the office's propositions given"),
new_code_cell("""learner = SpecLearner(random_state=0).fit(demos, env)
for h in learner.history_:
    print(h["iteration"], h["formula"], f"gain={h['gain']:.3f}", "added" if h["added"] else "stop")
print("learned:", learner.formula_, "| ground truth:", task.formula)
print("success of the greedy nominal policy on the ground truth:", learner.success_rate(task.formula))
print("policy entropy:", round(learner.entropy_, 3))"""),
new_markdown_cell("The learned automaton (reward on reaching an accepting state):"),
new_code_cell("learner.dfa_"),
new_markdown_cell("""## Without propositions

Now the learner sees only cell ids. Every visited cell is a candidate proposition "the agent is in this
cell"; a chosen cell becomes `p0`, `p1`, ... and the labeling grows with it."""),
new_code_cell("""blind = SpecLearner(propositions="learn", random_state=0).fit(demos, env)
print("learned:", blind.formula_)
for p in blind.labeling_.propositions:
    print(" ", p, "=", blind.labeling_.meanings[p])
print("success on the ground truth:", blind.success_rate(task.formula))
print(blind.labeling_.to_json()[:300])"""),
new_markdown_cell("""## Without policy updates

If the nominal policy stays a random walk, each iteration can only add another formula that random walks
violate, and the specification grows long (the ablation of the thesis)."""),
new_code_cell("""random_nominal = SpecLearner(policy_updates=False, prune=False, max_iterations=4 if QUICK else 10,
                             random_state=0).fit(demos, env)
print(random_nominal.formula_, "| length", random_nominal.length_, "vs", learner.length_)"""),
]
nb = new_notebook(cells=cells, metadata={"kernelspec": {"name": "python3", "display_name": "Python 3", "language": "python"}})
nbformat.write(nb, str(Path(__file__).resolve().parent.parent / "notebooks" / "07_spec_from_demonstrations.ipynb"))
